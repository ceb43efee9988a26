#include "ohm_mirror_detector3d/core/dual_return.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
constexpr double kPi = 3.14159265358979323846;
// A point this close to the origin is a driver's "no return" (zeros), not a measurement.
constexpr float kOriginEpsilon = 1e-6f;
constexpr std::int32_t kNone = -1;
// The azimuth step is read from this many rings at most, each with at least this many first
// returns; gaps below kSameAzimuthDeg are two returns of one firing.
constexpr std::size_t kStepRings = 8;
constexpr std::size_t kMinRingReturns = 16;
constexpr double kSameAzimuthDeg = 1e-4;
// See estimateAzimuthStepDeg: an eighth of the rotation seen still gets its step.
constexpr double kMaxColumnsPerReturn = 8.0;

// Signed difference a - b of two azimuths in [0, 360), in [-180, 180).
double azimuthDifference(double a, double b)
{
  double d = a - b;
  if (d >= 180.0)
    d -= 360.0;
  else if (d < -180.0)
    d += 360.0;
  return d;
}

// Azimuth of p in [0, 360) degrees, counter-clockwise from +x.
double azimuthOf(const Eigen::Vector3f& p)
{
  double azimuth = std::atan2(static_cast<double>(p.y()), static_cast<double>(p.x())) * 180.0 / kPi;
  if (azimuth < 0.0)
    azimuth += 360.0;
  return azimuth;
}

bool isReturn(const Eigen::Vector3f& p)
{
  return p.allFinite() && p.squaredNorm() >= kOriginEpsilon * kOriginEpsilon;
}

int returnBase(const DualReturnInput& input)
{
  for (std::size_t i = 0; i < input.size(); ++i)
    if (input.returns[i] == 0)
      return 0;
  return 1;
}
}  // namespace

std::string validateAzimuthResolution(double degrees)
{
  if (degrees == kAzimuthStepFromCloud ||
      (std::isfinite(degrees) && degrees >= kMinAzimuthResolutionDeg && degrees <= kMaxAzimuthResolutionDeg))
    return "";
  std::ostringstream message;
  message << "azimuth_resolution_deg = " << degrees << " is out of range: allowed " << kMinAzimuthResolutionDeg
          << " .. " << kMaxAzimuthResolutionDeg
          << " [deg], the azimuth step of the lidar (e.g. 0.17578125 for 2048 columns, 0.2 for a Velodyne at 10 Hz), "
             "or 0 (or not given) to work it out from each cloud";
  return message.str();
}

std::size_t azimuthBins(double degrees)
{
  return static_cast<std::size_t>(std::max(1.0, std::round(360.0 / degrees)));
}

double estimateAzimuthStepDeg(const DualReturnInput& input)
{
  const std::size_t n = input.size();
  const int base = returnBase(input);
  std::vector<std::size_t> counts;
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::int64_t ring = input.rings[i];
    if (input.returns[i] != base || ring < 0 || ring >= kMaxRings || !isReturn(input.points.points[i]))
      continue;
    if (static_cast<std::size_t>(ring) >= counts.size())
      counts.resize(static_cast<std::size_t>(ring) + 1, 0);
    ++counts[static_cast<std::size_t>(ring)];
  }
  std::vector<std::size_t> rings;
  for (std::size_t r = 0; r < counts.size(); ++r)
    if (counts[r] >= kMinRingReturns)
      rings.push_back(r);
  if (rings.empty())
    return 0.0;
  // Rings spread over the field of view, so that one odd ring (a lidar's own housing) cannot
  // decide alone.
  std::vector<std::int32_t> slot(counts.size(), -1);
  const std::size_t chosen = std::min(kStepRings, rings.size());
  for (std::size_t k = 0; k < chosen; ++k)
    slot[rings[k * rings.size() / chosen]] = static_cast<std::int32_t>(k);
  std::vector<std::vector<double>> azimuths(chosen);
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::int64_t ring = input.rings[i];
    if (input.returns[i] != base || ring < 0 || static_cast<std::size_t>(ring) >= slot.size() ||
        slot[static_cast<std::size_t>(ring)] < 0 || !isReturn(input.points.points[i]))
      continue;
    azimuths[static_cast<std::size_t>(slot[static_cast<std::size_t>(ring)])].push_back(
        azimuthOf(input.points.points[i]));
  }
  std::vector<double> gaps;
  for (std::vector<double>& ring : azimuths)
  {
    std::sort(ring.begin(), ring.end());
    for (std::size_t k = 0; k < ring.size(); ++k)
    {
      const double gap = k + 1 < ring.size() ? ring[k + 1] - ring[k] : ring.front() + 360.0 - ring.back();
      if (gap > kSameAzimuthDeg)
        gaps.push_back(gap);
    }
  }
  if (gaps.empty())
    return 0.0;
  const auto middle = gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 2);
  std::nth_element(gaps.begin(), middle, gaps.end());
  // No ring needs more columns than kMaxColumnsPerReturn times its returns: returns bunched into
  // a small arc (a corrupt cloud) must not make a grid of millions of empty cells. A ring may
  // return from a small part of the rotation only: a lidar with a 120 degree field of view, or
  // one hemmed in by the robot's body or by people standing next to it (the 128-ring lidar's
  // random scene 45007: at most 816 returns in a ring of 2048 firings). Twice the returns, as
  // until stop 50, took that ring's step for 0.22 instead of 0.176 degrees, and 13341 of the
  // frame's 66779 points shared a bin with another and were lost.
  const std::size_t most = *std::max_element(counts.begin(), counts.end());
  const double finest =
      std::max(kMinAzimuthResolutionDeg, 360.0 / (kMaxColumnsPerReturn * static_cast<double>(most)));
  const double step = std::min(std::max(*middle, finest), kMaxAzimuthResolutionDeg);
  return 360.0 / static_cast<double>(azimuthBins(step));
}

