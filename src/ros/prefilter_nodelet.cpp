#include "ohm_mirror_detector3d/ros/prefilter_nodelet.h"

#include <pluginlib/class_list_macros.hpp>
#include <ros/master.h>
#include <std_msgs/Float64MultiArray.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <vector>

#include "ohm_mirror_detector3d/core/object_map_file.h"
#include "ohm_mirror_detector3d/core/removal_report.h"
#include "ohm_mirror_detector3d/ros/conversions.h"
#include "ohm_mirror_detector3d/core/legacy_values.h"
#include "ohm_mirror_detector3d/ros/parameters.h"

namespace ohm_mirror_detector3d
{
namespace
{
// How often what waits for tf (scans, sensor_frame sweeps) is tried again.
constexpr double kTfPollSeconds = 0.02;
// A stage that removes an implausible share says so at most this often (every sweep may).
constexpr double kRemovalWarningSeconds = 10.0;
// The post-filter switched on (reconfigure) without a fixed_frame says so at most this often.
constexpr double kNoFixedFrameSeconds = 10.0;

std::string joinLines(const std::vector<std::string>& lines)
{
  std::string joined;
  for (const std::string& line : lines)
    joined += "\n  " + line;
  return joined;
}

std::string joinWords(const std::vector<std::string>& words)
{
  std::string joined;
  for (const std::string& word : words)
    joined += (joined.empty() ? "" : ", ") + word;
  return joined;
}

// How often the master's record of the input topics' types is checked.
constexpr double kPublisherCheckSeconds = 2.0;

// A topic under its own name, or under the name `name_param` gives it (resolved like any
// relative name of the node); a value that is no string is an error.
std::string topicName(const ros_io::ParamSource& source, const ros::NodeHandle& private_nh,
                      const std::string& own_name, const std::string& name_param, std::vector<std::string>& errors)
{
  std::string topic;
  if (source.has(name_param) && !source.get(name_param, topic))
    errors.push_back("parameter " + source.describe(name_param) + " has the wrong type: expected a topic name");
  return topic.empty() ? private_nh.resolveName(own_name) : topic;
}

// The names in `names` that nothing asked `source` for.
std::vector<std::string> notAsked(const std::vector<std::string>& names, const ros_io::RecordingParamSource& source)
{
  std::vector<std::string> unused;
  for (const std::string& name : names)
    if (!source.wasAsked(name))
      unused.push_back(name);
  return unused;
}
}  // namespace

void PreFilterNodelet::onInit()
{
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  // Before anything writes back under the private namespace (writeParams, reconfigure).
  const std::vector<std::string> set_names = ros_io::privateParameterNames(pnh);
  const ros_io::NodeHandleParamSource server(pnh);
  const ros_io::RecordingParamSource source(server);

  std::vector<std::string> errors;
  core::Params params = ros_io::readParams(source, errors);
  const std::vector<std::string> range_errors = params.validate();
  errors.insert(errors.end(), range_errors.begin(), range_errors.end());
  // Values that are refused are refused as given, not mapped.
  const std::vector<std::string> legacy_mappings =
      errors.empty() ? core::mapLegacyValues([&](const std::string& name) { return source.has(name); }, params) :
                      std::vector<std::string>();
  const ros_io::InputMode* mode = &ros_io::runTimeInputMode();
  std::string input_mode;
  if (source.has("input_mode") && !source.get("input_mode", input_mode))
    errors.push_back("parameter " + source.describe("input_mode") + " has the wrong type: expected a string");
  if (!input_mode.empty())
  {
    mode = ros_io::findInputMode(input_mode);
    if (mode == nullptr)
      errors.push_back(ros_io::unknownInputModeMessage(input_mode));
  }
  ros_io::InputOptions options;
  if (mode != nullptr && mode->default_topic != nullptr)
    options.input_topic = topicName(source, pnh, "input", "sub_input_scan", errors);
  options.echo1_topic = pnh.resolveName("echo1");
  options.echo2_topic = pnh.resolveName("echo2");
  // Its messages name the input topics too, as every other input problem does.
  options.log_name = getName() + " (input " +
                     (options.input_topic.empty() ? options.echo1_topic + " + " + options.echo2_topic :
                                                    options.input_topic) +
                     ")";
  if (mode != nullptr)
    ros_io::readInputOptions(source, *mode, options, errors);
  fixed_frame_ = options.fixed_frame;
  if (params.post_filter != 0 && fixed_frame_.empty())
    errors.push_back("post_filter = 1 needs fixed_frame (the frame the object map is kept in, e.g. odom)");
  if (source.has("map_file") && !source.get("map_file", map_file_))
    errors.push_back("parameter " + source.describe("map_file") + " has the wrong type: expected a file path");
  const auto refuseIfBad = [this, &errors]() {
    if (errors.empty())
      return;
    const std::string message = "refusing to start, bad parameters:" + joinLines(errors);
    NODELET_FATAL_STREAM(message);
    throw std::invalid_argument(message);
  };
  refuseIfBad();
  for (const std::string& mapping : legacy_mappings)
    NODELET_INFO_STREAM(getName() << ": " << mapping);

  // Everything a sweep passes through is ready before the outputs are advertised: a subscriber
  // that connects at once subscribes the input (updateSubscription).
  pipeline_.setParams(params);
  if (!map_file_.empty())
  {
    const std::string problem = core::loadObjectMap(map_file_, fixed_frame_, pipeline_.objectMap());
    if (problem.empty())
      NODELET_INFO_STREAM(getName() << ": object map loaded from " << map_file_ << " ("
                                    << pipeline_.objectMap().objects().size() << " objects)");
    else
      NODELET_ERROR_STREAM(getName() << ": starting with an empty object map: " << problem);
  }
  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  ros_io::SweepReceiver& receiver = *this;
  input_ = std::make_unique<ros_io::SweepInput>(*mode, options, *tf_buffer_, receiver,
                                                []() { return ros::WallTime::now().toSec(); });
  if (input_->readsTf())
  {
    // Started here so that tf is buffered by the time the first sweep comes.
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, getNodeHandle(), true);
  }
  advertiseOutputs(source, std::string(mode->name) == "hokuyo3d_legacy", errors);
  refuseIfBad();

