#include "ohm_mirror_detector3d/core/reflection_evidence.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "ohm_mirror_detector3d/core/median.h"
#include "ohm_mirror_detector3d/core/parallel.h"

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// Directions are binned on a cube map: the face of a direction's largest coordinate, and on it
// the other two divided by that one (gnomonic coordinates in [-1, 1]), in square cells. A cell
// is as wide as the search window at a face centre and narrower towards the edges (the window
// then spans more cells); no trigonometry per point.
constexpr std::uint32_t kMaxCellsPerSide = 512;

// The window around a direction: this many of the sweep's coarser angular steps, so that the
// nearest return on every side of the direction is inside it.
constexpr float kWindowSteps = 1.25f;

// Neighbouring returns along a row or a column are looked for this many beams ahead (a
// dual-return grid finer than the lidar's azimuth step leaves empty cells between them), in a
// sample of about this many beams per axis.
constexpr std::size_t kNeighbourSearch = 8;
constexpr std::size_t kStepSamplesPerAxis = 64;
// A sweep without columns (one row: an unorganised cloud) has its neighbouring scan line
// somewhere further along the row: the nearest return among this many beams beyond the row
// neighbours is taken for it (a scan line of up to 4096 beams).
constexpr std::size_t kMaxLineLag = 4096;
// Steps outside this range are no sweep's sampling (a repeated return, a jump across the grid).
constexpr float kMinStep = 1e-5f;
constexpr float kMaxStep = 10.0f * static_cast<float>(M_PI) / 180.0f;



// A return x lies in the window around a unit direction d when its offset (x.e1, x.e2) / depth
// (depth = x.d) is within radius r: |x|^2 - depth^2 <= r^2 depth^2. Returns with |x|^2 above
// depth^2 (1 + r^2 (1 + kWindowSlack)) are skipped before that exact test: the slack (1 % of
// r^2) is far above the float rounding of either side (1e-7 relative to |x|^2, r^2 >= 1e-10),
// so no return the exact test keeps is skipped.
constexpr float kWindowSlack = 0.01f;
// The angle of a return that passes the window's test above is below radius * (1 + kWindowSlack / 2)
// (the window's radius is a tangent, above the angle); its unit vector differs from the window's
// direction by less than that angle in every coordinate. With a margin for the float rounding:
constexpr float kFaceReach = 1.05f;

// A surface seen at up to 80 degrees from its normal changes its range by up to tan(80 deg)
// times range times angle: returns that differ by more than that lie on different surfaces.
constexpr float kMaxGrazingSlope = 5.67f;

// A surface whose normal is within this of being perpendicular to the plane (sin of 15 deg)
// is taken to map onto itself under the reflection: the normal of a few returns a beam step
// apart is no more precise than that.
constexpr float kSelfSymmetricNormal = 0.2588f;
// A neighbourhood is a surface (and its normal trustworthy) when its covariance is not a line
// and is flat (ratios of ascending eigenvalues).
constexpr float kMinSurfaceSpread = 0.05f;
constexpr float kMaxSurfaceThickness = 0.25f;
constexpr std::size_t kMinSurfaceCandidates = 4;
// The normal of the surface a reflected point lands on decides whether the reflection maps that
// surface onto itself (a floor, a side wall: then a real point behind the plane would land there
// too). The returns of the test's window, a beam step or two apart, give it to no better than
// tens of degrees where the range noise is a centimetre (a floor at 2 m seen by a 128-ring lidar:
// 0.35 deg rings, 1.2 cm apart): measured on random scenes 2000-2017 (Ouster), 95 % of the
// transmitted points behind glass that were taken for phantoms had landed on a surface within
// 15 deg of perpendicular to the pane. So the normal comes from the returns within a ball of at
// least kNormalBallRadius, and kNormalBallSpacings beam spacings, around the point seen (a
// sample of at most kNormalSamples of them), the window no wider than kMaxNormalWindow.
constexpr float kNormalBallRadius = 0.15f;  // [m]
constexpr float kNormalBallSpacings = 4.0f;
constexpr float kMaxNormalWindow = 0.1f;  // [rad]
constexpr std::size_t kNormalSamples = 96;
constexpr std::size_t kMinNormalReturns = 8;
// Incidence cosines below this (grazing) are taken as this in the Lambert correction of
// landingIntensityShare: a surface seen edge-on says nothing about its brightness.
constexpr float kMinLambertCosine = 0.05f;

