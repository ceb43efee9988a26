// The real scene where a mirror's phantoms may land, for the type decision: real points (seen
// in front of the plane) with nearest-neighbour queries bounded by a reach, on the spatial
// index. The queries look at the point's own cell first and otherwise at the 3 x 3 columns of
// 3 cells around it, in a fixed order, so that results (ties included) do not depend on
// anything but the points and the query.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "ohm_mirror_detector3d/core/spatial_index.h"

namespace ohm_mirror_detector3d
{
namespace core
{
class RealScene
{
public:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

  // Indexes `points` (at least one) on cells at least `reach` wide; the queries find points
  // within `reach`. Keeps its buffers from build to build.
  void build(const std::vector<Eigen::Vector3f>& points, float reach);

  const std::vector<Eigen::Vector3f>& points() const { return points_; }

  // Index of the nearest point within reach of q, or kNone; its squared distance in `squared`.
  std::uint32_t nearest(const Eigen::Vector3f& q, float& squared) const;

  // The (at most) k nearest points within reach of q as (squared distance, index).
  void nearestK(const Eigen::Vector3f& q, std::size_t k, std::vector<std::pair<float, std::uint32_t>>& out) const;

  // The surface normal of the real scene at point `index`, from its nearest neighbours within
  // reach; infinite when they do not form a surface (a line, a corner). Computed on first use:
  // only the real points that phantoms land on need one.
  const Eigen::Vector3f& surfaceNormal(std::size_t index);

private:
  // Spatial-index key of p's cell, clamped to the grid's inner cells.
  std::uint64_t key(const Eigen::Vector3f& p) const;
  // Whether q lies in one of the grid's inner cells (where key() needs no clamping).
  bool inside(const Eigen::Vector3f& q) const;

  template <typename Visit>
  void forEachColumn(const Eigen::Vector3f& q, Visit visit) const;

  std::vector<Eigen::Vector3f> points_;
  float reach_ = 0.0f;
  BoxGrid grid_;
  SpatialIndex index_;
  std::vector<Eigen::Vector3f> normals_;  // NaN: not computed yet; infinite: no surface there
  std::vector<std::pair<float, std::uint32_t>> neighbourhood_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
