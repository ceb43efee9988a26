// The input modes, one table for the nodelet and prefilter_bag: per mode the topics and message
// types it reads and an adapter that turns its messages into a core::Sweep and its
// core::SweepContext. The nodelet subscribes to the topics (InputTopic::subscribe), prefilter_bag
// feeds them the recorded messages (InputTopic::addSerialized); both then get the same sweeps,
// contexts and problems from the same adapter code.
//
// Adding a mode: an InputAdapter subclass in src/ros/input_modes.cpp and a row in inputModes()
// (its name also among the allowed values of the input_mode row of core/parameters.def, which
// test_input_modes compares with this table).
#pragma once

#include <ros/message_traits.h>
#include <ros/node_handle.h>
#include <ros/serialization.h>
#include <ros/subscriber.h>
#include <tf2/buffer_core.h>
#include <topic_tools/shape_shifter.h>

#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "ohm_mirror_detector3d/core/dual_return.h"
#include "ohm_mirror_detector3d/core/sweep.h"
#include "ohm_mirror_detector3d/core/sweep_context.h"
#include "ohm_mirror_detector3d/ros/multi_echo_scan.h"
#include "ohm_mirror_detector3d/ros/parameters.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
// What the modes read besides their messages: their topics (the nodelet: its resolved topic
// names; prefilter_bag: --input-topic, --echo1-topic, --echo2-topic) and their start-up
// parameters (readInputOptions).
struct InputOptions
{
  std::string input_topic;             // every mode but two_topics; empty: the mode's default_topic
  std::string echo1_topic = "/echo1";  // two_topics
  std::string echo2_topic = "/echo2";
  // two_topics: 0 pairs clouds with equal stamps; > 0 those at most this many seconds apart.
  double approximate_sync = 0.0;
  double azimuth_resolution_deg = core::kAzimuthStepFromCloud;  // dual_return
  MultiEchoScanOptions scan_options;                             // multi_echo_scan
  // The scanner's tf frame when the clouds come in another frame; empty: the clouds' own frame.
  std::string sensor_frame;
  // The post-filter's fixed frame: each sweep's pose in it is looked up in tf (fixed_from_sweep of
  // the context); empty: none.
  std::string fixed_frame;
  // Prefixes the log messages the modes write themselves (multi_echo_scan's tf waits).
  std::string log_name;
};

// An input that makes no sweep (dropped), or a usable one with something worth a warning.
struct InputProblem
{
  InputProblem() = default;
  InputProblem(bool dropped_, std::string what_, std::string topic_, std::string text_, std::string detail_ = "")
    : dropped(dropped_), what(std::move(what_)), topic(std::move(topic_)), text(std::move(text_)),
      detail(std::move(detail_))
  {
  }

  bool dropped = true;
  std::string what;   // "sweep", "scan" or "message"
  std::string topic;  // where it came from, e.g. "/prefilter/input" or "/echo1 + /echo2"
  std::string text;   // what is wrong: the kind of problem, by which it is counted and throttled
  std::string detail;  // "" or the particulars of this one (stamps, counts), shown after it
  // Not dropped, but an error all the same (a sweep processed single-sweep for want of its
  // fixed pose): logged as an error, not a warning.
  bool error = false;

  // "WHAT on TOPIC: TEXT"
  std::string describe() const { return what + " on " + topic + ": " + text; }
  // describe() and the detail: "WHAT on TOPIC: TEXT (DETAIL)"
  std::string describeInFull() const { return describe() + (detail.empty() ? "" : " (" + detail + ")"); }
};

// The message type an input reads, as its publisher (or the bag) announced it: told by the
// default mode when it has found which mode reads a topic, and by hokuyo3d_legacy whenever the
// definition it decodes changes (the outputs in the original's types follow it).
struct FoundInputType
{
  std::string topic;
  std::string mode;  // the input mode that reads it
  std::string datatype;
  std::string md5sum;
  std::string definition;  // the full message definition
};

// Where the sweeps of an input mode go: the pipeline (the nodelet, prefilter_bag), or a stage
// on the way (SensorPoseQueue).
class SweepReceiver
{
public:
  virtual ~SweepReceiver() = default;
  // A complete sweep. The receiver may swap the sweep's buffers with its own (std::swap),
  // which saves a copy; the adapter refills whatever it gets back.
  virtual void sweepReady(core::Sweep& sweep, const core::SweepContext& context) = 0;
  virtual void inputProblem(const InputProblem& problem) = 0;
  // Before the sweeps of a newly found type (see FoundInputType).
  virtual void inputTypeFound(const FoundInputType& /*type*/) {}
};

