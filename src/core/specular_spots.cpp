#include "ohm_mirror_detector3d/core/specular_spots.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "ohm_mirror_detector3d/core/median.h"

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// The window's median is taken over at most about this many of its returns (every k-th row and
// column): enough for a median, and a wide window on a fine grid (the Ouster's 35 columns) costs
// no more than a narrow one.
constexpr std::size_t kWindowSamples = 64;
// Seeds must be at least this share of min_brightness_ratio times the sweep's median single
// return: a cheap test that spares the window's median to the many local maxima of noise on
// diffuse surfaces. A quarter leaves the window's own test to decide down to windows four times
// darker than the sweep's median.
constexpr float kSweepMedianShare = 0.25f;
// Sample of single returns for the sweep's median.
constexpr std::size_t kSweepSamples = 4096;
// A spot whose returns spread along a line (their second moment across it below this share of
// the one along it) is a line of beams, not a surface: no plane to be perpendicular to.
constexpr double kMinAspect = 0.01;
// Returns farther from the spot's plane than this (RMS) [m]: no plane. Above every family's
// range noise (1-3 cm).
constexpr double kMaxPlaneRms = 0.03;

// Calls visit(n) for the beams of the 3 x 3 block around beam b on a rows x cols grid (b too).
template <typename Visit>
void forEachAround(std::size_t b, std::size_t rows, std::size_t cols, Visit visit)
{
  const std::size_t row = b / cols;
  const std::size_t col = b % cols;
  for (std::size_t r = row > 0 ? row - 1 : 0; r <= std::min(rows - 1, row + 1); ++r)
    for (std::size_t c = col > 0 ? col - 1 : 0; c <= std::min(cols - 1, col + 1); ++c)
      visit(r * cols + c);
}

}  // namespace

SpecularSpots::SpecularSpots(const SpecularSpotConfig& config) : config_(config)
{
}

bool SpecularSpots::single(const SweepLabels& labels, std::size_t beam)
{
  const Label second = labels.echoes[1][beam];
  return labels.echoes[0][beam] == Label::unchecked && (second == Label::unchecked || second == Label::nanPoint);
}

