// How a sweep samples the directions around the sensor, worked out from the sweep itself: the
// grid of beams its neighbourhood tests walk (neighbouring rows and columns) and the angle
// between neighbouring beams along both. Sensors differ by two orders of magnitude here (a
// rotating UTM-30LX-EW at 1000 scans per half rotation, a 64-ring lidar at 0.6 degrees), so
// every neighbourhood test and size limit that follows the sensor is expressed in these terms.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct SweepSampling
{
  enum class Layout
  {
    // Cell (row, col) of a rows x cols grid holds beam row * cols + col, and neighbouring
    // cells hold neighbouring beams: an organised sweep, or a 1 x N sweep folded at its scan
    // period (rows of `cols` beams), or a single scan line (rows = 1).
    grid,
    // Consecutive beams are no neighbours and no period folds them into a grid (an
    // unorganised cloud in no scan order): only the angular step is known.
    unordered,
    // Too few returns to tell (an empty or nearly empty sweep).
    unknown,
  };

  Layout layout = Layout::unknown;
  std::size_t rows = 0;
  std::size_t cols = 0;
  // The sweep was 1 x N (or N x 1) and is folded into rows of `cols` beams (its scan period).
  bool folded = false;
  // Column cols - 1 neighbours column 0 (a spinning lidar's full turn).
  bool wraps = false;
  // Row rows - 1 neighbours row 0 with the columns reversed (a 2D scanner turned half a
  // rotation: its last scan line sees along its first one, from the other side).
  bool flips_at_seam = false;
  // Median angle [rad] between a beam and the beam in the next row (same column), and in the
  // next column (same row). On a grid whose rows are too few to tell (one scan line), the row
  // step is taken equal to the column step; on an unordered sweep both are the median angle
  // to the nearest other beam.
  double row_step = 0.0;
  double col_step = 0.0;

  bool hasGrid() const { return layout == Layout::grid; }
  bool known() const { return layout != Layout::unknown; }
  // Solid angle of one beam's share of the directions [sr].
  double beamSolidAngle() const { return row_step * col_step; }
  double maxStep() const { return row_step > col_step ? row_step : col_step; }
};

// Works out a sweep's sampling from the directions of its returns (both echoes of a beam lie
// along one direction; the first finite one is used). Owns its buffers.
class SamplingEstimator
{
public:
  // The sampling of `sweep`, whose beams start at `sensor_origin` (the origin its ranges were
  // computed from). Deterministic. A 1 x N sweep is folded at the period P (a divisor of N)
  // for which beam i + P is the nearest to beam i across the scan direction (the angle between
  // the steps to i + 1 and to i + P above 60 degrees); without one it is a single scan line
  // when consecutive beams are neighbours (their angle at most twice the angle to the nearest
  // other beam), otherwise unordered.
  const SweepSampling& estimate(const Sweep& sweep, const Eigen::Vector3f& sensor_origin);

private:
  // The unit direction of beam b of the sweep being estimated (its first finite echo), NaN
  // without a return: computed when asked, since an estimate looks at a few thousand beams.
  Eigen::Vector3f direction(std::size_t b) const;
  // Median angle between beam b and beam b + offset over a deterministic sample of beams b
  // for which `usable(b)`; 0 when fewer than a handful of pairs have both directions.
  template <typename Usable>
  double medianAngle(std::size_t offset, Usable usable);
  void estimateGrid(std::size_t rows, std::size_t cols, bool folded);
  bool foldAtPeriod(std::size_t beams);
  double nearestNeighbourAngle();

  SweepSampling sampling_;
  const Sweep* sweep_ = nullptr;  // during estimate()
  Eigen::Vector3f origin_ = Eigen::Vector3f::Zero();
  std::size_t beams_ = 0;
  std::vector<float> angles_;
  std::vector<float> cosines_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
