#include "ohm_mirror_detector3d/core/params.h"

#include <cmath>
#include <sstream>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// The names users see: the ROS parameter name (original launch file) and the paper's symbol.
std::string describe(const char* ros_name, const char* paper_name, double value)
{
  std::ostringstream out;
  out << ros_name << " (" << paper_name << ") = " << value;
  return out.str();
}

// A bound as people write it ("0", "0.5"), not std::to_string's "0.000000".
std::string bound(double value)
{
  std::ostringstream out;
  out << value;
  return out.str();
}

void requireAbove(std::vector<std::string>& errors, const char* ros_name, const char* paper_name,
                  double value, double lower_exclusive, const char* unit)
{
  if (!std::isfinite(value) || !(value > lower_exclusive))
    errors.push_back(describe(ros_name, paper_name, value) + " is out of range: must be finite and > " +
                     bound(lower_exclusive) + " " + unit);
}

void requireAtLeast(std::vector<std::string>& errors, const char* ros_name, const char* paper_name,
                    double value, double lower_inclusive, const char* unit)
{
  if (!std::isfinite(value) || !(value >= lower_inclusive))
    errors.push_back(describe(ros_name, paper_name, value) + " is out of range: must be finite and >= " +
                     bound(lower_inclusive) + " " + unit);
}
}  // namespace

std::vector<std::string> Params::validate() const
{
  std::vector<std::string> errors;
  requireAtLeast(errors, "min_measure_distance", "d_min", min_range, 0.0, "m");
  requireAbove(errors, "max_measure_distance", "d_max", max_range, 0.0, "m");
  if (std::isfinite(min_range) && std::isfinite(max_range) && min_range >= max_range)
    errors.push_back(describe("min_measure_distance", "d_min", min_range) +
                     " must be smaller than max_measure_distance (d_max) = " + bound(max_range));
  requireAbove(errors, "outlierFilter_searchRadius", "r", outlier_radius, 0.0, "m");
  requireAtLeast(errors, "outlierFilter_minNeighbors", "n_inlier", outlier_min_neighbors, 1, "points");
  requireAbove(errors, "substract_threshold_distance", "d_thres", echo_threshold, 0.0, "m");
  requireAbove(errors, "planeDetection_threshold_distance", "d_thres_plane", plane_threshold, 0.0, "m");
  // Three points span a plane; fewer cannot make an object.
  requireAtLeast(errors, "planeDetection_minAmountPoints", "n_object", min_object_points, 3, "points");
  requireAtLeast(errors, "visionCone_threshold", "d_thres_visionCone", vision_cone_margin, 0.0, "m");
  requireAbove(errors, "max_Dist_ICP", "ICP max correspondence distance", icp_max_distance, 0.0, "m");
  requireAbove(errors, "fitness_Fct_ICP", "ICP fitness threshold", icp_fitness_threshold, 0.0, "m^2");
  requireAtLeast(errors, "icp_min_points", "ICP minimum evidence", icp_min_points, 3, "points");
  requireAbove(errors, "icp_min_inlier_fraction", "ICP minimum inlier fraction", icp_min_inlier_fraction, 0.0, "");
  if (std::isfinite(icp_min_inlier_fraction) && icp_min_inlier_fraction > 1.0)
    errors.push_back(describe("icp_min_inlier_fraction", "ICP minimum inlier fraction", icp_min_inlier_fraction) +
                     " is out of range: must be in (0, 1]");
  return errors;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
