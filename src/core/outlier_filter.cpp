#include "ohm_mirror_detector3d/core/outlier_filter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "ohm_mirror_detector3d/core/parallel.h"

// The spatial index with cells at least as large as the radius, so that every neighbour of a
// point lies in its own cell or one of the 26 around it. A cell's points are contiguous, the
// distance loop streams through plain float arrays, and the three cells of a column along z
// are one contiguous range: a point has at most 11 ranges to look at (own cell, the cells
// above and below, 8 columns), found by pointers that only move forward as the cells are
// visited in key order, without a lookup.
//
// Expected O(N) for bounded density. Per point, each larger range is first judged by the
// bounding box of its points: wholly within r counts all its points at once, wholly beyond
// r is skipped, only the rest is scanned point by point. The scan stops as soon as the
// point has n_inlier neighbours or can no longer reach them, so dense regions cost a
// bounded number of distance tests per point whatever the density.

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// Cells slightly larger than r: the float distance test may accept pairs a few ulps
// beyond r, and those must still be in adjacent cells.
constexpr double kCellMargin = 1.0 + 1e-4;

// The bounding-box shortcuts must never disagree with the per-point float test, whatever
// its rounding (or fused multiply-add on some targets); a relative margin far above float
// rounding keeps them on the safe side, and pairs inside the margin get the exact test.
constexpr float kBoxMargin = 1e-5f;

// Points of a cell are stored padded to whole blocks so that the distance loop has no
// scalar tail; padding points are NaN, which no comparison accepts.
constexpr std::uint32_t kBlock = 8;

// Counts points of [begin, end) (whole blocks) within r of q on top of `count`, stopping
// once `need` is reached; the exit is checked once per block so that the block itself
// has no branch and vectorises.
inline std::size_t countWithin(const float* xs, const float* ys, const float* zs, std::uint32_t begin,
                               std::uint32_t end, float qx, float qy, float qz, float r2, std::size_t count,
                               std::size_t need)
{
  for (std::uint32_t j = begin; j < end; j += kBlock)
  {
    // Block-local pointers: with xs[j + t] the compiler must allow for j + t wrapping
    // around in 32 bits and loads each lane on its own instead of one vector load.
    const float* bx = xs + j;
    const float* by = ys + j;
    const float* bz = zs + j;
    std::uint32_t block = 0;
    // At -O3 gcc would unroll this loop completely before vectorising and end up scalar.
#pragma GCC unroll 1
    for (std::uint32_t t = 0; t < kBlock; ++t)
    {
      const float dx = bx[t] - qx;
      const float dy = by[t] - qy;
      const float dz = bz[t] - qz;
      block += (dx * dx + dy * dy + dz * dz <= r2) ? 1u : 0u;
    }
    count += block;
    if (count >= need)
      break;
  }
  return count;
}

inline bool isFinite(const Eigen::Vector3f& p)
{
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
}

// Neighbouring cells as seen from the cell being judged: one cell or a column of up to
// three, contiguous in the sorted arrays.
struct Range
{
  std::uint32_t begin;  // in the sorted arrays
  std::uint32_t end;    // padded end
  std::uint32_t count;  // real points
  float box[6];         // min x, y, z, max x, y, z
};

// Ranges smaller than this are scanned without looking at their box first: a block or
// two costs about as much as the box test, and the branch it adds mispredicts.
constexpr std::uint32_t kBoxTestMinPoints = 2 * kBlock;

// Side by side, no range of work smaller than this (below it the threads cost more than they save).
constexpr std::size_t kMinCellsPerPart = 256;
constexpr std::size_t kMinBeamsPerPart = 4096;

}  // namespace

std::size_t OutlierFilter::apply(const Sweep& sweep, Label subject, SweepLabels& labels)
{
  return applySphere(sweep, subject, labels, config_.radius);
}

