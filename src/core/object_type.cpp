#include "ohm_mirror_detector3d/core/object_type.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "ohm_mirror_detector3d/core/block_box.h"
#include "ohm_mirror_detector3d/core/vision_cone.h"

// Why this is not pcl::IterativeClosestPoint on the whole scene (which it was, and which the
// bench still runs as its baseline): the registration only has to answer "do the phantoms
// land on the real scene near where a pure reflection puts them?". So
// - the phantoms are a deterministic sample of at most kMaxSamples points (evenly spread
//   over the behind points in beam order): the inlier fraction and fitness are shares and
//   means, and a few hundred points estimate them to a few percent;
// - the target is only the real scene where they can land (the box of the mirrored points
//   grown by icp_max_distance), thinned to one point per small voxel, so that a dense
//   scanner does not pay for points that add no information at the ICP's 10 cm scale;
// - nearest neighbours come from a uniform grid of cells icp_max_distance wide over that
//   target (built in O(n) by a counting sort, queried over 3 x 3 columns of 3 cells, bounded
//   by the correspondence distance) instead of a kd-tree: a far point costs 9 short scans,
//   where an unbounded kd-tree search for it walks much of the tree;
// - ICP stops once an iteration moves the phantoms by less than a micrometre.
// Together they take the type decision from seconds to about a millisecond per object on a
// 1080 x 1000 sweep, with the same decisions.

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// A mirror's phantoms, reflected across a plane fitted to its surface echoes, already land
// on the real scene; ICP only takes out the small error of the fitted plane. A larger
// correction means ICP slid them onto some other structure.
constexpr float kMaxCorrectionAngle = 5.0f * static_cast<float>(M_PI) / 180.0f;
constexpr int kIcpIterations = 30;
// ICP has converged when an iteration turns by less than this [rad] and moves by less than
// this [m] (0.5 mm at 5 m; the scanner's noise is 1 cm), or when the mean squared distance of
// the correspondences changed by less than this share.
constexpr float kIcpStepRotation = 1e-4f;
constexpr float kIcpStepTranslation = 1e-4f;
constexpr double kIcpRelativeMseChange = 1e-5;
constexpr int kPlaneRefinementIterations = 10;
constexpr int kNormalNeighbours = 20;
// At most this many of the points behind an object are registered (see the top of the file).
constexpr std::size_t kMaxSamples = 512;
// The real scene is thinned to one point per voxel of icp_max_distance / kVoxelsPerDistance,
// at most kMaxVoxel wide: the 1 cm noise of the scanner stays the largest error.
constexpr float kVoxelsPerDistance = 5.0f;
constexpr float kMaxVoxel = 0.02f;
// Most cells of the neighbour grid; a larger target box gets larger cells (still correct:
// a cell only has to be at least icp_max_distance wide).
constexpr std::size_t kMaxGridCells = std::size_t(1) << 20;
// Huber threshold of the plane refinement: this many robust sigmas (1.4826 MAD), and never
// below the scanner's noise.
constexpr float kHuberScale = 1.0f;
constexpr float kMadToSigma = 1.4826f;
constexpr float kMinHuberThreshold = 0.01f;
// Shape of a real point's neighbourhood that gives a trustworthy surface normal (ratios of
// its covariance eigenvalues, ascending).
constexpr float kMinSurfaceSpread = 0.05f;
constexpr float kMaxSurfaceThickness = 0.1f;
// Glass needs a clear contradiction: fewer than this share of the inlier fraction a mirror
// needs, before and after ICP. Between the two the evidence is ambiguous and the type stays
// unknown rather than being a confident wrong call (e.g. a mirror reflecting mostly sky).
constexpr float kGlassFractionOfRequired = 0.5f;

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// Beams per block of the sweep's block boxes (see ObjectTypeAnalyzer::beginSweep), and the
// slack of the tests on them, far above float rounding.
constexpr std::size_t kBlockBeams = 64;
constexpr float kBlockSlack = 1e-4f;

// Least and largest signed distance from the plane (n, d) of any point of the box.
float minSide(const Eigen::AlignedBox3f& box, const Eigen::Vector3f& n, float d)
{
  const Eigen::Vector3f centre = box.center();
  const Eigen::Vector3f half = 0.5f * box.sizes();
  return n.dot(centre) + d - n.cwiseAbs().dot(half);
}
float maxSide(const Eigen::AlignedBox3f& box, const Eigen::Vector3f& n, float d)
{
  const Eigen::Vector3f centre = box.center();
  const Eigen::Vector3f half = 0.5f * box.sizes();
  return n.dot(centre) + d + n.cwiseAbs().dot(half);
}

