// Input mode dual_return: one cloud holding both returns of every beam, each point tagged
// with its ring and its return index. Binning puts every point into a rings x azimuth-bins
// grid and pairs the two returns of a beam, so the pipeline sees an ordinary Sweep.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// azimuth_resolution_deg when it is not given: the azimuth step is worked out from each cloud
// (estimateAzimuthStepDeg). A fixed bin width fits one lidar only: 360 / 2048 puts two of a
// Velodyne's firings (0.16 deg apart) into some bins and drops one of them.
constexpr double kAzimuthStepFromCloud = 0.0;
constexpr double kMinAzimuthResolutionDeg = 0.01;  // 36000 bins
constexpr double kMaxAzimuthResolutionDeg = 10.0;
// Rings at or above this are out of range (a corrupt ring value must not size the grid).
constexpr std::int64_t kMaxRings = 1024;

// Empty when `degrees` is a usable azimuth_resolution_deg (kAzimuthStepFromCloud included),
// otherwise why not.
std::string validateAzimuthResolution(double degrees);

// Columns of the grid: 360 / degrees rounded to a whole number (the bins then are
// 360 / columns wide, which differs from `degrees` only when it does not divide 360).
std::size_t azimuthBins(double degrees);

// The points of a dual-return cloud in input order. Positions in the sensor frame (origin =
// optical centre); `rings` and `returns` are the raw values of the ring and return fields.
struct DualReturnInput
{
  EchoCloud points;  // points and intensities (ranges unused)
  bool has_intensity = false;
  std::vector<std::int64_t> rings;
  std::vector<std::int64_t> returns;

  std::size_t size() const { return points.points.size(); }
};

// What binning did with the points of one cloud; every input point is in exactly one count
// besides `paired_beams`/`single_beams`.
struct DualReturnStats
{
  int return_base = 1;              // 1 when the return indices are 1/2, 0 when they are 0/1
  std::size_t points = 0;
  std::size_t binned = 0;           // points in a grid cell
  std::size_t paired_beams = 0;     // cells with both returns
  std::size_t single_beams = 0;     // cells with one return
  std::size_t no_return = 0;        // non-finite, or exactly at the origin (some drivers' "no return")
  std::size_t ring_out_of_range = 0;
  std::size_t return_out_of_range = 0;  // neither the first nor the second return (e.g. a third)
  std::size_t duplicates = 0;       // lost a cell to a point of the same return nearer the bin centre
  double azimuth_resolution_deg = 0.0;  // the bin width used (360 / cols)
  bool azimuth_from_cloud = false;      // worked out from the cloud (estimateAzimuthStepDeg)

  std::size_t unbinned() const { return no_return + ring_out_of_range + return_out_of_range + duplicates; }
};

// The lidar's azimuth step [deg] as the cloud shows it: the median gap between the azimuths
// of neighbouring first returns of a ring (over up to 8 rings spread over those with returns;
// firings without a return leave wider gaps, which the median ignores while they are fewer
// than half), rounded to a whole number of steps per turn. 0 when no ring has a handful of
// first returns.
double estimateAzimuthStepDeg(const DualReturnInput& input);

// Fills `sweep` from a dual-return cloud:
// - return base: 0-based (0/1) when some point has return index 0, otherwise 1-based (1/2);
// - rows = largest in-range ring + 1 (rings 0 .. kMaxRings - 1), cols =
//   azimuthBins(azimuth_resolution_deg), or with kAzimuthStepFromCloud the step
//   estimateAzimuthStepDeg finds (one column when it finds none);
//   beam = ring * cols + bin, bin = azimuth (atan2(y, x), counter-clockwise from +x) divided
//   by the bin width, rounded;
// - echo 0 of a beam is its first return (index 1, or 0), echo 1 the second;
// - a second return is paired with the first return of its ring whose azimuth is nearest,
//   if that is within half a bin; a second return without such a partner becomes a
//   single-return beam in its own bin (echo 0) when that bin has no first return;
// - two points claiming the same cell and echo: the one nearer the bin centre (for a
//   second return: nearer its partner's azimuth) keeps it, ties to the earlier point;
// - points without a cell (no return, ring or return index out of range, the loser of a
//   claim, a second return that found neither partner nor free bin) go to sweep.unbinned.
// sweep.input_cells gets the cell (or unbinned index) of every input point, in input order.
// Its ranges are computed from the sensor origin at zero (the points are in the sensor frame).
// DualReturnBinner does the same with buffers it keeps from cloud to cloud.
DualReturnStats binDualReturns(const DualReturnInput& input, double azimuth_resolution_deg, Sweep& sweep);

// A sentence about the points that binning could not place (rings or return indices out of
// range, points sharing a cell), or an empty string when there are none worth a warning
// (non-finite points are normal, REP-117). The node warns with it, the Python bindings put it
// in stats["warnings"].
std::string describeUnbinned(const DualReturnStats& stats);

class DualReturnBinner
{
public:
  DualReturnStats bin(const DualReturnInput& input, double azimuth_resolution_deg, Sweep& sweep);

private:
  enum class Kind : std::uint8_t;
  struct Claim
  {
    std::int64_t cell = -1;
    int echo = 0;
    double score = 0.0;
  };
  std::vector<Kind> kinds_;
  std::vector<double> azimuths_;
  std::vector<std::int32_t> owner_[2];
  std::vector<Claim> claims_;
  std::vector<std::size_t> unpaired_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