// The normal of a neighbourhood from its covariance (float or double), zero when the
// neighbourhood is no surface: a line, or not flat (kMinSurfaceSpread, kMaxSurfaceThickness).
template <typename Matrix>
Eigen::Vector3f flatSurfaceNormal(const Matrix& covariance)
{
  Eigen::SelfAdjointEigenSolver<Matrix> solver;
  solver.computeDirect(covariance);
  const auto spread_values = solver.eigenvalues();  // ascending
  if (!(spread_values[1] >= kMinSurfaceSpread * spread_values[2]) ||
      !(spread_values[0] <= kMaxSurfaceThickness * spread_values[1]))
    return Eigen::Vector3f::Zero();
  return solver.eigenvectors().col(0).template cast<float>();
}

// The sweep's echo separation (see ReflectionEvidence::echoSeparation): the kSeparationRank-th
// smallest distance between the two echoes of a beam, from at least kMinSeparationSamples double
// echoes. Not a quantile: in a sweep full of a mirror's phantoms (random scene 4001 of the
// rotating Hokuyo: 25556 double echoes, 0.3 m resolved) even the 1 % quantile is a phantom's
// distance behind the mirror (1.1 m); the few smallest are the sensor's (mixed pixels at depth
// edges), and the rank keeps one odd return from deciding.
constexpr std::size_t kSeparationRank = 3;
constexpr std::size_t kMinSeparationSamples = 100;

// Side by side (build's threads), no range of returns smaller than this.
constexpr std::size_t kMinReturnsPerPart = 16384;

float median(std::vector<float>& values)
{
  return values.empty() ? 0.0f : medianInPlace(values);
}

float angleBetween(const Eigen::Vector3f& a, const Eigen::Vector3f& b)
{
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Keys of the index: the cube-map cell of a point's direction from the origin (the points are
// written relative to it), numbered (face * n + u) * n + v.
struct DirectionCells
{
  float inverse_cell;
  std::uint32_t n;

  std::uint64_t key(float x, float y, float z) const
  {
    const float ax = std::fabs(x), ay = std::fabs(y), az = std::fabs(z);
    int face;
    float major, u, v;
    if (ax >= ay && ax >= az)
    {
      face = x > 0.0f ? 1 : 0;
      major = ax;
      u = y;
      v = z;
    }
    else if (ay >= az)
    {
      face = y > 0.0f ? 3 : 2;
      major = ay;
      u = z;
      v = x;
    }
    else
    {
      face = z > 0.0f ? 5 : 4;
      major = az;
      u = x;
      v = y;
    }
    const float inverse_major = major > 0.0f ? 1.0f / major : 0.0f;
    return cell(face, u * inverse_major, v * inverse_major);
  }

  std::uint32_t axisCell(float coordinate) const
  {
    const float c = (coordinate + 1.0f) * inverse_cell;
    return static_cast<std::uint32_t>(std::min(std::max(c, 0.0f), static_cast<float>(n - 1)));
  }
  std::uint64_t cell(int face, float u, float v) const
  {
    return (static_cast<std::uint64_t>(face) * n + axisCell(u)) * n + axisCell(v);
  }
};

// Axes (major, u, v) of each face, as DirectionCells::key numbers them.
constexpr int kFaceAxes[6][3] = { { 0, 1, 2 }, { 0, 1, 2 }, { 1, 2, 0 }, { 1, 2, 0 }, { 2, 0, 1 }, { 2, 0, 1 } };
}  // namespace

const char* reflectionOutcomeName(ReflectionOutcome outcome)
{
  switch (outcome)
  {
    case ReflectionOutcome::noReturn: return "noReturn";
    case ReflectionOutcome::occluded: return "occluded";
    case ReflectionOutcome::phantom: return "phantom";
    case ReflectionOutcome::ambiguous: return "ambiguous";
    case ReflectionOutcome::transmitted: return "transmitted";
  }
  return "invalid-outcome";
}

