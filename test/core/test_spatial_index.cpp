#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <vector>

#include "ohm_mirror_detector3d/core/real_scene.h"
#include "ohm_mirror_detector3d/core/spatial_index.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::AnchoredGrid;
using core::SpatialIndex;
using Eigen::Vector3f;

std::vector<Vector3f> randomPoints(std::mt19937& rng, std::size_t count, float extent)
{
  std::uniform_real_distribution<float> coordinate(-extent, extent);
  std::vector<Vector3f> points(count);
  for (Vector3f& p : points)
    p = Vector3f(coordinate(rng), coordinate(rng), coordinate(rng));
  return points;
}

void write(SpatialIndex& index, const std::vector<Vector3f>& points)
{
  index.reservePoints(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    index.pointX()[i] = points[i].x();
    index.pointY()[i] = points[i].y();
    index.pointZ()[i] = points[i].z();
    index.pointId()[i] = static_cast<std::uint32_t>(i);
  }
  index.setPointCount(points.size());
}

// Everything a build says about the points, checked against the grid that made it.
void expectGrouped(const SpatialIndex& index, const std::vector<Vector3f>& points, const AnchoredGrid& grid,
                   std::uint32_t block)
{
  std::vector<int> seen(points.size(), 0);
  for (std::size_t c = 0; c < index.cellCount(); ++c)
  {
    if (c > 0)
    {
      ASSERT_LT(index.cellKeys()[c - 1], index.cellKeys()[c]) << "cells in key order";
    }
    ASSERT_GT(index.cellSize(c), 0u);
    EXPECT_EQ(index.findCell(index.cellKeys()[c]), c);
    EXPECT_EQ(index.cellBegin(c) % block, 0u);
    std::uint32_t previous = 0;
    for (std::uint32_t j = index.cellBegin(c); j < index.cellBegin(c) + index.cellSize(c); ++j)
    {
      const std::uint32_t id = index.sortedId()[j];
      ASSERT_LT(id, points.size());
      if (j > index.cellBegin(c))
      {
        EXPECT_LT(previous, id) << "a cell keeps the order the points were written in";
      }
      previous = id;
      ++seen[id];
      EXPECT_EQ(grid.key(points[id].x(), points[id].y(), points[id].z()), index.cellKeys()[c]);
      EXPECT_EQ(index.cellOfPoint(id), c);
      EXPECT_EQ(index.sortedX()[j], points[id].x());
      const float* box = index.cellBox(c);
      EXPECT_TRUE(box[0] <= points[id].x() && points[id].x() <= box[3]);
      EXPECT_TRUE(box[1] <= points[id].y() && points[id].y() <= box[4]);
      EXPECT_TRUE(box[2] <= points[id].z() && points[id].z() <= box[5]);
    }
    for (std::uint32_t j = index.cellBegin(c) + index.cellSize(c); j < index.cellBegin(c + 1); ++j)
      EXPECT_TRUE(std::isnan(index.sortedX()[j])) << "padding is NaN";
  }
  for (std::size_t i = 0; i < points.size(); ++i)
    EXPECT_EQ(seen[i], 1) << "point " << i << " is in exactly one cell";
}

TEST(SpatialIndex, GroupsEveryPointIntoTheCellOfItsKeyInKeyOrder)
{
  std::mt19937 rng(3);
  const std::vector<Vector3f> points = randomPoints(rng, 3000, 2.0f);
  SpatialIndex index;
  write(index, points);
  const AnchoredGrid grid(points[0], 0.25, 1);
  SpatialIndex::Options options;
  options.block = 8;
  options.boxes = true;
  options.lookup = true;
  index.build(grid, options);
  EXPECT_GT(index.cellCount(), 100u);
  expectGrouped(index, points, grid, 8);
  EXPECT_EQ(index.findCell(core::cell_key::pack(0, 0, 0)), SpatialIndex::kNoCell);
}

TEST(SpatialIndex, NeighbouringCellsDifferByTheAxisSteps)
{
  const AnchoredGrid grid(Vector3f(1.0f, 2.0f, 3.0f), 0.5, 2);
  const std::uint64_t key = grid.key(1.2f, 2.2f, 3.2f);
  EXPECT_EQ(grid.key(1.7f, 2.2f, 3.2f), key + core::cell_key::kStepX);
  EXPECT_EQ(grid.key(1.2f, 1.7f, 3.2f), key - core::cell_key::kStepY);
  EXPECT_EQ(grid.key(0.2f, 2.2f, 4.2f), key - 2 * core::cell_key::kStepX + 2 * core::cell_key::kStepZ);
  // Far points are clamped to the border cells, `reach` cells inside the key range, so that
  // their neighbours' keys still do not carry into the next axis.
  const std::uint64_t far = grid.key(1e9f, 2.2f, -1e9f);
  EXPECT_EQ(far >> (2 * core::cell_key::kAxisBits), core::cell_key::kAxisMax - 2);
  EXPECT_EQ(far & core::cell_key::kAxisMax, 2u);
}