// Point i of echo 2 repeating echo 1 (a single return) is one measurement, not two.
bool isRepeatedReturn(const Sweep& sweep, std::size_t k, std::size_t i)
{
  return k == 1 && sweep.echoes[1].points[i] == sweep.echoes[0].points[i];
}

// The real points where phantoms can land, on a uniform grid of cells at least `reach` wide:
// every point within `reach` of a query lies in its cell or one of the 26 around it. Cells
// are numbered (x * ny + y) * nz + z, so the three cells of a column along z are one
// contiguous range of the sorted points.
class NeighbourGrid
{
public:
  void build(const std::vector<Eigen::Vector3f>& points, float reach)
  {
    reach_ = reach;
    Eigen::AlignedBox3f box;
    for (const Eigen::Vector3f& p : points)
      box.extend(p);
    // One spare cell on every side, so that the 3 x 3 x 3 block of any point in the box
    // stays inside the grid.
    double cell = reach;
    const Eigen::Vector3d extent = (box.max() - box.min()).cast<double>();
    while ((std::floor(extent.x() / cell) + 3) * (std::floor(extent.y() / cell) + 3) *
               (std::floor(extent.z() / cell) + 3) >
           static_cast<double>(kMaxGridCells))
      cell *= 1.5;
    inv_cell_ = static_cast<float>(1.0 / cell);
    corner_ = box.min() - Eigen::Vector3f::Constant(static_cast<float>(cell));
    nx_ = static_cast<std::size_t>(extent.x() / cell) + 3;
    ny_ = static_cast<std::size_t>(extent.y() / cell) + 3;
    nz_ = static_cast<std::size_t>(extent.z() / cell) + 3;

    // Counting sort by cell.
    start_.assign(nx_ * ny_ * nz_ + 1, 0);
    cell_of_.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      cell_of_[i] = cellIndex(points[i]);
      ++start_[cell_of_[i] + 1];
    }
    for (std::size_t c = 1; c < start_.size(); ++c)
      start_[c] += start_[c - 1];
    fill_.assign(start_.begin(), start_.end() - 1);
    sorted_.resize(points.size());
    original_.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      const std::uint32_t to = fill_[cell_of_[i]]++;
      sorted_[to] = points[i];
      original_[to] = static_cast<std::uint32_t>(i);
    }
  }

  // Index (into the points given to build) of the nearest point within reach of q, or kNone;
  // its squared distance in `squared`.
  std::uint32_t nearest(const Eigen::Vector3f& q, float& squared) const
  {
    float best = reach_ * reach_;
    std::uint32_t found = kNone;
    // The query's own cell first: a neighbour nearer than the cell's nearest face is the
    // nearest of all (the common case once ICP has aligned the phantoms), and the other 26
    // cells need no look.
    if (!sorted_.empty() && q.allFinite() && inside(q))
    {
      const std::uint32_t own = cellIndex(q);
      for (std::uint32_t j = start_[own]; j < start_[own + 1]; ++j)
      {
        const float d = (sorted_[j] - q).squaredNorm();
        if (d <= best)
        {
          best = d;
          found = j;
        }
      }
      const Eigen::Array3f c = ((q - corner_) * inv_cell_).array();
      const Eigen::Array3f fraction = c - c.floor();
      const float face = std::min(fraction.minCoeff(), (1.0f - fraction).minCoeff()) / inv_cell_;
      if (found != kNone && best < face * face)
      {
        squared = best;
        return original_[found];
      }
    }
    forEachColumn(q, [&](std::uint32_t begin, std::uint32_t end) {
      for (std::uint32_t j = begin; j < end; ++j)
      {
        const float d = (sorted_[j] - q).squaredNorm();
        if (d <= best)
        {
          best = d;
          found = j;
        }
      }
    });
    squared = best;
    return found == kNone ? kNone : original_[found];
  }

  // Indices of the (at most) k nearest points within reach of q, nearest first.
  void nearestK(const Eigen::Vector3f& q, std::size_t k, std::vector<std::pair<float, std::uint32_t>>& out) const
  {
    out.clear();
    const float max_squared = reach_ * reach_;
    forEachColumn(q, [&](std::uint32_t begin, std::uint32_t end) {
      for (std::uint32_t j = begin; j < end; ++j)
      {
        const float d = (sorted_[j] - q).squaredNorm();
        if (d <= max_squared)
          out.emplace_back(d, original_[j]);
      }
    });
    if (out.size() > k)
    {
      std::nth_element(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(k), out.end());
      out.resize(k);
    }
  }

