#include "ohm_mirror_detector3d/ros/dual_return.h"

#include <vector>

#include "ohm_mirror_detector3d/ros/conversions.h"
#include "ohm_mirror_detector3d/ros/point_fields.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
const char* const kReturnFieldNames[3] = { "return", "return_type", "echo" };
const char* const kRingFieldNames[2] = { "ring", "channel" };

double readAzimuthResolution(const ParamSource& source, std::vector<std::string>& errors)
{
  double resolution = core::kAzimuthStepFromCloud;
  if (source.has("azimuth_resolution_deg") && !source.get("azimuth_resolution_deg", resolution))
    errors.push_back("parameter " + source.describe("azimuth_resolution_deg") +
                     " has the wrong type: expected a number");
  else if (!core::validateAzimuthResolution(resolution).empty())
    errors.push_back(core::validateAzimuthResolution(resolution));
  return resolution;
}

std::string readDualReturnCloud(const sensor_msgs::PointCloud2& cloud, core::DualReturnInput& input)
{
  std::string used;
  std::string problem = readEchoCloud(cloud, input.points, input.has_intensity);
  if (problem.empty())
    problem = readIntegerField(cloud, "return-index", { std::begin(kReturnFieldNames), std::end(kReturnFieldNames) },
                               input.returns, used);
  if (problem.empty())
    problem = readIntegerField(cloud, "ring", { std::begin(kRingFieldNames), std::end(kRingFieldNames) },
                               input.rings, used);
  return problem;
}

std::string dualReturnCloudToSweep(const sensor_msgs::PointCloud2& cloud, double azimuth_resolution_deg,
                                   core::DualReturnInput& input, core::DualReturnBinner& binner, core::Sweep& sweep,
                                   core::DualReturnStats& stats)
{
  const std::string problem = readDualReturnCloud(cloud, input);
  if (!problem.empty())
    return problem;
  stats = binner.bin(input, azimuth_resolution_deg, sweep);
  return "";
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