  source.markUsed("diagnostic_period");  // diagnostic_updater reads it itself
  for (const std::string& warning :
       ros_io::unusedParameterWarnings(notAsked(set_names, source), source,
                                       *mode->name == '\0' ? std::string("input_mode not set") :
                                                             "input_mode " + std::string(mode->name)))
    NODELET_WARN_STREAM(warning);
  ros_io::writeParams(pnh, params);

  save_map_service_ = pnh.advertiseService("save_map", &PreFilterNodelet::onSaveMap, this);
  load_map_service_ = pnh.advertiseService("load_map", &PreFilterNodelet::onLoadMap, this);
  reconfigure_server_ = std::make_unique<dynamic_reconfigure::Server<PreFilterConfig>>(reconfigure_mutex_, pnh);
  reconfigure_server_->setCallback(
      [this](PreFilterConfig& config, std::uint32_t level) { onReconfigure(config, level); });

  if (!input_->describe().empty())
    NODELET_INFO_STREAM(input_->describe());

  startDiagnostics();
  std::string inputs;
  for (const std::unique_ptr<ros_io::InputTopic>& topic : input_->topics())
    inputs += (inputs.empty() ? "" : " and ") + topic->name + " (" + topic->datatype + ")";
  const std::string legacy = legacy_.describe();
  NODELET_INFO_STREAM("pre-filter ready: input_mode " << (*mode->name == '\0' ? "not set" : mode->name) << ", input "
                                                      << inputs << "; publishing " << labelled_pub_.getTopic() << ", "
                                                      << cleaned_pub_.getTopic() << ", " << objects_pub_.getTopic()
                                                      << ", " << markers_pub_.getTopic()
                                                      << (fixed_frame_.empty() ? "" : ", " + map_objects_pub_.getTopic() +
                                                                                          " (in " + fixed_frame_ + ")")
                                                      << (legacy.empty() ? "" : "; the original's outputs: " + legacy));
  // nodelet 1.10.0 (Debian 11, Noetic until 2021) disables the nodelet's callback queues while onInit
  // runs and drops what is queued meanwhile, among it the connect callback of a subscriber that
  // connected to an output since it was advertised: that subscriber would never subscribe the input.
  // So look once here; where the callback does come (later nodelet), it finds the input subscribed.
  updateSubscription();
}

