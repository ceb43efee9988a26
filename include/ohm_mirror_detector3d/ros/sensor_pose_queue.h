// sensor_frame: the scanner's pose for sweeps whose clouds come in another frame than the
// scanner's (a driver that publishes in base_link). A sweep waits here until tf has the
// transform sweep frame <- sensor_frame at its stamp, as tf2_ros::MessageFilter makes a message
// wait: outside the pipeline and its lock, so reconfigure and the other callbacks go on while
// it waits. The whole transform (rotation and translation) becomes the context's sensor pose.
// fixed_frame (the post-filter): the sweep also waits for fixed_frame <- sweep frame, which becomes
// the context's fixed_from_sweep. A sweep whose fixed pose will not come (or not in time) is not
// dropped: it goes on without one (processed single-sweep), with a problem reported (not dropped)
// that says so.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <string>

#include <Eigen/Geometry>
#include <tf2/buffer_core.h>

#include "ohm_mirror_detector3d/ros/input_mode.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
class SensorPoseQueue : public SweepReceiver
{
public:
  // At most this many sweeps wait; one more drops the oldest (sweeps are large, and a late one
  // is worth less than the next).
  static constexpr std::size_t kMaxWaitingSweeps = 2;
  // A sweep waits at most this long for its transform.
  static constexpr double kMaxWaitSeconds = 5.0;

  // Hands the sweeps, with their sensor pose, and every problem on to `next`. `topic` names the
  // input in the messages; `clock` gives seconds, for how long a sweep has waited (the nodelet:
  // wall time; prefilter_bag: the bag time of the message being read). `tf` is filled by the
  // caller, possibly on another thread (a tf listener).
  // Either frame may be empty (not looked up).
  SensorPoseQueue(const std::string& sensor_frame, const std::string& fixed_frame, const std::string& topic,
                  const tf2::BufferCore& tf, SweepReceiver& next, std::function<double()> clock);

  // A converted sweep (its context's sensor pose still the identity): handed on at once when
  // tf has the transform and no older sweep waits, otherwise queued (the sweep's buffers are
  // taken; `sweep` is left empty).
  void sweepReady(core::Sweep& sweep, const core::SweepContext& context) override;
  void inputProblem(const InputProblem& problem) override { next_.inputProblem(problem); }
  void inputTypeFound(const FoundInputType& type) override { next_.inputTypeFound(type); }

  // Hands on, in order, the waiting sweeps whose transforms have come; drops, with an error
  // naming both frames, those whose transform will not come (tf holds newer transforms between
  // the two frames but none for their stamp: a gap, or older than tf's cache) and those that
  // waited longer than kMaxWaitSeconds. One call at a time does the work; a concurrent one
  // returns at once (the running one picks up what was queued meanwhile).
  void poll();
  // The end of the bag (prefilter_bag): drops every waiting sweep, with an error.
  void finish();
  // Forgets the waiting sweeps (the nodelet, on subscribing again).
  void reset();
  std::size_t waitingSweeps();

private:
  enum class Lookup
  {
    found,  // `context` holds the sensor pose
    wait,   // not in tf yet
    never   // will not come
  };
  struct Waiting
  {
    core::Sweep sweep;
    core::SweepContext context;
    double since = 0.0;
    std::uint64_t id = 0;
  };

  // One transform target <- source at the context's stamp into `pose`.
  Lookup lookUp(const std::string& target, const std::string& source, const core::SweepContext& context,
                Eigen::Isometry3d& pose, std::string& reason) const;
  // What becomes of a sweep now: handed on (with both poses, or without the fixed one and a
  // problem reported), dropped, or left waiting (false). `waited`: seconds it has waited.
  bool settle(core::Sweep& sweep, const core::SweepContext& context, double waited);
  // Hands on or drops the waiting sweeps; the caller holds deliver_mutex_.
  void deliverWaiting();
  void drop(const core::SweepContext& context, const std::string& why);

  std::string sensor_frame_;
  std::string fixed_frame_;
  std::string topic_;
  const tf2::BufferCore& tf_;
  SweepReceiver& next_;
  std::function<double()> clock_;

  std::mutex waiting_mutex_;  // guards waiting_ and next_id_
  std::deque<Waiting> waiting_;
  std::uint64_t next_id_ = 0;
  // Sweeps with lower ids were forgotten by reset() (one being settled then is not put back).
  std::uint64_t next_id_reset_ = 0;
  // Held by the thread that hands sweeps on, so that they go on in the order they came.
  std::mutex deliver_mutex_;
};

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
