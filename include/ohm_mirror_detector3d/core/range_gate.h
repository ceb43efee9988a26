// Stage distanceThresFilter of the paper: range gate and non-finite returns.
#pragma once

#include <cstddef>

#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct RangeGateConfig
{
  double min_range;  // d_min [m]
  double max_range;  // d_max [m]
};

class RangeGate
{
public:
  explicit RangeGate(const RangeGateConfig& config);

  // Labels nanPoint every return of both echoes that is non-finite (REP-117: NaN, +Inf, -Inf
  // in any coordinate) or whose range (from the sensor origin, Sweep::computeRanges) lies
  // outside [min_range, max_range]. Other labels are left as they are. Returns the number of
  // points it labelled.
  std::size_t apply(const Sweep& sweep, SweepLabels& labels) const;

private:
  float min_range_;
  float max_range_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