void ReflectionEvidence::build(const Sweep& sweep, const SweepLabels& labels, const Eigen::Vector3f& sensor_origin,
                               int threads)
{
  origin_ = sensor_origin;
  step_ = 0.0f;
  echo_separation_ = 0.0f;
  index_.reservePoints(0);
  index_.setPointCount(0);
  const std::size_t beams = sweep.beamCount();
  const std::vector<Eigen::Vector3f>& first = sweep.echoes[0].points;
  auto usable = [&](std::size_t i) { return labels.echoes[0][i] != Label::nanPoint && first[i].allFinite(); };

  // The sweep's angular steps: along a row (the next return within a few columns) and along a
  // column (the next within a few rows; in a sweep of one row, the nearest return beyond the
  // row neighbours), medians over a sample of beams.
  row_angles_.clear();
  column_angles_.clear();
  const std::size_t row_stride = std::max<std::size_t>(1, sweep.rows / kStepSamplesPerAxis);
  const std::size_t column_stride = std::max<std::size_t>(1, sweep.cols / kStepSamplesPerAxis);
  for (std::size_t r = 0; r < sweep.rows; r += row_stride)
    for (std::size_t c = 0; c < sweep.cols; c += column_stride)
    {
      const std::size_t i = r * sweep.cols + c;
      if (!usable(i))
        continue;
      const Eigen::Vector3f from = first[i] - origin_;
      for (std::size_t k = 1; k <= kNeighbourSearch && c + k < sweep.cols; ++k)
        if (usable(i + k))
        {
          row_angles_.push_back(angleBetween(from, first[i + k] - origin_));
          break;
        }
      for (std::size_t k = 1; k <= kNeighbourSearch && r + k < sweep.rows; ++k)
        if (usable(i + k * sweep.cols))
        {
          column_angles_.push_back(angleBetween(from, first[i + k * sweep.cols] - origin_));
          break;
        }
    }
  if (column_angles_.empty())
    for (std::size_t c = 0; c < sweep.cols; c += column_stride)
    {
      if (!usable(c))
        continue;
      // The largest cosine, as cos^2 of the returns in the same half space (no square root per return).
      const Eigen::Vector3f from = (first[c] - origin_).normalized();
      float best_squared_cosine = -1.0f;
      const std::size_t end = std::min(sweep.cols, c + kNeighbourSearch + kMaxLineLag);
      for (std::size_t j = c + kNeighbourSearch + 1; j < end; ++j)
      {
        if (!usable(j))
          continue;
        const Eigen::Vector3f x = first[j] - origin_;
        const float along = from.dot(x);
        if (along > 0.0f)
          best_squared_cosine = std::max(best_squared_cosine, along * along / x.squaredNorm());
      }
      if (best_squared_cosine > 0.0f)
        column_angles_.push_back(std::acos(std::min(1.0f, std::sqrt(best_squared_cosine))));
    }
  auto implausible = [](float a) { return !(a >= kMinStep && a <= kMaxStep); };
  row_angles_.erase(std::remove_if(row_angles_.begin(), row_angles_.end(), implausible), row_angles_.end());
  column_angles_.erase(std::remove_if(column_angles_.begin(), column_angles_.end(), implausible), column_angles_.end());
  step_ = std::max(median(row_angles_), median(column_angles_));
  if (!(step_ > 0.0f))
  {
    step_ = 0.0f;
    return;
  }
  radius_ = kWindowSteps * step_;
  cells_per_side_ = std::min(kMaxCellsPerSide, static_cast<std::uint32_t>(std::ceil(2.0f / radius_)));
  cell_ = 2.0f / static_cast<float>(cells_per_side_);
  inverse_cell_ = 1.0f / cell_;

  index_.reservePoints(2 * beams);
  float* xs = index_.pointX();
  float* ys = index_.pointY();
  float* zs = index_.pointZ();
  std::uint32_t* ids = index_.pointId();
  // Each return's intensity in the order it is indexed (its id is that position): the index
  // sorts the ids along with the points, so a return's intensity is one lookup by its id. An id
  // that numbered the beam instead had to be divided into echo and beam for every return: that
  // loop took 2.1 ms of the 1080 x 400 sweep's 12 ms build.
  indexed_intensities_.resize(2 * beams);
  // One pass on one thread: ranges side by side (count, then write) took longer on two threads
  // than this on one (1080 x 400: 5.9 against 4.7 ms, medians of 15): it is memory-bound.
  std::size_t count = 0;
  // The echo separation on the way: the kSeparationRank smallest distances between a beam's two
  // echoes (ascending), over the double echoes whose first echo is indexed too.
  std::array<float, kSeparationRank> smallest;
  smallest.fill(std::numeric_limits<float>::infinity());
  std::size_t double_echoes = 0;
  for (std::size_t k = 0; k < 2; ++k)
  {
    const std::vector<Eigen::Vector3f>& points = sweep.echoes[k].points;
    const std::vector<float>& intensities = sweep.echoes[k].intensities;
    for (std::size_t i = 0; i < beams; ++i)
    {
      if (labels.echoes[k][i] == Label::nanPoint || !points[i].allFinite() || (k == 1 && points[i] == first[i]))
        continue;
      const Eigen::Vector3f x = points[i] - origin_;
      xs[count] = x.x();
      ys[count] = x.y();
      zs[count] = x.z();
      ids[count] = static_cast<std::uint32_t>(count);
      indexed_intensities_[count] = i < intensities.size() ? intensities[i] : std::numeric_limits<float>::quiet_NaN();
      ++count;
      if (k == 1 && usable(i))
      {
        ++double_echoes;
        float separation = std::fabs(x.norm() - (first[i] - origin_).norm());
        for (float& s : smallest)
          if (separation < s)
            std::swap(separation, s);
      }
    }
  }
  if (double_echoes >= kMinSeparationSamples)
    echo_separation_ = smallest.back();
  index_.setPointCount(count);
  SpatialIndex::Options options;
  options.lookup = true;
  options.dense_cells = 6 * static_cast<std::size_t>(cells_per_side_) * cells_per_side_;
  options.threads = threads;
  index_.build(DirectionCells{ inverse_cell_, cells_per_side_ }, options);
  const float* sorted_x = index_.sortedX();
  const float* sorted_y = index_.sortedY();
  const float* sorted_z = index_.sortedZ();
  const std::uint32_t* sorted_ids = index_.sortedId();
  squared_ranges_.resize(count);
  intensities_.resize(count);
  const std::size_t sorted_parts = partsFor(count, threads, kMinReturnsPerPart);
  runTasks(sorted_parts, threads, [&](std::size_t part, std::size_t) {
    for (std::size_t j = partBegin(count, sorted_parts, part); j < partBegin(count, sorted_parts, part + 1); ++j)
    {
      squared_ranges_[j] = sorted_x[j] * sorted_x[j] + sorted_y[j] * sorted_y[j] + sorted_z[j] * sorted_z[j];
      intensities_[j] = indexed_intensities_[sorted_ids[j]];
    }
  });
}

