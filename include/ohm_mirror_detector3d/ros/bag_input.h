// prefilter_bag's input modes: which topics of a bag a mode reads and how their messages
// become sweeps, with the nodelet's conversion functions (conversions.h).
//
// Each mode is a BagInput subclass in bag_input.cpp and a row in bagInputModes(), and runs
// the nodelet's conversion for its input (pair, two_topics, dual_return, hokuyo3d_legacy,
// multi_echo_scan).
#pragma once

#include <ros/time.h>
#include <rosbag/message_instance.h>
#include <std_msgs/Header.h>

#include <memory>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/core/dual_return.h"
#include "ohm_mirror_detector3d/core/sweep.h"
#include "ohm_mirror_detector3d/core/sweep_context.h"
#include "ohm_mirror_detector3d/ros/multi_echo_scan.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
// What the modes read: their topics (prefilter_bag's --input-topic, --echo1-topic,
// --echo2-topic) and their start-up parameters (from --params, read as the nodelet reads them).
struct BagInputOptions
{
  std::string input_topic;             // pair, dual_return, hokuyo3d_legacy, multi_echo_scan;
                                       // empty: the mode's default_input_topic
  std::string echo1_topic = "/echo1";  // two_topics
  std::string echo2_topic = "/echo2";
  double azimuth_resolution_deg = core::kDefaultAzimuthResolutionDeg;  // dual_return
  MultiEchoScanOptions scan_options;                                   // multi_echo_scan
};

// A topic a mode reads and the message type it must have there.
struct BagInputTopic
{
  std::string topic;
  std::string datatype;  // e.g. ohm_mirror_detector3d/EchoPair
  std::string md5sum;    // of this build's definition of datatype
  std::string option;    // the command-line option that names the topic, for error messages;
                         // empty for a fixed name (/tf, /tf_static)
  bool required = true;  // false: the bag may lack it (/tf_static)
};

// Receives what a mode makes of the messages.
class SweepSink
{
public:
  virtual ~SweepSink() = default;
  // The sweep passed to BagInput::add holds a complete sweep: process it with `context`, stamp
  // and frame the outputs with `header` and record them at `bag_time`.
  virtual void sweepReady(const std_msgs::Header& header, const core::SweepContext& context,
                          const ros::Time& bag_time) = 0;
  // An input message (or pair of them) that makes no sweep, and why.
  virtual void sweepDropped(const std::string& reason, const ros::Time& bag_time) = 0;
};

class BagInput
{
public:
  virtual ~BagInput() = default;
  virtual std::vector<BagInputTopic> topics() const = 0;
  // Called for every message on topics(), in bag time order. Fills `sweep` and calls
  // sink.sweepReady for each sweep it completes (or sink.sweepDropped). May keep messages
  // until their partners arrive.
  virtual void add(const rosbag::MessageInstance& message, core::Sweep& sweep, SweepSink& sink) = 0;
  // The end of the bag: reports what is still waiting for a partner as dropped.
  virtual void finish(SweepSink& /*sink*/) {}
};

struct BagInputMode
{
  const char* name;
  const char* help;  // one line for --help
  // What scripts/synthesize_sweep --bag writes for this mode; null for two_topics.
  const char* default_input_topic;
  std::unique_ptr<BagInput> (*make)(const BagInputOptions& options);
};

// The modes, the default first. The other modes plug in here.
const std::vector<BagInputMode>& bagInputModes();
// Null when there is no such mode.
const BagInputMode* findBagInputMode(const std::string& name);

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
