#include "ohm_mirror_detector3d/core/sweep_sampling.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "ohm_mirror_detector3d/core/median.h"
#include "ohm_mirror_detector3d/core/spatial_index.h"

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// Beams looked at per estimate: a median needs no more than a few thousand, whatever the size
// of the sweep (a 1080 x 1000 sweep costs the same as a 64 x 600 one).
constexpr std::size_t kGridSamples = 4096;
constexpr std::size_t kPeriodSamples = 192;
constexpr std::size_t kNeighbourSamples = 512;
// Fewer pairs than this tell nothing.
constexpr std::size_t kMinPairs = 8;
// The step to beam i + P must cross the scan direction (the step to i + 1): |cos| below this.
constexpr float kMaxPeriodCosine = 0.5f;
// A period's neighbour lies at most this many consecutive steps (and this angle) away: farther
// beams are no neighbours, whatever divides the sweep.
constexpr double kMaxPeriodStepRatio = 20.0;
constexpr double kMaxPeriodAngle = 0.35;  // rad, 20 deg
// Consecutive beams of a scan line are at most this many times the nearest-neighbour angle apart.
constexpr double kMaxLineStepRatio = 2.0;
// The last column neighbours the first when they are at most this many column steps apart.
constexpr double kMaxWrapStepRatio = 1.5;

// The k-th of a deterministic sample of [0, n): Fibonacci hashing spreads it over the range
// without falling into step with the grid's columns.
std::size_t sampleIndex(std::size_t k, std::size_t n)
{
  return static_cast<std::size_t>((static_cast<std::uint64_t>(k) * 0x9E3779B97F4A7C15ULL) % n);
}

// Angle between two unit vectors, accurate for the small angles between neighbouring beams.
float angleBetween(const Eigen::Vector3f& a, const Eigen::Vector3f& b)
{
  const float chord = std::min((a - b).norm(), 2.0f);
  return 2.0f * std::asin(0.5f * chord);
}

}  // namespace

Eigen::Vector3f SamplingEstimator::direction(std::size_t b) const
{
  const Eigen::Vector3f& p1 = sweep_->echoes[0].points[b];
  const Eigen::Vector3f& p = p1.allFinite() ? p1 : sweep_->echoes[1].points[b];
  const Eigen::Vector3f d = p - origin_;
  const float length = d.norm();
  return p.allFinite() && length > 0.0f ? Eigen::Vector3f(d / length)
                                        : Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
}

template <typename Usable>
double SamplingEstimator::medianAngle(std::size_t offset, Usable usable)
{
  const std::size_t n = beams_;
  angles_.clear();
  if (offset == 0 || offset >= n)
    return 0.0;
  const std::size_t samples = std::min(n, kGridSamples);
  for (std::size_t k = 0; k < samples; ++k)
  {
    const std::size_t b = samples == n ? k : sampleIndex(k, n);
    if (b + offset >= n || !usable(b))
      continue;
    const Eigen::Vector3f a = direction(b);
    const Eigen::Vector3f c = direction(b + offset);
    if (a.allFinite() && c.allFinite())
      angles_.push_back(angleBetween(a, c));
  }
  return angles_.size() >= kMinPairs ? static_cast<double>(medianInPlace(angles_)) : 0.0;
}

void SamplingEstimator::estimateGrid(std::size_t rows, std::size_t cols, bool folded)
{
  SweepSampling& s = sampling_;
  s.layout = SweepSampling::Layout::grid;
  s.rows = rows;
  s.cols = cols;
  s.folded = folded;
  s.col_step = medianAngle(1, [cols](std::size_t b) { return b % cols + 1 < cols; });
  s.row_step = medianAngle(cols, [cols, rows](std::size_t b) { return b / cols + 1 < rows; });
  if (s.row_step <= 0.0)
    s.row_step = s.col_step;
  if (s.col_step <= 0.0)
    s.col_step = s.row_step;
  if (s.col_step <= 0.0)
  {
    s.layout = SweepSampling::Layout::unknown;
    return;
  }
  // The first and last column of every row: a full turn when they are neighbours.
  angles_.clear();
  if (cols >= 3)
    for (std::size_t r = 0; r < rows; ++r)
    {
      const Eigen::Vector3f first = direction(r * cols);
      const Eigen::Vector3f last = direction(r * cols + cols - 1);
      if (first.allFinite() && last.allFinite())
        angles_.push_back(angleBetween(first, last));
    }
  s.wraps = angles_.size() >= 3 && medianInPlace(angles_) <= kMaxWrapStepRatio * s.col_step;
  // The first and the last row, one of them reversed: a 2D scanner turned half a rotation looks
  // along its first scan line again at its end, from the other side.
  angles_.clear();
  if (rows >= 3)
    for (std::size_t c = 0; c < cols; ++c)
    {
      const Eigen::Vector3f first = direction(c);
      const Eigen::Vector3f last = direction((rows - 1) * cols + cols - 1 - c);
      if (first.allFinite() && last.allFinite())
        angles_.push_back(angleBetween(first, last));
    }
  s.flips_at_seam = angles_.size() >= 3 && medianInPlace(angles_) <= kMaxWrapStepRatio * s.row_step;
}

