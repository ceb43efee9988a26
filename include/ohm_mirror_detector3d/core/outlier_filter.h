// Stage outlierFilter of the paper: sparse points become nanPoint.
#pragma once

#include <cstddef>

#include "ohm_mirror_detector3d/core/spatial_index.h"
#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct OutlierFilterConfig
{
  double radius;      // r [m]
  int min_neighbors;  // n_inlier
};

// Finds the neighbours of points within a radius among a chosen subset of a sweep's points
// (both echoes), on the spatial index rather than a kd-tree. Owns its buffers and reuses them
// from call to call.
class OutlierFilter
{
public:
  explicit OutlierFilter(const OutlierFilterConfig& config) : config_(config) {}

  // Every point of both echoes labelled `subject` that has fewer than min_neighbors other
  // `subject` points within radius becomes nanPoint. Points are judged on the labels as they
  // were before the call (removing one outlier does not turn its neighbours into outliers). A
  // point repeated in both echoes of a beam (a single return) is one point, not its own
  // neighbour. Returns the number of points it labelled nanPoint.
  //
  // "Within r" is inclusive: squared distance, computed in float, <= r^2 rounded to float.
  // Only the two echoes of one beam are merged when equal; equal points of different beams
  // are distinct and neighbours of each other. A non-finite point labelled `subject` has no
  // neighbours and is never one: it becomes nanPoint too.
  // A radius that is NaN or negative holds no neighbour, min_neighbors <= 0 removes nothing.
  std::size_t apply(const Sweep& sweep, Label subject, SweepLabels& labels);

private:
  // Gathers the subject points (one per distinct point of a beam, in beam order) into the
  // index; returns how many non-finite subject points it labelled nanPoint on the way.
  std::size_t gather(const Sweep& sweep, Label subject, SweepLabels& labels);

  OutlierFilterConfig config_;
  // Point ids: beam index << 2 | echo mask (bit k: echo k); < 2^30 beams.
  SpatialIndex index_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
