// Bounding box of a block of consecutive beams, for the stages that skip whole blocks.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
#include <vector>

#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct BlockBox
{
  Eigen::AlignedBox3f box;   // of the finite points kept; empty (Eigen's null box) if none
  bool any_non_finite = false;  // a kept point was not finite
};

// Box of points[begin, end) for which keep(i) holds. Without a branch per point: a
// sweep's NaN points (no return) come in irregular runs, and a branch on each of them
// mispredicts often enough to cost more than the rest of the loop. x - x is 0 for a
// finite x and NaN otherwise, so a point is finite when the sum of those is 0.
template <typename Keep>
BlockBox blockBox(const Eigen::Vector3f* points, std::size_t begin, std::size_t end, Keep keep)
{
  const float inf = std::numeric_limits<float>::infinity();
  float low_x = inf, low_y = inf, low_z = inf;
  float high_x = -inf, high_y = -inf, high_z = -inf;
  std::size_t finite_count = 0;
  std::size_t kept_count = 0;
  for (std::size_t i = begin; i < end; ++i)
  {
    const float x = points[i].x();
    const float y = points[i].y();
    const float z = points[i].z();
    const bool kept = keep(i);
    const bool use = kept && ((x - x) + (y - y) + (z - z)) == 0.0f;
    kept_count += kept ? 1 : 0;
    finite_count += use ? 1 : 0;
    const float lx = use ? x : inf, ly = use ? y : inf, lz = use ? z : inf;
    const float hx = use ? x : -inf, hy = use ? y : -inf, hz = use ? z : -inf;
    low_x = lx < low_x ? lx : low_x;
    low_y = ly < low_y ? ly : low_y;
    low_z = lz < low_z ? lz : low_z;
    high_x = hx > high_x ? hx : high_x;
    high_y = hy > high_y ? hy : high_y;
    high_z = hz > high_z ? hz : high_z;
  }
  BlockBox result;
  result.any_non_finite = finite_count != kept_count;
  if (finite_count > 0)
    result.box = Eigen::AlignedBox3f(Eigen::Vector3f(low_x, low_y, low_z), Eigen::Vector3f(high_x, high_y, high_z));
  return result;
}

// The box of all finite points of each block of `block_beams` beams, per echo (echo k's block b:
// boxes[k][b]): what the stages that read a sweep block by block skip with.
using SweepBlockBoxes = std::array<std::vector<Eigen::AlignedBox3f>, 2>;

inline void sweepBlockBoxes(const Sweep& sweep, std::size_t block_beams, SweepBlockBoxes& boxes)
{
  const std::size_t beams = sweep.beamCount();
  for (std::size_t k = 0; k < 2; ++k)
  {
    boxes[k].resize((beams + block_beams - 1) / block_beams);
    const Eigen::Vector3f* points = sweep.echoes[k].points.data();
    for (std::size_t block = 0; block < boxes[k].size(); ++block)
      boxes[k][block] = blockBox(points, block * block_beams, std::min(beams, (block + 1) * block_beams),
                                 [](std::size_t) { return true; })
                            .box;
  }
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