std::size_t OutlierFilter::applySphere(const Sweep& sweep, Label subject, SweepLabels& labels, double radius)
{
  // With n_inlier <= 0 nobody can have too few neighbours; relabelling nanPoint as
  // nanPoint changes nothing.
  if (config_.min_neighbors <= 0 || subject == Label::nanPoint)
    return 0;

  // A NaN or negative radius has no neighbours in it; r = 0 still holds exact duplicates
  // of other beams. Any cell at least r wide is correct, so a degenerate r gets 1 m cells.
  const float r2 = radius >= 0.0 ? static_cast<float>(radius * radius) : -1.0f;
  double cell_size = radius * kCellMargin;
  if (!(cell_size >= 1e-6) || !std::isfinite(1.0 / cell_size))
    cell_size = std::isinf(radius) ? std::numeric_limits<double>::infinity() : 1.0;
  const float r2_inside = r2 >= 0.0f ? r2 * (1.0f - kBoxMargin) : -1.0f;
  const float r2_outside = r2 >= 0.0f ? r2 * (1.0f + kBoxMargin) : -1.0f;

  std::size_t removed = gather(sweep, subject, labels);
  if (index_.pointCount() == 0)
    return removed;
  // Cell coordinates relative to the first point, so the 21-bit fields cover the cloud
  // wherever it is.
  const Eigen::Vector3f anchor(index_.pointX()[0], index_.pointY()[0], index_.pointZ()[0]);
  SpatialIndex::Options options;
  options.block = kBlock;
  options.boxes = true;
  index_.build(AnchoredGrid(anchor, cell_size, 1), options);

  // The point itself is always within r of itself, so it needs n_inlier + 1 including itself.
  const std::size_t need = static_cast<std::size_t>(config_.min_neighbors) + 1;

  const float* xs = index_.sortedX();
  const float* ys = index_.sortedY();
  const float* zs = index_.sortedZ();
  const std::uint32_t* owners = index_.sortedId();
  std::vector<Label>& labels1 = labels.echoes[0];
  std::vector<Label>& labels2 = labels.echoes[1];

  const std::size_t cell_count = index_.cellCount();
  const std::uint64_t* keys = index_.cellKeys();
  auto cellRange = [&](std::size_t first, std::size_t last, Range& range) {
    // [first, last) are consecutive cells, hence one contiguous span of the arrays.
    range.begin = index_.cellBegin(first);
    range.end = index_.cellBegin(last);
    range.count = 0;
    const float* box = index_.cellBox(first);
    std::copy(box, box + 6, range.box);
    for (std::size_t cell = first; cell < last; ++cell, box += 6)
    {
      range.count += index_.cellSize(cell);
      for (int a = 0; a < 3; ++a)
      {
        range.box[a] = std::min(range.box[a], box[a]);
        range.box[a + 3] = std::max(range.box[a + 3], box[a + 3]);
      }
    }
  };

  // The 8 neighbouring columns, faces before diagonals (nearer first, earlier exit). As
  // cells are visited in increasing key, the key of each neighbouring column increases
  // too, so each column's search pointer only moves forward.
  constexpr std::int64_t kY = cell_key::kStepY;
  constexpr std::int64_t kX = cell_key::kStepX;
  constexpr std::array<std::int64_t, 8> column_offsets = { -kX, kX, -kY, kY, -kX - kY, -kX + kY, kX - kY, kX + kY };

  // Decisions depend only on the gathered coordinates, never on labels, so writing labels as we go
  // cannot cascade, and the cells are judged in ranges side by side; a range's column cursors
  // start where a search from its first cell puts them.
  const std::size_t parts = partsFor(cell_count, config_.threads, kMinCellsPerPart);
  std::vector<std::size_t> removed_in(parts, 0);
  runTasks(parts, config_.threads, [&](std::size_t part, std::size_t) {
    const std::size_t first_cell = partBegin(cell_count, parts, part);
    const std::size_t end_cell = partBegin(cell_count, parts, part + 1);
    std::size_t& removed_here = removed_in[part];
    auto remove = [&](std::uint32_t owner) {
      const std::size_t beam = owner >> 2;
      if (owner & 1u)
      {
        labels1[beam] = Label::nanPoint;
        ++removed_here;
      }
      if (owner & 2u)
      {
        labels2[beam] = Label::nanPoint;
        ++removed_here;
      }
    };
    std::array<std::size_t, 8> column_cursor{};
    if (first_cell < end_cell)
      for (std::size_t col = 0; col < column_offsets.size(); ++col)
      {
        const std::uint64_t low =
            static_cast<std::uint64_t>(static_cast<std::int64_t>(keys[first_cell]) + column_offsets[col]) - 1;
        column_cursor[col] = static_cast<std::size_t>(std::lower_bound(keys, keys + cell_count, low) - keys);
      }
    std::array<Range, 11> ranges;
    for (std::size_t c = first_cell; c < end_cell; ++c)
    {
      const std::uint64_t key = keys[c];
      std::size_t range_count = 0;
      cellRange(c, c + 1, ranges[range_count++]);
      if (c > 0 && keys[c - 1] == key - 1)
        cellRange(c - 1, c, ranges[range_count++]);
      if (c + 1 < cell_count && keys[c + 1] == key + 1)
        cellRange(c + 1, c + 2, ranges[range_count++]);
      for (std::size_t col = 0; col < column_offsets.size(); ++col)
      {
        // The clamped coordinates keep key + offset +- 1 inside the key's own fields.
        const std::uint64_t low = static_cast<std::uint64_t>(static_cast<std::int64_t>(key) + column_offsets[col]) - 1;
        std::size_t first = column_cursor[col];
        while (first < cell_count && keys[first] < low)
          ++first;
        column_cursor[col] = first;
        std::size_t last = first;
        while (last < cell_count && keys[last] <= low + 2)
          ++last;
        if (last > first)
          cellRange(first, last, ranges[range_count++]);
      }

      std::size_t total = 0;
      for (std::size_t k = 0; k < range_count; ++k)
        total += ranges[k].count;
      const std::uint32_t begin = index_.cellBegin(c);
      const std::uint32_t end = begin + index_.cellSize(c);
      if (total < need)
      {
        for (std::uint32_t i = begin; i < end; ++i)
          remove(owners[i]);
        continue;
      }
      for (std::uint32_t i = begin; i < end; ++i)
      {
        const float qx = xs[i], qy = ys[i], qz = zs[i];
        std::size_t count = 0;
        std::size_t unseen = total;
        for (std::size_t k = 0; k < range_count; ++k)
        {
          const Range& range = ranges[k];
          bool scan = true;
          if (range.count >= kBoxTestMinPoints)
          {
            const float* box = range.box;
            const float far_x = std::max(qx - box[0], box[3] - qx);
            const float far_y = std::max(qy - box[1], box[4] - qy);
            const float far_z = std::max(qz - box[2], box[5] - qz);
            const float near_x = std::max(std::max(box[0] - qx, qx - box[3]), 0.0f);
            const float near_y = std::max(std::max(box[1] - qy, qy - box[4]), 0.0f);
            const float near_z = std::max(std::max(box[2] - qz, qz - box[5]), 0.0f);
            if (far_x * far_x + far_y * far_y + far_z * far_z <= r2_inside)
            {
              count += range.count;
              scan = false;
            }
            else if (near_x * near_x + near_y * near_y + near_z * near_z > r2_outside)
            {
              scan = false;
            }
          }
          if (scan)
            count = countWithin(xs, ys, zs, range.begin, range.end, qx, qy, qz, r2, count, need);
          unseen -= range.count;
          if (count >= need || count + unseen < need)
            break;
        }
        if (count < need)
          remove(owners[i]);
      }
    }
  });
  for (const std::size_t r : removed_in)
    removed += r;
  return removed;
}