TEST(SpatialIndex, AColumnIsTheThreeCellsAlongZ)
{
  // Points in cells z = 0 .. 4 of one column (cells 1 m wide), and one in the next column.
  std::vector<Vector3f> points;
  for (int z = 0; z < 5; ++z)
    points.push_back(Vector3f(0.5f, 0.5f, 0.5f + z));
  points.push_back(Vector3f(1.5f, 0.5f, 2.5f));
  SpatialIndex index;
  write(index, points);
  const AnchoredGrid grid(Vector3f(0.5f, 0.5f, 0.5f), 1.0, 1);
  SpatialIndex::Options options;
  options.lookup = true;
  index.build(grid, options);
  const SpatialIndex::Range column = index.columnPoints(grid.key(0.5f, 0.5f, 2.5f));
  std::set<std::uint32_t> ids;
  for (std::uint32_t j = column.begin; j < column.end; ++j)
    ids.insert(index.sortedId()[j]);
  EXPECT_EQ(ids, (std::set<std::uint32_t>{ 1, 2, 3 }));
  const SpatialIndex::Range own = index.cellPoints(grid.key(0.5f, 0.5f, 2.5f));
  ASSERT_EQ(own.end - own.begin, 1u);
  EXPECT_EQ(index.sortedId()[own.begin], 2u);
  // The column's top end, and a column with no points.
  const SpatialIndex::Range top = index.columnPoints(grid.key(0.5f, 0.5f, 4.5f));
  EXPECT_EQ(top.end - top.begin, 2u);
  const SpatialIndex::Range empty = index.columnPoints(grid.key(5.5f, 0.5f, 2.5f));
  EXPECT_EQ(empty.end, empty.begin);
}

TEST(SpatialIndex, ADenseBuildGroupsLikeAHashedOne)
{
  // Cell numbers of a 6 x 5 x 4 grid of 0.5 m cells, z fastest.
  struct Numbers
  {
    std::uint64_t key(float x, float y, float z) const
    {
      auto axis = [](float v, int n) { return static_cast<std::uint64_t>(std::min(std::max(v / 0.5f, 0.0f), n - 1.0f)); };
      return (axis(x, 6) * 5 + axis(y, 5)) * 4 + axis(z, 4);
    }
  };
  std::mt19937 rng(5);
  std::vector<Vector3f> points = randomPoints(rng, 500, 1.0f);
  for (Vector3f& p : points)
    p += Vector3f::Constant(1.0f);
  SpatialIndex hashed, dense;
  write(hashed, points);
  write(dense, points);
  SpatialIndex::Options options;
  options.lookup = true;
  hashed.build(Numbers(), options);
  options.dense_cells = 6 * 5 * 4;
  dense.build(Numbers(), options);
  EXPECT_EQ(dense.cellCount(), 120u);
  for (std::uint64_t key = 1; key + 1 < 120; ++key)
  {
    const SpatialIndex::Range a = hashed.cellPoints(key), b = dense.cellPoints(key);
    ASSERT_EQ(a.end - a.begin, b.end - b.begin) << key;
    for (std::uint32_t j = 0; j < a.end - a.begin; ++j)
      EXPECT_EQ(hashed.sortedId()[a.begin + j], dense.sortedId()[b.begin + j]);
    const SpatialIndex::Range ca = hashed.columnPoints(key), cb = dense.columnPoints(key);
    ASSERT_EQ(ca.end - ca.begin, cb.end - cb.begin) << key;
    for (std::uint32_t j = 0; j < ca.end - ca.begin; ++j)
      EXPECT_EQ(hashed.sortedId()[ca.begin + j], dense.sortedId()[cb.begin + j]);
  }
  for (std::size_t i = 0; i < points.size(); ++i)
    EXPECT_EQ(dense.cellOfPoint(i), Numbers().key(points[i].x(), points[i].y(), points[i].z()));
}

TEST(SpatialIndex, GivesTheSameCellsWhenReusedForBuildsOfOtherSizes)
{
  std::mt19937 rng(11);
  SpatialIndex reused;
  SpatialIndex::Options options;
  options.block = 8;
  options.boxes = true;
  options.lookup = true;
  for (std::size_t count : { 5000u, 20u, 1u, 9000u, 5000u })
  {
    const std::vector<Vector3f> points = randomPoints(rng, count, 3.0f);
    const AnchoredGrid grid(points[0], 0.2, 1);
    write(reused, points);
    reused.build(grid, options);
    SpatialIndex fresh;
    write(fresh, points);
    fresh.build(grid, options);
    ASSERT_EQ(reused.cellCount(), fresh.cellCount()) << count;
    for (std::size_t c = 0; c < fresh.cellCount(); ++c)
    {
      ASSERT_EQ(reused.cellKeys()[c], fresh.cellKeys()[c]);
      ASSERT_EQ(reused.cellSize(c), fresh.cellSize(c));
    }
    expectGrouped(reused, points, grid, 8);
  }
}

