#include "ohm_mirror_detector3d/ros/sensor_pose_queue.h"

#include <ros/time.h>
#include <tf2/exceptions.h>

#include <sstream>
#include <utility>

#include "ohm_mirror_detector3d/ros/conversions.h"
#include "ohm_mirror_detector3d/ros/tf_availability.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
namespace
{
std::string formatSeconds(double seconds)
{
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(3);
  out << seconds;
  return out.str();
}

ros::Time stampOf(const core::SweepContext& context)
{
  ros::Time stamp;
  stamp.fromNSec(context.stamp_ns);
  return stamp;
}
}  // namespace

SensorPoseQueue::SensorPoseQueue(const std::string& sensor_frame, const std::string& fixed_frame,
                                 const std::string& topic, const tf2::BufferCore& tf, SweepReceiver& next,
                                 std::function<double()> clock)
  : sensor_frame_(sensor_frame), fixed_frame_(fixed_frame), topic_(topic), tf_(tf), next_(next), clock_(std::move(clock))
{
}

SensorPoseQueue::Lookup SensorPoseQueue::lookUp(const std::string& target, const std::string& source,
                                                const core::SweepContext& context, Eigen::Isometry3d& pose,
                                                std::string& reason) const
{
  const std::string& frame = context.frame_id;
  if (target == source)
  {
    pose = Eigen::Isometry3d::Identity();
    return Lookup::found;  // e.g. the clouds are in the scanner's frame after all
  }
  if (frame.empty() || frame[0] == '/')
  {
    reason = "tf cannot use the cloud's frame_id '" + frame + "' (empty, or it starts with '/')";
    return Lookup::never;
  }
  const ros::Time stamp = stampOf(context);
  const auto found = [&]() {
    if (!tf_.canTransform(target, source, stamp, &reason))
      return false;
    try
    {
      pose = toIsometry(tf_.lookupTransform(target, source, stamp).transform);
      return true;
    }
    catch (const tf2::TransformException& e)
    {
      reason = e.what();
      return false;
    }
  };
  if (found())
    return Lookup::found;
  if (transformMayStillCome(tf_, target, source, stamp, reason))
    return Lookup::wait;
  // A tf listener fills the buffer on its own thread: the transform may have come between the
  // first try and the look at the newest one. Only a second miss means it never will.
  return found() ? Lookup::found : Lookup::never;
}

void SensorPoseQueue::drop(const core::SweepContext& context, const std::string& why)
{
  next_.inputProblem(InputProblem{ true, "sweep", topic_,
                                   "no transform from sensor_frame '" + sensor_frame_ + "' to the cloud's frame '" +
                                       context.frame_id + "' " + why });
}

bool SensorPoseQueue::settle(core::Sweep& sweep, const core::SweepContext& context, double waited)
{
  const bool timed_out = waited > kMaxWaitSeconds;
  const std::string stamp = formatSeconds(stampOf(context).toSec());
  core::SweepContext placed = context;
  std::string reason;
  if (!sensor_frame_.empty())
  {
    switch (lookUp(context.frame_id, sensor_frame_, context, placed.sensor_pose, reason))
    {
      case Lookup::found: break;
      case Lookup::never: drop(context, "will come for its stamp " + stamp + ": " + reason); return true;
      case Lookup::wait:
        if (!timed_out)
          return false;
        drop(context, "after waiting " + formatSeconds(waited) + " s for its stamp " + stamp + ": " + reason);
        return true;
    }
  }
  if (!fixed_frame_.empty())
  {
    Eigen::Isometry3d fixed_from_sweep = Eigen::Isometry3d::Identity();
    const Lookup lookup = lookUp(fixed_frame_, context.frame_id, context, fixed_from_sweep, reason);
    if (lookup == Lookup::wait && !timed_out)
      return false;
    if (lookup == Lookup::found)
    {
      placed.has_fixed_pose = true;
      placed.fixed_frame_id = fixed_frame_;
      placed.fixed_from_sweep = fixed_from_sweep;
    }
    else
    {
      InputProblem problem(false, "sweep", topic_,
                           "no transform from the cloud's frame '" + context.frame_id + "' to fixed_frame '" +
                               fixed_frame_ + "': processed single-sweep, not merged into the object map nor "
                               "labelled against it",
                           (lookup == Lookup::never ? "none will come for its stamp " :
                                                      "waited " + formatSeconds(waited) + " s for its stamp ") +
                               stamp + ": " + reason);
      problem.error = true;
      next_.inputProblem(problem);
    }
  }
  next_.sweepReady(sweep, placed);
  return true;
}

void SensorPoseQueue::sweepReady(core::Sweep& sweep, const core::SweepContext& context)
{
  std::unique_lock<std::mutex> deliver(deliver_mutex_, std::try_to_lock);
  bool older_waiting = true;
  {
    std::lock_guard<std::mutex> lock(waiting_mutex_);
    older_waiting = !waiting_.empty();
  }
  if (deliver.owns_lock() && !older_waiting && settle(sweep, context, 0.0))
    return;
  Waiting overflow;
  bool overflowed = false;
  {
    std::lock_guard<std::mutex> lock(waiting_mutex_);
    if (waiting_.size() >= kMaxWaitingSweeps)
    {
      overflow.context = waiting_.front().context;
      waiting_.pop_front();
      overflowed = true;
    }
    waiting_.emplace_back();
    Waiting& waiting = waiting_.back();
    std::swap(waiting.sweep, sweep);
    waiting.context = context;
    waiting.since = clock_();
    waiting.id = next_id_++;
  }
  if (overflowed)
    drop(overflow.context, "has come for the stamp " + formatSeconds(stampOf(overflow.context).toSec()) + ", and " +
                               std::to_string(kMaxWaitingSweeps) + " newer sweeps wait: dropping the oldest");
  if (deliver.owns_lock())
    deliverWaiting();
}

void SensorPoseQueue::poll()
{
  std::unique_lock<std::mutex> deliver(deliver_mutex_, std::try_to_lock);
  if (deliver.owns_lock())
    deliverWaiting();
}

void SensorPoseQueue::deliverWaiting()
{
  for (;;)
  {
    Waiting taken;
    {
      std::lock_guard<std::mutex> lock(waiting_mutex_);
      if (waiting_.empty())
        return;
      std::swap(taken, waiting_.front());
      waiting_.pop_front();
    }
    // Settled outside the lock (the receiver runs the pipeline); one that must wait on goes
    // back to the front, unless a reset() came meanwhile.
    if (settle(taken.sweep, taken.context, clock_() - taken.since))
      continue;
    std::lock_guard<std::mutex> lock(waiting_mutex_);
    if (taken.id >= next_id_reset_)
      waiting_.push_front(std::move(taken));
    return;
  }
}

void SensorPoseQueue::finish()
{
  std::deque<Waiting> waiting;
  {
    std::lock_guard<std::mutex> lock(waiting_mutex_);
    std::swap(waiting, waiting_);
  }
  for (const Waiting& sweep : waiting)
    drop(sweep.context, "for the stamp " + formatSeconds(stampOf(sweep.context).toSec()) + " by the end of the bag");
}

void SensorPoseQueue::reset()
{
  std::lock_guard<std::mutex> lock(waiting_mutex_);
  waiting_.clear();
  next_id_reset_ = next_id_;
}

std::size_t SensorPoseQueue::waitingSweeps()
{
  std::lock_guard<std::mutex> lock(waiting_mutex_);
  return waiting_.size();
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