void PreFilterNodelet::advertiseOutputs(const ros_io::ParamSource& source, bool every_legacy_output,
                                        std::vector<std::string>& errors)
{
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  const ros::SubscriberStatusCallback on_connection = [this](const ros::SingleSubscriberPublisher&) {
    updateSubscription();
  };
  const std::string labelled = topicName(source, pnh, "labelled", "pub_labelled", errors);
  const std::string objects = topicName(source, pnh, "objects", "pub_objects", errors);
  const std::string markers = topicName(source, pnh, "markers", "pub_markers", errors);
  for (const ros_io::LegacyOutput& output : ros_io::legacyOutputs())
    topicName(source, pnh, output.default_topic, output.parameter, errors);
  if (!errors.empty())
    return;
  std::lock_guard<std::mutex> lock(subscription_mutex_);
  labelled_pub_ = pnh.advertise<sensor_msgs::PointCloud2>(labelled, 1, on_connection, on_connection);
  // The original's pub_cleaned and pub_scan name its own outputs (legacy_): ~cleaned has no other name.
  cleaned_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("cleaned", 1, on_connection, on_connection);
  objects_pub_ = pnh.advertise<ReflectiveObjectArray>(objects, 1, on_connection, on_connection);
  markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>(markers, 1, on_connection, on_connection);
  legacy_.advertise(pnh, source, every_legacy_output, on_connection);
  map_objects_pub_ = pnh.advertise<ReflectiveObjectArray>("map_objects", 1, on_connection, on_connection);
  map_markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("map_markers", 1, on_connection, on_connection);
  map_evidence_pub_ = pnh.advertise<ObjectMapEvidence>("map_evidence", 1, on_connection, on_connection);
  // Not an output: subscribing to it alone does not start the pre-filter.
  timing_pub_ = pnh.advertise<std_msgs::Float64MultiArray>("timing", 10);
}

void PreFilterNodelet::startDiagnostics()
{
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  diagnostics_ = std::make_unique<diagnostic_updater::Updater>(getNodeHandle(), pnh, getName());
  diagnostics_->setHardwareID(input_->topicNames());
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
                      objects_pub_.getNumSubscribers() > 0 || markers_pub_.getNumSubscribers() > 0 ||
                      map_objects_pub_.getNumSubscribers() > 0 || map_markers_pub_.getNumSubscribers() > 0 ||
                      map_evidence_pub_.getNumSubscribers() > 0 || legacy_.anySubscribed();
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
  publisher_check_timer_ = pnh.createWallTimer(ros::WallDuration(kPublisherCheckSeconds),
                                               [this](const ros::WallTimerEvent&) { checkInputPublishers(); });
  subscribed_ = true;
  NODELET_DEBUG("an output has subscribers: subscribed to the input");
}

void PreFilterNodelet::unsubscribe()
{
  for (ros::Subscriber& subscriber : input_subscribers_)
    subscriber.shutdown();
  input_subscribers_.clear();
  poll_timer_.stop();
  publisher_check_timer_.stop();
  subscribed_ = false;
  NODELET_DEBUG("no output has subscribers: unsubscribed from the input");
}

void PreFilterNodelet::checkInputPublishers()
{
  ros::master::V_TopicInfo published;
  if (!ros::master::getTopics(published))
    return;  // the master is away: roscpp says so itself
  std::string found;
  for (const std::unique_ptr<ros_io::InputTopic>& topic : input_->topics())
  {
    if (topic->md5sum == "*")
      continue;  // it takes any type and names what it cannot read
    for (const ros::master::TopicInfo& info : published)
      if (info.name == topic->name && info.datatype != topic->datatype && info.datatype != "*")
      {
        const std::string problem = "its publisher sends " + info.datatype + ", but " + topic->datatype +
                                    " is read here, so roscpp refuses the connection; " +
                                    ros_io::modeThatReads(info.datatype);
        reportInputProblem(ros_io::InputProblem{ true, "messages", topic->name, problem });
        found = topic->name + ": " + problem;
      }
  }
  stats_.recordPublisherProblem(found);
}

void PreFilterNodelet::onReconfigure(PreFilterConfig& config, std::uint32_t /*level*/)
{
  const core::Params params = ros_io::fromConfig(config);
  const std::vector<std::string> errors = params.validate();
  if (!errors.empty())
  {
    // The caller gets the kept values back in the reconfigure response (dynparam get, rqt_reconfigure).
    NODELET_ERROR_STREAM("dynamic_reconfigure refused, the previous configuration stays in force:"
                         << joinLines(errors) << "\n  kept: " << joinWords(ros_io::keptValues(active_config_, config)));
    // dynamic_reconfigure publishes whatever the callback leaves in `config`.
    config = active_config_;
    return;
  }
  std::lock_guard<std::mutex> lock(pipeline_mutex_);
  pipeline_.setParams(params);
  active_config_ = config;
}