std::size_t OutlierFilter::apply(const Sweep& sweep, const SweepSampling& sampling, Label subject,
                                 SweepLabels& labels)
{
  if (!config_.follows_sampling)
    return apply(sweep, subject, labels);
  if (config_.min_neighbors <= 0 || subject == Label::nanPoint)
    return 0;
  if (sampling.hasGrid() && sampling.rows * sampling.cols == sweep.beamCount())
    return applyOnGrid(sweep, sampling, subject, labels);
  if (sampling.layout == SweepSampling::Layout::unordered)
    return applySphere(sweep, subject, labels, unorderedRadius(sweep, sampling, subject, labels));
  // Nothing to judge the points by: only what cannot be a point goes.
  return markSubjects(sweep, subject, labels);
}

std::size_t OutlierFilter::markSubjects(const Sweep& sweep, Label subject, SweepLabels& labels)
{
  const std::size_t beams = sweep.beamCount();
  subject_.assign(beams, 0);
  std::size_t removed = 0;
  for (std::size_t b = 0; b < beams; ++b)
  {
    std::uint8_t bits = 0;
    for (int k = 0; k < 2; ++k)
    {
      Label& label = labels.echoes[k][b];
      if (label != subject)
        continue;
      if (!isFinite(sweep.echoes[k].points[b]))
      {
        label = Label::nanPoint;
        ++removed;
        continue;
      }
      bits |= k == 0 ? kFirst : kSecond;
    }
    if ((bits & (kFirst | kSecond)) == (kFirst | kSecond) && sweep.echoes[0].points[b] == sweep.echoes[1].points[b])
      bits = kFirst | kRepeated;
    subject_[b] = bits;
  }
  return removed;
}