enum class DualReturnBinner::Kind : std::uint8_t
{
  first,
  second,
  no_return,
  ring_out_of_range,
  return_out_of_range
};

DualReturnStats binDualReturns(const DualReturnInput& input, double azimuth_resolution_deg, Sweep& sweep)
{
  DualReturnBinner binner;
  return binner.bin(input, azimuth_resolution_deg, sweep);
}

DualReturnStats DualReturnBinner::bin(const DualReturnInput& input, double azimuth_resolution_deg, Sweep& sweep)
{
  DualReturnStats stats;
  const std::size_t n = input.size();
  stats.points = n;
  stats.azimuth_from_cloud = azimuth_resolution_deg == kAzimuthStepFromCloud;
  const double resolution = stats.azimuth_from_cloud ? estimateAzimuthStepDeg(input) : azimuth_resolution_deg;
  const std::size_t cols = resolution > 0.0 ? azimuthBins(resolution) : 1;
  const double step = 360.0 / static_cast<double>(cols);
  stats.azimuth_resolution_deg = step;
  stats.return_base = returnBase(input);

  // Classify every point: which echo, its azimuth and bin, or why it has no cell.
  std::vector<Kind>& kinds = kinds_;
  std::vector<double>& azimuths = azimuths_;
  kinds.resize(n);
  azimuths.assign(n, 0.0);
  std::int64_t max_ring = -1;
  for (std::size_t i = 0; i < n; ++i)
  {
    const Eigen::Vector3f& p = input.points.points[i];
    const std::int64_t echo = input.returns[i] - stats.return_base;
    const std::int64_t ring = input.rings[i];
    if (echo != 0 && echo != 1)
      kinds[i] = Kind::return_out_of_range;
    else if (ring < 0 || ring >= kMaxRings)
      kinds[i] = Kind::ring_out_of_range;
    else if (!isReturn(p))
      kinds[i] = Kind::no_return;
    else
    {
      kinds[i] = echo == 0 ? Kind::first : Kind::second;
      azimuths[i] = azimuthOf(p);
      max_ring = std::max(max_ring, ring);
    }
  }

  const std::size_t rows = static_cast<std::size_t>(max_ring + 1);
  const std::size_t cells = rows * cols;
  auto binOf = [&](std::size_t i) {
    return static_cast<std::int64_t>(std::llround(azimuths[i] / step)) % static_cast<std::int64_t>(cols);
  };
  auto cellOf = [&](std::int64_t ring, std::int64_t bin) { return ring * static_cast<std::int64_t>(cols) + bin; };

  // Owners of each cell and echo, and the claims of every point.
  std::vector<std::int32_t>* owner = owner_;
  owner[0].assign(cells, kNone);
  owner[1].assign(cells, kNone);
  std::vector<Claim>& claims = claims_;
  claims.assign(n, Claim());
  auto claim = [&](std::size_t i, std::int64_t cell, int echo, double score) {
    claims[i] = Claim{ cell, echo, score };
    std::int32_t& current = owner[echo][static_cast<std::size_t>(cell)];
    // Ties go to the earlier point: points are visited in input order.
    if (current == kNone || score < claims[static_cast<std::size_t>(current)].score)
      current = static_cast<std::int32_t>(i);
  };

  // First returns: their own bin.
  for (std::size_t i = 0; i < n; ++i)
  {
    if (kinds[i] != Kind::first)
      continue;
    const std::int64_t bin = binOf(i);
    claim(i, cellOf(input.rings[i], bin), 0,
          std::abs(azimuthDifference(azimuths[i], static_cast<double>(bin) * step)));
  }
  // Second returns: the nearest first return of the ring within half a bin, among the
  // winners of the neighbouring bins (a partner within half a bin lies in one of them).
  std::vector<std::size_t>& unpaired = unpaired_;
  unpaired.clear();
  for (std::size_t i = 0; i < n; ++i)
  {
    if (kinds[i] != Kind::second)
      continue;
    const std::int64_t ring = input.rings[i];
    const std::int64_t bin = binOf(i);
    std::int64_t best_cell = -1;
    double best = 0.5 * step;
    for (std::int64_t offset = -1; offset <= 1; ++offset)
    {
      const std::int64_t b = (bin + offset + static_cast<std::int64_t>(cols)) % static_cast<std::int64_t>(cols);
      const std::int64_t cell = cellOf(ring, b);
      const std::int32_t partner = owner[0][static_cast<std::size_t>(cell)];
      if (partner == kNone)
        continue;
      const double d = std::abs(azimuthDifference(azimuths[i], azimuths[static_cast<std::size_t>(partner)]));
      if (d <= best)
      {
        best = d;
        best_cell = cell;
      }
    }
    if (best_cell >= 0)
      claim(i, best_cell, 1, best);
    else
      unpaired.push_back(i);
  }
  // A second return without a partner is the only return of its beam: echo 0 of its own
  // bin, unless a first return holds that bin (then it has no cell).
  for (std::size_t i : unpaired)
  {
    const std::int64_t bin = binOf(i);
    const std::int64_t cell = cellOf(input.rings[i], bin);
    const std::int32_t current = owner[0][static_cast<std::size_t>(cell)];
    if (current != kNone && kinds[static_cast<std::size_t>(current)] == Kind::first)
    {
      claims[i] = Claim{ cell, 0, std::numeric_limits<double>::infinity() };  // loses
      continue;
    }
    claim(i, cell, 0, std::abs(azimuthDifference(azimuths[i], static_cast<double>(bin) * step)));
  }

  // Fill the sweep.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  sweep.resize(rows, cols);
  sweep.has_intensity = input.has_intensity;
  for (EchoCloud& echo : sweep.echoes)
  {
    std::fill(echo.points.begin(), echo.points.end(), Eigen::Vector3f::Constant(nan));
    std::fill(echo.intensities.begin(), echo.intensities.end(), nan);
  }
  sweep.input_cells.resize(n);
  sweep.unbinned.points.clear();
  sweep.unbinned.intensities.clear();
  sweep.unbinned.ranges.clear();
  for (std::size_t i = 0; i < n; ++i)
  {
    const Eigen::Vector3f& p = input.points.points[i];
    const float intensity = input.points.intensities[i];
    const Claim& c = claims[i];
    const bool placed = (kinds[i] == Kind::first || kinds[i] == Kind::second) &&
                        owner[c.echo][static_cast<std::size_t>(c.cell)] == static_cast<std::int32_t>(i);
    if (placed)
    {
      sweep.echoes[static_cast<std::size_t>(c.echo)].points[static_cast<std::size_t>(c.cell)] = p;
      sweep.echoes[static_cast<std::size_t>(c.echo)].intensities[static_cast<std::size_t>(c.cell)] = intensity;
      sweep.input_cells[i] = PointRef{ static_cast<std::uint32_t>(c.cell), static_cast<std::uint8_t>(c.echo) };
      ++stats.binned;
      continue;
    }
    switch (kinds[i])
    {
      case Kind::no_return: ++stats.no_return; break;
      case Kind::ring_out_of_range: ++stats.ring_out_of_range; break;
      case Kind::return_out_of_range: ++stats.return_out_of_range; break;
      default: ++stats.duplicates;
    }
    sweep.input_cells[i] = PointRef{ static_cast<std::uint32_t>(sweep.unbinned.points.size()), PointRef::kNoCell };
    sweep.unbinned.points.push_back(p);
    sweep.unbinned.intensities.push_back(intensity);
    sweep.unbinned.ranges.push_back(p.allFinite() ? p.norm() : nan);
  }
  for (std::size_t cell = 0; cell < cells; ++cell)
  {
    const bool first = owner[0][cell] != kNone;
    const bool second = owner[1][cell] != kNone;
    stats.paired_beams += first && second;
    stats.single_beams += first != second;
  }
  sweep.computeRanges(Eigen::Vector3f::Zero());
  return stats;
}