private:
  std::uint32_t cellIndex(const Eigen::Vector3f& p) const
  {
    const Eigen::Vector3f c = (p - corner_) * inv_cell_;
    // Clamped to the grid's inner cells: only query points outside the box get here with
    // out-of-range coordinates, and for them the clamped block is still a superset of the
    // points within reach (none, or those near the border).
    auto axis = [](float v, std::size_t n) {
      return static_cast<std::size_t>(std::min(std::max(v, 1.0f), static_cast<float>(n - 2)));
    };
    return static_cast<std::uint32_t>((axis(c.x(), nx_) * ny_ + axis(c.y(), ny_)) * nz_ + axis(c.z(), nz_));
  }

  // Whether q lies in one of the grid's inner cells (where cellIndex needs no clamping).
  bool inside(const Eigen::Vector3f& q) const
  {
    const Eigen::Vector3f c = (q - corner_) * inv_cell_;
    return c.x() >= 1.0f && c.y() >= 1.0f && c.z() >= 1.0f && c.x() < static_cast<float>(nx_ - 1) &&
           c.y() < static_cast<float>(ny_ - 1) && c.z() < static_cast<float>(nz_ - 1);
  }

  template <typename Visit>
  void forEachColumn(const Eigen::Vector3f& q, Visit visit) const
  {
    if (sorted_.empty() || !q.allFinite())
      return;
    // A query further than reach outside the box has no neighbour.
    const Eigen::Vector3f c = (q - corner_) * inv_cell_;
    if (c.x() < 0.0f || c.y() < 0.0f || c.z() < 0.0f || c.x() >= static_cast<float>(nx_) ||
        c.y() >= static_cast<float>(ny_) || c.z() >= static_cast<float>(nz_))
      return;
    const std::uint32_t centre = cellIndex(q);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
      {
        const std::int64_t column = static_cast<std::int64_t>(centre) +
                                    (static_cast<std::int64_t>(dx) * static_cast<std::int64_t>(ny_) + dy) *
                                        static_cast<std::int64_t>(nz_);
        visit(start_[static_cast<std::size_t>(column - 1)], start_[static_cast<std::size_t>(column + 2)]);
      }
  }

  float reach_ = 0.0f;
  float inv_cell_ = 1.0f;
  Eigen::Vector3f corner_ = Eigen::Vector3f::Zero();
  std::size_t nx_ = 0, ny_ = 0, nz_ = 0;
  std::vector<std::uint32_t> start_;  // first sorted point of each cell, and the end
  std::vector<std::uint32_t> fill_;
  std::vector<std::uint32_t> cell_of_;
  std::vector<Eigen::Vector3f> sorted_;
  std::vector<std::uint32_t> original_;
};

// Open-addressing set of voxel keys, reused from object to object.
class VoxelSet
{
public:
  void reset(std::size_t expected)
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

  // True when the key was not in the set yet (and is now).
  bool insert(std::uint64_t key)
  {
    // Fibonacci hashing: the top bits of the product depend on every bit of the key.
    std::size_t slot = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ULL) >> shift_);
    while (keys_[slot] != kEmpty)
    {
      if (keys_[slot] == key)
        return false;
      slot = (slot + 1) & mask_;
    }
    keys_[slot] = key;
    return true;
  }

private:
  static constexpr std::uint64_t kEmpty = std::numeric_limits<std::uint64_t>::max();
  std::vector<std::uint64_t> keys_;
  std::size_t mask_ = 0;
  int shift_ = 58;  // 64 - log2(capacity)
};

// Cells of the landing box (at least icp_max_distance wide) within two cells of a sampled
// mirrored point: the only places where ICP (which moves the phantoms by at most
// icp_max_distance for a mirror) and the refinement look for real points. A room-sized box
// holds a hundred times more real points than these cells.
class LandingCells
{
public:
  void build(const Eigen::AlignedBox3f& box, float min_cell, const std::vector<Eigen::Vector3f>& mirrored)
  {
    const Eigen::Vector3d extent = (box.max() - box.min()).cast<double>();
    double cell = min_cell;
    while ((std::floor(extent.x() / cell) + 1) * (std::floor(extent.y() / cell) + 1) *
               (std::floor(extent.z() / cell) + 1) >
           static_cast<double>(kMaxGridCells))
      cell *= 1.5;
    inv_cell_ = static_cast<float>(1.0 / cell);
    corner_ = box.min();
    n_ = (extent / cell).array().floor().cast<std::int64_t>() + 1;
    marked_.assign(static_cast<std::size_t>(n_.prod()), 0);
    for (const Eigen::Vector3f& p : mirrored)
    {
      const Eigen::Array3f c = ((p - corner_) * inv_cell_).array().floor();
      Eigen::Array<std::int64_t, 3, 1> lo, hi;
      for (int a = 0; a < 3; ++a)
      {
        lo[a] = std::max<std::int64_t>(0, static_cast<std::int64_t>(c[a]) - 2);
        hi[a] = std::min<std::int64_t>(n_[a] - 1, static_cast<std::int64_t>(c[a]) + 2);
      }
      for (std::int64_t x = lo[0]; x <= hi[0]; ++x)
        for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
          for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
            marked_[static_cast<std::size_t>((x * n_[1] + y) * n_[2] + z)] = 1;
    }
  }