std::size_t OutlierFilter::supportOnGrid(const Sweep& sweep, const BeamNeighbourhood& neighbourhood, std::size_t beam,
                                         int echo, std::size_t need) const
{
  const Eigen::Vector3f& p = sweep.echoes[echo].points[beam];
  const float range = sweep.echoes[echo].ranges[beam];
  const std::size_t cols = neighbourhood.cols();
  std::size_t count = 0;
  neighbourhood.anyNeighbour(beam / cols, beam % cols, [&](std::size_t other, std::size_t k) {
    const std::uint8_t bits = subject_[other];
    if (bits == 0)
      return false;
    const float limit = neighbourhood.limitSquared(range, k);
    if ((bits & kFirst) && (sweep.echoes[0].points[other] - p).squaredNorm() <= limit)
      ++count;
    if ((bits & kSecond) && (sweep.echoes[1].points[other] - p).squaredNorm() <= limit)
      ++count;
    return count >= need;
  });
  return count;
}

std::size_t OutlierFilter::applyOnGrid(const Sweep& sweep, const SweepSampling& sampling, Label subject,
                                       SweepLabels& labels)
{
  std::size_t removed = markSubjects(sweep, subject, labels);
  const BeamNeighbourhood neighbourhood(sampling, config_.neighbourhood);
  const std::size_t need = static_cast<std::size_t>(config_.min_neighbors);
  const std::size_t beams = sweep.beamCount();
  // Decisions read subject_ (the labels before the call) only, so removals cannot cascade, and
  // ranges of beams are judged side by side.
  const std::size_t parts = partsFor(beams, config_.threads, kMinBeamsPerPart);
  std::vector<std::size_t> removed_in(parts, 0);
  runTasks(parts, config_.threads, [&](std::size_t part, std::size_t) {
    std::size_t& removed_here = removed_in[part];
    for (std::size_t b = partBegin(beams, parts, part); b < partBegin(beams, parts, part + 1); ++b)
    {
      const std::uint8_t bits = subject_[b];
      if (bits == 0)
        continue;
      if ((bits & kFirst) && supportOnGrid(sweep, neighbourhood, b, 0, need) < need)
      {
        labels.echoes[0][b] = Label::nanPoint;
        ++removed_here;
        if (bits & kRepeated)
        {
          labels.echoes[1][b] = Label::nanPoint;
          ++removed_here;
        }
      }
      if ((bits & kSecond) && supportOnGrid(sweep, neighbourhood, b, 1, need) < need)
      {
        labels.echoes[1][b] = Label::nanPoint;
        ++removed_here;
      }
    }
  });
  for (const std::size_t r : removed_in)
    removed += r;
  return removed;
}

