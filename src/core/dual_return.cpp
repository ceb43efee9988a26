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

// Signed difference a - b of two azimuths in degrees, in [-180, 180).
double azimuthDifference(double a, double b)
{
  double d = std::fmod(a - b + 180.0, 360.0);
  if (d < 0.0)
    d += 360.0;
  return d - 180.0;
}

// Where a point wants to go and how well it fits there (smaller is better).
struct Claim
{
  std::int64_t cell = -1;
  int echo = 0;
  double score = 0.0;
};
}  // namespace

std::string validateAzimuthResolution(double degrees)
{
  if (std::isfinite(degrees) && degrees >= kMinAzimuthResolutionDeg && degrees <= kMaxAzimuthResolutionDeg)
    return "";
  std::ostringstream message;
  message << "azimuth_resolution_deg = " << degrees << " is out of range: allowed " << kMinAzimuthResolutionDeg
          << " .. " << kMaxAzimuthResolutionDeg
          << " [deg], the azimuth step of the lidar (e.g. 0.17578125 for 2048 columns, 0.2 for a Velodyne at 10 Hz)";
  return message.str();
}

std::size_t azimuthBins(double degrees)
{
  return static_cast<std::size_t>(std::max(1.0, std::round(360.0 / degrees)));
}

DualReturnStats binDualReturns(const DualReturnInput& input, double azimuth_resolution_deg, Sweep& sweep)
{
  DualReturnStats stats;
  const std::size_t n = input.size();
  stats.points = n;
  const std::size_t cols = azimuthBins(azimuth_resolution_deg);
  const double step = 360.0 / static_cast<double>(cols);

  for (std::size_t i = 0; i < n; ++i)
    if (input.returns[i] == 0)
    {
      stats.return_base = 0;
      break;
    }

  // Classify every point: which echo, its azimuth and bin, or why it has no cell.
  enum class Kind : std::uint8_t
  {
    first,
    second,
    no_return,
    ring_out_of_range,
    return_out_of_range
  };
  std::vector<Kind> kinds(n);
  std::vector<double> azimuths(n, 0.0);
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
    else if (!p.allFinite() || p.squaredNorm() < kOriginEpsilon * kOriginEpsilon)
      kinds[i] = Kind::no_return;
    else
    {
      kinds[i] = echo == 0 ? Kind::first : Kind::second;
      double azimuth = std::atan2(static_cast<double>(p.y()), static_cast<double>(p.x())) * 180.0 / kPi;
      if (azimuth < 0.0)
        azimuth += 360.0;
      azimuths[i] = azimuth;
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
  std::vector<std::int32_t> owner[2] = { std::vector<std::int32_t>(cells, kNone),
                                         std::vector<std::int32_t>(cells, kNone) };
  std::vector<Claim> claims(n);
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
  std::vector<std::size_t> unpaired;
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

}  // namespace core
}  // namespace ohm_mirror_detector3d