  // p must lie in the box given to build.
  bool contains(const Eigen::Vector3f& p) const
  {
    const Eigen::Vector3f c = (p - corner_) * inv_cell_;
    const std::int64_t x = std::min<std::int64_t>(static_cast<std::int64_t>(c.x()), n_[0] - 1);
    const std::int64_t y = std::min<std::int64_t>(static_cast<std::int64_t>(c.y()), n_[1] - 1);
    const std::int64_t z = std::min<std::int64_t>(static_cast<std::int64_t>(c.z()), n_[2] - 1);
    return marked_[static_cast<std::size_t>((x * n_[1] + y) * n_[2] + z)] != 0;
  }

private:
  float inv_cell_ = 1.0f;
  Eigen::Vector3f corner_ = Eigen::Vector3f::Zero();
  Eigen::Array<std::int64_t, 3, 1> n_ = Eigen::Array<std::int64_t, 3, 1>::Ones();
  std::vector<char> marked_;
};

std::uint64_t voxelKey(const Eigen::Vector3f& p, const Eigen::Vector3f& corner, float inv_voxel)
{
  // 21 bits per axis: the landing box is at most 2^21 voxels (42 km at 2 cm) wide.
  const Eigen::Vector3f c = (p - corner) * inv_voxel;
  auto axis = [](float v) { return static_cast<std::uint64_t>(std::min(std::max(v, 0.0f), 2097151.0f)); };
  return (axis(c.x()) << 42) | (axis(c.y()) << 21) | axis(c.z());
}
}  // namespace

struct ObjectTypeAnalyzer::Buffers
{
  // Bounding box of the finite points of each block of kBlockBeams beams, per echo, and the
  // sweep they belong to (see beginSweep).
  std::array<std::vector<Eigen::AlignedBox3f>, 2> block_boxes;
  const Sweep* boxes_of = nullptr;
  std::size_t boxes_beams = 0;

  std::vector<Eigen::Vector3f> all_behind;    // every point behind the object, as measured
  std::vector<Eigen::Vector3f> behind;        // the sample of them that is registered
  std::vector<Eigen::Vector3f> mirrored;      // the sample reflected across the plane
  std::vector<Eigen::Vector3f> aligned;       // mirrored, moved by ICP
  std::vector<Eigen::Vector3f> candidates;    // real points where the sample can land
  LandingCells landing;
  std::vector<Eigen::Vector3f> real;          // candidates thinned to one per voxel
  NeighbourGrid grid;
  VoxelSet voxels;
  Eigen::Matrix3Xf source_matches;
  Eigen::Matrix3Xf target_matches;

  std::vector<Eigen::Vector3f> surface;  // the surface echoes its plane was fitted to
  struct Correspondence
  {
    Eigen::Vector3d jacobian;
    float residual;
  };
  std::vector<Correspondence> correspondences;
  std::vector<float> absolute_residuals;
  std::vector<Eigen::Vector3f> real_normals;  // NaN: not computed yet; infinite: no surface there
  std::vector<std::pair<float, std::uint32_t>> neighbourhood;

  // The surface normal of the real scene at real point `index`, from its nearest neighbours.
  const Eigen::Vector3f& realNormal(std::size_t index);

  // Points within max_distance of a real point, and their squared distances' sum.
  std::size_t countMatches(const std::vector<Eigen::Vector3f>& points, double& squared_sum) const;
  // Point-to-point ICP of `mirrored` onto `real` (the correspondences within max_distance,
  // the rigid motion that best aligns them, repeated); leaves the result in `aligned`.
  // With stop_when_too_far, stops once the correction exceeds what a mirror allows.
  bool registerMirrored(bool stop_when_too_far, float max_distance, Eigen::Matrix4f& correction);
  void refineMirrorPlane(const Eigen::Vector3f& origin, float max_distance, double phantom_weight,
                         ReflectiveObject& object);
};

