// The pipeline's parameters: one field per pipeline row of parameters.def (names, symbols,
// ranges and docs are there and in param_table.h), with the defaults of the original launch
// file, except where the default follows the sensor (automatic below).
#pragma once

#include <string>
#include <vector>

namespace ohm_mirror_detector3d
{
namespace core
{
// The value of a parameter that is not set and follows the sweep's sampling instead
// (stage_configs.h resolves it): 0, which no such parameter allows as a value of its own. So
// Params always tells a value the user set from one left to the sensor (the original launch
// file's values mean what they meant there), on the parameter server, in dynamic_reconfigure
// (0 = automatic) and in Python alike.
constexpr double kAutomatic = 0.0;

// The default of such a parameter in parameters.def: automatic("what it follows").
struct AutomaticDefault
{
  const char* meaning;
  constexpr operator double() const { return kAutomatic; }
  constexpr operator int() const { return static_cast<int>(kAutomatic); }
};
constexpr AutomaticDefault automatic(const char* meaning)
{
  return AutomaticDefault{ meaning };
}

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