std::size_t SpecularSpots::apply(const Sweep& sweep, const SweepSampling& sampling,
                                 const Eigen::Vector3f& sensor_origin, SweepLabels& labels)
{
  const std::size_t rows = sweep.rows;
  const std::size_t cols = sweep.cols;
  const std::size_t beams = sweep.beamCount();
  // Forget the last sweep's spots (only the beams they touched: clearing every beam's marks cost
  // as much as the rest of the stage on a sweep without spots).
  if (state_.size() != beams)
  {
    state_.assign(beams, 0);
    in_spot_.assign(beams, 0);
  }
  else
  {
    for (const std::uint32_t b : touched_)
    {
      state_[b] = 0;
      in_spot_[b] = 0;
    }
  }
  touched_.clear();
  if (!config_.enabled || !sweep.has_intensity || !sampling.hasGrid() || sampling.rows != rows ||
      sampling.cols != cols || !(sampling.row_step > 0.0) || !(sampling.col_step > 0.0) || beams == 0)
    return 0;

  // Intensity x range^2 of a single return: a beam the echo comparison left alone (no second
  // echo of its own, or one within its threshold), first echo unchecked; NaN for any other beam.
  // Computed where it is looked at: a pass storing it for every beam cost 1.7 ms of a 1080 x 400
  // sweep, mostly for beams no spot is near.
  const std::vector<float>& ranges = sweep.echoes[0].ranges;
  const std::vector<float>& intensities = sweep.echoes[0].intensities;
  if (intensities.size() < beams || ranges.size() < beams)
    return 0;
  const auto brightness = [&](std::size_t b) {
    const float range = ranges[b];
    const float intensity = intensities[b];
    if (!single(labels, b) || !(range > 0.0f) || !(intensity > 0.0f) || !std::isfinite(intensity))
      return std::numeric_limits<float>::quiet_NaN();
    return intensity * range * range;
  };
  window_.clear();
  const std::size_t sweep_stride = std::max<std::size_t>(1, beams / kSweepSamples);
  for (std::size_t b = 0; b < beams; b += sweep_stride)
  {
    const float q = brightness(b);
    if (std::isfinite(q))
      window_.push_back(q);
  }
  if (window_.size() < config_.min_points)
    return 0;
  const float ratio = static_cast<float>(config_.min_brightness_ratio);
  const float sweep_median = medianInPlace(window_);
  const float seed_floor = kSweepMedianShare * ratio * sweep_median;

  const std::size_t half_rows = static_cast<std::size_t>(std::lround(config_.window / sampling.row_step));
  const std::size_t half_cols = static_cast<std::size_t>(std::lround(config_.window / sampling.col_step));
  const std::size_t window_beams = (2 * half_rows + 1) * (2 * half_cols + 1);
  const std::size_t stride = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(window_beams) / kWindowSamples))));
  std::size_t labelled = 0;
  for (std::size_t seed = 0; seed < beams; ++seed)
  {
    // The cheap test first (no labels): most beams are far below the floor.
    if (!(intensities[seed] * ranges[seed] * ranges[seed] >= seed_floor) || state_[seed] != 0)
      continue;
    const float bright = brightness(seed);
    if (!(bright >= seed_floor))
      continue;
    // A local maximum among its eight neighbours.
    bool maximum = true;
    forEachAround(seed, rows, cols, [&](std::size_t n) { maximum = maximum && !(brightness(n) > bright); });
    if (!maximum)
      continue;
    const std::size_t row = seed / cols;
    const std::size_t col = seed % cols;
    // The median single return of the window around it.
    // Where most of the window returned no single return (a window to the sky larger than it),
    // the spot's own returns would be its median: the sweep's median single return stands in.
    window_.clear();
    std::size_t looked_at = 0;
    const std::size_t r0 = row >= half_rows ? row - half_rows : 0;
    const std::size_t c0 = col >= half_cols ? col - half_cols : 0;
    for (std::size_t r = r0; r <= std::min(rows - 1, row + half_rows); r += stride)
      for (std::size_t c = c0; c <= std::min(cols - 1, col + half_cols); c += stride)
      {
        ++looked_at;
        const float q = brightness(r * cols + c);
        if (std::isfinite(q))
          window_.push_back(q);
      }
    const float reference = 2 * window_.size() >= looked_at ? medianInPlace(window_) : sweep_median;
    const float threshold = ratio * reference;
    if (!(bright >= threshold))
      continue;

    // The spot: the seed's connected single returns at least that bright.
    spot_.clear();
    const auto take = [this](std::size_t n) {
      state_[n] = 2;
      spot_.push_back(static_cast<std::uint32_t>(n));
      touched_.push_back(static_cast<std::uint32_t>(n));
    };
    take(seed);
    for (std::size_t k = 0; k < spot_.size(); ++k)
      forEachAround(spot_[k], rows, cols, [&](std::size_t n) {
        if (state_[n] == 0 && brightness(n) >= threshold)
          take(n);
      });
    const std::optional<SpotPlane> plane =
        spot_.size() >= config_.min_points ?
            plausible(sweep, labels, sensor_origin, seed, std::max<std::size_t>(1, half_rows),
                      std::max<std::size_t>(1, half_cols)) :
            std::nullopt;
    bool keep = plane.has_value();
    if (keep)
    {
      // The spot's rim: the single returns next to it on its plane. Only the brightest share of
      // the beam comes back from the spot's centre; around it the same surface returns dimmer
      // echoes (a beam straddling the spot's edge), and without them a spot on a coarse grid
      // (three rings of a 32-ring lidar) is too thin for an object.
      const std::size_t core_size = spot_.size();
      bool touches_surface = false;
      for (std::size_t k = 0; k < core_size; ++k)
        forEachAround(spot_[k], rows, cols, [&](std::size_t n) {
          // Next to the echo comparison's surface echoes, the spot is part of a surface the
          // double echoes found already (or of what lies behind one: a pane's reflection).
          touches_surface = touches_surface || labels.echoes[0][n] == Label::errorSurface ||
                            labels.echoes[1][n] == Label::errorSurface;
          const Eigen::Vector3f& p = sweep.echoes[0].points[n];
          if (state_[n] == 0 && single(labels, n) && p.allFinite() &&
              std::fabs(plane->normal.dot(p.cast<double>() - plane->point)) <= kMaxPlaneRms)
            take(n);
        });
      keep = !touches_surface;
    }
    for (const std::uint32_t b : spot_)
    {
      state_[b] = 1;
      if (keep)
      {
        labels.echoes[0][b] = Label::errorSurface;
        in_spot_[b] = 1;
      }
    }
    labelled += keep ? spot_.size() : 0;
  }
  return labelled;
}

