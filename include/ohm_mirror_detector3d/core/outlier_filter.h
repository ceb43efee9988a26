// Stage outlierFilter of the paper: sparse points become nanPoint.
#pragma once

#include <cstdint>
#include <vector>

#include "ohm_mirror_detector3d/core/params.h"
#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// Finds the neighbours of points within a radius among a chosen subset of a sweep's points
// (both echoes), without a kd-tree. Owns its buffers and reuses them from call to call.
class OutlierFilter
{
public:
  // Every point of both echoes labelled `subject` that has fewer than
  // params.outlier_min_neighbors other `subject` points within params.outlier_radius
  // becomes nanPoint. Points are judged on the labels as they were before the call
  // (removing one outlier does not turn its neighbours into outliers). A point repeated
  // in both echoes of a beam (a single return) is one point, not its own neighbour.
  // Returns the number of points it labelled nanPoint.
  std::size_t apply(const Sweep& sweep, const Params& params, Label subject, SweepLabels& labels);
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