// What an adapter works with while it handles a message: where its results go, and the
// transforms it may look up (multi_echo_scan). The nodelet's tf listener fills `tf`;
// prefilter_bag fills it from the bag's /tf and /tf_static, in bag order.
struct InputSink
{
  SweepReceiver& receiver;
  const tf2::BufferCore& tf;
};

// One topic of a mode: its name, its message type, and the adapter's handler of its messages.
class InputTopic
{
public:
  InputTopic(std::string name, std::string datatype, std::string md5sum, std::string option, std::uint32_t queue_size)
    : name(std::move(name))
    , datatype(std::move(datatype))
    , md5sum(std::move(md5sum))
    , option(std::move(option))
    , queue_size(queue_size)
  {
  }
  virtual ~InputTopic() = default;

  const std::string name;
  const std::string datatype;      // e.g. ohm_mirror_detector3d/EchoPair
  const std::string md5sum;        // of this build's definition; "*": any type (decoded from its definition)
  const std::string option;        // prefilter_bag's option that names the topic
  const std::uint32_t queue_size;  // of the nodelet's subscriber

  // The nodelet: subscribes `nh` to the topic; its messages go to the adapter with `sink`.
  virtual ros::Subscriber subscribe(ros::NodeHandle& nh, const InputSink& sink) const = 0;
  // A message taken as a ShapeShifter (the default mode, which reads any type), of this topic's
  // type: to the adapter as it is (a ShapeShifter topic) or deserialized into the type.
  virtual void addShapeShifter(const topic_tools::ShapeShifter::ConstPtr& message, const InputSink& sink) const = 0;
  // prefilter_bag: one recorded message, its serialized bytes and the connection header it was
  // recorded with (type, md5sum, message_definition). Returns why it cannot be read ("" when
  // it went to the adapter).
  virtual std::string addSerialized(const std::vector<std::uint8_t>& bytes,
                                    const boost::shared_ptr<ros::M_string>& connection_header,
                                    const InputSink& sink) const = 0;
};

// A topic of message type M, whose messages go to `handler`, however they came.
template <typename M>
class TypedInputTopic final : public InputTopic
{
public:
  using Handler = std::function<void(const boost::shared_ptr<const M>& message, const InputSink& sink)>;

  // `datatype`: shown instead of M's own (a ShapeShifter topic names the type it expects).
  TypedInputTopic(const std::string& name, const std::string& option, std::uint32_t queue_size, Handler handler,
                  const std::string& datatype = ros::message_traits::DataType<M>::value())
    : InputTopic(name, datatype, ros::message_traits::MD5Sum<M>::value(), option, queue_size)
    , handler_(std::move(handler))
  {
  }

  ros::Subscriber subscribe(ros::NodeHandle& nh, const InputSink& sink) const override
  {
    return nh.subscribe<M>(name, queue_size,
                           [this, sink](const boost::shared_ptr<const M>& message) { handler_(message, sink); });
  }

  void addShapeShifter(const topic_tools::ShapeShifter::ConstPtr& message, const InputSink& sink) const override
  {
    if constexpr (std::is_same<M, topic_tools::ShapeShifter>::value)
      handler_(message, sink);
    else
      handler_(message->instantiate<M>(), sink);
  }

  std::string addSerialized(const std::vector<std::uint8_t>& bytes,
                            const boost::shared_ptr<ros::M_string>& connection_header,
                            const InputSink& sink) const override
  {
    // As rosbag's MessageInstance::instantiate: the connection header first (a ShapeShifter
    // takes its type and definition from it), then the bytes.
    const boost::shared_ptr<M> message(new M);
    try
    {
      ros::serialization::PreDeserializeParams<M> params;
      params.message = message;
      params.connection_header = connection_header;
      ros::serialization::PreDeserialize<M>::notify(params);
      ros::serialization::IStream stream(const_cast<std::uint8_t*>(bytes.data()),
                                         static_cast<std::uint32_t>(bytes.size()));
      ros::serialization::deserialize(stream, *message);
    }
    catch (const std::exception& e)
    {
      return std::string("cannot be read: ") + e.what();
    }
    handler_(message, sink);
    return "";
  }

private:
  Handler handler_;
};