std::size_t SpecularSpots::typeOpenSpots(std::vector<ReflectiveObject>& objects) const
{
  std::size_t typed = 0;
  for (ReflectiveObject& object : objects)
  {
    if (object.type != ObjectType::unknown || object.evidence.phantom_points > 0 || object.surface_inliers.empty())
      continue;
    std::size_t from_spots = 0;
    for (const PointRef& ref : object.surface_inliers)
      from_spots += ref.echo == 0 && ref.beam < in_spot_.size() && in_spot_[ref.beam] != 0 ? 1 : 0;
    if (2 * from_spots < object.surface_inliers.size())
      continue;
    object.type = ObjectType::glass;
    object.evidence.typed_as_open_spot = true;
    ++typed;
  }
  return typed;
}

std::optional<SpecularSpots::SpotPlane> SpecularSpots::plausible(const Sweep& sweep, const SweepLabels& labels,
                                                                 const Eigen::Vector3f& sensor_origin,
                                                                 std::size_t brightest, std::size_t band_rows,
                                                                 std::size_t band_cols) const
{
  const std::vector<Eigen::Vector3f>& points = sweep.echoes[0].points;
  const std::size_t rows = sweep.rows;
  const std::size_t cols = sweep.cols;
  // Plane of the spot.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const std::uint32_t b : spot_)
    mean += points[b].cast<double>();
  mean /= static_cast<double>(spot_.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  std::size_t r_min = rows, r_max = 0, c_min = cols, c_max = 0;
  for (const std::uint32_t b : spot_)
  {
    const Eigen::Vector3d d = points[b].cast<double>() - mean;
    covariance += d * d.transpose();
    r_min = std::min<std::size_t>(r_min, b / cols);
    r_max = std::max<std::size_t>(r_max, b / cols);
    c_min = std::min<std::size_t>(c_min, b % cols);
    c_max = std::max<std::size_t>(c_max, b % cols);
  }
  covariance /= static_cast<double>(spot_.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  const Eigen::Vector3d moments = solver.eigenvalues();  // ascending
  if (!(moments[1] >= kMinAspect * moments[2]) || !(moments[0] <= kMaxPlaneRms * kMaxPlaneRms))
    return std::nullopt;
  const Eigen::Vector3d normal = solver.eigenvectors().col(0);
  const Eigen::Vector3d beam = (points[brightest] - sensor_origin).cast<double>().normalized();
  if (!(std::fabs(normal.dot(beam)) >= std::cos(config_.max_incidence)))
    return std::nullopt;

  // The band around the spot's box on the grid: rays that went through the plane, returning
  // nothing or from beyond it. (The spot's own dimmer returns around it, and the wall or frame
  // the pane sits in, lie on the plane and count as closed.)
  Eigen::Vector3d towards_sensor = normal;
  if (towards_sensor.dot(sensor_origin.cast<double>() - mean) < 0.0)
    towards_sensor = -towards_sensor;
  std::size_t band = 0, open = 0;
  const std::size_t r0 = r_min >= band_rows ? r_min - band_rows : 0;
  const std::size_t c0 = c_min >= band_cols ? c_min - band_cols : 0;
  for (std::size_t r = r0; r <= std::min(rows - 1, r_max + band_rows); ++r)
    for (std::size_t c = c0; c <= std::min(cols - 1, c_max + band_cols); ++c)
    {
      if (r >= r_min && r <= r_max && c >= c_min && c <= c_max)
        continue;
      const std::size_t b = r * cols + c;
      ++band;
      bool any = false, beyond = false;
      for (int echo = 0; echo < 2; ++echo)
      {
        const Eigen::Vector3f& p = sweep.echoes[echo].points[b];
        if (labels.echoes[echo][b] == Label::nanPoint || !p.allFinite())
          continue;
        any = true;
        beyond = beyond || towards_sensor.dot(p.cast<double>() - mean) < -config_.open_depth;
      }
      open += !any || beyond ? 1 : 0;
    }
  if (!(band > 0 && static_cast<double>(open) >= config_.min_open_share * static_cast<double>(band)))
    return std::nullopt;
  return SpotPlane{ mean, normal };
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
