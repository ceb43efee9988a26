#include "ohm_mirror_detector3d/ros/parameters.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
namespace
{
// One pipeline parameter: its name in the original launch file (also the name in
// cfg/PreFilter.cfg), the paper's symbol (nullptr when it has none), and the field of
// core::Params it sets.
struct ParamName
{
  const char* ros_name;
  const char* paper_name;
  double core::Params::*real_field;
  int core::Params::*integer_field;
};

const ParamName kParamNames[] = {
  { "min_measure_distance", "d_min", &core::Params::min_range, nullptr },
  { "max_measure_distance", "d_max", &core::Params::max_range, nullptr },
  { "outlierFilter_searchRadius", "r", &core::Params::outlier_radius, nullptr },
  { "outlierFilter_minNeighbors", "n_inlier", nullptr, &core::Params::outlier_min_neighbors },
  { "substract_threshold_distance", "d_thres", &core::Params::echo_threshold, nullptr },
  { "planeDetection_threshold_distance", "d_thres_plane", &core::Params::plane_threshold, nullptr },
  { "planeDetection_minAmountPoints", "n_object", nullptr, &core::Params::min_object_points },
  { "visionCone_threshold", "d_thres_visionCone", &core::Params::vision_cone_margin, nullptr },
  { "max_Dist_ICP", "icp_max_distance", &core::Params::icp_max_distance, nullptr },
  { "fitness_Fct_ICP", "icp_fitness_threshold", &core::Params::icp_fitness_threshold, nullptr },
  // Ours, not the paper's or the original launch file's: one name only.
  { "icp_min_points", nullptr, nullptr, &core::Params::icp_min_points },
  { "icp_min_inlier_fraction", nullptr, &core::Params::icp_min_inlier_fraction, nullptr },
};

// Reads `name` as T when present. Returns false and explains when it is present but not a T.
template <typename T>
bool readOne(const ParamSource& source, const std::string& name, T& value, bool& present,
             std::vector<std::string>& errors)
{
  present = source.has(name);
  if (!present)
    return true;
  if (source.get(name, value))
    return true;
  // An integer given for a real parameter is fine; get(double) already accepts it.
  errors.push_back("parameter " + source.describe(name) + " has the wrong type: expected " +
                   (std::is_same<T, int>::value ? "an integer" : "a number"));
  return false;
}

template <typename T>
void readAliased(const ParamSource& source, const ParamName& param, T& field, std::vector<std::string>& errors)
{
  T by_ros_name = field;
  T by_paper_name = field;
  bool has_ros_name = false;
  bool has_paper_name = false;
  const bool ok = readOne(source, param.ros_name, by_ros_name, has_ros_name, errors) &
                  (param.paper_name == nullptr ||
                   readOne(source, param.paper_name, by_paper_name, has_paper_name, errors));
  if (!ok)
    return;
  if (has_ros_name && has_paper_name && by_ros_name != by_paper_name)
  {
    errors.push_back(std::string("parameters ") + param.ros_name + " = " + std::to_string(by_ros_name) + " and " +
                     param.paper_name + " = " + std::to_string(by_paper_name) +
                     " name the same value and disagree; give only one");
    return;
  }
  if (has_ros_name)
    field = by_ros_name;
  else if (has_paper_name)
    field = by_paper_name;
}
}  // namespace

core::Params readParams(const ParamSource& source, std::vector<std::string>& errors)
{
  core::Params params;
  for (const ParamName& param : kParamNames)
  {
    if (param.real_field != nullptr)
      readAliased(source, param, params.*param.real_field, errors);
    else
      readAliased(source, param, params.*param.integer_field, errors);
  }
  return params;
}

core::Params readParams(const ros::NodeHandle& private_nh, std::vector<std::string>& errors)
{
  return readParams(NodeHandleParamSource(private_nh), errors);
}

void writeParams(const ros::NodeHandle& private_nh, const core::Params& params)
{
  for (const ParamName& param : kParamNames)
  {
    if (param.real_field != nullptr)
      private_nh.setParam(param.ros_name, params.*param.real_field);
    else
      private_nh.setParam(param.ros_name, params.*param.integer_field);
  }
}

core::Params fromConfig(const PreFilterConfig& config)
{
  core::Params params;
  params.min_range = config.min_measure_distance;
  params.max_range = config.max_measure_distance;
  params.outlier_radius = config.outlierFilter_searchRadius;
  params.outlier_min_neighbors = config.outlierFilter_minNeighbors;
  params.echo_threshold = config.substract_threshold_distance;
  params.plane_threshold = config.planeDetection_threshold_distance;
  params.min_object_points = config.planeDetection_minAmountPoints;
  params.vision_cone_margin = config.visionCone_threshold;
  params.icp_max_distance = config.max_Dist_ICP;
  params.icp_fitness_threshold = config.fitness_Fct_ICP;
  params.icp_min_points = config.icp_min_points;
  params.icp_min_inlier_fraction = config.icp_min_inlier_fraction;
  return params;
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
