// The input path of the nodelet and of prefilter_bag, the same code for both: the input mode's
// adapter (input_mode.h) and, with sensor_frame or fixed_frame, the wait for the scanner's pose
// and the sweep's pose in the fixed frame (SensorPoseQueue), up to a receiver that runs the pipeline. The front ends only deliver the
// messages (subscribe(), or addSerialized() per recorded message), fill the tf buffer when
// readsTf(), and call poll().
#pragma once

#include <ros/node_handle.h>
#include <ros/subscriber.h>
#include <tf2/buffer_core.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/ros/input_mode.h"
#include "ohm_mirror_detector3d/ros/sensor_pose_queue.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
class SweepInput
{
public:
  // `tf`: the front end's transforms (it fills them when readsTf()); `clock`: seconds now, for
  // how long a sweep may wait for tf (the nodelet: wall time; prefilter_bag: bag time).
  SweepInput(const InputMode& mode, const InputOptions& options, const tf2::BufferCore& tf, SweepReceiver& receiver,
             std::function<double()> clock);

  const std::vector<std::unique_ptr<InputTopic>>& topics() const { return adapter_->topics(); }
  // The topics' names joined by " + ", for messages.
  std::string topicNames() const;
  // Whether transforms are looked up (multi_echo_scan, or sensor_frame or fixed_frame set).
  bool readsTf() const { return adapter_->readsTf() || pose_queue_ != nullptr; }
  // The adapter's line for the log at start-up ("" for none).
  std::string describe() const { return adapter_->describe(); }

  // The nodelet: a subscriber per topic.
  std::vector<ros::Subscriber> subscribe(ros::NodeHandle& nh) const;
  // prefilter_bag: one recorded message on `topic` (one of topics()); one that cannot be read
  // is reported to the receiver as dropped.
  void addSerialized(const InputTopic& topic, const std::vector<std::uint8_t>& bytes,
                     const boost::shared_ptr<ros::M_string>& connection_header) const;

  // Hands on what waited for transforms that have come since.
  void poll();
  // Forgets what waits or is half assembled (the nodelet, on subscribing again).
  void reset();
  // The end of the bag (prefilter_bag): reports what still waits as dropped.
  void finish();

private:
  std::unique_ptr<InputAdapter> adapter_;
  SweepReceiver& receiver_;
  std::unique_ptr<SensorPoseQueue> pose_queue_;  // null without sensor_frame and fixed_frame
  InputSink sink_;                               // to pose_queue_, or straight to receiver_
};

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
