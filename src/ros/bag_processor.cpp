#include "ohm_mirror_detector3d/ros/bag_processor.h"

#include <ros/serialization.h>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>
#include <tf2/buffer_core.h>
#include <tf2_msgs/TFMessage.h>
#include <topic_tools/shape_shifter.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <memory>
#include <set>
#include <sstream>

#include "ohm_mirror_detector3d/core/removal_report.h"
#include "ohm_mirror_detector3d/ros/conversions.h"
#include "ohm_mirror_detector3d/ros/message_pipeline.h"
#include "ohm_mirror_detector3d/ros/sweep_input.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
namespace
{
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// How often a dropped sweep is reported per reason before it is only counted.
constexpr std::size_t kReportedDropsPerReason = 3;

double secondsSince(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// "  /topic  type  (N messages)" for every topic of the bag.
std::string describeTopics(rosbag::Bag& bag)
{
  std::map<std::string, std::set<std::string>> types;
  rosbag::View all(bag);
  for (const rosbag::ConnectionInfo* connection : all.getConnections())
    types[connection->topic].insert(connection->datatype);
  if (types.empty())
    return "\n  (none: the bag is empty)";
  std::ostringstream out;
  for (const auto& entry : types)
  {
    std::string joined;
    for (const std::string& type : entry.second)
      joined += (joined.empty() ? "" : ", ") + type;
    out << "\n  " << entry.first << "  " << joined << "  ("
        << rosbag::View(bag, rosbag::TopicQuery(entry.first)).size() << " messages)";
  }
  return out.str();
}

const char* const kTfTopic = "/tf";
const char* const kTfStaticTopic = "/tf_static";

// A topic the bag must (or may) have, with the type it must have there.
struct WantedTopic
{
  std::string name;
  std::string datatype;
  std::string md5sum;    // "*": any type
  std::string option;    // the command-line option that names it; empty for /tf, /tf_static
  bool required = true;  // false: the bag may lack it
};

// The mode's topics and, when transforms are looked up, /tf and /tf_static (each optional here;
// checkTopics wants at least one).
std::vector<WantedTopic> wantedTopics(const SweepInput& input)
{
  std::vector<WantedTopic> wanted;
  for (const std::unique_ptr<InputTopic>& topic : input.topics())
    wanted.push_back({ topic->name, topic->datatype, topic->md5sum, topic->option, true });
  if (input.readsTf())
    for (const char* tf_topic : { kTfTopic, kTfStaticTopic })
      wanted.push_back({ tf_topic, ros::message_traits::DataType<tf2_msgs::TFMessage>::value(),
                         ros::message_traits::MD5Sum<tf2_msgs::TFMessage>::value(), "", false });
  return wanted;
}

// Refuses a bag that lacks one of the mode's topics (or both tf topics when transforms are
// looked up: `tf_user` says who needs them) or has one with another type.
void checkTopics(rosbag::Bag& bag, const std::string& path, const std::string& mode,
                 const std::vector<WantedTopic>& topics, const std::string& tf_user)
{
  rosbag::View all(bag);
  std::map<std::string, std::vector<const rosbag::ConnectionInfo*>> connections;
  for (const rosbag::ConnectionInfo* connection : all.getConnections())
    connections[connection->topic].push_back(connection);
  for (const WantedTopic& wanted : topics)
  {
    const auto found = connections.find(wanted.name);
    if (found == connections.end())
    {
      if (!wanted.required)
        continue;
      throw BagToolError(path + " has no topic " + wanted.name + " (input mode " + mode + "; " +
                         (wanted.option.empty() ? "" : "name another with " + wanted.option + " or ") +
                         "choose another --input-mode). Its topics are:" + describeTopics(bag));
    }
    for (const rosbag::ConnectionInfo* connection : found->second)
    {
      if (wanted.md5sum == "*")
        continue;  // any type: the mode's decoder names what a message lacks
      if (connection->datatype != wanted.datatype)
        throw BagToolError("topic " + wanted.name + " in " + path + " has type " + connection->datatype +
                           ", but input mode " + mode + " needs " + wanted.datatype + ". The bag's topics are:" +
                           describeTopics(bag));
      if (connection->md5sum != wanted.md5sum)
        throw BagToolError("topic " + wanted.name + " in " + path + " has " + wanted.datatype + " with MD5 " +
                           connection->md5sum + ", but this build's " + wanted.datatype + " has MD5 " +
                           wanted.md5sum + " (a different message definition)");
    }
  }
  if (!tf_user.empty() && connections.count(kTfTopic) == 0 && connections.count(kTfStaticTopic) == 0)
    throw BagToolError(path + " has neither " + kTfTopic + " nor " + kTfStaticTopic + ", which " + tf_user +
                       " needs (the transforms are taken from the bag). Its topics are:" + describeTopics(bag));
}

// No input mode given: the mode that reads the type of the input topic in the bag, as the
// nodelet's default mode chooses it (matchInputType), with the topic set in `input` when it was
// not given (the first of the chosen modes' default topics the bag has).
const InputMode& modeFromBag(rosbag::Bag& bag, const std::string& path, InputOptions& input, std::ostream& log)
{
  rosbag::View all(bag);
  std::map<std::string, const rosbag::ConnectionInfo*> first_connection;
  for (const rosbag::ConnectionInfo* connection : all.getConnections())
    first_connection.emplace(connection->topic, connection);
  std::string topic = input.input_topic;
  std::string candidates;
  for (const InputMode* mode : runTimeChoices())
  {
    candidates += std::string(candidates.empty() ? "" : ", ") + mode->default_topic;
    if (topic.empty() && first_connection.count(mode->default_topic) > 0)
      topic = mode->default_topic;
  }
  if (topic.empty())
    throw BagToolError("no --input-mode given and " + path + " has none of " + candidates +
                       " (give --input-mode and --input-topic). Its topics are:" + describeTopics(bag));
  const auto found = first_connection.find(topic);
  if (found == first_connection.end())
    throw BagToolError(path + " has no topic " + topic + " (name another with --input-topic). Its topics are:" +
                       describeTopics(bag));
  const rosbag::ConnectionInfo& connection = *found->second;
  topic_tools::ShapeShifter::ConstPtr message;
  for (const rosbag::MessageInstance& instance : rosbag::View(bag, rosbag::TopicQuery(topic)))
  {
    message = instance.instantiate<topic_tools::ShapeShifter>();
    break;
  }
  const InputTypeMatch match =
      matchInputType(connection.datatype, connection.md5sum, connection.msg_def, message.get());
  if (match.mode == nullptr)
    throw BagToolError("no --input-mode given, and the messages on " + topic + " in " + path + " choose none: " +
                       match.problem + " (--input-mode MODE, with its parameters in --params)");
  log << "prefilter_bag: no --input-mode given: " << topic << " holds " << connection.datatype
      << ", read as input mode " << match.mode->name << "\n";
  input.input_topic = topic;
  return *match.mode;
}

// The output file under its partial name until commit(); removed if never committed.
class PartialOutput
{
public:
  PartialOutput(const std::string& final_path, std::ostream& log)
    : final_path_(final_path), partial_path_(partialOutputPath(final_path)), log_(log)
  {
  }
  ~PartialOutput()
  {
    if (committed_ || !opened_)
      return;
    bag_.close();
    std::error_code error;
    if (fs::remove(partial_path_, error))
      log_ << "prefilter_bag: removed the incomplete output " << partial_path_ << "; " << final_path_
           << " was not written\n";
    else if (fs::exists(partial_path_, error))
      log_ << "prefilter_bag: could not remove the incomplete output " << partial_path_ << "\n";
  }

  // The bag the output goes to; written to only after open().
  rosbag::Bag& bag() { return bag_; }

  void open()
  {
    try
    {
      opened_ = true;
      bag_.open(partial_path_, rosbag::bagmode::Write);
    }
    catch (const rosbag::BagException& e)
    {
      throw BagToolError("cannot write " + partial_path_ + ": " + e.what());
    }
  }

  void commit()
  {
    bag_.close();
    std::error_code error;
    fs::rename(partial_path_, final_path_, error);
    if (error)
      throw BagToolError("cannot rename " + partial_path_ + " to " + final_path_ + ": " + error.message());
    committed_ = true;
  }

private:
  std::string final_path_;
  std::string partial_path_;
  std::ostream& log_;
  rosbag::Bag bag_;
  bool opened_ = false;
  bool committed_ = false;
};

std::string formatMs(double seconds)
{
  std::ostringstream out;
  out << std::fixed << std::setprecision(1) << seconds * 1e3 << " ms";
  return out.str();
}

// Runs the pipeline on each sweep the input completes and writes its outputs at the bag time of
// the message being read.
class Processor : public SweepReceiver
{
public:
  Processor(const BagToolOptions& options, rosbag::Bag& out, BagToolSummary& summary, std::ostream& log)
    : options_(options), pipeline_(options.params), out_(out), summary_(summary), log_(log)
  {
    const std::string prefix = options.prefix == "/" ? "" : options.prefix;
    labelled_topic_ = prefix + "/labelled";
    cleaned_topic_ = prefix + "/cleaned";
    objects_topic_ = prefix + "/objects";
    markers_topic_ = prefix + "/markers";
    if (options.params.post_filter != 0)
    {
      map_objects_topic_ = prefix + "/map_objects";
      map_markers_topic_ = prefix + "/map_markers";
      map_evidence_topic_ = prefix + "/map_evidence";
    }
  }

  // With post_filter the map's topics too (written for every sweep with a fixed pose).
  std::vector<std::string> outputTopics() const
  {
    std::vector<std::string> topics = { labelled_topic_, cleaned_topic_, objects_topic_, markers_topic_ };
    if (!map_objects_topic_.empty())
      topics.insert(topics.end(), { map_objects_topic_, map_markers_topic_, map_evidence_topic_ });
    return topics;
  }

  // Called before each message the input reads, so that a sweep's time includes its conversion.
  void startMessage(const ros::Time& bag_time)
  {
    message_start_ = Clock::now();
    bag_time_ = bag_time;
  }
  // The bag time of the message being read: the clock of the wait for sensor_frame's transform.
  const ros::Time& bagTime() const { return bag_time_; }

  void sweepReady(core::Sweep& sweep, const core::SweepContext& context) override
  {
    std::swap(pipeline_.sweep(), sweep);
    OutputMessages outputs;
    OutputRequest request;
    request.map_objects = request.map_markers = request.map_evidence = !map_objects_topic_.empty();
    const core::PipelineResult& result = pipeline_.process(context, request, outputs);
    const double seconds = secondsSince(message_start_);
    summary_.sweep_seconds.push_back(seconds);
    ++summary_.sweeps_processed;
    for (const core::ReflectiveObject& object : result.objects)
      ++summary_.objects_by_type[core::objectTypeName(object.type)];
    warnImplausibleRemovals(result);
    out_.write(labelled_topic_, bag_time_, *outputs.labelled);
    out_.write(cleaned_topic_, bag_time_, *outputs.cleaned);
    out_.write(objects_topic_, bag_time_, *outputs.objects);
    out_.write(markers_topic_, bag_time_, *outputs.markers);
    if (outputs.map_objects)
    {
      out_.write(map_objects_topic_, bag_time_, *outputs.map_objects);
      out_.write(map_markers_topic_, bag_time_, *outputs.map_markers);
      out_.write(map_evidence_topic_, bag_time_, *outputs.map_evidence);
    }
    if (options_.verbose)
    {
      log_ << "sweep " << summary_.sweeps_processed << " (stamp " << toHeader(context).stamp << ", bag time "
           << bag_time_ << "): " << formatMs(seconds) << ", " << result.objects.size() << " object(s)";
      for (const core::ReflectiveObject& object : result.objects)
        log_ << std::fixed << std::setprecision(1) << "; " << core::objectTypeName(object.type) << " "
             << object.width * 100.0f << " x " << object.height * 100.0f << " cm";
      log_ << std::defaultfloat << "\n";
    }
    message_start_ = Clock::now();
  }

  void inputProblem(const InputProblem& problem) override
  {
    const std::string reason = problem.describe();
    if (problem.dropped)
    {
      ++summary_.sweeps_dropped;
      const std::size_t seen = ++summary_.drop_reasons[reason];
      if (seen <= kReportedDropsPerReason || options_.verbose)
        log_ << "prefilter_bag: dropping input at bag time " << bag_time_ << ": " << problem.describeInFull()
             << (seen == kReportedDropsPerReason && !options_.verbose ? " (more of these are only counted)" : "")
             << "\n";
      return;
    }
    const std::size_t seen = ++warnings_[reason];
    if (seen <= kReportedDropsPerReason || options_.verbose)
      log_ << "prefilter_bag: " << (problem.error ? "error" : "warning") << " at bag time " << bag_time_ << ": " << problem.describeInFull()
           << (seen == kReportedDropsPerReason && !options_.verbose ? " (more of these are not shown)" : "") << "\n";
  }

private:
  // Like the nodelet's throttled warning: the first few sweeps in full, then only a count at the end.
  void warnImplausibleRemovals(const core::PipelineResult& result)
  {
    const std::vector<std::string> warnings = core::removalWarnings(result.removals, pipeline_.params());
    if (warnings.empty())
      return;
    const std::size_t seen = ++implausible_sweeps_;
    if (seen > kReportedDropsPerReason && !options_.verbose)
      return;
    for (const std::string& warning : warnings)
      log_ << "prefilter_bag: warning at bag time " << bag_time_ << ": " << warning << "\n";
    if (seen == kReportedDropsPerReason && !options_.verbose)
      log_ << "prefilter_bag: (further sweeps with an implausible removal are not shown)\n";
  }

  const BagToolOptions& options_;
  MessagePipeline pipeline_;
  rosbag::Bag& out_;
  BagToolSummary& summary_;
  std::ostream& log_;
  std::string labelled_topic_, cleaned_topic_, objects_topic_, markers_topic_;
  std::string map_objects_topic_, map_markers_topic_, map_evidence_topic_;  // empty without post_filter
  Clock::time_point message_start_ = Clock::now();
  ros::Time bag_time_;
  std::map<std::string, std::size_t> warnings_;  // text -> count, to limit the lines
  std::size_t implausible_sweeps_ = 0;
};

// Fills `tf` from a /tf or /tf_static message, as a tf listener does; a message or transform
// tf refuses is reported as dropped.
void addTransforms(const rosbag::MessageInstance& message, tf2::BufferCore& tf, SweepReceiver& receiver)
{
  tf2_msgs::TFMessage::ConstPtr transforms;
  try
  {
    transforms = message.instantiate<tf2_msgs::TFMessage>();
  }
  catch (const std::exception& e)
  {
    receiver.inputProblem(
        InputProblem{ true, "message", message.getTopic(), std::string("cannot be read: ") + e.what() });
    return;
  }
  const bool is_static = message.getTopic() == kTfStaticTopic;
  for (const geometry_msgs::TransformStamped& transform : transforms->transforms)
  {
    try
    {
      tf.setTransform(transform, "bag", is_static);  // logs and ignores a bad transform
    }
    catch (const std::exception& e)
    {
      receiver.inputProblem(InputProblem{ true, "transform", message.getTopic(), e.what() });
    }
  }
}

// "12/200 input messages, 6 sweeps, 2.9 sweeps/s": rewritten in place on a terminal, a
// line every few seconds otherwise (a log file).
class Progress
{
public:
  Progress(std::ostream& log, std::size_t total) : log_(log), total_(total), tty_(isatty(STDERR_FILENO) == 1) {}

  void update(const BagToolSummary& summary, bool last = false)
  {
    const double elapsed = secondsSince(start_);
    if (!last && elapsed - printed_at_ < (tty_ ? 0.5 : 5.0))
      return;
    printed_at_ = elapsed;
    std::ostringstream line;
    line << "prefilter_bag: " << summary.input_messages << "/" << total_ << " input messages, "
         << summary.sweeps_processed << " sweeps, " << std::fixed << std::setprecision(1)
         << (elapsed > 0.0 ? summary.sweeps_processed / elapsed : 0.0) << " sweeps/s";
    if (tty_)
      log_ << "\r" << line.str() << "\033[K" << (last ? "\n" : "") << std::flush;
    else
      log_ << line.str() << "\n";
  }

private:
  std::ostream& log_;
  std::size_t total_;
  bool tty_;
  Clock::time_point start_ = Clock::now();
  double printed_at_ = 0.0;
};
}  // namespace

std::string partialOutputPath(const std::string& output_path)
{
  return output_path + ".partial";
}

double quantile(std::vector<double> values, double q)
{
  if (values.empty())
    return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const std::size_t rank = static_cast<std::size_t>(std::ceil(q * values.size()));
  return values[std::min(values.size() - 1, rank == 0 ? 0 : rank - 1)];
}

BagToolSummary runPrefilterBag(const BagToolOptions& options, std::ostream& log)
{
  const Clock::time_point start = Clock::now();
  BagToolSummary summary;

  const InputMode* mode = options.input_mode.empty() ? nullptr : findInputMode(options.input_mode);
  if (mode == nullptr && !options.input_mode.empty())
    throw BagToolError(unknownInputModeMessage(options.input_mode));
  std::error_code error;
  if (!fs::exists(options.input_path, error))
    throw BagToolError("input bag " + options.input_path + " does not exist");
  if (fs::exists(options.output_path, error) && fs::equivalent(options.input_path, options.output_path, error))
    throw BagToolError("the output bag must not be the input bag (" + options.input_path + ")");

  rosbag::Bag in;
  try
  {
    in.open(options.input_path, rosbag::bagmode::Read);
  }
  catch (const rosbag::BagException& e)
  {
    throw BagToolError("cannot read " + options.input_path + " as a ROS bag: " + e.what());
  }
  InputOptions input_options = options.input;
  if (options.params.post_filter != 0 && input_options.fixed_frame.empty())
    throw BagToolError("post_filter = 1 needs fixed_frame (the frame the object map is kept in; tf from the bag's "
                       "/tf and /tf_static places every sweep in it)");
  if (mode == nullptr)
    mode = &modeFromBag(in, options.input_path, input_options, log);
  const std::string mode_name = mode->name;
  // Opened once the bag's topics are checked.
  PartialOutput output(options.output_path, log);
  rosbag::Bag& out = output.bag();
  std::unique_ptr<Processor> processor;
  try
  {
    processor.reset(new Processor(options, out, summary, log));
  }
  catch (const std::invalid_argument& e)
  {
    throw BagToolError(std::string("bad parameters: ") + e.what());
  }
  // The transforms of the bag, in bag order: the nodelet's tf listener, without a master.
  tf2::BufferCore tf;  // default cache time, as the nodelet's tf2_ros::Buffer
  const Processor& clock = *processor;
  SweepInput input(*mode, input_options, tf, *processor, [&clock]() { return clock.bagTime().toSec(); });
  const std::vector<WantedTopic> wanted = wantedTopics(input);
  std::set<std::string> read_topics;
  for (const WantedTopic& topic : wanted)
    if (!read_topics.insert(topic.name).second)
      throw BagToolError("input mode " + mode_name + " reads " + topic.name + " twice; its topics must differ");
  std::string tf_user;
  if (input.readsTf())
    tf_user = !input_options.sensor_frame.empty() ? "sensor_frame '" + input_options.sensor_frame + "'" :
              !input_options.fixed_frame.empty()  ? "fixed_frame '" + input_options.fixed_frame + "'" :
                                                    "input mode " + mode_name;
  checkTopics(in, options.input_path, mode_name, wanted, tf_user);
  output.open();
  std::map<std::string, const InputTopic*> input_topics;
  for (const std::unique_ptr<InputTopic>& topic : input.topics())
    input_topics[topic->name] = topic.get();

  std::vector<std::string> topic_list(read_topics.begin(), read_topics.end());
  const std::size_t total_inputs = rosbag::View(in, rosbag::TopicQuery(topic_list)).size();

  const std::vector<std::string> output_topics = processor->outputTopics();
  const std::set<std::string> output_topic_names(output_topics.begin(), output_topics.end());
  // A bag that already holds outputs (a processed bag processed again): the new ones replace them.
  if (!options.only_outputs)
  {
    rosbag::View all(in);
    std::set<std::string> replaced;
    for (const rosbag::ConnectionInfo* connection : all.getConnections())
      if (output_topic_names.count(connection->topic) > 0 && replaced.insert(connection->topic).second)
        log << "prefilter_bag: " << options.input_path << " already has " << connection->topic
            << "; its messages are not copied, the new outputs replace them\n";
  }

  std::unique_ptr<rosbag::View> view(options.only_outputs ? new rosbag::View(in, rosbag::TopicQuery(topic_list)) :
                                                            new rosbag::View(in));
  Progress progress(log, total_inputs);
  std::vector<std::uint8_t> bytes;
  try
  {
    for (const rosbag::MessageInstance& message : *view)
    {
      if (options.stop != nullptr && *options.stop)
      {
        summary.interrupted = true;
        break;
      }
      const std::string& topic = message.getTopic();
      if (!options.only_outputs && output_topic_names.count(topic) == 0)
      {
        out.write(topic, message.getTime(), message, message.getConnectionHeader());
        ++summary.copied_messages;
      }
      if (read_topics.count(topic) == 0)
        continue;
      ++summary.input_messages;
      processor->startMessage(message.getTime());
      const auto input_topic = input_topics.find(topic);
      if (input_topic == input_topics.end())
        addTransforms(message, tf, *processor);
      else
      {
        std::string problem;
        try
        {
          bytes.resize(message.size());
          ros::serialization::OStream stream(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
          message.write(stream);
        }
        catch (const std::exception& e)
        {
          problem = std::string("cannot be read: ") + e.what();
        }
        if (problem.empty())
          input.addSerialized(*input_topic->second, bytes, message.getConnectionHeader());
        else
          processor->inputProblem(InputProblem{ true, "message", topic, problem });
      }
      // What waited for transforms may go on now (the nodelet's timer does this).
      input.poll();
      progress.update(summary);
    }
    if (!summary.interrupted)
      input.finish();
  }
  catch (const rosbag::BagException& e)
  {
    throw BagToolError("error while reading " + options.input_path + " or writing " +
                       partialOutputPath(options.output_path) + ": " + e.what());
  }
  progress.update(summary, true);
  summary.wall_seconds = secondsSince(start);
  if (summary.interrupted)
  {
    log << "prefilter_bag: interrupted after " << summary.sweeps_processed << " sweeps\n";
    return summary;  // ~PartialOutput removes the file
  }
  output.commit();
  summary.wall_seconds = secondsSince(start);
  return summary;
}

void printSummary(const BagToolSummary& summary, std::ostream& out)
{
  std::ostringstream text;
  text << std::fixed << std::setprecision(1);
  text << "sweeps processed: " << summary.sweeps_processed << "\n";
  text << "sweeps dropped:   " << summary.sweeps_dropped << (summary.sweeps_dropped > 0 ? ", because:" : "") << "\n";
  std::vector<std::pair<std::size_t, std::string>> reasons;
  for (const auto& entry : summary.drop_reasons)
    reasons.emplace_back(entry.second, entry.first);
  std::sort(reasons.rbegin(), reasons.rend());
  constexpr std::size_t kShownReasons = 10;
  for (std::size_t i = 0; i < reasons.size() && i < kShownReasons; ++i)
    text << "  " << std::setw(6) << reasons[i].first << " x " << reasons[i].second << "\n";
  if (reasons.size() > kShownReasons)
    text << "  and " << reasons.size() - kShownReasons << " other reasons\n";
  text << "objects found:    ";
  std::size_t objects = 0;
  for (const core::ObjectType type : { core::ObjectType::mirror, core::ObjectType::glass, core::ObjectType::unknown })
  {
    const auto found = summary.objects_by_type.find(core::objectTypeName(type));
    const std::size_t count = found == summary.objects_by_type.end() ? 0 : found->second;
    objects += count;
    text << (type == core::ObjectType::mirror ? "" : ", ") << count << " " << core::objectTypeName(type);
  }
  text << " (" << objects << " over all sweeps)\n";
  if (!summary.sweep_seconds.empty())
    text << "per-sweep time:   median " << formatMs(quantile(summary.sweep_seconds, 0.5)) << ", p95 "
         << formatMs(quantile(summary.sweep_seconds, 0.95)) << " (conversion, pipeline, output messages)\n";
  text << "throughput:       "
       << (summary.wall_seconds > 0.0 ? summary.sweeps_processed / summary.wall_seconds : 0.0) << " sweeps/s\n";
  text << "wall time:        " << std::setprecision(2) << summary.wall_seconds << " s\n";
  out << text.str();
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