template <typename Run>
void ReflectionEvidence::forEachCellRun(const Eigen::Vector3f& direction, float radius, Run run) const
{
  const DirectionCells cells{ inverse_cell_, cells_per_side_ };
  // A face holds the directions whose coordinate along its axis is the largest; a direction
  // within the window differs from the window's direction by less than kFaceReach * radius in
  // every coordinate (of unit vectors), so a face whose axis coordinate falls short of another
  // by more than twice that holds none of the window's returns. Without this test a face almost
  // perpendicular to the direction had a huge window in its gnomonic coordinates (below), clamped
  // to a strip across the face: on the 64 x 600 dual-return frame 154 of 22227 faces the tests'
  // windows looked at held 1.14 of the 1.89 million returns they looked at.
  const float reach = 2.0f * kFaceReach * radius * direction.norm();
  // Every face the window reaches: in gnomonic coordinates (u, v) of a face, an angle `radius`
  // around the direction spans about radius * (1 + u^2 + v^2) / sqrt(1 + v^2) along u (and
  // likewise along v); a tenth more covers the curvature over the window.
  for (int face = 0; face < 6; ++face)
  {
    const int* axes = kFaceAxes[face];
    const float major = (face & 1) ? direction[axes[0]] : -direction[axes[0]];
    if (!(major > 0.0f) ||
        major + reach < std::max(std::fabs(direction[axes[1]]), std::fabs(direction[axes[2]])))
      continue;
    const float u = direction[axes[1]] / major;
    const float v = direction[axes[2]] / major;
    const float stretch = 1.1f * radius * (1.0f + u * u + v * v);
    const float half_u = stretch / std::sqrt(1.0f + v * v);
    const float half_v = stretch / std::sqrt(1.0f + u * u);
    if (u - half_u > 1.0f || u + half_u < -1.0f || v - half_v > 1.0f || v + half_v < -1.0f)
      continue;
    const std::uint32_t u_low = cells.axisCell(u - half_u), u_high = cells.axisCell(u + half_u);
    const std::uint32_t v_low = cells.axisCell(v - half_v), v_high = cells.axisCell(v + half_v);
    for (std::uint32_t cu = u_low; cu <= u_high; ++cu)
    {
      // The cells v_low .. v_high of this row are consecutive keys: one range of points.
      const std::uint64_t row = (static_cast<std::uint64_t>(face) * cells_per_side_ + cu) * cells_per_side_;
      const SpatialIndex::Range points = index_.cellRunPoints(row + v_low, row + v_high);
      run(points.begin, points.end);
    }
  }
}

