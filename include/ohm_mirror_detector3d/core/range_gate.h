// Stage distanceThresFilter of the paper: range gate and non-finite returns.
#pragma once

#include "ohm_mirror_detector3d/core/params.h"
#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// Labels nanPoint every return of both echoes that is non-finite (REP-117: NaN,
// +Inf, -Inf in any coordinate) or whose range lies outside [min_range, max_range].
// Other labels are left as they are. Returns the number of points it labelled.
std::size_t applyRangeGate(const Sweep& sweep, const Params& params, SweepLabels& labels);

}  // namespace core
}  // namespace ohm_mirror_detector3d