std::size_t OutlierFilter::releaseIsolatedSurfaceEchoes(const Sweep& sweep, const SweepSampling& sampling,
                                                       SweepLabels& labels)
{
  if (!config_.follows_sampling || !sampling.hasGrid() || sampling.rows * sampling.cols != sweep.beamCount() ||
      config_.min_neighbors <= 0)
    return 0;
  markSubjects(sweep, Label::errorSurface, labels);
  const BeamNeighbourhood neighbourhood(sampling, config_.neighbourhood);
  const std::size_t need = static_cast<std::size_t>(config_.min_neighbors);
  std::size_t released = 0;
  for (std::size_t b = 0; b < sweep.beamCount(); ++b)
  {
    const std::uint8_t bits = subject_[b];
    if (bits == 0)
      continue;
    const int echo = (bits & kFirst) ? 0 : 1;
    if (supportOnGrid(sweep, neighbourhood, b, echo, need) >= need)
      continue;
    // Its partner is the far echo of the beam (error); a beam has one errorSurface echo.
    for (int k = 0; k < 2; ++k)
      if (labels.echoes[k][b] == Label::errorSurface || labels.echoes[k][b] == Label::error)
        labels.echoes[k][b] = Label::unchecked;
    ++released;
  }
  return released;
}

double OutlierFilter::unorderedRadius(const Sweep& sweep, const SweepSampling& sampling, Label subject,
                                      const SweepLabels& labels)
{
  // A sample of the subject points' ranges is enough for a percentile.
  constexpr std::size_t kSamples = 4096;
  ranges_.clear();
  const std::size_t beams = sweep.beamCount();
  const std::size_t stride = beams / kSamples + 1;
  for (std::size_t b = 0; b < beams; b += stride)
    for (int k = 0; k < 2; ++k)
      if (labels.echoes[k][b] == subject && std::isfinite(sweep.echoes[k].ranges[b]))
        ranges_.push_back(sweep.echoes[k].ranges[b]);
  if (ranges_.empty())
    return config_.neighbourhood.noise_floor;
  const auto at = ranges_.begin() + static_cast<std::ptrdiff_t>(ranges_.size() * 9 / 10);
  std::nth_element(ranges_.begin(), at, ranges_.end());
  const BeamNeighbourhoodConfig& n = config_.neighbourhood;
  return n.noise_floor + n.step_factor * std::max(n.half_width, 1) * sampling.maxStep() * static_cast<double>(*at);
}

std::size_t OutlierFilter::gather(const Sweep& sweep, Label subject, SweepLabels& labels)
{
  const std::vector<Eigen::Vector3f>& points1 = sweep.echoes[0].points;
  const std::vector<Eigen::Vector3f>& points2 = sweep.echoes[1].points;
  std::vector<Label>& labels1 = labels.echoes[0];
  std::vector<Label>& labels2 = labels.echoes[1];
  // Guards against a caller whose arrays disagree in size rather than reading past one.
  const std::size_t beams = std::min({ points1.size(), points2.size(), labels1.size(), labels2.size() });

  index_.reservePoints(2 * beams);
  float* xs = index_.pointX();
  float* ys = index_.pointY();
  float* zs = index_.pointZ();
  std::uint32_t* owners = index_.pointId();
  std::size_t n = 0;
  std::size_t removed = 0;
  auto add = [&](const Eigen::Vector3f& p, std::uint32_t owner) {
    xs[n] = p.x();
    ys[n] = p.y();
    zs[n] = p.z();
    owners[n] = owner;
    ++n;
  };

  for (std::size_t i = 0; i < beams; ++i)
  {
    const bool subject1 = labels1[i] == subject;
    const bool subject2 = labels2[i] == subject;
    if (!subject1 && !subject2)
      continue;
    const std::uint32_t beam_bits = static_cast<std::uint32_t>(i) << 2;
    const bool finite1 = subject1 && isFinite(points1[i]);
    const bool finite2 = subject2 && isFinite(points2[i]);
    if (subject1 && !finite1)
    {
      labels1[i] = Label::nanPoint;
      ++removed;
    }
    if (subject2 && !finite2)
    {
      labels2[i] = Label::nanPoint;
      ++removed;
    }
    if (finite1 && finite2 && points1[i] == points2[i])
    {
      add(points1[i], beam_bits | 3u);
      continue;
    }
    if (finite1)
      add(points1[i], beam_bits | 1u);
    if (finite2)
      add(points2[i], beam_bits | 2u);
  }
  index_.setPointCount(n);
  return removed;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
