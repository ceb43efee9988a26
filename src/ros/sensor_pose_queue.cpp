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

SensorPoseQueue::SensorPoseQueue(const std::string& sensor_frame, const std::string& topic, const tf2::BufferCore& tf,
                                 SweepReceiver& next, std::function<double()> clock)
  : sensor_frame_(sensor_frame), topic_(topic), tf_(tf), next_(next), clock_(std::move(clock))
{
}

SensorPoseQueue::Lookup SensorPoseQueue::lookUp(core::SweepContext& context, std::string& reason) const
{
  const std::string& frame = context.frame_id;
  if (frame == sensor_frame_)
    return Lookup::found;  // the clouds are in the scanner's frame after all: the identity
  if (frame.empty() || frame[0] == '/')
  {
    reason = "tf cannot use the cloud's frame_id '" + frame + "' (empty, or it starts with '/')";
    return Lookup::never;
  }
  const ros::Time stamp = stampOf(context);
  const auto found = [&]() {
    if (!tf_.canTransform(frame, sensor_frame_, stamp, &reason))
      return false;
    try
    {
      context.sensor_pose = toIsometry(tf_.lookupTransform(frame, sensor_frame_, stamp).transform);
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
  if (transformMayStillCome(tf_, frame, sensor_frame_, stamp, reason))
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

void SensorPoseQueue::sweepReady(core::Sweep& sweep, const core::SweepContext& context)
{
  std::unique_lock<std::mutex> deliver(deliver_mutex_, std::try_to_lock);
  bool older_waiting = true;
  {
    std::lock_guard<std::mutex> lock(waiting_mutex_);
    older_waiting = !waiting_.empty();
  }
  if (deliver.owns_lock() && !older_waiting)
  {
    core::SweepContext placed = context;
    std::string reason;
    switch (lookUp(placed, reason))
    {
      case Lookup::found:
        next_.sweepReady(sweep, placed);
        return;
      case Lookup::never:
        drop(context, "will come for its stamp " + formatSeconds(stampOf(context).toSec()) + ": " + reason);
        return;
      case Lookup::wait:
        break;
    }
  }
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
    core::SweepContext context;
    double since = 0.0;
    std::uint64_t id = 0;
    {
      std::lock_guard<std::mutex> lock(waiting_mutex_);
      if (waiting_.empty())
        return;
      context = waiting_.front().context;
      since = waiting_.front().since;
      id = waiting_.front().id;
    }
    std::string reason;
    const Lookup lookup = lookUp(context, reason);
    const double waited = clock_() - since;
    if (lookup == Lookup::wait && waited <= kMaxWaitSeconds)
      return;
    Waiting taken;
    {
      std::lock_guard<std::mutex> lock(waiting_mutex_);
      // An overflow or reset() may have removed it meanwhile.
      if (waiting_.empty() || waiting_.front().id != id)
        continue;
      std::swap(taken, waiting_.front());
      waiting_.pop_front();
    }
    if (lookup == Lookup::found)
      next_.sweepReady(taken.sweep, context);
    else if (lookup == Lookup::never)
      drop(context, "will come for its stamp " + formatSeconds(stampOf(context).toSec()) + ": " + reason);
    else
      drop(context, "after waiting " + formatSeconds(waited) + " s for its stamp " +
                        formatSeconds(stampOf(context).toSec()) + ": " + reason);
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
}

std::size_t SensorPoseQueue::waitingSweeps()
{
  std::lock_guard<std::mutex> lock(waiting_mutex_);
  return waiting_.size();
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