TEST(CellKeySet, AcceptsEachKeyOnce)
{
  core::CellKeySet set;
  set.reset(5000);
  std::size_t accepted = 0;
  for (std::uint64_t round = 0; round < 2; ++round)
    for (std::uint64_t key = 0; key < 5000; ++key)
      accepted += set.insert(core::cell_key::pack(key % 17, key / 17, 3)) ? 1 : 0;
  EXPECT_EQ(accepted, 5000u);
}

TEST(BoxGrid, GrowsItsCellsUntilTheBoxFitsAndPadsEverySide)
{
  const Eigen::AlignedBox3f box(Vector3f(-5.0f, 0.0f, 1.0f), Vector3f(5.0f, 20.0f, 3.0f));
  const core::BoxGrid small(box, 0.1, 1, 100000);
  const core::BoxGrid fine(box, 1.0, 0, 1000000);
  EXPECT_LE(small.cells(0) * small.cells(1) * small.cells(2), 100000u);
  EXPECT_GT(small.inverseCell(), 0.0f);
  EXPECT_LT(small.inverseCell(), 10.0f) << "cells grew beyond the 0.1 m asked for";
  EXPECT_EQ(fine.cells(0), 11u);
  EXPECT_EQ(fine.cells(1), 21u);
  EXPECT_EQ(fine.cells(2), 3u);
  // Every point of the box is `padding` cells inside the grid (up to rounding).
  for (const Vector3f& p : { Vector3f(box.min()), Vector3f(box.max()), Vector3f(box.center()) })
  {
    const Vector3f c = small.coordinates(p);
    for (int a = 0; a < 3; ++a)
    {
      EXPECT_GE(c[a], 1.0f - 1e-5f);
      EXPECT_LT(c[a], static_cast<float>(small.cells(a) - 1));
    }
  }
}

// The nearest point within reach by brute force; ties to the larger distance-order index do
// not matter here: the check compares distances.
float bruteNearest(const std::vector<Vector3f>& points, const Vector3f& q, float reach)
{
  float best = std::numeric_limits<float>::infinity();
  for (const Vector3f& p : points)
    best = std::min(best, (p - q).squaredNorm());
  return best <= reach * reach ? best : std::numeric_limits<float>::infinity();
}

TEST(RealScene, FindsTheNearestPointWithinReachAndTheKNearest)
{
  std::mt19937 rng(17);
  const std::vector<Vector3f> points = randomPoints(rng, 2000, 1.0f);
  core::RealScene scene;
  const float reach = 0.1f;
  scene.build(points, reach);
  const std::vector<Vector3f> queries = randomPoints(rng, 500, 1.3f);
  std::size_t found = 0;
  for (const Vector3f& q : queries)
  {
    float squared = 0.0f;
    const std::uint32_t nearest = scene.nearest(q, squared);
    const float expected = bruteNearest(points, q, reach);
    if (std::isinf(expected))
    {
      EXPECT_EQ(nearest, core::RealScene::kNone);
      continue;
    }
    ++found;
    ASSERT_NE(nearest, core::RealScene::kNone);
    EXPECT_EQ(squared, expected);
    EXPECT_EQ((points[nearest] - q).squaredNorm(), expected);

    std::vector<std::pair<float, std::uint32_t>> k_nearest;
    scene.nearestK(q, 5, k_nearest);
    std::vector<float> within;
    for (const Vector3f& p : points)
      if ((p - q).squaredNorm() <= reach * reach)
        within.push_back((p - q).squaredNorm());
    std::sort(within.begin(), within.end());
    within.resize(std::min<std::size_t>(within.size(), 5));
    std::vector<float> got;
    for (const auto& n : k_nearest)
      got.push_back(n.first);
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, within);
  }
  EXPECT_GT(found, 100u);
  float squared = 0.0f;
  EXPECT_EQ(scene.nearest(Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()), squared),
            core::RealScene::kNone);
}

TEST(RealScene, GivesAPlanesNormalAndNoneForALine)
{
  std::vector<Vector3f> points;
  for (int a = 0; a < 10; ++a)
    for (int b = 0; b < 10; ++b)
      points.push_back(Vector3f(0.01f * a, 0.01f * b, 0.0f));  // the plane z = 0
  for (int a = 0; a < 10; ++a)
    points.push_back(Vector3f(1.0f + 0.01f * a, 0.0f, 0.0f));  // a line
  core::RealScene scene;
  scene.build(points, 0.05f);
  const Vector3f plane_normal = scene.surfaceNormal(55);
  EXPECT_NEAR(std::fabs(plane_normal.z()), 1.0f, 1e-4f);
  EXPECT_TRUE(std::isinf(scene.surfaceNormal(104).x()));
}

}  // namespace
}  // namespace ohm_mirror_detector3d