bool SamplingEstimator::foldAtPeriod(std::size_t beams)
{
  const double consecutive = medianAngle(1, [](std::size_t) { return true; });
  if (consecutive <= 0.0)
    return false;
  std::size_t best_period = 0;
  float best_angle = std::numeric_limits<float>::infinity();
  const std::size_t samples = std::min(beams, kPeriodSamples);
  auto tryPeriod = [&](std::size_t period) {
    if (period < 2 || period > beams / 2)
      return;
    angles_.clear();
    cosines_.clear();
    for (std::size_t k = 0; k < samples; ++k)
    {
      const std::size_t b = sampleIndex(k, beams - period);
      const Eigen::Vector3f d = direction(b);
      const Eigen::Vector3f next = direction(b + 1);
      const Eigen::Vector3f across = direction(b + period);
      if (!d.allFinite() || !next.allFinite() || !across.allFinite())
        continue;
      const Eigen::Vector3f along_step = next - d;
      const Eigen::Vector3f across_step = across - d;
      const float norms = along_step.norm() * across_step.norm();
      if (!(norms > 0.0f))
        continue;
      angles_.push_back(angleBetween(d, across));
      cosines_.push_back(std::fabs(along_step.dot(across_step)) / norms);
    }
    if (angles_.size() < kMinPairs || medianInPlace(cosines_) >= kMaxPeriodCosine)
      return;
    const float angle = medianInPlace(angles_);
    if (angle < best_angle)
    {
      best_angle = angle;
      best_period = period;
    }
  };
  for (std::size_t divisor = 1; divisor * divisor <= beams; ++divisor)
  {
    if (beams % divisor != 0)
      continue;
    tryPeriod(divisor);
    if (divisor * divisor != beams)
      tryPeriod(beams / divisor);
  }
  if (best_period == 0 || best_angle > kMaxPeriodStepRatio * consecutive || best_angle > kMaxPeriodAngle)
    return false;
  estimateGrid(beams / best_period, best_period, true);
  return true;
}

double SamplingEstimator::nearestNeighbourAngle()
{
  SpatialIndex index;
  index.reservePoints(beams_);
  std::size_t m = 0;
  for (std::size_t b = 0; b < beams_; ++b)
  {
    const Eigen::Vector3f d = direction(b);
    if (!d.allFinite())
      continue;
    index.pointX()[m] = d.x();
    index.pointY()[m] = d.y();
    index.pointZ()[m] = d.z();
    index.pointId()[m] = static_cast<std::uint32_t>(b);
    ++m;
  }
  index.setPointCount(m);
  if (m < kMinPairs)
    return 0.0;
  // The mean spacing of m directions spread over the whole sphere: real sweeps cover less of it,
  // so their nearest neighbours lie within a cell or the next.
  const double cell = std::sqrt(4.0 * 3.14159265358979323846 / static_cast<double>(m));
  const AnchoredGrid grid(Eigen::Vector3f::Zero(), cell, 1);
  SpatialIndex::Options options;
  options.lookup = true;
  index.build(grid, options);
  const float* xs = index.sortedX();
  const float* ys = index.sortedY();
  const float* zs = index.sortedZ();
  angles_.clear();
  const std::size_t samples = std::min(m, kNeighbourSamples);
  std::size_t seen = 0;
  for (std::size_t k = 0; k < samples; ++k)
  {
    const std::size_t b = sampleIndex(k, beams_);
    // The sample walks the beams; skip the ones without a return.
    const Eigen::Vector3f d = direction(b);
    if (!d.allFinite())
      continue;
    ++seen;
    const std::uint64_t key = grid.key(d.x(), d.y(), d.z());
    float best = std::numeric_limits<float>::infinity();
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
      {
        const std::uint64_t column =
            static_cast<std::uint64_t>(static_cast<std::int64_t>(key) + dx * cell_key::kStepX + dy * cell_key::kStepY);
        const SpatialIndex::Range range = index.columnPoints(column);
        for (std::uint32_t i = range.begin; i < range.end; ++i)
        {
          const float ex = xs[i] - d.x(), ey = ys[i] - d.y(), ez = zs[i] - d.z();
          const float chord2 = ex * ex + ey * ey + ez * ez;
          if (chord2 > 0.0f && chord2 < best)
            best = chord2;
        }
      }
    if (std::isfinite(best))
      angles_.push_back(2.0f * std::asin(std::min(0.5f * std::sqrt(best), 1.0f)));
  }
  return angles_.size() >= kMinPairs && 2 * angles_.size() >= seen ? static_cast<double>(medianInPlace(angles_)) : 0.0;
}

const SweepSampling& SamplingEstimator::estimate(const Sweep& sweep, const Eigen::Vector3f& sensor_origin)
{
  sampling_ = SweepSampling();
  sweep_ = &sweep;
  origin_ = sensor_origin;
  beams_ = sweep.beamCount();
  const std::size_t beams = sweep.beamCount();
  if (beams < 2)
    return sampling_;
  if (sweep.rows > 1 && sweep.cols > 1)
  {
    estimateGrid(sweep.rows, sweep.cols, false);
    return sampling_;
  }
  if (foldAtPeriod(beams))
    return sampling_;
  // One row of `beams`, the same angular step along and across it.
  auto oneRow = [&](SweepSampling::Layout layout, double step) -> const SweepSampling& {
    sampling_.layout = layout;
    sampling_.rows = 1;
    sampling_.cols = beams;
    sampling_.row_step = step;
    sampling_.col_step = step;
    return sampling_;
  };
  const double consecutive = medianAngle(1, [](std::size_t) { return true; });
  const double nearest = nearestNeighbourAngle();
  if (consecutive > 0.0 && (nearest <= 0.0 || consecutive <= kMaxLineStepRatio * nearest))
    return oneRow(SweepSampling::Layout::grid, consecutive);
  if (nearest > 0.0)
    return oneRow(SweepSampling::Layout::unordered, nearest);
  return sampling_;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
