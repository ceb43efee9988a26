#include "ohm_mirror_detector3d/core/spatial_index.h"

#include <algorithm>
#include <cmath>

namespace ohm_mirror_detector3d
{
namespace core
{
AnchoredGrid::AnchoredGrid(const Eigen::Vector3f& anchor, double cell_size, int reach)
  : anchor_x_(anchor.x())
  , anchor_y_(anchor.y())
  , anchor_z_(anchor.z())
  , inverse_cell_(std::isinf(cell_size) ? 0.0 : 1.0 / cell_size)
  , bias_(static_cast<double>(std::uint64_t(1) << (cell_key::kAxisBits - 1)))
  , low_(static_cast<double>(reach))
  , high_(static_cast<double>(cell_key::kAxisMax) - static_cast<double>(reach))
{
}

BoxGrid::BoxGrid(const Eigen::AlignedBox3f& box, double min_cell, int padding, std::size_t max_cells)
{
  const Eigen::Vector3d extent = (box.max() - box.min()).cast<double>();
  const double spare = 1.0 + 2.0 * padding;
  double cell = min_cell;
  while ((std::floor(extent.x() / cell) + spare) * (std::floor(extent.y() / cell) + spare) *
             (std::floor(extent.z() / cell) + spare) >
         static_cast<double>(max_cells))
    cell *= 1.5;
  inverse_cell_ = static_cast<float>(1.0 / cell);
  corner_ = box.min() - Eigen::Vector3f::Constant(static_cast<float>(padding * cell));
  for (int a = 0; a < 3; ++a)
    counts_[a] = static_cast<std::size_t>(extent[a] / cell) + 1 + 2 * static_cast<std::size_t>(padding);
}

void CellKeySet::reset(std::size_t expected)
{
  std::size_t capacity = 64;
  shift_ = 58;
  while (capacity < 2 * expected)
  {
    capacity <<= 1;
    --shift_;
  }
  keys_.assign(capacity, kEmpty);
  mask_ = capacity - 1;
}

bool CellKeySet::insert(std::uint64_t key)
{
  std::size_t slot = static_cast<std::size_t>(cell_key::hash(key, shift_));
  while (keys_[slot] != kEmpty)
  {
    if (keys_[slot] == key)
      return false;
    slot = (slot + 1) & mask_;
  }
  keys_[slot] = key;
  return true;
}

void SpatialIndex::reservePoints(std::size_t capacity)
{
  // Written through pointers by the caller: push_back's capacity test per element would cost
  // more than the rest of a gathering loop.
  if (xs_.size() < capacity)
  {
    xs_.resize(capacity);
    ys_.resize(capacity);
    zs_.resize(capacity);
    ids_.resize(capacity);
    point_keys_.resize(capacity);
  }
}

void SpatialIndex::resetTable(std::size_t capacity)
{
  if (table_keys_.size() < capacity)
  {
    table_keys_.resize(capacity);
    table_cells_.resize(capacity);
  }
  std::fill(table_keys_.begin(), table_keys_.begin() + static_cast<std::ptrdiff_t>(capacity), kEmptyKey);
  table_mask_ = capacity - 1;
  int bits = 0;
  while ((std::size_t(1) << bits) < capacity)
    ++bits;
  table_shift_ = 64 - bits;
}

void SpatialIndex::groupDense(std::size_t cells)
{
  // A counting sort by cell number: no table, no sort of cells.
  dense_ = true;
  cell_keys_.clear();
  cell_start_.assign(cells + 1, 0);
  for (std::size_t i = 0; i < point_count_; ++i)
    ++cell_start_[point_keys_[i] + 1];
  for (std::size_t c = 1; c <= cells; ++c)
    cell_start_[c] += cell_start_[c - 1];
  first_seen_counts_.assign(cell_start_.begin(), cell_start_.end() - 1);
  if (sorted_x_.size() < point_count_)
  {
    sorted_x_.resize(point_count_);
    sorted_y_.resize(point_count_);
    sorted_z_.resize(point_count_);
    sorted_ids_.resize(point_count_);
  }
  for (std::size_t i = 0; i < point_count_; ++i)
  {
    const std::uint32_t to = first_seen_counts_[point_keys_[i]]++;
    sorted_x_[to] = xs_[i];
    sorted_y_[to] = ys_[i];
    sorted_z_[to] = zs_[i];
    sorted_ids_[to] = ids_[i];
  }
}

void SpatialIndex::group(std::size_t key_runs, const Options& options)
{
  dense_ = false;
  const std::size_t point_count = point_count_;

  // A table for about as many cells as the previous build had keeps it in cache (sweeps of
  // one scanner look alike); it grows when needed. key_runs bounds the distinct cells from
  // above, which caps it for small builds. Load factor stays <= 1/2.
  const std::size_t expected_cells = std::min(key_runs, std::max<std::size_t>(cell_keys_.size(), 8));
  std::size_t capacity = 16;
  while (capacity < 4 * expected_cells)
    capacity <<= 1;
  resetTable(capacity);

  first_seen_keys_.clear();
  first_seen_counts_.clear();
  if (point_cells_.size() < point_count)
    point_cells_.resize(point_count);
  std::uint64_t last_key = kEmptyKey;
  std::uint32_t last_cell = kNoCell;
  for (std::size_t i = 0; i < point_count; ++i)
  {
    const std::uint64_t key = point_keys_[i];
    if (key != last_key)
    {
      const std::uint64_t slot = tableSlot(key);
      if (table_keys_[slot] == kEmptyKey)
      {
        const std::uint32_t cell = static_cast<std::uint32_t>(first_seen_keys_.size());
        first_seen_keys_.push_back(key);
        first_seen_counts_.push_back(0);
        if (2 * first_seen_keys_.size() > table_mask_ + 1)
        {
          // Rehash every cell so far, this one included, into a table twice the size.
          resetTable(2 * (table_mask_ + 1));
          for (std::uint32_t c = 0; c <= cell; ++c)
          {
            std::uint64_t s = cell_key::hash(first_seen_keys_[c], table_shift_);
            while (table_keys_[s] != kEmptyKey)
              s = (s + 1) & table_mask_;
            table_keys_[s] = first_seen_keys_[c];
            table_cells_[s] = c;
          }
        }
        else
        {
          table_keys_[slot] = key;
          table_cells_[slot] = cell;
        }
        last_cell = cell;
      }
      else
      {
        last_cell = table_cells_[slot];
      }
      last_key = key;
    }
    point_cells_[i] = last_cell;
    ++first_seen_counts_[last_cell];
  }

  // Key order makes a column of cells contiguous and lets a caller that visits cells in key
  // order find its neighbours with pointers that only move forward. Sorting cells, not
  // points, keeps this at a fraction of the work.
  const std::uint32_t block = std::max<std::uint32_t>(options.block, 1);
  const std::size_t cell_count = first_seen_keys_.size();
  key_order_.resize(cell_count);
  for (std::size_t c = 0; c < cell_count; ++c)
    key_order_[c] = { first_seen_keys_[c], static_cast<std::uint32_t>(c) };
  std::sort(key_order_.begin(), key_order_.end());
  cell_rank_.resize(cell_count);
  cell_keys_.resize(cell_count);
  cell_counts_.resize(cell_count);
  cell_start_.resize(cell_count + 1);
  std::uint32_t padded_total = 0;
  for (std::size_t c = 0; c < cell_count; ++c)
  {
    const std::uint32_t seen = key_order_[c].second;
    cell_rank_[seen] = static_cast<std::uint32_t>(c);
    cell_keys_[c] = key_order_[c].first;
    cell_counts_[c] = first_seen_counts_[seen];
    cell_start_[c] = padded_total;
    padded_total += (cell_counts_[c] + block - 1) / block * block;
  }
  cell_start_[cell_count] = padded_total;

  // Counting sort into (padded) slots; first_seen_counts_ serves as the fill cursor. Never
  // shrunk, so that a smaller build does not pay for re-initialising on the next.
  if (sorted_x_.size() < padded_total)
  {
    sorted_x_.resize(padded_total);
    sorted_y_.resize(padded_total);
    sorted_z_.resize(padded_total);
    sorted_ids_.resize(padded_total);
  }
  std::vector<std::uint32_t>& cursor = first_seen_counts_;
  for (std::size_t c = 0; c < cell_count; ++c)
    cursor[c] = cell_start_[cell_rank_[c]];
  for (std::size_t i = 0; i < point_count; ++i)
  {
    const std::uint32_t to = cursor[point_cells_[i]]++;
    sorted_x_[to] = xs_[i];
    sorted_y_[to] = ys_[i];
    sorted_z_[to] = zs_[i];
    sorted_ids_[to] = ids_[i];
  }

  const float nan = std::numeric_limits<float>::quiet_NaN();
  if (options.boxes)
    cell_boxes_.resize(6 * cell_count);
  if (block > 1 || options.boxes)
  {
    for (std::size_t c = 0; c < cell_count; ++c)
    {
      const std::uint32_t begin = cell_start_[c];
      const std::uint32_t end = begin + cell_counts_[c];
      std::fill(sorted_x_.data() + end, sorted_x_.data() + cell_start_[c + 1], nan);
      std::fill(sorted_y_.data() + end, sorted_y_.data() + cell_start_[c + 1], nan);
      std::fill(sorted_z_.data() + end, sorted_z_.data() + cell_start_[c + 1], nan);
      if (!options.boxes)
        continue;
      float box[6] = { sorted_x_[begin], sorted_y_[begin], sorted_z_[begin],
                       sorted_x_[begin], sorted_y_[begin], sorted_z_[begin] };
      for (std::uint32_t i = begin + 1; i < end; ++i)
      {
        box[0] = std::min(box[0], sorted_x_[i]);
        box[1] = std::min(box[1], sorted_y_[i]);
        box[2] = std::min(box[2], sorted_z_[i]);
        box[3] = std::max(box[3], sorted_x_[i]);
        box[4] = std::max(box[4], sorted_y_[i]);
        box[5] = std::max(box[5], sorted_z_[i]);
      }
      std::copy(box, box + 6, &cell_boxes_[6 * c]);
    }
  }
  if (options.lookup)
  {
    for (std::size_t s = 0; s <= table_mask_; ++s)
      if (table_keys_[s] != kEmptyKey)
        table_cells_[s] = cell_rank_[table_cells_[s]];
  }
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
