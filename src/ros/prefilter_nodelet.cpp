#include "ohm_mirror_detector3d/ros/prefilter_nodelet.h"

#include <pluginlib/class_list_macros.hpp>
#include <std_msgs/Float64MultiArray.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <vector>

#include "ohm_mirror_detector3d/core/removal_report.h"
#include "ohm_mirror_detector3d/ros/conversions.h"
#include "ohm_mirror_detector3d/ros/parameters.h"

namespace ohm_mirror_detector3d
{
namespace
{
// How often what waits for tf (scans, sensor_frame sweeps) is tried again.
constexpr double kTfPollSeconds = 0.02;
// A stage that removes an implausible share says so at most this often (every sweep may).
constexpr double kRemovalWarningSeconds = 10.0;

std::string joinLines(const std::vector<std::string>& lines)
{
  std::string joined;
  for (const std::string& line : lines)
    joined += "\n  " + line;
  return joined;
}

// A topic under its current name, or under the name a legacy launch file gives it with
// a `sub_*` / `pub_*` parameter (resolved like any relative name of the node).
std::string topicName(const ros::NodeHandle& private_nh, const std::string& own_name,
                      const std::vector<std::string>& legacy_params)
{
  for (const std::string& legacy : legacy_params)
  {
    std::string topic;
    if (private_nh.getParam(legacy, topic) && !topic.empty())
      return topic;
  }
  return private_nh.resolveName(own_name);
}
}  // namespace

void PreFilterNodelet::onInit()
{
  ros::NodeHandle& pnh = getPrivateNodeHandle();

  std::vector<std::string> errors;
  const core::Params params = ros_io::readParams(pnh, errors);
  const std::vector<std::string> range_errors = params.validate();
  errors.insert(errors.end(), range_errors.begin(), range_errors.end());
  std::string input_mode;
  pnh.param<std::string>("input_mode", input_mode, ros_io::inputModes().front().name);
  const ros_io::InputMode* mode = ros_io::findInputMode(input_mode);
  if (mode == nullptr)
    errors.push_back(ros_io::unknownInputModeMessage(input_mode));
  ros_io::InputOptions options;
  input_topic_ = topicName(pnh, "input", { "sub_input_scan" });
  options.input_topic = input_topic_;
  options.echo1_topic = pnh.resolveName("echo1");
  options.echo2_topic = pnh.resolveName("echo2");
  // Its messages name the input topic too, as every other input problem does.
  options.log_name = getName() + " (input " + input_topic_ + ")";
  if (mode != nullptr)
    ros_io::readInputOptions(ros_io::NodeHandleParamSource(pnh), *mode, options, errors);
  if (!errors.empty())
  {
    const std::string message = "refusing to start, bad parameters:" + joinLines(errors);
    NODELET_FATAL_STREAM(message);
    throw std::invalid_argument(message);
  }
  pipeline_.setParams(params);
  ros_io::writeParams(pnh, params);
  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  ros_io::SweepReceiver& receiver = *this;
  input_ = std::make_unique<ros_io::SweepInput>(*mode, options, *tf_buffer_, receiver,
                                                []() { return ros::WallTime::now().toSec(); });
  if (input_->readsTf())
  {
    // Started here so that tf is buffered by the time the first sweep comes.
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, getNodeHandle(), true);
  }

  reconfigure_server_ = std::make_unique<dynamic_reconfigure::Server<PreFilterConfig>>(reconfigure_mutex_, pnh);
  reconfigure_server_->setCallback(
      [this](PreFilterConfig& config, std::uint32_t level) { onReconfigure(config, level); });

  if (!input_->describe().empty())
    NODELET_INFO_STREAM(input_->describe());

  advertiseOutputs();
  startDiagnostics();
  NODELET_INFO("pre-filter ready: input_mode %s, publishing %s, %s, %s, %s", mode->name,
               labelled_pub_.getTopic().c_str(), cleaned_pub_.getTopic().c_str(), objects_pub_.getTopic().c_str(),
               markers_pub_.getTopic().c_str());
}

void PreFilterNodelet::advertiseOutputs()
{
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  const ros::SubscriberStatusCallback on_connection = [this](const ros::SingleSubscriberPublisher&) {
    updateSubscription();
  };
  std::lock_guard<std::mutex> lock(subscription_mutex_);
  labelled_pub_ = pnh.advertise<sensor_msgs::PointCloud2>(topicName(pnh, "labelled", { "pub_labelled" }), 1,
                                                          on_connection, on_connection);
  cleaned_pub_ = pnh.advertise<sensor_msgs::PointCloud2>(topicName(pnh, "cleaned", { "pub_cleaned", "pub_scan" }),
                                                         1, on_connection, on_connection);
  objects_pub_ = pnh.advertise<ReflectiveObjectArray>(topicName(pnh, "objects", { "pub_objects" }), 1,
                                                      on_connection, on_connection);
  markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>(topicName(pnh, "markers", { "pub_markers" }), 1,
                                                                on_connection, on_connection);
  // Not an output: subscribing to it alone does not start the pre-filter.
  timing_pub_ = pnh.advertise<std_msgs::Float64MultiArray>("timing", 10);
}

