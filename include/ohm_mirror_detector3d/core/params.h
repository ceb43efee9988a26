// The pipeline's parameters with the defaults of the original launch file: one field per
// pipeline row of parameters.def (names, symbols, ranges and docs are there and in
// param_table.h).
#pragma once

#include <string>
#include <vector>

namespace ohm_mirror_detector3d
{
namespace core
{
struct Params
{
#define OHM_PIPELINE_PARAMETER(field, type, default_value, ...) type field = default_value;
#define OHM_START_UP_PARAMETER(...)
#include "ohm_mirror_detector3d/core/parameters.def"
#undef OHM_PIPELINE_PARAMETER
#undef OHM_START_UP_PARAMETER

  // One message per bad value, naming the parameter (ROS name and paper name), the
  // value and the allowed range; empty when every value is acceptable.
  std::vector<std::string> validate() const;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
