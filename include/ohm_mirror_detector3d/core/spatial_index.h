// Neighbours of points on a uniform grid, for every stage that needs them: the outlier filter
// (all points of a sweep), the patch connectivity of object extraction (one plane's inliers) and
// the type decision (the real scene where phantoms land, and voxel thinning of it).
//
// Cells are 64-bit keys of 21 bits per axis, so that the key of a neighbouring cell is the key
// plus a constant; a grid maps points to cell coordinates (AnchoredGrid: unbounded, anchored at
// a point; BoxGrid: a box of at most a given number of cells). SpatialIndex groups points by
// cell: each cell's points are contiguous and cells are in key order, so the (up to) three cells
// of a column along z are one contiguous range, and a cell is found by its key in O(1).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "ohm_mirror_detector3d/core/parallel.h"

namespace ohm_mirror_detector3d
{
namespace core
{
namespace cell_key
{
constexpr int kAxisBits = 21;
constexpr std::uint64_t kAxisMax = (std::uint64_t(1) << kAxisBits) - 1;
// Key offsets of a step along each axis (no carry between fields while coordinates stay in range).
constexpr std::int64_t kStepX = std::int64_t(1) << (2 * kAxisBits);
constexpr std::int64_t kStepY = std::int64_t(1) << kAxisBits;
constexpr std::int64_t kStepZ = 1;

inline std::uint64_t pack(std::uint64_t x, std::uint64_t y, std::uint64_t z)
{
  return (x << (2 * kAxisBits)) | (y << kAxisBits) | z;
}

// Fibonacci hashing: the top `64 - shift` bits of the product depend on every bit of the key.
inline std::uint64_t hash(std::uint64_t key, int shift)
{
  return (key * 0x9E3779B97F4A7C15ULL) >> shift;
}

// The key of p's cell in a grid with the given corner and 1 / cell size, in float, each
// coordinate clamped to [0, kAxisMax].
inline std::uint64_t of(const Eigen::Vector3f& p, const Eigen::Vector3f& corner, float inverse_cell)
{
  const Eigen::Vector3f c = (p - corner) * inverse_cell;
  auto axis = [](float v) { return static_cast<std::uint64_t>(std::min(std::max(v, 0.0f), 2097151.0f)); };
  return pack(axis(c.x()), axis(c.y()), axis(c.z()));
}
}  // namespace cell_key

// An unbounded grid of cubic cells, anchored at a point. Coordinates are clamped to
// [reach, 2^21 - 1 - reach] so that the cells within `reach` of any cell have keys key + offset
// (cell_key::kStep*). Clamping maps far points onto the border cells; since it never moves two
// coordinates further apart, points within a cell's reach still land within it: a stage that
// tests distances stays exact (only slower for points more than ~2^20 cells, 105 km at 0.1 m,
// from the anchor), a stage that trusts "same cell" (object extraction) may join such points.
class AnchoredGrid
{
public:
  AnchoredGrid(const Eigen::Vector3f& anchor, double cell_size, int reach);

  std::uint64_t key(float x, float y, float z) const
  {
    return cell_key::pack(axis(x, anchor_x_), axis(y, anchor_y_), axis(z, anchor_z_));
  }

private:
  std::uint64_t axis(float value, float anchor) const
  {
    // Truncation is floor here because the value is clamped positive first; this keeps
    // std::floor (a libm call without SSE4.1) out of the per-point loop.
    double t = (static_cast<double>(value) - static_cast<double>(anchor)) * inverse_cell_ + bias_;
    t = std::min(std::max(t, low_), high_);
    return static_cast<std::uint64_t>(t);
  }

  float anchor_x_, anchor_y_, anchor_z_;
  double inverse_cell_;
  double bias_;  // the anchor sits in the middle of the key range
  double low_, high_;
};

// A grid over a box: cells at least `min_cell` wide, grown by half until the box, with
// `padding` spare cells on every side, has at most `max_cells` cells. Coordinates in float.
class BoxGrid
{
public:
  BoxGrid() = default;
  BoxGrid(const Eigen::AlignedBox3f& box, double min_cell, int padding, std::size_t max_cells);