template <typename Visit>
void ReflectionEvidence::forEachNear(const Eigen::Vector3f& direction, const Eigen::Vector3f& unit, float radius,
                                     std::size_t max_visits, Visit visit) const
{
  // Everything the loop reads, in locals: through references and members the compiler reloaded
  // them for every return (a visit's writes might have changed them, as far as it could tell).
  const float* xs = index_.sortedX();
  const float* ys = index_.sortedY();
  const float* zs = index_.sortedZ();
  const float* squared_ranges = squared_ranges_.data();
  const float ux = unit.x(), uy = unit.y(), uz = unit.z();
  const float cosine_bound = 1.0f + radius * radius * (1.0f + kWindowSlack);
  std::size_t stride = 1;
  if (max_visits > 0)
  {
    std::size_t total = 0;
    forEachCellRun(direction, radius, [&](std::uint32_t begin, std::uint32_t end) { total += end - begin; });
    stride = std::max<std::size_t>(1, total / max_visits);
  }
  // Every stride-th return of the cells' runs taken together.
  std::size_t position = 0;
  forEachCellRun(direction, radius, [&](std::uint32_t begin, std::uint32_t end) {
    const std::size_t first = (stride - position % stride) % stride;
    position += end - begin;
    for (std::size_t j = begin + first; j < end; j += stride)
    {
      const float depth = xs[j] * ux + ys[j] * uy + zs[j] * uz;
      if (depth > 0.0f && squared_ranges[j] <= depth * depth * cosine_bound)
        visit(Eigen::Vector3f(xs[j], ys[j], zs[j]), j);
    }
  });
}

Eigen::Vector3f ReflectionEvidence::surfaceNormalAround(const Eigen::Vector3f& seen_point, float seen) const
{
  const float window = std::min(kMaxNormalWindow, std::max(radius_, kNormalBallRadius / seen));
  const float ball = std::min(std::max(kNormalBallRadius, kNormalBallSpacings * step_ * seen), window * seen);
  const float ball_squared = ball * ball;
  const Eigen::Vector3f unit = seen_point / seen;
  std::size_t count = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  forEachNear(seen_point, unit, window, kNormalSamples, [&](const Eigen::Vector3f& x, std::size_t) {
    if ((x - seen_point).squaredNorm() > ball_squared)
      return;
    // Relative to the point seen, so that the moments stay well conditioned.
    const Eigen::Vector3d d = (x - seen_point).cast<double>();
    sum += d;
    second += d * d.transpose();
    ++count;
  });
  if (count < kMinNormalReturns)
    return Eigen::Vector3f::Zero();
  const Eigen::Vector3d mean = sum / static_cast<double>(count);
  return flatSurfaceNormal(Eigen::Matrix3d(second / static_cast<double>(count) - mean * mean.transpose()));
}

