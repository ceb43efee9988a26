#include "ohm_mirror_detector3d/ros/prefilter_nodelet.h"

#include <pluginlib/class_list_macros.hpp>
#include <std_msgs/Float64MultiArray.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <vector>

#include "ohm_mirror_detector3d/ros/conversions.h"
#include "ohm_mirror_detector3d/ros/dual_return.h"
#include "ohm_mirror_detector3d/ros/parameters.h"

namespace ohm_mirror_detector3d
{
namespace
{
// Throttle period of the errors about bad input, so a broken driver cannot flood the log.
constexpr double kErrorThrottleSeconds = 5.0;
// How long a sweep waits for the transform of sensor_frame at its stamp.
constexpr double kTfWaitSeconds = 0.2;
// A sweep is large and a late one is worth less than the next: keep few.
constexpr std::uint32_t kInputQueueSize = 2;

// Scans are small and come at 40 Hz; keep 10 s of them while a sweep is processed.
constexpr std::uint32_t kScanQueueSize = 400;
// How often the scans that wait for their transforms are retried.
constexpr double kScanRetrySeconds = 0.02;

const char* const kInputModes[] = { "pair", "two_topics", "dual_return", "hokuyo3d_legacy",
                                      "multi_echo_scan" };

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
  pnh.param<std::string>("input_mode", input_mode_, kInputModes[0]);
  if (std::find(std::begin(kInputModes), std::end(kInputModes), input_mode_) == std::end(kInputModes))
  {
    std::string allowed;
    for (const char* mode : kInputModes)
      allowed += std::string(allowed.empty() ? "'" : ", '") + mode + "'";
    errors.push_back("input_mode '" + input_mode_ + "' is unknown: allowed values are " + allowed);
  }
  ros_io::MultiEchoScanOptions scan_options;
  if (input_mode_ == "multi_echo_scan")
    scan_options = ros_io::readMultiEchoScanOptions(pnh, errors);
  azimuth_resolution_deg_ = ros_io::readAzimuthResolution(ros_io::NodeHandleParamSource(pnh), errors);
  pnh.param<std::string>("sensor_frame", sensor_frame_, "");
  if (!sensor_frame_.empty() && sensor_frame_[0] == '/')
    sensor_frame_.erase(0, 1);
  if (!sensor_frame_.empty() && input_mode_ == "multi_echo_scan")
    errors.push_back("sensor_frame is not used in input_mode multi_echo_scan (the origin comes from the scans' "
                     "frame in sweep_frame); remove it");
  if (!errors.empty())
  {
    const std::string message = "refusing to start, bad parameters:" + joinLines(errors);
    NODELET_FATAL_STREAM(message);
    throw std::invalid_argument(message);
  }
  pipeline_.setParams(params);
  ros_io::writeParams(pnh, params);
  if (!sensor_frame_.empty())
  {
    // Started here so that tf is buffered by the time the first sweep comes.
    sensor_tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
    sensor_tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*sensor_tf_buffer_);
  }
  input_topic_ = topicName(pnh, "input", { "sub_input_scan" });
  if (input_mode_ == "multi_echo_scan")
  {
    // Its messages name the input topic too, as every other input problem does.
    scan_input_ = std::make_unique<ros_io::MultiEchoScanInput>(scan_options, getNodeHandle(),
                                                               getName() + " (input " + input_topic_ + ")");
  }

  reconfigure_server_ = std::make_unique<dynamic_reconfigure::Server<PreFilterConfig>>(reconfigure_mutex_, pnh);
  reconfigure_server_->setCallback(
      [this](PreFilterConfig& config, std::uint32_t level) { onReconfigure(config, level); });

  if (input_mode_ == "dual_return")
    NODELET_INFO("dual_return: %zu azimuth bins of %.8g deg", core::azimuthBins(azimuth_resolution_deg_),
                 360.0 / static_cast<double>(core::azimuthBins(azimuth_resolution_deg_)));

