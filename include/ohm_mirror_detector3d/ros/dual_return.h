// Input mode dual_return: one PointCloud2 with both returns of every beam.
#pragma once

#include <sensor_msgs/PointCloud2.h>

#include <string>
#include <vector>

#include "ohm_mirror_detector3d/core/dual_return.h"
#include "ohm_mirror_detector3d/core/sweep.h"
#include "ohm_mirror_detector3d/ros/parameters.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
// Field names accepted for the return index and the ring, first match wins.
extern const char* const kReturnFieldNames[3];  // return, return_type, echo
extern const char* const kRingFieldNames[2];    // ring, channel

// Reads `azimuth_resolution_deg` (default core::kAzimuthStepFromCloud); appends a
// message to `errors` when it has the wrong type or is out of range. The nodelet and
// prefilter_bag both read it here.
double readAzimuthResolution(const ParamSource& source, std::vector<std::string>& errors);

// Reads x y z (float32), the optional numeric intensity, a return-index field and a ring
// field (integer types) of every point (row-major) into `input`. Returns an empty string on
// success, otherwise what is wrong, naming the field.
std::string readDualReturnCloud(const sensor_msgs::PointCloud2& cloud, core::DualReturnInput& input);

// Fills `sweep` from a dual-return cloud (see core::binDualReturns). `input` and `binner` are
// buffers reused from call to call. Returns an empty string on success, otherwise the problem.
std::string dualReturnCloudToSweep(const sensor_msgs::PointCloud2& cloud, double azimuth_resolution_deg,
                                   core::DualReturnInput& input, core::DualReturnBinner& binner, core::Sweep& sweep,
                                   core::DualReturnStats& stats);

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