ObjectTypeAnalyzer::ObjectTypeAnalyzer(const ObjectTypeConfig& config) : config_(config), buffers_(new Buffers)
{
}
ObjectTypeAnalyzer::~ObjectTypeAnalyzer() = default;
ObjectTypeAnalyzer::ObjectTypeAnalyzer(ObjectTypeAnalyzer&&) noexcept = default;
ObjectTypeAnalyzer& ObjectTypeAnalyzer::operator=(ObjectTypeAnalyzer&&) noexcept = default;

void ObjectTypeAnalyzer::beginSweep(const Sweep& sweep)
{
  Buffers& b = *buffers_;
  const std::size_t beams = sweep.beamCount();
  for (std::size_t k = 0; k < 2; ++k)
  {
    std::vector<Eigen::AlignedBox3f>& boxes = b.block_boxes[k];
    boxes.resize((beams + kBlockBeams - 1) / kBlockBeams);
    const Eigen::Vector3f* points = sweep.echoes[k].points.data();
    for (std::size_t block = 0; block < boxes.size(); ++block)
      boxes[block] = blockBox(points, block * kBlockBeams, std::min(beams, (block + 1) * kBlockBeams),
                              [](std::size_t) { return true; })
                         .box;
  }
  b.boxes_of = &sweep;
  b.boxes_beams = beams;
}