  // p in cell units from the grid's corner (p's cell is the integer part).
  Eigen::Vector3f coordinates(const Eigen::Vector3f& p) const { return (p - corner_) * inverse_cell_; }
  float inverseCell() const { return inverse_cell_; }
  // Cells along each axis.
  std::size_t cells(int axis) const { return counts_[axis]; }

private:
  Eigen::Vector3f corner_ = Eigen::Vector3f::Zero();
  float inverse_cell_ = 1.0f;
  std::size_t counts_[3] = { 1, 1, 1 };
};

// Open-addressing set of cell keys (voxel thinning: the first point per cell).
class CellKeySet
{
public:
  // Empty, for about `expected` keys (load factor at most 1/2).
  void reset(std::size_t expected);
  // True when the key was not in the set yet (and is now).
  bool insert(std::uint64_t key);

private:
  static constexpr std::uint64_t kEmpty = std::numeric_limits<std::uint64_t>::max();
  std::vector<std::uint64_t> keys_;
  std::size_t mask_ = 0;
  int shift_ = 58;  // 64 - log2(capacity)
};

// Points grouped by cell. The caller writes the points (coordinates and an id each) after
// reservePoints(), says how many with setPointCount(), then build() groups them: every cell's
// points are contiguous in the sorted arrays, in the order they were written, and cells are in
// key order. Cells are found by key through a hash table (any grid), or, for a bounded grid
// whose keys are cell numbers below Options::dense_cells, through a table with an entry per
// cell (faster lookups, for grids queried often). Buffers are kept from build to build (never
// shrunk), so a reused index does not allocate.
class SpatialIndex
{
public:
  static constexpr std::uint32_t kNoCell = std::numeric_limits<std::uint32_t>::max();
  static constexpr std::uint64_t kEmptyKey = std::numeric_limits<std::uint64_t>::max();
  // Side by side (Options::threads), no range of points smaller than this.
  static constexpr std::size_t kMinPointsPerPart = 16384;

  struct Options
  {
    // Each cell's points padded with NaN points to a multiple of this (a distance loop over
    // whole blocks then needs no scalar tail; NaN passes no distance test).
    std::uint32_t block = 1;
    bool boxes = false;   // bounding box of every cell (hashed lookup only)
    bool lookup = false;  // findCell(), cellOfPoint(), cellPoints(), columnPoints()
    // When > 0: the keys are cell numbers below this, numbered so that z runs fastest, and
    // every number is a cell (empty or not): cell index == key, no hashing (block 1, no boxes).
    std::size_t dense_cells = 0;
    // The points' keys are worked out in ranges on this many threads (core/parallel.h; the
    // same index for any number).
    int threads = 1;
  };

  // Room for `capacity` points: pointX()[i] .. pointId()[i] for i < capacity, written by the
  // caller. Keeps what was written when it does not grow.
  void reservePoints(std::size_t capacity);
  void setPointCount(std::size_t count) { point_count_ = count; }
  float* pointX() { return xs_.data(); }
  float* pointY() { return ys_.data(); }
  float* pointZ() { return zs_.data(); }
  std::uint32_t* pointId() { return ids_.data(); }
  std::size_t pointCount() const { return point_count_; }

  // Groups the points by their keys in `grid` (a type with key(x, y, z)).
  template <typename Grid>
  void build(const Grid& grid, const Options& options)
  {
    const std::size_t n = point_count_;
    const float* xs = xs_.data();
    const float* ys = ys_.data();
    const float* zs = zs_.data();
    std::uint64_t* keys = point_keys_.data();
    // Runs of equal keys in point order: at least the number of distinct cells, a cheap
    // bound for sizing the table. Worked out in ranges side by side, each range's first key
    // compared with the key before it.
    const std::size_t parts = partsFor(n, options.threads, kMinPointsPerPart);
    std::vector<std::size_t> runs_in(parts, 0);
    runTasks(parts, options.threads, [&](std::size_t part, std::size_t) {
      const std::size_t begin = partBegin(n, parts, part), end = partBegin(n, parts, part + 1);
      std::uint64_t last_key = begin > 0 ? grid.key(xs[begin - 1], ys[begin - 1], zs[begin - 1]) :
                                           std::numeric_limits<std::uint64_t>::max();
      std::size_t runs = 0;
      for (std::size_t i = begin; i < end; ++i)
      {
        const std::uint64_t key = grid.key(xs[i], ys[i], zs[i]);
        keys[i] = key;
        runs += key != last_key ? 1 : 0;
        last_key = key;
      }
      runs_in[part] = runs;
    });
    std::size_t runs = 0;
    for (const std::size_t r : runs_in)
      runs += r;
    if (options.dense_cells > 0)
      groupDense(options.dense_cells);
    else
      group(runs, options);
  }

