// What the stages that delete points removed of one sweep, and when that share is implausible:
// a stage whose parameters do not fit the sensor (a fixed 0.1 m / 50-neighbour outlier filter on
// a 64-ring lidar deletes three quarters of every frame and nearly all second returns) must be
// named, not silently obeyed. The core counts, judges and words it (describeRemoval); the front
// ends pass it on: the nodelet as a throttled warning and a diagnostics WARN, prefilter_bag in
// its log, Python in the stats' "warnings".
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/core/param_table.h"
#include "ohm_mirror_detector3d/core/params.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct RemovalCounts
{
  // Points of both echoes after the range gate (a single return repeated in both echoes once).
  std::size_t in_range_points = 0;
  std::size_t outlier_removed = 0;  // of them, nanPoint after the outlier filter's first pass
  // Second echoes of beams with two distinct returns in range: what reveals mirrors and glass.
  std::size_t second_returns = 0;
  std::size_t second_returns_removed = 0;  // of them, nanPoint after the first pass
  // errorSurface points the outlier filter's second pass judged, and those it made nanPoint.
  std::size_t surface_echoes = 0;
  std::size_t surface_echoes_removed = 0;
};

// Above these shares a removal is implausible: real sweeps hold few outliers, and second
// returns lie on surfaces (mirrors, glass, both sides of a depth edge), so a filter that deletes
// (nearly) all of them does not fit the sensor.
constexpr double kImplausibleInRangeShare = 0.10;
constexpr double kImplausibleSecondReturnShare = 0.90;
constexpr double kImplausibleSurfaceEchoShare = 0.50;
// Fewer points than these are too few to judge a share by.
constexpr std::size_t kMinInRangeJudged = 100;
constexpr std::size_t kMinSecondReturnsJudged = 20;
constexpr std::size_t kMinSurfaceEchoesJudged = 20;

enum class RemovedPoints
{
  in_range_points,  // by the outlier filter
  second_returns,   // by the outlier filter
  surface_echoes,   // by the outlier filter's pass over the errorSurface points
};

struct ImplausibleRemoval
{
  RemovedPoints what;
  std::size_t removed;
  std::size_t of;
  // The parameters of the stage that removed them (the outlier filter's r and n_inlier).
  std::vector<const ParamInfo*> parameters;

  double share() const { return of > 0 ? static_cast<double>(removed) / static_cast<double>(of) : 0.0; }
};

// The removals of `counts` above their limits, in the order of RemovedPoints.
std::vector<ImplausibleRemoval> implausibleRemovals(const RemovalCounts& counts);

// One sentence: what was removed, the share, the parameters that did it with their values in
// `params` (or that they follow the sensor), and what to do about it.
std::string describeRemoval(const ImplausibleRemoval& removal, const Params& params);
// describeRemoval of each of implausibleRemovals(counts): what the front ends warn with.
std::vector<std::string> removalWarnings(const RemovalCounts& counts, const Params& params);

}  // namespace core
}  // namespace ohm_mirror_detector3d
