#include "ohm_mirror_detector3d/ros/legacy_values.h"

#include <sstream>

#include "ohm_mirror_detector3d/core/param_table.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
namespace
{
// Whether `legacy_name` is set and no other name of its parameter is.
bool givenOnlyUnder(const ParamSource& source, const std::string& legacy_name)
{
  if (!source.has(legacy_name))
    return false;
  for (const std::string& name : core::findParameter(legacy_name)->names())
    if (name != legacy_name && source.has(name))
      return false;
  return true;
}
}  // namespace

std::vector<std::string> mapLegacyValues(const ParamSource& source, core::Params& params)
{
  std::vector<std::string> lines;
  if (givenOnlyUnder(source, "outlierFilter_minNeighbors") && givenOnlyUnder(source, "outlierFilter_searchRadius") &&
      params.outlier_min_neighbors > 1 && params.outlier_radius != core::kAutomatic)
  {
    std::ostringstream line;
    line << "outlierFilter_minNeighbors " << params.outlier_min_neighbors << " within outlierFilter_searchRadius "
         << params.outlier_radius
         << " m (the original's names) is a density tuned for the original's sweep; read as automatic (r and "
            "n_inlier 0: neighbours in the sweep's own beam grid); set r and n_inlier to use a sphere";
    lines.push_back(line.str());
    params.outlier_min_neighbors = static_cast<int>(core::kAutomatic);
    params.outlier_radius = core::kAutomatic;
  }
  const double landing_tolerance = core::Params().icp_max_distance;
  if (givenOnlyUnder(source, "max_Dist_ICP") && params.icp_max_distance < landing_tolerance)
  {
    std::ostringstream line;
    line << "max_Dist_ICP " << params.icp_max_distance
         << " m (the original's name) was a correspondence limit inside ICP; read as the landing tolerance of a "
            "reflected return, at least the default "
         << landing_tolerance << " m that single noisy returns need; set icp_max_distance to use a smaller one";
    lines.push_back(line.str());
    params.icp_max_distance = landing_tolerance;
  }
  return lines;
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
