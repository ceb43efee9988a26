// Stage outlierFilter of the paper: sparse points become nanPoint.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ohm_mirror_detector3d/core/beam_neighbourhood.h"
#include "ohm_mirror_detector3d/core/spatial_index.h"
#include "ohm_mirror_detector3d/core/sweep.h"
#include "ohm_mirror_detector3d/core/sweep_sampling.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct OutlierFilterConfig
{
  double radius = 0.0;    // r [m]: the metric neighbourhood, a sphere (unless follows_sampling)
  int min_neighbors = 1;  // n_inlier
  // The neighbourhood in the sweep's own sampling instead of the sphere: the returns of the
  // beams around (BeamNeighbourhood), which grows with range and the angular step.
  bool follows_sampling = false;
  BeamNeighbourhoodConfig neighbourhood;
  int threads = 1;  // core/parallel.h
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

  // The same test in the neighbourhood the config says: with follows_sampling, a point is an
  // outlier when fewer than min_neighbors returns of the beams around it on the sampling's grid
  // (both echoes; the other echo of its own beam is no neighbour, a single return repeated in
  // both echoes is one point) lie closer than the neighbourhood's limit for its range. On a
  // sweep without a grid (unordered) the sphere of radius noise_floor + step_factor *
  // half_width * step * R90 is used instead (R90: the 90th percentile of the subject points'
  // ranges, so that all but the farthest tenth have at least their grid neighbourhood); with
  // the sampling unknown (almost no returns) only non-finite subject points are removed.
  // Otherwise apply(sweep, subject, labels).
  std::size_t apply(const Sweep& sweep, const SweepSampling& sampling, Label subject, SweepLabels& labels);

  // The errorSurface pass in the sweep's sampling (with follows_sampling, on a grid): an
  // errorSurface point with fewer than min_neighbors errorSurface points of the beams around
  // it within the neighbourhood's limit is no surface echo. Both echoes of its beam become
  // unchecked again: the far echo survived the first pass, so it lies on something seen by the
  // beams around, and neither echo is lost. Returns the number of beams released.
  std::size_t releaseIsolatedSurfaceEchoes(const Sweep& sweep, const SweepSampling& sampling, SweepLabels& labels);

private:
  // Bits of subject_ per beam: echo 1 a subject point, echo 2 a subject point, echo 2 the same
  // point as echo 1 (a single return repeated: one point).
  static constexpr std::uint8_t kFirst = 1;
  static constexpr std::uint8_t kSecond = 2;
  static constexpr std::uint8_t kRepeated = 4;
  std::size_t applySphere(const Sweep& sweep, Label subject, SweepLabels& labels, double radius);
  std::size_t markSubjects(const Sweep& sweep, Label subject, SweepLabels& labels);
  // How many subject returns of the beams around echo `echo` of `beam` lie within the limit, up
  // to `need`.
  std::size_t supportOnGrid(const Sweep& sweep, const BeamNeighbourhood& neighbourhood, std::size_t beam,
                            int echo, std::size_t need) const;
  std::size_t applyOnGrid(const Sweep& sweep, const SweepSampling& sampling, Label subject, SweepLabels& labels);
  double unorderedRadius(const Sweep& sweep, const SweepSampling& sampling, Label subject,
                         const SweepLabels& labels);


  // Gathers the subject points (one per distinct point of a beam, in beam order) into the
  // index; returns how many non-finite subject points it labelled nanPoint on the way.
  std::size_t gather(const Sweep& sweep, Label subject, SweepLabels& labels);

  OutlierFilterConfig config_;
  std::vector<std::uint8_t> subject_;  // per beam: kFirst | kSecond | kRepeated
  std::vector<float> ranges_;          // a sample of subject ranges (unordered sweeps)
  // Point ids: beam index << 2 | echo mask (bit k: echo k); < 2^30 beams.
  SpatialIndex index_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
