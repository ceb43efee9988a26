#include "ohm_mirror_detector3d/core/real_scene.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// Most cells of the grid; a larger box gets larger cells (still correct: a cell only has to be
// at least reach wide).
constexpr std::size_t kMaxGridCells = std::size_t(1) << 20;
constexpr int kNormalNeighbours = 20;
// Shape of a real point's neighbourhood that gives a trustworthy surface normal (ratios of
// its covariance eigenvalues, ascending).
constexpr float kMinSurfaceSpread = 0.05f;
constexpr float kMaxSurfaceThickness = 0.1f;

// Keys of the index: the number of a point's cell, (x * ny + y) * nz + z, z running fastest so
// that a column of cells is a run of numbers (see RealScene::key).
struct InnerCellNumbers
{
  const BoxGrid& grid;

  std::uint64_t key(float x, float y, float z) const
  {
    const Eigen::Vector3f c = grid.coordinates(Eigen::Vector3f(x, y, z));
    // Clamped to the grid's inner cells: only query points outside the box get here with
    // out-of-range coordinates, and for them the clamped block is still a superset of the
    // points within reach (none, or those near the border).
    auto axis = [this, &c](int a) {
      return static_cast<std::uint64_t>(std::min(std::max(c[a], 1.0f), static_cast<float>(grid.cells(a) - 2)));
    };
    return (axis(0) * grid.cells(1) + axis(1)) * grid.cells(2) + axis(2);
  }
};
}  // namespace