void ObjectTypeAnalyzer::analyze(const Sweep& sweep, const Eigen::Vector3f& sensor_origin, const SweepLabels& labels,
                                 ReflectiveObject& object)
{
  Buffers& b = *buffers_;
  const bool blocked = b.boxes_of == &sweep && b.boxes_beams == sweep.beamCount();
  const Eigen::Vector3f normal = object.plane.head<3>();
  const float plane_offset = object.plane[3];
  TypeEvidence& evidence = object.evidence;
  evidence = TypeEvidence();
  object.type = ObjectType::unknown;

  const float plane_threshold = static_cast<float>(config_.plane_threshold);
  const float margin = static_cast<float>(config_.cone_margin);
  const float max_distance = static_cast<float>(config_.icp_max_distance);
  const std::size_t min_points = static_cast<std::size_t>(config_.icp_min_points);

  b.all_behind.clear();
  const VisionCone cone(object, sensor_origin, plane_threshold, margin);
  Eigen::AlignedBox3f landing_zone;
  Eigen::Vector3f direction_sum = Eigen::Vector3f::Zero();
  const std::size_t beams = sweep.beamCount();
  for (std::size_t k = 0; k < 2; ++k)
  {
    for (std::size_t i = 0; i < beams; ++i)
    {
      // A block whose box lies wholly in front of the plane's surface band has no point behind.
      if (blocked && i % kBlockBeams == 0)
      {
        const Eigen::AlignedBox3f& box = b.block_boxes[k][i / kBlockBeams];
        if (box.isEmpty() || minSide(box, normal, plane_offset) > -plane_threshold + kBlockSlack)
        {
          i += kBlockBeams - 1;
          continue;
        }
      }
      if (labels.echoes[k][i] == Label::nanPoint || isRepeatedReturn(sweep, k, i))
        continue;
      const Eigen::Vector3f& p = sweep.echoes[k].points[i];
      // Most points are in front of the plane: skip them before the cone test.
      if (!(cone.side(p) < -plane_threshold) || cone.locate(p).relation != ConeRelation::behind)
        continue;
      const Eigen::Vector3f mirrored = object.reflect(p);
      b.all_behind.push_back(p);
      landing_zone.extend(mirrored);
      direction_sum += (mirrored - sensor_origin).normalized();
    }
  }
  evidence.mirrored_points = b.all_behind.size();
  if (evidence.mirrored_points < min_points)
    return;

  // The sample: kMaxSamples points spread evenly over the behind points in beam order.
  b.behind.clear();
  b.mirrored.clear();
  const std::size_t total = b.all_behind.size();
  const std::size_t samples = std::min(total, kMaxSamples);
  for (std::size_t s = 0; s < samples; ++s)
  {
    const Eigen::Vector3f& p = b.all_behind[(2 * s + 1) * total / (2 * samples)];
    b.behind.push_back(p);
    b.mirrored.push_back(object.reflect(p));
  }
  // Every sampled phantom stands for this many in the plane refinement's least squares.
  const double phantom_weight = static_cast<double>(total) / static_cast<double>(samples);

  // The directions in which the mirrored points lie, as a cone around their mean direction:
  // real points seen in it tell that the sensor looked there.
  const Eigen::Vector3f mean_direction = direction_sum.normalized();
  float min_cosine = 1.0f;
  for (const Eigen::Vector3f& p : b.all_behind)
    min_cosine = std::min(min_cosine, (object.reflect(p) - sensor_origin).normalized().dot(mean_direction));

  // d.m >= c |d| without a square root per point (c may be negative for a very wide spread).
  const float min_cosine_squared = min_cosine * min_cosine;
  auto inTheirDirections = [&](const Eigen::Vector3f& d) {
    const float along = d.dot(mean_direction);
    if (min_cosine >= 0.0f)
      return along >= 0.0f && along * along >= min_cosine_squared * d.squaredNorm();
    return along >= 0.0f || along * along <= min_cosine_squared * d.squaredNorm();
  };
  landing_zone.min().array() -= max_distance;
  landing_zone.max().array() += max_distance;
  b.landing.build(landing_zone, max_distance, b.mirrored);
  b.candidates.clear();
  std::size_t seen_in_their_directions = 0;
  Eigen::AlignedBox3f grown_landing_zone = landing_zone;
  grown_landing_zone.min().array() -= kBlockSlack;
  grown_landing_zone.max().array() += kBlockSlack;
  for (std::size_t k = 0; k < 2; ++k)
  {
    for (std::size_t i = 0; i < beams; ++i)
    {
      // Blocks with no point in front of the plane, or, once enough points were seen in the
      // phantoms' directions, none in the landing box, hold nothing for this loop.
      if (blocked && i % kBlockBeams == 0)
      {
        const Eigen::AlignedBox3f& box = b.block_boxes[k][i / kBlockBeams];
        if (box.isEmpty() || maxSide(box, normal, plane_offset) < plane_threshold - kBlockSlack ||
            (seen_in_their_directions >= min_points && !box.intersects(grown_landing_zone)))
        {
          i += kBlockBeams - 1;
          continue;
        }
      }
      const Label label = labels.echoes[k][i];
      if ((label != Label::unchecked && label != Label::valid) || isRepeatedReturn(sweep, k, i))
        continue;
      const Eigen::Vector3f& p = sweep.echoes[k].points[i];
      if (!(cone.side(p) > plane_threshold))
        continue;
      // Only whether there are icp_min_points matters.
      if (seen_in_their_directions < min_points && inTheirDirections(p - sensor_origin))
        ++seen_in_their_directions;
      if (landing_zone.contains(p) && b.landing.contains(p))
        b.candidates.push_back(p);
    }
  }
  if (seen_in_their_directions < min_points)
    return;

  // One real point per voxel (the first in beam order).
  const float voxel = std::min(max_distance / kVoxelsPerDistance, kMaxVoxel);
  b.real.clear();
  b.voxels.reset(b.candidates.size());
  for (const Eigen::Vector3f& p : b.candidates)
    if (b.voxels.insert(voxelKey(p, landing_zone.min(), 1.0f / voxel)))
      b.real.push_back(p);
  if (b.candidates.size() < 3)
  {
    // The sensor looked there and nothing real lies where the mirrored points land.
    evidence.inlier_fraction = 0.0f;
    object.type = ObjectType::glass;
    return;
  }
  b.grid.build(b.real, max_distance);

  // Shares of the sample within max_distance of a real point before ICP, and after it.
  double unused = 0.0;
  const float fraction_before_icp = static_cast<float>(b.countMatches(b.mirrored, unused)) / samples;
  const float min_fraction = static_cast<float>(config_.icp_min_inlier_fraction);
  // Once ICP has moved the phantoms further than a mirror's may move, the object is no
  // mirror; if enough of them matched before ICP it is no glass either, and nothing ICP does
  // next can change that: it may stop there (on scenes where it slides along a floor, most of
  // its iterations).
  const bool may_stop_when_too_far = !(fraction_before_icp < kGlassFractionOfRequired * min_fraction);
  evidence.icp_converged = b.registerMirrored(may_stop_when_too_far, max_distance, evidence.icp_correction);

  double squared_sum = 0.0;
  const std::size_t matched = b.countMatches(b.aligned, squared_sum);
  evidence.inlier_fraction = static_cast<float>(matched) / static_cast<float>(samples);
  evidence.matched_points =
      static_cast<std::size_t>(std::lround(static_cast<double>(evidence.inlier_fraction) * total));
  evidence.icp_fitness =
      matched > 0 ? static_cast<float>(squared_sum / matched) : std::numeric_limits<float>::infinity();
  const Eigen::Affine3f correction(evidence.icp_correction);
  const float correction_angle = Eigen::AngleAxisf(correction.rotation()).angle();
  const bool small_correction =
      correction.translation().norm() <= max_distance && correction_angle <= kMaxCorrectionAngle;
  const bool fits = evidence.icp_converged && small_correction && evidence.inlier_fraction >= min_fraction &&
                    evidence.icp_fitness <= static_cast<float>(config_.icp_fitness_threshold);
  if (fits)
  {
    object.type = ObjectType::mirror;
    b.surface.clear();
    for (const PointRef& ref : object.surface_inliers)
      b.surface.push_back(sweep.echoes[ref.echo].points[ref.beam]);
    b.refineMirrorPlane(sensor_origin, max_distance, phantom_weight, object);
  }
  else if (std::max(fraction_before_icp, evidence.inlier_fraction) < kGlassFractionOfRequired * min_fraction)
    object.type = ObjectType::glass;
}

