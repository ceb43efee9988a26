// Whether a transform that tf does not have yet can still come: the one decision behind both
// waits for tf (SensorPoseQueue for sensor_frame, MultiEchoScanInput for scans), which keep an
// input waiting while it can and drop it once it cannot.
#pragma once

#include <ros/time.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>

#include <string>

namespace ohm_mirror_detector3d
{
namespace ros_io
{
// A missing transform target <- source at `time` can still come only while tf's newest
// transform between the two frames is older than `time` (or there is none yet, or only a static
// one, stamped 0). Once tf holds newer ones, `time` lies before its cache or in a gap. When tf
// has no transform between the frames at all, `reason` gets tf's words. Never waits.
inline bool transformMayStillCome(const tf2::BufferCore& tf, const std::string& target, const std::string& source,
                                  const ros::Time& time, std::string& reason)
{
  try
  {
    const ros::Time latest = tf.lookupTransform(target, source, ros::Time(0)).header.stamp;
    return latest.isZero() || latest < time;
  }
  catch (const tf2::TransformException& e)
  {
    reason = e.what();
    return true;
  }
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