ReflectionEvidence::Sighting ReflectionEvidence::sight(const Eigen::Vector3f& q, float range, float tol) const
{
  Sighting sighting;
  sighting.along = q / range;
  const Eigen::Vector3f& along = sighting.along;
  const Eigen::Vector3f helper = std::fabs(along.z()) < 0.9f ? Eigen::Vector3f::UnitZ() : Eigen::Vector3f::UnitX();
  sighting.e1 = along.cross(helper).normalized();
  sighting.e2 = along.cross(sighting.e1);
  // The basis and the count in locals while the window is gathered: as members of `sighting`,
  // which the candidates are written into, the compiler reloaded and stored them for every one.
  const Eigen::Vector3f along_local = along;
  const Eigen::Vector3f e1 = sighting.e1;
  const Eigen::Vector3f e2 = sighting.e2;

  // The returns within the window, in q's tangent basis; the nearest in each quadrant around
  // q's direction are the corners of the patch of range image that q's direction falls in.
  std::array<Candidate, kMaxCandidates>& candidates = sighting.candidates;
  std::size_t count = 0;
  std::array<int, 4> nearest = { -1, -1, -1, -1 };
  std::array<float, 4> nearest_offset = { 0.0f, 0.0f, 0.0f, 0.0f };
  const float radius_squared = radius_ * radius_;
  forEachNear(q, along_local, radius_, 0, [&](const Eigen::Vector3f& x, std::size_t j) {
    const float depth = x.dot(along_local);
    if (!(depth > 0.0f) || count == kMaxCandidates)
      return;
    const float inverse_depth = 1.0f / depth;
    const float a = x.dot(e1) * inverse_depth;
    const float b = x.dot(e2) * inverse_depth;
    const float offset = a * a + b * b;
    if (offset > radius_squared)
      return;
    const int quadrant = (a >= 0.0f ? 1 : 0) + (b >= 0.0f ? 2 : 0);
    if (nearest[quadrant] < 0 || offset < nearest_offset[quadrant])
    {
      nearest[quadrant] = static_cast<int>(count);
      nearest_offset[quadrant] = offset;
    }
    candidates[count++] = Candidate{ a, b, depth, x.norm(), x, j };
  });
  sighting.count = count;
  std::array<int, 4>& corners = sighting.corners;
  std::size_t& corner_count = sighting.corner_count;
  for (int k : nearest)
    if (k >= 0)
      corners[corner_count++] = k;
  if (corner_count == 0)
    return sighting;

  // One surface when the corners' ranges differ by no more than a surface seen at up to 80
  // degrees could across their spread of directions.
  float low = std::numeric_limits<float>::infinity(), high = -low, widest = 0.0f;
  int closest = corners[0];
  for (std::size_t k = 0; k < corner_count; ++k)
  {
    const Candidate& c = candidates[static_cast<std::size_t>(corners[k])];
    low = std::min(low, c.range);
    high = std::max(high, c.range);
    const float offset = c.a * c.a + c.b * c.b;
    widest = std::max(widest, offset);
    const Candidate& best = candidates[static_cast<std::size_t>(closest)];
    if (offset < best.a * best.a + best.b * best.b)
      closest = corners[k];
  }
  sighting.closest = closest;
  const float spread = 2.0f * std::sqrt(widest) + step_;
  sighting.one_surface = high - low <= tol + kMaxGrazingSlope * range * spread;

  // On one surface: the range in q's direction from the plane through the corners. For a plane
  // the reciprocal depth along q's direction is exactly linear in (a, b), so a least-squares fit
  // of 1 / depth = w0 + wa a + wb b over the corners gives it (1 / w0) even at grazing incidence.
  if (sighting.one_surface && corner_count >= 3)
  {
    Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Zero();
    Eigen::Vector3d right = Eigen::Vector3d::Zero();
    const double scale = 1.0 / radius_;  // (a, b) in units of the window: a well-scaled system
    for (std::size_t k = 0; k < corner_count; ++k)
    {
      const Candidate& c = candidates[static_cast<std::size_t>(corners[k])];
      const Eigen::Vector3d row(1.0, c.a * scale, c.b * scale);
      normal_matrix += row * row.transpose();
      right += row / static_cast<double>(c.depth);
    }
    if (std::fabs(normal_matrix.determinant()) > 1e-3)
    {
      sighting.fit = normal_matrix.inverse() * right;
      sighting.fit.tail<2>() *= scale;
      sighting.fitted = sighting.fit[0] > 0.0;
    }
  }
  if (sighting.one_surface)
    sighting.seen = sighting.fitted ? static_cast<float>(1.0 / sighting.fit[0]) :
                                      candidates[static_cast<std::size_t>(closest)].range;
  return sighting;
}

Eigen::Vector3f ReflectionEvidence::Sighting::fittedNormal() const
{
  return (static_cast<float>(fit[0]) * along + static_cast<float>(fit[1]) * e1 + static_cast<float>(fit[2]) * e2)
      .normalized();
}

bool ReflectionEvidence::pathPiercesSeenSurface(const Eigen::Vector3f& from, const Eigen::Vector3f& q,
                                                const Sighting& at_q, const LandingTolerance& tolerance,
                                                float behind) const
{
  // The surface seen in front of q, locally the plane through the corners' fit; the path from
  // the crossing (from) to q meets that plane at c, when it does between the two.
  if (!at_q.fitted)
    return false;
  const Eigen::Vector3f surface_normal = at_q.fittedNormal();
  const Eigen::Vector3f seen_point = at_q.seen * at_q.along;
  const float side_from = surface_normal.dot(from - seen_point);
  const float side_q = surface_normal.dot(q - seen_point);
  if (!(side_from * side_q < 0.0f))
    return false;
  const Eigen::Vector3f c = from + (side_from / (side_from - side_q)) * (q - from);
  const float range = c.norm();
  if (!(range > 0.0f))
    return false;
  const float tol = tolerance.at(range, behind);
  // Too near either end, c is the pane (the wall it sits in) or q's own surface.
  if ((c - from).norm() <= tol || (c - q).norm() <= tol)
    return false;
  const Sighting at_c = sight(c, range, tol);
  return at_c.one_surface && std::fabs(at_c.seen - range) <= tol;
}