void RealScene::build(const std::vector<Eigen::Vector3f>& points, float reach)
{
  points_ = points;
  reach_ = reach;
  Eigen::AlignedBox3f box;
  for (const Eigen::Vector3f& p : points)
    box.extend(p);
  // One spare cell on every side, so that the 3 x 3 x 3 block of any point in the box stays
  // inside the grid.
  grid_ = BoxGrid(box, reach, 1, kMaxGridCells);
  index_.reservePoints(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    index_.pointX()[i] = points[i].x();
    index_.pointY()[i] = points[i].y();
    index_.pointZ()[i] = points[i].z();
    index_.pointId()[i] = static_cast<std::uint32_t>(i);
  }
  index_.setPointCount(points.size());
  // Queried thousands of times per object: cells are looked up in a table with an entry per
  // cell rather than hashed.
  SpatialIndex::Options options;
  options.lookup = true;
  options.dense_cells = grid_.cells(0) * grid_.cells(1) * grid_.cells(2);
  index_.build(InnerCellNumbers{ grid_ }, options);
  normals_.assign(points.size(), Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
}

std::uint64_t RealScene::key(const Eigen::Vector3f& p) const
{
  return InnerCellNumbers{ grid_ }.key(p.x(), p.y(), p.z());
}

bool RealScene::inside(const Eigen::Vector3f& q) const
{
  const Eigen::Vector3f c = grid_.coordinates(q);
  return c.x() >= 1.0f && c.y() >= 1.0f && c.z() >= 1.0f && c.x() < static_cast<float>(grid_.cells(0) - 1) &&
         c.y() < static_cast<float>(grid_.cells(1) - 1) && c.z() < static_cast<float>(grid_.cells(2) - 1);
}

template <typename Visit>
void RealScene::forEachColumn(const Eigen::Vector3f& q, Visit visit) const
{
  if (points_.empty() || !q.allFinite())
    return;
  // A query further than reach outside the box has no neighbour.
  const Eigen::Vector3f c = grid_.coordinates(q);
  if (c.x() < 0.0f || c.y() < 0.0f || c.z() < 0.0f || c.x() >= static_cast<float>(grid_.cells(0)) ||
      c.y() >= static_cast<float>(grid_.cells(1)) || c.z() >= static_cast<float>(grid_.cells(2)))
    return;
  const std::int64_t centre = static_cast<std::int64_t>(key(q));
  const std::int64_t ny = static_cast<std::int64_t>(grid_.cells(1));
  const std::int64_t nz = static_cast<std::int64_t>(grid_.cells(2));
  for (std::int64_t dx = -1; dx <= 1; ++dx)
    for (std::int64_t dy = -1; dy <= 1; ++dy)
    {
      const SpatialIndex::Range column = index_.columnPoints(static_cast<std::uint64_t>(centre + (dx * ny + dy) * nz));
      visit(column.begin, column.end);
    }
}

std::uint32_t RealScene::nearest(const Eigen::Vector3f& q, float& squared) const
{
  const float* xs = index_.sortedX();
  const float* ys = index_.sortedY();
  const float* zs = index_.sortedZ();
  float best = reach_ * reach_;
  std::uint32_t found = kNone;
  // The query's own cell first: a neighbour nearer than the cell's nearest face is the
  // nearest of all (the common case once ICP has aligned the phantoms), and the other 26
  // cells need no look.
  if (!points_.empty() && q.allFinite() && inside(q))
  {
    const SpatialIndex::Range own = index_.cellPoints(key(q));
    for (std::uint32_t j = own.begin; j < own.end; ++j)
    {
      const float d = (Eigen::Vector3f(xs[j], ys[j], zs[j]) - q).squaredNorm();
      if (d <= best)
      {
        best = d;
        found = j;
      }
    }
    const Eigen::Array3f c = grid_.coordinates(q).array();
    const Eigen::Array3f fraction = c - c.floor();
    const float face = std::min(fraction.minCoeff(), (1.0f - fraction).minCoeff()) / grid_.inverseCell();
    if (found != kNone && best < face * face)
    {
      squared = best;
      return index_.sortedId()[found];
    }
  }
  forEachColumn(q, [&](std::uint32_t begin, std::uint32_t end) {
    for (std::uint32_t j = begin; j < end; ++j)
    {
      const float d = (Eigen::Vector3f(xs[j], ys[j], zs[j]) - q).squaredNorm();
      if (d <= best)
      {
        best = d;
        found = j;
      }
    }
  });
  squared = best;
  return found == kNone ? kNone : index_.sortedId()[found];
}

void RealScene::nearestK(const Eigen::Vector3f& q, std::size_t k,
                         std::vector<std::pair<float, std::uint32_t>>& out) const
{
  out.clear();
  const float* xs = index_.sortedX();
  const float* ys = index_.sortedY();
  const float* zs = index_.sortedZ();
  const std::uint32_t* ids = index_.sortedId();
  const float max_squared = reach_ * reach_;
  forEachColumn(q, [&](std::uint32_t begin, std::uint32_t end) {
    for (std::uint32_t j = begin; j < end; ++j)
    {
      const float d = (Eigen::Vector3f(xs[j], ys[j], zs[j]) - q).squaredNorm();
      if (d <= max_squared)
        out.emplace_back(d, ids[j]);
    }
  });
  if (out.size() > k)
  {
    std::nth_element(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(k), out.end());
    out.resize(k);
  }
}

const Eigen::Vector3f& RealScene::surfaceNormal(std::size_t index)
{
  Eigen::Vector3f& normal = normals_[index];
  if (normal.allFinite() || std::isinf(normal.x()))
    return normal;
  nearestK(points_[index], kNormalNeighbours, neighbourhood_);
  normal.setConstant(std::numeric_limits<float>::infinity());  // too few neighbours: no surface
  if (neighbourhood_.size() < 3)
    return normal;
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  for (const auto& n : neighbourhood_)
    centroid += points_[n.second];
  centroid /= static_cast<float>(neighbourhood_.size());
  Eigen::Matrix3f covariance = Eigen::Matrix3f::Zero();
  for (const auto& n : neighbourhood_)
  {
    const Eigen::Vector3f d = points_[n.second] - centroid;
    covariance += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> solver(covariance);
  const Eigen::Vector3f spread = solver.eigenvalues();  // ascending
  // Only a neighbourhood that is a surface gives a normal: not a line (a scan line on a wall
  // seen at a grazing angle, neighbours all along it) and flat (not a corner or an edge).
  if (spread[1] < kMinSurfaceSpread * spread[2] || spread[0] > kMaxSurfaceThickness * spread[1])
    return normal;
  normal = solver.eigenvectors().col(0);
  return normal;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