void PreFilterNodelet::startDiagnostics()
{
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  diagnostics_ = std::make_unique<diagnostic_updater::Updater>(getNodeHandle(), pnh, getName());
  diagnostics_->setHardwareID(input_topic_);
  diagnostics_->add("pre-filter", [this](diagnostic_updater::DiagnosticStatusWrapper& status) {
    bool subscribed = false;
    {
      std::lock_guard<std::mutex> lock(subscription_mutex_);
      subscribed = subscribed_;
    }
    stats_.report(status, subscribed);
  });
  // A wall timer: under use_sim_time (a bag played with --clock) a paused clock must not
  // silence the diagnostics.
  diagnostics_timer_ = pnh.createWallTimer(ros::WallDuration(diagnostics_->getPeriod()),
                                           [this](const ros::WallTimerEvent&) { diagnostics_->force_update(); });
}

void PreFilterNodelet::updateSubscription()
{
  std::lock_guard<std::mutex> lock(subscription_mutex_);
  const bool wanted = labelled_pub_.getNumSubscribers() > 0 || cleaned_pub_.getNumSubscribers() > 0 ||
                      objects_pub_.getNumSubscribers() > 0 || markers_pub_.getNumSubscribers() > 0;
  if (wanted && !subscribed_)
    subscribe();
  else if (!wanted && subscribed_)
    unsubscribe();
}

void PreFilterNodelet::subscribe()
{
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  input_->reset();
  input_subscribers_ = input_->subscribe(pnh);
  if (input_->readsTf())
    poll_timer_ = pnh.createWallTimer(ros::WallDuration(kTfPollSeconds),
                                      [this](const ros::WallTimerEvent&) { input_->poll(); });
  subscribed_ = true;
  NODELET_DEBUG("an output has subscribers: subscribed to the input");
}

void PreFilterNodelet::unsubscribe()
{
  for (ros::Subscriber& subscriber : input_subscribers_)
    subscriber.shutdown();
  input_subscribers_.clear();
  poll_timer_.stop();
  subscribed_ = false;
  NODELET_DEBUG("no output has subscribers: unsubscribed from the input");
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

void PreFilterNodelet::sweepReady(core::Sweep& sweep, const core::SweepContext& context)
{
  std::lock_guard<std::mutex> lock(pipeline_mutex_);
  std::swap(pipeline_.sweep(), sweep);
  processAndPublish(context);
}

void PreFilterNodelet::inputProblem(const ros_io::InputProblem& problem)
{
  reportInputProblem(problem);
  if (problem.dropped)
    stats_.recordDropped(problem.what == "sweep" ? problem.text : problem.what + ": " + problem.text);
}

void PreFilterNodelet::reportInputProblem(const ros_io::InputProblem& problem)
{
  std::size_t suppressed = 0;
  {
    std::lock_guard<std::mutex> lock(problem_mutex_);
    if (!problem_throttle_.shouldReport(problem.topic, problem.text, ros::WallTime::now().toSec(), suppressed))
      return;
  }
  const std::string repeats =
      suppressed > 0 ? " (and " + std::to_string(suppressed) + " more like it since the last report)" : "";
  if (problem.dropped)
    NODELET_ERROR_STREAM("dropping " << problem.describe() << repeats);
  else
    NODELET_WARN_STREAM(problem.describe() << repeats);
}

void PreFilterNodelet::processAndPublish(const core::SweepContext& context)
{
  ros_io::OutputRequest request;
  request.labelled = labelled_pub_.getNumSubscribers() > 0;
  request.cleaned = cleaned_pub_.getNumSubscribers() > 0;
  request.objects = objects_pub_.getNumSubscribers() > 0;
  request.markers = markers_pub_.getNumSubscribers() > 0;
  ros_io::OutputMessages outputs;
  const auto start = ros_io::ProcessingStats::Clock::now();
  const core::PipelineResult& result = pipeline_.process(context, request, outputs);
  const double seconds = std::chrono::duration<double>(ros_io::ProcessingStats::Clock::now() - start).count();
  stats_.recordProcessed(seconds, result.objects.size(), pipeline_.sweep().beamCount() * 2);
  const std::vector<std::string> warnings = core::removalWarnings(result.removals, pipeline_.params());
  if (!warnings.empty())
  {
    std::string text = warnings.front();
    for (std::size_t i = 1; i < warnings.size(); ++i)
      text += "; " + warnings[i];
    stats_.recordImplausibleRemoval(text);
    NODELET_WARN_STREAM_THROTTLE(kRemovalWarningSeconds, text);
  }
  if (outputs.labelled)
    labelled_pub_.publish(outputs.labelled);
  if (outputs.cleaned)
    cleaned_pub_.publish(outputs.cleaned);
  if (timing_pub_.getNumSubscribers() > 0)
  {
    // For make bench (bench/nodelet_latency.py): the core's time and the age of the input
    // stamp when `cleaned` was published, both in seconds.
    const double age = (ros::Time::now() - ros_io::toHeader(context).stamp).toSec();
    std_msgs::Float64MultiArray timing;
    timing.layout.dim.resize(1);
    timing.layout.dim[0].label = "core_s,stamp_to_cleaned_published_s";
    timing.layout.dim[0].size = 2;
    timing.layout.dim[0].stride = 2;
    timing.data = { result.times.total, age };
    timing_pub_.publish(timing);
  }
  if (outputs.objects)
    objects_pub_.publish(outputs.objects);
  if (outputs.markers)
    markers_pub_.publish(outputs.markers);
}

}  // namespace ohm_mirror_detector3d

PLUGINLIB_EXPORT_CLASS(ohm_mirror_detector3d::PreFilterNodelet, nodelet::Nodelet)
