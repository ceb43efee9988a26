#include "ohm_mirror_detector3d/ros/sweep_input.h"

#include <utility>

namespace ohm_mirror_detector3d
{
namespace ros_io
{
namespace
{
std::unique_ptr<SensorPoseQueue> makePoseQueue(const InputOptions& options, const std::string& topics,
                                               const tf2::BufferCore& tf, SweepReceiver& receiver,
                                               std::function<double()> clock)
{
  if (options.sensor_frame.empty() && options.fixed_frame.empty())
    return nullptr;
  return std::unique_ptr<SensorPoseQueue>(
      new SensorPoseQueue(options.sensor_frame, options.fixed_frame, topics, tf, receiver, std::move(clock)));
}
}  // namespace

SweepInput::SweepInput(const InputMode& mode, const InputOptions& options, const tf2::BufferCore& tf,
                       SweepReceiver& receiver, std::function<double()> clock)
  : adapter_(mode.make(options))
  , receiver_(receiver)
  , pose_queue_(makePoseQueue(options, topicNames(), tf, receiver, std::move(clock)))
  , sink_{ pose_queue_ ? static_cast<SweepReceiver&>(*pose_queue_) : receiver, tf }
{
}

std::string SweepInput::topicNames() const
{
  std::string names;
  for (const std::unique_ptr<InputTopic>& topic : adapter_->topics())
    names += (names.empty() ? "" : " + ") + topic->name;
  return names;
}

std::vector<ros::Subscriber> SweepInput::subscribe(ros::NodeHandle& nh) const
{
  std::vector<ros::Subscriber> subscribers;
  for (const std::unique_ptr<InputTopic>& topic : adapter_->topics())
    subscribers.push_back(topic->subscribe(nh, sink_));
  return subscribers;
}

void SweepInput::addSerialized(const InputTopic& topic, const std::vector<std::uint8_t>& bytes,
                               const boost::shared_ptr<ros::M_string>& connection_header) const
{
  const std::string problem = topic.addSerialized(bytes, connection_header, sink_);
  if (!problem.empty())
    receiver_.inputProblem(InputProblem{ true, "message", topic.name, problem });
}

void SweepInput::poll()
{
  adapter_->poll(sink_);
  if (pose_queue_)
    pose_queue_->poll();
}

void SweepInput::reset()
{
  adapter_->reset();
  if (pose_queue_)
    pose_queue_->reset();
}

void SweepInput::finish()
{
  adapter_->finish(sink_);
  if (pose_queue_)
    pose_queue_->finish();
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