bool ObjectTypeAnalyzer::Buffers::registerMirrored(bool stop_when_too_far, float max_distance,
                                                   Eigen::Matrix4f& correction)
{
  correction.setIdentity();
  aligned = mirrored;
  bool converged = false;
  double previous_mse = -1.0;
  for (int iteration = 0; iteration < kIcpIterations; ++iteration)
  {
    std::size_t used = 0;
    double squared_sum = 0.0;
    source_matches.resize(3, static_cast<Eigen::Index>(aligned.size()));
    target_matches.resize(3, static_cast<Eigen::Index>(aligned.size()));
    for (const Eigen::Vector3f& p : aligned)
    {
      float squared = 0.0f;
      const std::uint32_t nearest = grid.nearest(p, squared);
      if (nearest == kNone)
        continue;
      squared_sum += squared;
      source_matches.col(static_cast<Eigen::Index>(used)) = p;
      target_matches.col(static_cast<Eigen::Index>(used)) = real[nearest];
      ++used;
    }
    // Like PCL's ICP: fewer than 3 correspondences cannot fix a rigid motion.
    if (used < 3)
      return false;
    converged = true;
    const Eigen::Matrix4f step = Eigen::umeyama(source_matches.leftCols(static_cast<Eigen::Index>(used)),
                                                target_matches.leftCols(static_cast<Eigen::Index>(used)), false);
    if (!step.allFinite())
      return false;
    const Eigen::Affine3f motion(step);
    for (Eigen::Vector3f& p : aligned)
      p = motion * p;
    correction = step * correction;
    const double mse = squared_sum / static_cast<double>(used);
    if ((Eigen::AngleAxisf(motion.linear()).angle() < kIcpStepRotation &&
         motion.translation().norm() < kIcpStepTranslation) ||
        (previous_mse >= 0.0 && std::fabs(mse - previous_mse) <= kIcpRelativeMseChange * previous_mse))
    {
      break;
    }
    previous_mse = mse;
    if (stop_when_too_far)
    {
      const Eigen::Affine3f total(correction);
      if (total.translation().norm() > max_distance ||
          Eigen::AngleAxisf(total.linear()).angle() > kMaxCorrectionAngle)
        break;
    }
  }
  // Reaching the iteration cap counts as converged, as in PCL.
  return converged;
}

