// Stage outlierFilter of the paper: sparse points become nanPoint.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct OutlierFilterConfig
{
  double radius;      // r [m]
  int min_neighbors;  // n_inlier
};

// Finds the neighbours of points within a radius among a chosen subset of a sweep's points
// (both echoes), without a kd-tree. Owns its buffers and reuses them from call to call.
class OutlierFilter
{
public:
  explicit OutlierFilter(const OutlierFilterConfig& config) : config_(config) {}

  // Every point of both echoes labelled `subject` that has fewer than min_neighbors other
  // `subject` points within radius becomes nanPoint. Points are judged on the labels as they
  // were before the call (removing one outlier does not turn its neighbours into outliers). A
  // point repeated in both echoes of a beam (a single return) is one point, not its own
  // neighbour. Returns the number of points it labelled nanPoint.
  //
  // "Within r" is inclusive: squared distance, computed in float, <= r^2 rounded to float.
  // Only the two echoes of one beam are merged when equal; equal points of different beams
  // are distinct and neighbours of each other. A non-finite point labelled `subject` has no
  // neighbours and is never one: it becomes nanPoint too.
  // A radius that is NaN or negative holds no neighbour, min_neighbors <= 0 removes nothing.
  std::size_t apply(const Sweep& sweep, Label subject, SweepLabels& labels);

private:
  OutlierFilterConfig config_;

  // Fills the gathered arrays from the subject points; returns how many non-finite subject
  // points it labelled nanPoint on the way.
  std::size_t gather(const Sweep& sweep, Label subject, double cell_size, SweepLabels& labels);
  // Groups the gathered points by cell, cells in key order, into the sorted arrays.
  void buildGrid();
  void resetTable(std::size_t capacity);  // empty, capacity a power of two

  // Gathered subject points (one per distinct point of a beam), in beam order; the
  // first point_count_ entries are this sweep's.
  std::size_t point_count_ = 0;
  std::vector<float> xs_, ys_, zs_;
  std::vector<std::uint32_t> owners_;       // beam index << 2 | echo mask (bit k: echo k); < 2^30 beams
  std::vector<std::uint64_t> point_keys_;   // packed cell coordinates of each point
  std::size_t key_runs_ = 0;                // runs of equal keys in beam order: >= distinct cells

  // Open-addressing table cell key -> cell in order of first appearance; size a power of two.
  std::vector<std::uint64_t> table_keys_;
  std::vector<std::uint32_t> table_cells_;
  std::uint64_t table_mask_ = 0;
  int table_shift_ = 64;
  std::vector<std::uint64_t> first_seen_keys_;
  std::vector<std::uint32_t> first_seen_counts_;
  std::vector<std::uint32_t> point_cells_;  // cell of each gathered point
  std::vector<std::pair<std::uint64_t, std::uint32_t>> key_order_;  // (key, first-seen cell), sorted
  std::vector<std::uint32_t> cell_rank_;    // first-seen cell -> cell in key order

  // Cells in key order: key, where its points start in the sorted arrays, how many there
  // are, and their bounding box (min x, y, z, max x, y, z).
  std::vector<std::uint64_t> cell_keys_;
  std::vector<std::uint32_t> cell_start_;   // cell_count + 1 entries, multiples of the block size
  std::vector<std::uint32_t> cell_counts_;
  std::vector<float> cell_boxes_;           // 6 per cell

  // Gathered points sorted by cell key, structure of arrays for the distance loop; each
  // cell padded with NaN points to whole blocks.
  std::vector<float> sorted_x_, sorted_y_, sorted_z_;
  std::vector<std::uint32_t> sorted_owners_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
