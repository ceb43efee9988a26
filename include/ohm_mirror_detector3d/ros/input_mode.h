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

#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <string>
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
  double azimuth_resolution_deg = core::kAzimuthStepFromCloud;  // dual_return
  MultiEchoScanOptions scan_options;                             // multi_echo_scan
  // The scanner's tf frame when the clouds come in another frame; empty: the clouds' own frame.
  std::string sensor_frame;
  // Prefixes the log messages the modes write themselves (multi_echo_scan's tf waits).
  std::string log_name;
};

// An input that makes no sweep (dropped), or a usable one with something worth a warning.
struct InputProblem
{
  bool dropped = true;
  std::string what;   // "sweep", "scan" or "message"
  std::string topic;  // where it came from, e.g. "/prefilter/input" or "/echo1 + /echo2"
  std::string text;   // what is wrong

  // "WHAT on TOPIC: TEXT"
  std::string describe() const { return what + " on " + topic + ": " + text; }
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

// The modes, the default (pair) first.
const std::vector<InputMode>& inputModes();
// Null when there is no such mode.
const InputMode* findInputMode(const std::string& name);
// "input_mode 'NAME' is unknown: allowed values are 'pair', ..."
std::string unknownInputModeMessage(const std::string& name);

// Reads the start-up parameters of the input: azimuth_resolution_deg (every mode, as always),
// sensor_frame, and those of `mode`. The nodelet reads them from its private parameters,
// prefilter_bag from --params, with the same names, checks and messages; every bad value
// appends a message to `errors`.
void readInputOptions(const ParamSource& source, const InputMode& mode, InputOptions& options,
                      std::vector<std::string>& errors);

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