void ObjectTypeAnalyzer::Buffers::refineMirrorPlane(const Eigen::Vector3f& origin, float max_distance,
                                                   double phantom_weight, ReflectiveObject& object)
{
  // The plane fitted to a mirror's surface echoes is good to a few tenths of a degree (a
  // thousand echoes with 1 cm noise on 60 x 40 cm); reflection multiplies that by the
  // phantoms' distance behind the mirror: 0.1 deg is 2 cm at 5 m. The phantoms and the real
  // scene they show pin the plane down far better: find the plane whose reflection puts the
  // phantoms onto the real surfaces. Only the mirror's 3 degrees of freedom (normal tilt,
  // offset) are estimated, by Gauss-Newton; residuals are point-to-plane distances to the
  // real surface at the nearest real point, because point-to-point residuals carry the
  // offset between two samplings of a wall, which biases the tilt by as much again. The
  // surface echoes' distances to the plane stay in the same least squares (same noise, same
  // weight; each sampled phantom weighs for the phantoms it stands for): where the phantoms
  // constrain the plane poorly (all on one floor, say), the surface echoes keep it.
  (void)max_distance;  // the grid's reach
  Eigen::Vector3f normal = object.plane.head<3>();
  float offset = object.plane[3];
  real_normals.assign(real.size(), Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
  for (int iteration = 0; iteration < kPlaneRefinementIterations; ++iteration)
  {
    const Eigen::Vector3f helper = std::fabs(normal.z()) < 0.9f ? Eigen::Vector3f::UnitZ() : Eigen::Vector3f::UnitX();
    const Eigen::Vector3f u = normal.cross(helper).normalized();
    const Eigen::Vector3f v = normal.cross(u);
    Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
    Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3f& s : surface)
    {
      const Eigen::Vector3d jacobian(u.dot(s), v.dot(s), 1.0);
      hessian += jacobian * jacobian.transpose();
      gradient += jacobian * static_cast<double>(normal.dot(s) + offset);
    }
    // Phantom residuals first, then a robust (Huber) weight from their spread: a phantom
    // matched to the wrong surface (a corner, a part of the room the sensor did not see)
    // must not drag the mirror.
    correspondences.clear();
    for (const Eigen::Vector3f& p : behind)
    {
      const float side = normal.dot(p) + offset;
      const Eigen::Vector3f mirrored = p - 2.0f * side * normal;
      float squared = 0.0f;
      const std::uint32_t nearest = grid.nearest(mirrored, squared);
      if (nearest == kNone)
        continue;
      const Eigen::Vector3f& surface_normal = realNormal(nearest);
      if (!surface_normal.allFinite())
        continue;
      const float residual = surface_normal.dot(mirrored - real[nearest]);
      // Derivatives of p - 2 (n.p + d) n for n tilted towards u, towards v, and for d,
      // projected on the real surface's normal.
      const Eigen::Vector3d jacobian(surface_normal.dot(-2.0f * (u.dot(p) * normal + side * u)),
                                     surface_normal.dot(-2.0f * (v.dot(p) * normal + side * v)),
                                     surface_normal.dot(-2.0f * normal));
      correspondences.push_back({ jacobian, residual });
    }
    const std::size_t used = correspondences.size();
    if (used < 3)
      return;
    absolute_residuals.resize(used);
    for (std::size_t c = 0; c < used; ++c)
      absolute_residuals[c] = std::fabs(correspondences[c].residual);
    std::nth_element(absolute_residuals.begin(), absolute_residuals.begin() + used / 2, absolute_residuals.end());
    const float huber = std::max(kHuberScale * kMadToSigma * absolute_residuals[used / 2], kMinHuberThreshold);
    for (const Correspondence& c : correspondences)
    {
      const float magnitude = std::fabs(c.residual);
      const double weight = phantom_weight * (magnitude <= huber ? 1.0 : huber / magnitude);
      hessian += weight * c.jacobian * c.jacobian.transpose();
      gradient += weight * c.jacobian * static_cast<double>(c.residual);
    }
    const Eigen::Vector3d step = -hessian.ldlt().solve(gradient);
    if (!step.allFinite())
      return;
    normal = (normal + static_cast<float>(step[0]) * u + static_cast<float>(step[1]) * v).normalized();
    offset += static_cast<float>(step[2]);
    if (step.head<2>().norm() < 1e-6 && std::fabs(step[2]) < 1e-5)
      break;
  }
  // A refinement that turned the plane away from the sensor, or by more than ICP may move
  // the phantoms, fitted something else: keep the surface plane.
  if (!(normal.dot(origin) + offset > 0.0f) || normal.dot(object.plane.head<3>()) < std::cos(kMaxCorrectionAngle))
    return;
  object.plane.head<3>() = normal;
  object.plane[3] = offset;
  object.centre -= object.signedDistance(object.centre) * normal;
  // Keep the rectangle's axes in the refined plane (they turn by a fraction of a degree).
  object.width_axis = (object.width_axis - object.width_axis.dot(normal) * normal).normalized();
  object.height_axis = normal.cross(object.width_axis);
}

const Eigen::Vector3f& ObjectTypeAnalyzer::Buffers::realNormal(std::size_t index)
{
  Eigen::Vector3f& normal = real_normals[index];
  if (normal.allFinite() || std::isinf(normal.x()))
    return normal;
  // Computed on first use: only the real points phantoms land on need one. The neighbours
  // are the nearest ones within the grid's reach (icp_max_distance).
  grid.nearestK(real[index], kNormalNeighbours, neighbourhood);
  normal.setConstant(std::numeric_limits<float>::infinity());  // too few neighbours: no surface
  if (neighbourhood.size() < 3)
    return normal;
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  for (const auto& n : neighbourhood)
    centroid += real[n.second];
  centroid /= static_cast<float>(neighbourhood.size());
  Eigen::Matrix3f covariance = Eigen::Matrix3f::Zero();
  for (const auto& n : neighbourhood)
  {
    const Eigen::Vector3f d = real[n.second] - centroid;
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

std::size_t ObjectTypeAnalyzer::Buffers::countMatches(const std::vector<Eigen::Vector3f>& points,
                                                      double& squared_sum) const
{
  std::size_t matched = 0;
  squared_sum = 0.0;
  for (const Eigen::Vector3f& p : points)
  {
    float squared = 0.0f;
    if (grid.nearest(p, squared) != kNone)
    {
      ++matched;
      squared_sum += squared;
    }
  }
  return matched;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