bool ReflectionEvidence::landsClear(const Eigen::Vector4f& plane, const Eigen::Vector3f& p, float beyond) const
{
  if (step_ == 0.0f || index_.pointCount() == 0)
    return false;
  const Eigen::Vector3f normal = plane.head<3>();
  const Eigen::Vector3f q = p - 2.0f * (normal.dot(p) + plane[3]) * normal - origin_;
  const float range = q.norm();
  if (!(range > 0.0f))
    return false;
  const Eigen::Vector3f unit = q / range;
  const float squared_tangent = std::tan(radius_) * std::tan(radius_);
  const float limit = (range + beyond) * (range + beyond);
  bool clear = true;
  forEachNear(q, unit, radius_, 0, [&](const Eigen::Vector3f& x, std::size_t j) {
    if (!clear || squared_ranges_[j] >= limit)
      return;
    const float depth = x.dot(unit);
    if (depth > 0.0f && (x - depth * unit).squaredNorm() <= squared_tangent * depth * depth &&
        normal.dot(x + origin_) + plane[3] > beyond)
      clear = false;
  });
  return clear;
}

ReflectionTest ReflectionEvidence::test(const Eigen::Vector4f& plane, const Eigen::Vector3f& p,
                                        const LandingTolerance& tolerance, const ReflectionTestOptions& options) const
{
  ReflectionTest result;
  result.range_difference = std::numeric_limits<float>::quiet_NaN();
  if (step_ == 0.0f || index_.pointCount() == 0)
    return result;
  const Eigen::Vector3f normal = plane.head<3>();
  const float side = normal.dot(p) + plane[3];
  const Eigen::Vector3f q = p - 2.0f * side * normal - origin_;
  const float range = q.norm();
  if (!(range > 0.0f))
    return result;
  const float behind = -side;
  const float tol = tolerance.at(range, behind);
  const Sighting sighting = sight(q, range, tol);
  if (sighting.corner_count == 0)
    return result;
  const Eigen::Vector3f& along = sighting.along;
  const std::array<Candidate, kMaxCandidates>& candidates = sighting.candidates;
  const std::size_t count = sighting.count;
  const std::size_t corner_count = sighting.corner_count;
  const std::array<int, 4>& corners = sighting.corners;
  const int closest = sighting.closest;

  float seen = 0.0f;  // range of what the sensor saw in q's direction
  if (sighting.one_surface)
  {
    seen = sighting.seen;
    const float difference = seen - range;
    result.range_difference = difference;
    result.outcome = difference > tol  ? ReflectionOutcome::transmitted :
                     difference < -tol ? ReflectionOutcome::occluded :
                                         ReflectionOutcome::phantom;
    // Occluded: a surface was seen in front of q. The light of a phantom came along the path
    // from where the beam met the plane to q, so that path cannot pierce a surface the sensor
    // saw; if it does, p is real, seen through the plane (a pane in a wall: what lies behind it,
    // reflected, lies beyond the room's walls).
    if (options.check_path && result.outcome == ReflectionOutcome::occluded)
    {
      const Eigen::Vector3f to_p = p - origin_;
      const float origin_side = normal.dot(origin_) + plane[3];
      const Eigen::Vector3f crossing = (origin_side / (origin_side - side)) * to_p;
      if (origin_side > 0.0f && pathPiercesSeenSurface(crossing, q, sighting, tolerance, behind))
      {
        result.outcome = ReflectionOutcome::transmitted;
        result.path_blocked = true;
      }
    }
  }
  else
  {
    // A depth edge runs through the patch: q is on the far side of it when every corner is
    // beyond q (seen through), on a surface when a corner is at q's range, else behind the near
    // side (not seen).
    bool all_beyond = true;
    float best = std::numeric_limits<float>::infinity();
    for (std::size_t k = 0; k < corner_count; ++k)
    {
      const float difference = candidates[static_cast<std::size_t>(corners[k])].range - range;
      all_beyond = all_beyond && difference > tol;
      if (std::fabs(difference) < std::fabs(best))
        best = difference;
    }
    result.range_difference = best;
    result.outcome = all_beyond            ? ReflectionOutcome::transmitted :
                     std::fabs(best) <= tol ? ReflectionOutcome::phantom :
                                              ReflectionOutcome::occluded;
    seen = range + best;
  }
  if (result.outcome != ReflectionOutcome::phantom)
    return result;
  result.seen_intensity = intensities_[candidates[static_cast<std::size_t>(closest)].index];
  result.seen_range = seen;

  // q lies on a surface. If that surface is perpendicular to the plane, the reflection maps it
  // onto itself: a real point on it behind the plane (the floor seen through glass) would land
  // here as well as a phantom of it (the floor seen in a mirror). Its normal comes from the
  // corners' fit (the plane through the returns around q's direction), else from the returns
  // around q on it (their covariance; slower, so only without a fit); without either its
  // orientation is unknown and so is the answer. With wide_normal, a surface that these few
  // returns make out not to map onto itself is looked at again in a ball of returns around the
  // point seen (see kNormalBallRadius), whose normal decides when the ball holds one flat
  // surface: a noisy normal mostly errs that way (a floor is nearly perpendicular to the plane,
  // and noise can only tilt it away), and the second look costs only the points that would
  // otherwise be phantoms.
  Eigen::Vector3f surface_normal = Eigen::Vector3f::Zero();
  if (sighting.fitted)
    surface_normal = sighting.fittedNormal();
  else
  {
    auto onSurface = [&](const Candidate& c) {
      return std::fabs(c.range - seen) <= tol + kMaxGrazingSlope * seen * std::sqrt(c.a * c.a + c.b * c.b);
    };
    Eigen::Vector3f mean = Eigen::Vector3f::Zero();
    std::size_t on_surface = 0;
    for (std::size_t k = 0; k < count; ++k)
      if (onSurface(candidates[k]))
      {
        mean += candidates[k].point;
        ++on_surface;
      }
    if (on_surface >= kMinSurfaceCandidates)
    {
      mean /= static_cast<float>(on_surface);
      Eigen::Matrix3f covariance = Eigen::Matrix3f::Zero();
      for (std::size_t k = 0; k < count; ++k)
        if (onSurface(candidates[k]))
        {
          const Eigen::Vector3f d = candidates[k].point - mean;
          covariance += d * d.transpose();
        }
      surface_normal = flatSurfaceNormal(covariance);
    }
  }
  // Exactly: a real point on that surface behind the plane lands within tol when twice its
  // distance behind times |n_surface . n| is below tol; the normal's own uncertainty widens it.
  const float symmetric = std::max(kSelfSymmetricNormal, behind > 0.0f ? tol / (2.0f * behind) : 1.0f);
  if (options.wide_normal && !surface_normal.isZero() && std::fabs(surface_normal.dot(normal)) > symmetric)
  {
    const Eigen::Vector3f ball_normal = surfaceNormalAround(seen * along, seen);
    if (!ball_normal.isZero())
      surface_normal = ball_normal;
  }
  result.surface_normal = surface_normal;
  if (surface_normal.isZero() || std::fabs(surface_normal.dot(normal)) <= symmetric)
    result.outcome = ReflectionOutcome::ambiguous;
  return result;
}

