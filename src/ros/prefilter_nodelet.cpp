#include "ohm_mirror_detector3d/ros/prefilter_nodelet.h"

#include <pluginlib/class_list_macros.hpp>

#include <stdexcept>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/ros/conversions.h"
#include "ohm_mirror_detector3d/ros/parameters.h"

namespace ohm_mirror_detector3d
{
namespace
{
// Throttle period of the errors about bad input, so a broken driver cannot flood the log.
constexpr double kErrorThrottleSeconds = 5.0;

std::string joinLines(const std::vector<std::string>& lines)
{
  std::string joined;
  for (const std::string& line : lines)
    joined += "\n  " + line;
  return joined;
}
}  // namespace

void PreFilterNodelet::onInit()
{
  ros::NodeHandle& pnh = getPrivateNodeHandle();

  std::vector<std::string> errors;
  const core::Params params = ros_io::readParams(pnh, errors);
  const std::vector<std::string> range_errors = params.validate();
  errors.insert(errors.end(), range_errors.begin(), range_errors.end());
  std::string input_mode = kInputModePair;
  pnh.param<std::string>("input_mode", input_mode, input_mode);
  if (input_mode != kInputModePair)
    errors.push_back("input_mode '" + input_mode + "' is unknown: allowed values are 'pair'");
  if (!errors.empty())
  {
    const std::string message = "refusing to start, bad parameters:" + joinLines(errors);
    NODELET_FATAL_STREAM(message);
    throw std::invalid_argument(message);
  }
  pipeline_.setParams(params);
  ros_io::writeParams(pnh, params);

  reconfigure_server_ =
      std::make_unique<dynamic_reconfigure::Server<PreFilterConfig>>(reconfigure_mutex_, pnh);
  reconfigure_server_->setCallback(
      [this](PreFilterConfig& config, std::uint32_t level) { onReconfigure(config, level); });

  // Outputs are advertised in the node's private namespace (~labelled, ~cleaned) like the
  // input (~input), so several pre-filters can run side by side.
  const ros::SubscriberStatusCallback on_connection = [this](const ros::SingleSubscriberPublisher&) {
    updateSubscription();
  };
  std::lock_guard<std::mutex> lock(subscription_mutex_);
  labelled_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("labelled", 1, on_connection, on_connection);
  cleaned_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("cleaned", 1, on_connection, on_connection);
  NODELET_INFO("pre-filter ready: input_mode %s, waiting for subscribers of %s or %s", input_mode.c_str(),
               labelled_pub_.getTopic().c_str(), cleaned_pub_.getTopic().c_str());
}

void PreFilterNodelet::updateSubscription()
{
  std::lock_guard<std::mutex> lock(subscription_mutex_);
  const bool wanted = labelled_pub_.getNumSubscribers() > 0 || cleaned_pub_.getNumSubscribers() > 0;
  if (wanted && !input_sub_)
  {
    // A queue of 2 sweeps: a sweep is large, and a late one is worth less than the next.
    input_sub_ = getPrivateNodeHandle().subscribe<EchoPair>(
        "input", 2, [this](const EchoPair::ConstPtr& pair) { onEchoPair(pair); });
    NODELET_DEBUG("subscribed to %s", input_sub_.getTopic().c_str());
  }
  else if (!wanted && input_sub_)
  {
    NODELET_DEBUG("no subscribers left, unsubscribing from %s", input_sub_.getTopic().c_str());
    input_sub_.shutdown();
  }
}

void PreFilterNodelet::onReconfigure(PreFilterConfig& config, std::uint32_t /*level*/)
{
  const core::Params params = ros_io::fromConfig(config);
  const std::vector<std::string> errors = params.validate();
  if (!errors.empty())
  {
    NODELET_ERROR_STREAM("dynamic_reconfigure refused, the previous configuration stays in force:"
                         << joinLines(errors));
    // dynamic_reconfigure publishes whatever the callback leaves in `config`.
    config = active_config_;
    return;
  }
  std::lock_guard<std::mutex> lock(pipeline_mutex_);
  pipeline_.setParams(params);
  active_config_ = config;
}

void PreFilterNodelet::onEchoPair(const EchoPair::ConstPtr& pair)
{
  std::lock_guard<std::mutex> lock(pipeline_mutex_);
  const std::string problem = ros_io::echoPairToSweep(*pair, sweep_);
  if (!problem.empty())
  {
    NODELET_ERROR_STREAM_THROTTLE(kErrorThrottleSeconds,
                                  "dropping sweep on " << input_sub_.getTopic() << ": " << problem);
    return;
  }
  processAndPublish(pair->header);
}

void PreFilterNodelet::processAndPublish(const std_msgs::Header& header)
{
  const core::PipelineResult& result = pipeline_.process(sweep_);
  if (labelled_pub_.getNumSubscribers() > 0)
  {
    sensor_msgs::PointCloud2Ptr labelled(new sensor_msgs::PointCloud2);
    ros_io::toLabelledCloud(header, sweep_, result.labels, *labelled);
    labelled_pub_.publish(labelled);
  }
  if (cleaned_pub_.getNumSubscribers() > 0)
  {
    sensor_msgs::PointCloud2Ptr cleaned(new sensor_msgs::PointCloud2);
    ros_io::toCleanedCloud(header, result.cleaned, *cleaned);
    cleaned_pub_.publish(cleaned);
  }
}

}  // namespace ohm_mirror_detector3d

PLUGINLIB_EXPORT_CLASS(ohm_mirror_detector3d::PreFilterNodelet, nodelet::Nodelet)
