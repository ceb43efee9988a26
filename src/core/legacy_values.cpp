#include "ohm_mirror_detector3d/core/legacy_values.h"

#include <sstream>

#include "ohm_mirror_detector3d/core/param_table.h"

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// Whether `legacy_name` is set and no other name of its parameter is.
bool givenOnlyUnder(const std::function<bool(const std::string&)>& is_set, const std::string& legacy_name)
{
  if (!is_set(legacy_name))
    return false;
  for (const std::string& name : findParameter(legacy_name)->names())
    if (name != legacy_name && is_set(name))
      return false;
  return true;
}
}  // namespace

std::vector<std::string> mapLegacyValues(const std::function<bool(const std::string&)>& is_set, Params& params)
{
  std::vector<std::string> lines;
  if (givenOnlyUnder(is_set, "outlierFilter_minNeighbors") && givenOnlyUnder(is_set, "outlierFilter_searchRadius") &&
      params.outlier_min_neighbors > 1 && params.outlier_radius != kAutomatic)
  {
    std::ostringstream line;
    line << "outlierFilter_minNeighbors " << params.outlier_min_neighbors << " within outlierFilter_searchRadius "
         << params.outlier_radius
         << " m (the original's names) is a density tuned for the original's sweep; read as automatic (r and "
            "n_inlier 0: neighbours in the sweep's own beam grid); set r and n_inlier to use a sphere";
    lines.push_back(line.str());
    params.outlier_min_neighbors = static_cast<int>(kAutomatic);
    params.outlier_radius = kAutomatic;
  }
  const double landing_tolerance = Params().icp_max_distance;
  if (givenOnlyUnder(is_set, "max_Dist_ICP") && params.icp_max_distance < landing_tolerance)
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

}  // namespace core
}  // namespace ohm_mirror_detector3d