  advertiseOutputs();
  startDiagnostics();
  NODELET_INFO("pre-filter ready: input_mode %s, publishing %s, %s, %s, %s", input_mode_.c_str(),
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
  if (input_mode_ == "pair")
  {
    pair_sub_ = pnh.subscribe<EchoPair>(input_topic_, kInputQueueSize,
                                        [this](const EchoPair::ConstPtr& pair) { onEchoPair(pair); });
  }
  else if (input_mode_ == "dual_return")
  {
    dual_return_sub_ = pnh.subscribe<sensor_msgs::PointCloud2>(
        input_topic_, kInputQueueSize,
        [this](const sensor_msgs::PointCloud2::ConstPtr& cloud) { onDualReturnCloud(cloud); });
  }
  else if (input_mode_ == "hokuyo3d_legacy")
  {
    // ohm_hokuyo3d/CoordDistMulti, of a package we do not have: decoded from its definition.
    legacy_sub_ = pnh.subscribe<topic_tools::ShapeShifter>(
        input_topic_, kInputQueueSize,
        [this](const topic_tools::ShapeShifter::ConstPtr& message) { onLegacyMessage(message); });
  }
  else if (input_mode_ == "multi_echo_scan")
  {
    scan_input_->reset();
    scan_sub_ = pnh.subscribe<sensor_msgs::MultiEchoLaserScan>(
        input_topic_, kScanQueueSize,
        [this](const sensor_msgs::MultiEchoLaserScan::ConstPtr& scan) { onMultiEchoScan(scan); });
    scan_drain_timer_ = pnh.createWallTimer(ros::WallDuration(kScanRetrySeconds),
                                            [this](const ros::WallTimerEvent&) { onMultiEchoScan(nullptr); });
  }
  else
  {
    echo1_sub_.subscribe(pnh, "echo1", kInputQueueSize);
    echo2_sub_.subscribe(pnh, "echo2", kInputQueueSize);
    if (!echo_sync_)
    {
      echo_sync_ = std::make_unique<EchoSync>(echo1_sub_, echo2_sub_, kInputQueueSize * 2);
      echo_sync_->registerCallback(&PreFilterNodelet::onEchoClouds, this);
    }
  }
  subscribed_ = true;
  NODELET_DEBUG("an output has subscribers: subscribed to the input");
}

void PreFilterNodelet::unsubscribe()
{
  pair_sub_.shutdown();
  scan_sub_.shutdown();
  scan_drain_timer_.stop();
  echo1_sub_.unsubscribe();
  echo2_sub_.unsubscribe();
  dual_return_sub_.shutdown();
  legacy_sub_.shutdown();
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

void PreFilterNodelet::onEchoPair(const EchoPair::ConstPtr& pair)
{
  std::lock_guard<std::mutex> lock(pipeline_mutex_);
  const std::string problem = ros_io::echoPairToSweep(*pair, pipeline_.sweep());
  if (!problem.empty())
  {
    reportInputProblem(true, "sweep", input_topic_, problem);
    stats_.recordDropped(problem);
    return;
  }
  processAndPublish(pair->header);
}

void PreFilterNodelet::onEchoClouds(const sensor_msgs::PointCloud2::ConstPtr& echo1,
                                    const sensor_msgs::PointCloud2::ConstPtr& echo2)
{
  std::lock_guard<std::mutex> lock(pipeline_mutex_);
  const std::string problem = ros_io::echoCloudsToSweep(*echo1, *echo2, pipeline_.sweep());
  if (!problem.empty())
  {
    reportInputProblem(true, "sweep", echo1_sub_.getTopic() + " + " + echo2_sub_.getTopic(), problem);
    stats_.recordDropped(problem);
    return;
  }
  processAndPublish(echo1->header);
}

void PreFilterNodelet::onMultiEchoScan(const sensor_msgs::MultiEchoLaserScan::ConstPtr& scan)
{
  if (scan)
  {
    const std::string problem = scan_input_->addScan(scan);
    if (!problem.empty())
    {
      reportInputProblem(true, "scan", input_topic_, problem);
      stats_.recordDropped("scan: " + problem);
    }
  }
  scan_input_->drain([this](core::Sweep& sweep, const std_msgs::Header& header, const core::SweepContext& context) {
    std::lock_guard<std::mutex> lock(pipeline_mutex_);
    std::swap(pipeline_.sweep(), sweep);
    processAndPublish(header, context);
  });
}

void PreFilterNodelet::onDualReturnCloud(const sensor_msgs::PointCloud2::ConstPtr& cloud)
{
  std::lock_guard<std::mutex> lock(pipeline_mutex_);
  core::DualReturnStats stats;
  const std::string problem = ros_io::dualReturnCloudToSweep(*cloud, azimuth_resolution_deg_, dual_return_input_,
                                                             pipeline_.sweep(), stats);
  if (!problem.empty())
  {
    reportInputProblem(true, "sweep", input_topic_, problem);
    stats_.recordDropped(problem);
    return;
  }
  const std::string unbinned = ros_io::describeUnbinned(stats, azimuth_resolution_deg_);
  if (!unbinned.empty())
    reportInputProblem(false, "sweep", input_topic_, unbinned);
  processAndPublish(cloud->header);
}

void PreFilterNodelet::onLegacyMessage(const topic_tools::ShapeShifter::ConstPtr& message)
{
  std::lock_guard<std::mutex> lock(pipeline_mutex_);
  legacy_bytes_.resize(message->size());
  ros::serialization::OStream stream(legacy_bytes_.data(), static_cast<std::uint32_t>(legacy_bytes_.size()));
  message->write(stream);
  std_msgs::Header header;
  const std::string problem = legacy_decoder_.decode(message->getDataType(), message->getMessageDefinition(),
                                                     legacy_bytes_.data(), legacy_bytes_.size(), pipeline_.sweep(),
                                                     header);
  if (!problem.empty())
  {
    reportInputProblem(true, "sweep", input_topic_ + " (" + message->getDataType() + ")", problem);
    stats_.recordDropped(problem);
    return;
  }
  processAndPublish(header);
}

bool PreFilterNodelet::placeSensor(const std_msgs::Header& header, core::SweepContext& context)
{
  if (sensor_frame_.empty() || sensor_frame_ == header.frame_id)
    return true;
  try
  {
    const geometry_msgs::Transform sensor =
        sensor_tf_buffer_->lookupTransform(header.frame_id, sensor_frame_, header.stamp, ros::Duration(kTfWaitSeconds))
            .transform;
    context.sensor_pose = Eigen::Isometry3d::Identity();
    context.sensor_pose.linear() =
        Eigen::Quaterniond(sensor.rotation.w, sensor.rotation.x, sensor.rotation.y, sensor.rotation.z)
            .normalized()
            .toRotationMatrix();
    context.sensor_pose.translation() = Eigen::Vector3d(sensor.translation.x, sensor.translation.y, sensor.translation.z);
    pipeline_.sweep().computeRanges(context.sensorOrigin());
    return true;
  }
  catch (const tf2::TransformException& error)
  {
    NODELET_ERROR_STREAM_THROTTLE(kErrorThrottleSeconds, "dropping sweep: no transform from sensor_frame '"
                                                             << sensor_frame_ << "' to the cloud's frame '"
                                                             << header.frame_id << "': " << error.what());
    stats_.recordDropped(std::string("no transform from sensor_frame: ") + error.what());
    return false;
  }
}

void PreFilterNodelet::reportInputProblem(bool dropped, const std::string& what, const std::string& topic,
                                          const std::string& problem)
{
  std::size_t suppressed = 0;
  {
    std::lock_guard<std::mutex> lock(problem_mutex_);
    if (!problem_throttle_.shouldReport(topic, problem, ros::WallTime::now().toSec(), suppressed))
      return;
  }
  const std::string repeats =
      suppressed > 0 ? " (and " + std::to_string(suppressed) + " more like it since the last report)" : "";
  if (dropped)
    NODELET_ERROR_STREAM("dropping " << what << " on " << topic << ": " << problem << repeats);
  else
    NODELET_WARN_STREAM(what << " on " << topic << ": " << problem << repeats);
}

void PreFilterNodelet::processAndPublish(const std_msgs::Header& header)
{
  processAndPublish(header, ros_io::sensorFrameContext(header));
}

void PreFilterNodelet::processAndPublish(const std_msgs::Header& header, core::SweepContext context)
{
  if (!placeSensor(header, context))
    return;
  ros_io::OutputRequest request;
  request.labelled = labelled_pub_.getNumSubscribers() > 0;
  request.cleaned = cleaned_pub_.getNumSubscribers() > 0;
  request.objects = objects_pub_.getNumSubscribers() > 0;
  request.markers = markers_pub_.getNumSubscribers() > 0;
  ros_io::OutputMessages outputs;
  const auto start = ros_io::ProcessingStats::Clock::now();
  const core::PipelineResult& result = pipeline_.process(header, context, request, outputs);
  const double seconds = std::chrono::duration<double>(ros_io::ProcessingStats::Clock::now() - start).count();
  stats_.recordProcessed(seconds, result.objects.size(), pipeline_.sweep().beamCount() * 2);
  if (outputs.labelled)
    labelled_pub_.publish(outputs.labelled);
  if (outputs.cleaned)
    cleaned_pub_.publish(outputs.cleaned);
  if (timing_pub_.getNumSubscribers() > 0)
  {
    // For make bench (bench/nodelet_latency.py): the core's time and the age of the input
    // stamp when `cleaned` was published, both in seconds.
    const double age = (ros::Time::now() - header.stamp).toSec();
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