bool PreFilterNodelet::onSaveMap(MapFile::Request& request, MapFile::Response& response)
{
  const std::string path = request.path.empty() ? map_file_ : request.path;
  std::lock_guard<std::mutex> lock(pipeline_mutex_);
  response.message = path.empty() ? "no path given and no map_file set" :
                                    core::saveObjectMap(path, fixed_frame_, pipeline_.objectMap());
  response.success = response.message.empty();
  if (response.success)
    response.message = std::to_string(pipeline_.objectMap().objects().size()) + " objects saved to " + path;
  else
    NODELET_ERROR_STREAM(getName() << ": ~save_map: " << response.message);
  return true;
}

bool PreFilterNodelet::onLoadMap(MapFile::Request& request, MapFile::Response& response)
{
  const std::string path = request.path.empty() ? map_file_ : request.path;
  std::lock_guard<std::mutex> lock(pipeline_mutex_);
  if (path.empty())
  {
    response.success = false;
    response.message = "no path given and no map_file set: the map is kept";
    return true;
  }
  response.message = core::loadObjectMap(path, fixed_frame_, pipeline_.objectMap());
  response.success = response.message.empty();
  if (response.success)
    response.message = std::to_string(pipeline_.objectMap().objects().size()) + " objects loaded from " + path;
  else
    NODELET_ERROR_STREAM(getName() << ": ~load_map: the object map is empty now: " << response.message);
  return true;
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

void PreFilterNodelet::inputTypeFound(const ros_io::FoundInputType& type)
{
  {
    std::lock_guard<std::mutex> lock(problem_mutex_);
    if (type.topic == found_type_.topic && type.mode == found_type_.mode && type.md5sum == found_type_.md5sum &&
        type.definition == found_type_.definition)
      return;
    found_type_ = type;
  }
  NODELET_INFO_STREAM("input " << type.topic << ": " << type.datatype << " (md5sum " << type.md5sum
                               << "), read as input_mode " << type.mode);
  if (type.mode != "hokuyo3d_legacy")
    return;
  std::lock_guard<std::mutex> lock(pipeline_mutex_);
  const std::string problem = legacy_.useDefinition(type.datatype, type.definition);
  if (!problem.empty())
    NODELET_ERROR_STREAM("the outputs in the original's types keep their previous definition, the driver's on "
                         << type.topic << " does not fit them: " << problem);
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
    NODELET_ERROR_STREAM("dropping " << problem.describeInFull() << repeats);
  else if (problem.error)
    NODELET_ERROR_STREAM(problem.describeInFull() << repeats);
  else
    NODELET_WARN_STREAM(problem.describeInFull() << repeats);
}

void PreFilterNodelet::processAndPublish(const core::SweepContext& context)
{
  ros_io::OutputRequest request;
  request.labelled = labelled_pub_.getNumSubscribers() > 0;
  request.cleaned = cleaned_pub_.getNumSubscribers() > 0;
  request.objects = objects_pub_.getNumSubscribers() > 0;
  request.markers = markers_pub_.getNumSubscribers() > 0;
  request.map_objects = map_objects_pub_.getNumSubscribers() > 0;
  request.map_markers = map_markers_pub_.getNumSubscribers() > 0;
  request.map_evidence = map_evidence_pub_.getNumSubscribers() > 0;
  if (pipeline_.params().post_filter != 0 && fixed_frame_.empty())
    NODELET_ERROR_STREAM_THROTTLE(kNoFixedFrameSeconds, getName() << ": post_filter is 1 but fixed_frame is not set "
                                                                  "(a start-up parameter): every sweep is processed "
                                                                  "single-sweep");
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
  if (outputs.map_objects)
    map_objects_pub_.publish(outputs.map_objects);
  if (outputs.map_markers)
    map_markers_pub_.publish(outputs.map_markers);
  if (outputs.map_evidence)
    map_evidence_pub_.publish(outputs.map_evidence);
  legacy_.publish(ros_io::toHeader(context), pipeline_.sweep(), result, context.sensorOrigin());
}

}  // namespace ohm_mirror_detector3d

PLUGINLIB_EXPORT_CLASS(ohm_mirror_detector3d::PreFilterNodelet, nodelet::Nodelet)
