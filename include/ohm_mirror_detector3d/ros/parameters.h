// Pre-filter parameters on the ROS parameter server and in dynamic_reconfigure.
#pragma once

#include <ros/node_handle.h>

#include <string>
#include <vector>

#include "ohm_mirror_detector3d/PreFilterConfig.h"
#include "ohm_mirror_detector3d/core/params.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
// Reads every pipeline parameter from `private_nh`, under its original launch file name
// (e.g. `outlierFilter_searchRadius`) or its paper name (e.g. `r`); absent ones keep their
// defaults. Appends to `errors` a message for each value that cannot be read (wrong type,
// both names given with different values). Range checks are Params::validate()'s job.
core::Params readParams(const ros::NodeHandle& private_nh, std::vector<std::string>& errors);

// Writes the parameters back under their original names, so that the dynamic_reconfigure
// server starts from what was read (including values given under paper names).
void writeParams(const ros::NodeHandle& private_nh, const core::Params& params);

core::Params fromConfig(const PreFilterConfig& config);

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
