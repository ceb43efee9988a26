#include "ohm_mirror_detector3d/ros/dual_return.h"

#include <sstream>
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

std::string describeUnbinned(const core::DualReturnStats& stats)
{
  if (stats.ring_out_of_range + stats.return_out_of_range + stats.duplicates == 0)
    return "";
  std::ostringstream text;
  text << "labelled nanPoint (in no grid cell) " << stats.unbinned() << " of " << stats.points << " points:";
  if (stats.ring_out_of_range > 0)
    text << " " << stats.ring_out_of_range << " with a ring outside 0.." << core::kMaxRings - 1 << ";";
  if (stats.return_out_of_range > 0)
    text << " " << stats.return_out_of_range << " with a return index other than " << stats.return_base << " or "
         << stats.return_base + 1 << " (only the first two returns are compared);";
  if (stats.duplicates > 0)
  {
    text << " " << stats.duplicates << " sharing a ring and azimuth bin with another point of the same return";
    if (stats.azimuth_from_cloud)
      text << " (bins of " << stats.azimuth_resolution_deg
           << " deg, the azimuth step worked out from the cloud: its firings are not evenly spaced; give "
              "azimuth_resolution_deg);";
    else
      text << " (is azimuth_resolution_deg = " << stats.azimuth_resolution_deg
           << " coarser than the lidar's azimuth step? Leave it unset to work it out from the cloud);";
  }
  if (stats.no_return > 0)
    text << " " << stats.no_return << " without a return (non-finite or at the origin)";
  return text.str();
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