float landingIntensityShare(const Eigen::Vector3f& p, const Eigen::Vector3f& reflected, float intensity,
                            const ReflectionTest& test, const Eigen::Vector3f& origin)
{
  const float none = std::numeric_limits<float>::quiet_NaN();
  if (!(intensity > 0.0f) || !(test.seen_intensity > 0.0f) || !(test.seen_range > 0.0f) ||
      test.surface_normal.isZero())
    return none;
  const Eigen::Vector3f to_p = p - origin;
  const Eigen::Vector3f to_q = reflected - origin;
  const float range_p = to_p.norm(), range_q = to_q.norm();
  if (!(range_p > 0.0f) || !(range_q > 0.0f))
    return none;
  // The reflected path arrives at q along p's direction reflected across the plane, at the
  // angle to the surface's normal that p's direction makes with the normal's mirror image. That
  // is the angle to the normal itself for a surface parallel or perpendicular to the plane (a
  // wall facing it; a floor), where nearly every phantom lands; the normal's mirror image would
  // turn its noise into an error of twice the normal's tilt times the plane's obliquity
  // (measured: 3 % of a floor seen through glass taken for its reflection).
  const float cos_path = std::max(kMinLambertCosine, std::fabs(test.surface_normal.dot(to_p) / range_p));
  const float cos_seen = std::max(kMinLambertCosine, std::fabs(test.surface_normal.dot(to_q) / range_q));
  const float seen = test.seen_intensity * test.seen_range * test.seen_range / cos_seen;
  const float own = intensity * range_p * range_p / cos_path;
  return own / seen;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
