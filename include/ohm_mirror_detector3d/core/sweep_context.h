// What is known about a sweep besides its beams: when it was taken, in which frame, from where,
// and (when known) where that frame lies in a fixed frame. It travels beside every core::Sweep
// from the input adapter through the pipeline; stages that need the sensor's position or the
// sweep's place in the world read it here.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>

namespace ohm_mirror_detector3d
{
namespace core
{
struct SweepContext
{
  // Acquisition time of the sweep (the input header's stamp), nanoseconds since the epoch.
  std::uint64_t stamp_ns = 0;
  // The frame of the sweep's points; the outputs are in it too.
  std::string frame_id;
  // The scanner's optical frame in the sweep's frame: the translation is where every beam
  // starts (the apex of the vision cones), the rotation the scanner's own axes.
  Eigen::Isometry3d sensor_pose = Eigen::Isometry3d::Identity();
  // Optional: the sweep's frame in a fixed frame (odom, map), for objects kept over sweeps.
  bool has_fixed_pose = false;
  std::string fixed_frame_id;
  Eigen::Isometry3d fixed_from_sweep = Eigen::Isometry3d::Identity();

  Eigen::Vector3f sensorOrigin() const { return sensor_pose.translation().cast<float>(); }
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