// Turns the messages of one mode into sweeps. The handlers of its topics convert (into buffers
// the adapter owns and reuses) and hand each complete sweep, or each problem, to the sink.
class InputAdapter
{
public:
  virtual ~InputAdapter() = default;

  // The topics it reads.
  const std::vector<std::unique_ptr<InputTopic>>& topics() const { return topics_; }
  // True when it looks transforms up in InputSink::tf (the front end must then fill it).
  virtual bool readsTf() const { return false; }
  // A line for the log at start-up, "" for none.
  virtual std::string describe() const { return ""; }
  // Hands on what waited for transforms that have come since (multi_echo_scan's scans). The
  // nodelet calls it from a timer, prefilter_bag after every message.
  virtual void poll(const InputSink& /*sink*/) {}
  // Forgets what waits or is half assembled (the nodelet, on subscribing again).
  virtual void reset() {}
  // The end of the bag (prefilter_bag): reports what still waits as dropped.
  virtual void finish(const InputSink& /*sink*/) {}

protected:
  // `datatype`: see TypedInputTopic.
  template <typename M, typename Handler>
  void addTopic(const std::string& name, const std::string& option, std::uint32_t queue_size, Handler handler,
                const std::string& datatype = ros::message_traits::DataType<M>::value())
  {
    topics_.emplace_back(new TypedInputTopic<M>(name, option, queue_size, handler, datatype));
  }

private:
  std::vector<std::unique_ptr<InputTopic>> topics_;
};

struct InputMode
{
  const char* name;
  const char* help;           // one line for prefilter_bag --help
  // prefilter_bag's default --input-topic: what scripts/synthesize_sweep --bag writes for this
  // mode; null for two_topics.
  const char* default_topic;
  // Reads the mode's own start-up parameters into `options` (null: it has none) and appends a
  // message naming the parameter for every bad one.
  void (*read_options)(const ParamSource& source, InputOptions& options, std::vector<std::string>& errors);
  std::unique_ptr<InputAdapter> (*make)(const InputOptions& options);
};

// The modes a user can set (input_mode), pair first.
const std::vector<InputMode>& inputModes();
// Null when there is no such mode.
const InputMode* findInputMode(const std::string& name);
// "input_mode 'NAME' is unknown: allowed values are 'pair', ..."
std::string unknownInputModeMessage(const std::string& name);

// The default, when input_mode is not set: one topic (~input, sub_input_scan) of any type,
// whose messages go to the mode that reads their type without further parameters (pair for
// ohm_mirror_detector3d/EchoPair, hokuyo3d_legacy for ohm_hokuyo3d/CoordDistMulti or any type
// with its layout: matchInputType). Any other type is dropped with an error naming the type and
// the input_mode that reads it. Its name is "" (no value of input_mode).
const InputMode& runTimeInputMode();
// The modes runTimeInputMode() chooses from, in the order they are tried.
const std::vector<const InputMode*>& runTimeChoices();

// Which mode reads messages of a type, as runTimeInputMode() decides it.
struct InputTypeMatch
{
  const InputMode* mode = nullptr;  // one of runTimeChoices(); null: none of them reads it
  std::string problem;              // when null: why not, and the input_mode that would read it
};
// From the type a publisher (or a bag's connection) announces; `message` (may be null) is one
// message of it, from which a PointCloud2's fields tell dual_return from two_topics.
InputTypeMatch matchInputType(const std::string& datatype, const std::string& md5sum, const std::string& definition,
                              const topic_tools::ShapeShifter* message = nullptr);
// For a publisher of `datatype` on a topic that expects another type: which input_mode reads
// it, in words ("input_mode multi_echo_scan reads it (with sweep_frame ...)").
std::string modeThatReads(const std::string& datatype, const std::string& definition = "",
                          const topic_tools::ShapeShifter* message = nullptr);

// Reads the start-up parameters of the input: azimuth_resolution_deg (every mode, as always),
// sensor_frame, and those of `mode`. The nodelet reads them from its private parameters,
// prefilter_bag from --params, with the same names, checks and messages; every bad value
// appends a message to `errors`.
void readInputOptions(const ParamSource& source, const InputMode& mode, InputOptions& options,
                      std::vector<std::string>& errors);

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
