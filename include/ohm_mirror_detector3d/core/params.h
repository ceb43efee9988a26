// Parameters of the pre-filter with the defaults of the original launch file.
#pragma once

#include <string>
#include <vector>

namespace ohm_mirror_detector3d
{
namespace core
{
struct Params
{
  double min_range = 0.023;             // d_min [m]: nearer returns are nanPoint
  double max_range = 60.0;              // d_max [m]: farther returns are nanPoint
  double outlier_radius = 0.1;          // r [m]: neighbourhood radius of the outlier filter
  int outlier_min_neighbors = 50;       // n_inlier: fewer neighbours within r make a point an outlier
  double echo_threshold = 0.05;         // d_thres [m]: |d1 - d2| above it marks a discontinuous beam
  double plane_threshold = 0.05;        // d_thres_plane [m]: max distance of a surface point from its plane
  int min_object_points = 100;          // n_object: fewest errorSurface points that make an object
  double vision_cone_margin = 0.05;     // d_thres_visionCone [m]: growth of an object's vision cone
  double icp_max_distance = 0.1;        // [m] max correspondence distance of the mirror test's ICP
  double icp_fitness_threshold = 0.005; // [m^2] mean squared ICP distance below which a plane is a mirror
  int icp_min_points = 30;              // fewest points behind a plane (and real ones where they land) to decide its type
  double icp_min_inlier_fraction = 0.5; // share of mirrored points that must land on the real scene for a mirror

  // One message per bad value, naming the parameter (ROS name and paper name), the
  // value and the allowed range; empty when every value is acceptable.
  std::vector<std::string> validate() const;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