std::string describeUnbinned(const DualReturnStats& stats)
{
  if (stats.ring_out_of_range + stats.return_out_of_range + stats.duplicates == 0)
    return "";
  std::ostringstream text;
  text << "labelled nanPoint (in no grid cell) " << stats.unbinned() << " of " << stats.points << " points:";
  if (stats.ring_out_of_range > 0)
    text << " " << stats.ring_out_of_range << " with a ring outside 0.." << kMaxRings - 1 << ";";
  if (stats.return_out_of_range > 0)
    text << " " << stats.return_out_of_range << " with a return index other than " << stats.return_base << " or "
         << stats.return_base + 1 << " (only the first two returns are compared);";
  if (stats.duplicates > 0)
  {
    text << " " << stats.duplicates << " sharing a ring and azimuth bin with another point of the same return";
    if (stats.azimuth_from_cloud)
      text << " (bins of " << stats.azimuth_resolution_deg
           << " deg, the azimuth step worked out from the cloud: its firings are not evenly spaced; give "
              "azimuth_resolution_deg);";
    else
      text << " (is azimuth_resolution_deg = " << stats.azimuth_resolution_deg
           << " coarser than the lidar's azimuth step? Leave it unset to work it out from the cloud);";
  }
  if (stats.no_return > 0)
    text << " " << stats.no_return << " without a return (non-finite or at the origin)";
  return text.str();
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