  std::size_t cellCount() const { return cell_start_.size() - 1; }
  // The key of every cell (hashed lookup; a dense cell's key is its index).
  const std::uint64_t* cellKeys() const { return cell_keys_.data(); }
  // Cell c's points are sorted[cellBegin(c) .. cellBegin(c) + cellSize(c)), its padded end is
  // cellBegin(c + 1) (cellBegin(cellCount()) is the padded total).
  std::uint32_t cellBegin(std::size_t cell) const { return cell_start_[cell]; }
  std::uint32_t cellSize(std::size_t cell) const
  {
    return dense_ ? cell_start_[cell + 1] - cell_start_[cell] : cell_counts_[cell];
  }
  // min x, y, z, max x, y, z (Options::boxes).
  const float* cellBox(std::size_t cell) const { return &cell_boxes_[6 * cell]; }
  // The cell with this key, kNoCell when no point is in it (Options::lookup).
  std::uint32_t findCell(std::uint64_t key) const
  {
    if (dense_)
      return key < cellCount() ? static_cast<std::uint32_t>(key) : kNoCell;
    if (cell_keys_.empty())
      return kNoCell;
    const std::uint64_t slot = tableSlot(key);
    return table_keys_[slot] == key ? table_cells_[slot] : kNoCell;
  }
  // The cell of the i-th point as written (Options::lookup).
  std::uint32_t cellOfPoint(std::size_t i) const
  {
    return dense_ ? static_cast<std::uint32_t>(point_keys_[i]) : cell_rank_[point_cells_[i]];
  }

  // Positions in the sorted arrays, [begin, end).
  struct Range
  {
    std::uint32_t begin = 0;
    std::uint32_t end = 0;
  };
  // The points of the cell with this key; empty when there is none (Options::lookup, block 1).
  Range cellPoints(std::uint64_t key) const
  {
    const std::uint32_t cell = findCell(key);
    if (cell == kNoCell)
      return Range();
    return Range{ cell_start_[cell], cell_start_[cell] + cellSize(cell) };
  }
  // The points of the cells first_key .. last_key of a dense lookup (keys are cell numbers, so
  // consecutive cells are one contiguous range), in key order (Options::dense_cells, block 1).
  Range cellRunPoints(std::uint64_t first_key, std::uint64_t last_key) const
  {
    return Range{ cell_start_[first_key], cell_start_[last_key + 1] };
  }
  // The points of the cells key - kStepZ, key, key + kStepZ (a column of three along z, in
  // that order), one contiguous range (Options::lookup, block 1).
  Range columnPoints(std::uint64_t key) const
  {
    if (dense_)
      return Range{ cell_start_[key - cell_key::kStepZ], cell_start_[key + cell_key::kStepZ + 1] };
    // The cells of the column that exist are consecutive in key order: find the lowest, then
    // walk up while the keys stay within the column.
    std::uint32_t first = findCell(key - cell_key::kStepZ);
    if (first == kNoCell)
      first = findCell(key);
    if (first == kNoCell)
      first = findCell(key + cell_key::kStepZ);
    if (first == kNoCell)
      return Range();
    std::size_t last = first;
    while (last + 1 < cell_keys_.size() && cell_keys_[last + 1] <= key + cell_key::kStepZ)
      ++last;
    return Range{ cell_start_[first], cell_start_[last] + cell_counts_[last] };
  }

  const float* sortedX() const { return sorted_x_.data(); }
  const float* sortedY() const { return sorted_y_.data(); }
  const float* sortedZ() const { return sorted_z_.data(); }
  const std::uint32_t* sortedId() const { return sorted_ids_.data(); }

private:
  void group(std::size_t key_runs, const Options& options);
  void groupDense(std::size_t cells);
  void resetTable(std::size_t capacity);  // empty, capacity a power of two
  // The slot holding `key`, or the empty slot where it would go.
  std::uint64_t tableSlot(std::uint64_t key) const
  {
    std::uint64_t slot = cell_key::hash(key, table_shift_);
    while (table_keys_[slot] != key && table_keys_[slot] != kEmptyKey)
      slot = (slot + 1) & table_mask_;
    return slot;
  }

  std::size_t point_count_ = 0;
  std::vector<float> xs_, ys_, zs_;
  std::vector<std::uint32_t> ids_;
  std::vector<std::uint64_t> point_keys_;

  // Open-addressing table cell key -> cell in order of first appearance (after a build with
  // Options::lookup: -> cell in key order); size a power of two.
  std::vector<std::uint64_t> table_keys_;
  std::vector<std::uint32_t> table_cells_;
  std::uint64_t table_mask_ = 0;
  int table_shift_ = 64;
  std::vector<std::uint64_t> first_seen_keys_;
  std::vector<std::uint32_t> first_seen_counts_;
  std::vector<std::uint32_t> point_cells_;  // first-seen cell of each point
  std::vector<std::pair<std::uint64_t, std::uint32_t>> key_order_;  // (key, first-seen cell), sorted
  std::vector<std::uint32_t> cell_rank_;    // first-seen cell -> cell in key order

  bool dense_ = false;  // the last build's lookup (Options::dense_cells)
  std::vector<std::uint64_t> cell_keys_;
  std::vector<std::uint32_t> cell_start_ = { 0 };  // cell count + 1 entries
  std::vector<std::uint32_t> cell_counts_;
  std::vector<float> cell_boxes_;           // 6 per cell

  std::vector<float> sorted_x_, sorted_y_, sorted_z_;
  std::vector<std::uint32_t> sorted_ids_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
