// Object extraction (separateObject of the paper). Conventions of the objects made here:
// - plane: least-squares (PCA) plane of the patch, unit normal towards the sensor origin;
// - rectangle: minimum-area rectangle of the patch's points projected into that plane,
//   each extent grown by the part of the patch's typical sampling spacing that the beams'
//   footprint does not already cover (see buildObject);
// - width_axis: the rectangle side with the smaller |z| (more horizontal); on a plane within
//   10 deg of horizontal, the longer side;
// - height_axis = normal x width_axis, so width_axis x height_axis = normal (right-handed);
//   signs chosen so that height_axis points up (z > 0), or on a horizontal plane away from
//   the sensor. Seen from the sensor, width runs to the right and height up, and
//   ReflectiveObject::corners() go counter-clockwise.
#include "ohm_mirror_detector3d/core/object_extraction.h"

#include <pcl/PointIndices.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/ransac.h>
#include <pcl/sample_consensus/sac_model_plane.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "ohm_mirror_detector3d/core/min_area_rectangle.h"
#include "ohm_mirror_detector3d/core/spatial_index.h"
#include "ohm_mirror_detector3d/core/sweep_sampling.h"

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
using Cloud = pcl::PointCloud<pcl::PointXYZ>;
// pcl::Indices from PCL 1.11 on, std::vector<int> in PCL 1.10 (ROS Noetic).
using IndexVector = decltype(pcl::PointIndices::indices);

// Upper bound of RANSAC trials per plane. PCL stops earlier once a plane with the inlier
// fraction found so far would have been drawn with probability 0.99; the bound only
// matters when the remaining points are mostly off-plane clutter.
constexpr int kRansacMaxIterations = 1000;

// |n.z| above cos(10 deg): the plane counts as horizontal (floor or ceiling mirror), and
// its longer side is the width.
// Most points whose nearest neighbour is looked up to estimate a patch's spacing.
constexpr std::size_t kSpacingSamples = 2048;

const double kHorizontalNormalZ = 0.98480775301220806;  // cos(10 deg)

// The plane of a patch is refitted on the points within 3 robust sigma of it (see
// buildObject): 3 sigma removes a frame or wall 2-4 cm in front of a pane on every sensor family
// (surface noise 0.3-1 cm) and keeps 99.7 % of Gaussian noise; never nearer than 1 cm, so that a
// noise-free or quantised patch keeps its points. The kept set settles within a few rounds.
constexpr int kPlaneTrimIterations = 10;
constexpr double kPlaneTrimSigmas = 3.0;
constexpr double kPlaneTrimMinCutoff = 0.01;  // [m]
// A patch whose second spread is less than this many times its smallest (in variance: the
// extent across the strip under about 3 x the spread along the normal) does not fix its normal
// around its long axis; when its fitted normal is then more than 45 degrees from the beam, the
// plane facing the beam is taken (buildObject). Measured on held-out random scenes 42000-44024 of
// the four families and `make evaluate` (a temporary switch): 5 panes found or typed right that
// were not (the rotating Hokuyo, the 32-ring lidar), none the other way; ratios 5 and 20 changed
// the same objects (README, stop 50).
constexpr double kStripEigenvalueRatio = 10.0;
const double kMinStripIncidenceCosine = 0.70710678118654752;  // cos(45 deg)
// The least-median start of the cut: a sample of at most 256 points of the patch, 200 planes
// through three of them (with a quarter of the triples mixing in a frame's 15 % of the points,
// some 75 trials hit three of the pane's points, spread over it).
constexpr std::size_t kMedianSamples = 256;
constexpr int kMedianTrials = 200;
constexpr unsigned kMedianSeed = 12345;

// Key offsets of the 62 cells in [-2, 2]^3 that come after (0, 0, 0) in lexicographic order:
// every pair of neighbouring cells is visited once.
std::array<std::int64_t, 62> forwardCellOffsets()
{
  std::array<std::int64_t, 62> offsets{};
  std::size_t k = 0;
  for (std::int64_t dx = -2; dx <= 2; ++dx)
    for (std::int64_t dy = -2; dy <= 2; ++dy)
      for (std::int64_t dz = -2; dz <= 2; ++dz)
        if (dx > 0 || (dx == 0 && (dy > 0 || (dy == 0 && dz > 0))))
          offsets[k++] = dx * cell_key::kStepX + dy * cell_key::kStepY + dz * cell_key::kStepZ;
  return offsets;
}

// PCL's plane model as RANSAC uses it, with a faster inlier count. RANSAC scores each of
// its up to kRansacMaxIterations trial planes by countWithinDistance over every remaining
// candidate; PCL's generic version (as packaged, without SSE4.1) gathers each point through
// the index list into an Eigen vector and takes one dot product at a time. Here the
// candidates are copied once per plane search into contiguous coordinate arrays, and the
// count is a branch-free loop over them that the compiler vectorises. The count is the
// same number as PCL's for every trial plane: the same float operations in the same order
// (Eigen's 4-element dot sums as (a x + c z) + (b y + d)) and the same comparison against
// the threshold as a double, so RANSAC picks the same planes.
class CountingPlaneModel : public pcl::SampleConsensusModelPlane<pcl::PointXYZ>
{
public:
  CountingPlaneModel(const Cloud::ConstPtr& cloud, const IndexVector& indices, const std::vector<float>& xs,
                     const std::vector<float>& ys, const std::vector<float>& zs)
    : pcl::SampleConsensusModelPlane<pcl::PointXYZ>(cloud, indices, false), xs_(xs), ys_(ys), zs_(zs)
  {
  }

  // The base's own return type (std::size_t in the PCL versions we build with).
  using Count = decltype(std::declval<const pcl::SampleConsensusModelPlane<pcl::PointXYZ>&>().countWithinDistance(
      std::declval<const Eigen::VectorXf&>(), 0.0));

  Count countWithinDistance(const Eigen::VectorXf& model_coefficients, const double threshold) const override
  {
    if (!isModelValid(model_coefficients) || xs_.size() != indices_->size())
      return pcl::SampleConsensusModelPlane<pcl::PointXYZ>::countWithinDistance(model_coefficients, threshold);
    // |d| < threshold (as double) holds for a float d exactly when |d| < the smallest float
    // not below the threshold.
    float limit = static_cast<float>(threshold);
    if (static_cast<double>(limit) < threshold)
      limit = std::nextafter(limit, std::numeric_limits<float>::infinity());
    const float a = model_coefficients[0];
    const float b = model_coefficients[1];
    const float c = model_coefficients[2];
    const float d = model_coefficients[3];
    const float* x = xs_.data();
    const float* y = ys_.data();
    const float* z = zs_.data();
    const std::size_t n = xs_.size();
    std::uint32_t count = 0;
    for (std::size_t i = 0; i < n; ++i)
    {
      const float distance = (a * x[i] + c * z[i]) + (b * y[i] + d * 1.0f);
      count += std::fabs(distance) < limit ? 1u : 0u;
    }
    return static_cast<Count>(count);
  }

private:
  const std::vector<float>& xs_;
  const std::vector<float>& ys_;
  const std::vector<float>& zs_;
};

// Scratch of groupByRoot, kept across sweeps so that grouping allocates nothing.
struct GroupingScratch
{
  std::vector<std::int32_t> group_of_root;
  std::vector<std::uint32_t> item_group;
  std::vector<std::uint32_t> fill;
};

// Groups items 0 .. n - 1 by their union-find root (root_of(i) < root_count): groups are numbered
// in the order of their first item and keep their items ascending (a stable counting sort);
// group k is members[start[k] .. start[k + 1]). Returns the number of groups.
template <typename RootOf>
std::size_t groupByRoot(std::uint32_t n, std::size_t root_count, RootOf root_of, GroupingScratch& scratch,
                        std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& members)
{
  scratch.group_of_root.assign(root_count, -1);
  scratch.item_group.resize(n);
  start.assign(1, 0);
  for (std::uint32_t i = 0; i < n; ++i)
  {
    const std::uint32_t root = root_of(i);
    if (scratch.group_of_root[root] < 0)
    {
      scratch.group_of_root[root] = static_cast<std::int32_t>(start.size() - 1);
      start.push_back(0);
    }
    scratch.item_group[i] = static_cast<std::uint32_t>(scratch.group_of_root[root]);
    ++start[scratch.item_group[i] + 1];
  }
  const std::size_t groups = start.size() - 1;
  for (std::size_t g = 0; g < groups; ++g)
    start[g + 1] += start[g];
  scratch.fill.assign(start.begin(), start.end() - 1);
  members.resize(n);
  for (std::uint32_t i = 0; i < n; ++i)
    members[scratch.fill[scratch.item_group[i]]++] = i;
  return groups;
}

}  // namespace

struct ObjectExtractor::Workspace
{
  // Unassigned-or-not errorSurface points of the sweep (candidates), in beam order.
  Cloud::Ptr cloud{ new Cloud };
  std::vector<PointRef> refs;
  std::vector<char> assigned;
  IndexVector remaining;  // candidates not yet assigned to a plane, ascending
  std::vector<float> remaining_x, remaining_y, remaining_z;  // their coordinates, same order
  IndexVector inliers;
  IndexVector refined_inliers;
  Eigen::VectorXf coefficients;
  Eigen::VectorXf refined_coefficients;

  // Connected components of one plane's inliers on the spatial index with cells of half the
  // connection distance (any two points of one cell are connected; a partner is at most two
  // cells away).
  std::vector<Eigen::Vector3f> inlier_points;  // positions of `inliers`, same order
  SpatialIndex index;                     // of inlier_points, ids their positions
  std::vector<std::uint32_t> parent;      // union-find over the index's cells
  std::vector<std::uint32_t> patch_start;  // patch_count + 1 entries
  std::vector<std::uint32_t> patch_members;  // inlier positions grouped by patch, ascending

  // Connectivity on the sweep's grid: groups of candidates (positions into a member list),
  // group k is group_members[group_start[k] .. group_start[k + 1]).
  std::vector<std::int32_t> member_of_beam;  // per beam: position in the member list, or -1
  std::vector<std::uint32_t> member_parent;  // union-find over the member list
  std::vector<std::uint32_t> group_start;
  std::vector<std::uint32_t> group_members;
  GroupingScratch grouping;  // of splitPatches and groupOnGrid (never in use at once)
  // The connected groups of all candidates while their planes are fitted (groupOnGrid's
  // buffers then serve the patches).
  IndexVector candidates;
  std::vector<std::uint32_t> candidate_group_start;
  std::vector<std::uint32_t> candidate_group_members;
  // Beams across a patch: its points in grid order and the runs through them.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> grid_order;
  std::vector<std::uint32_t> run_along_row;
  std::vector<std::uint32_t> across;
  SamplingEstimator sampling_estimator;  // for extract() without a sampling

  // One patch in its plane.
  std::vector<Eigen::Vector2d> projected;
  std::vector<Eigen::Vector2d> hull;
  std::vector<std::pair<double, std::uint32_t>> sweep_order;
  std::vector<double> nearest;
  std::vector<std::uint8_t> kept;       // per patch point: within the plane's trim band
  std::vector<double> abs_residuals;    // per patch point: distance to the plane
  std::vector<double> sorted_residuals;  // the same, partly sorted for the median
  std::vector<Eigen::Vector3d> median_sample;  // leastMedianPlane's sample of the patch
  std::vector<double> sample_distance;          // and its distances to a trial plane

  std::uint32_t findMember(std::uint32_t m)
  {
    while (member_parent[m] != m)
    {
      member_parent[m] = member_parent[member_parent[m]];
      m = member_parent[m];
    }
    return m;
  }

  std::uint32_t find(std::uint32_t cell)
  {
    while (parent[cell] != cell)
    {
      parent[cell] = parent[parent[cell]];
      cell = parent[cell];
    }
    return cell;
  }

  void gather(const Sweep& sweep, const SweepLabels& labels);
  std::size_t splitPatches(double connection_distance);
  std::size_t groupOnGrid(const Sweep& sweep, const BeamNeighbourhood& neighbourhood, const IndexVector& members);
  void patchesFromGroups(const Sweep& sweep, const BeamNeighbourhood& neighbourhood);
  std::size_t beamsAcross(const SweepSampling& sampling, const IndexVector& members, const std::uint32_t* positions,
                          std::size_t count);
  bool anyPairCloser(std::uint32_t a, std::uint32_t b, float squared_distance) const;
  double typicalSpacing(const Eigen::Vector2d& sweep_direction);
  // Replaces the plane (normal, point) of patch points begin .. begin + count by the plane
  // through three of them that has the least median distance to a sample of them, when that
  // median is less than the given plane's.
  void leastMedianPlane(std::uint32_t begin, std::uint32_t count, Eigen::Vector3d& normal, Eigen::Vector3d& point);
  // Returns the patch's typical sample spacing. footprint_angle: the full angle of a beam's
  // footprint [rad].
  double buildObject(const Eigen::Vector3f& ransac_normal, const Eigen::Vector3f& origin, double footprint_angle,
                     std::uint32_t patch, ReflectiveObject& object);
  // The planes of the candidates in `remaining` (RANSAC loop), each cut into patches; appends
  // the patches that can be objects.
  void fitPlanes(const Sweep& sweep, const SweepSampling& sampling, const Eigen::Vector3f& origin,
                 const ObjectExtractionConfig& config, const BeamNeighbourhood* neighbourhood,
                 std::vector<ReflectiveObject>& objects);
};

void ObjectExtractor::WorkspaceDeleter::operator()(Workspace* workspace) const
{
  delete workspace;
}

void ObjectExtractor::Workspace::gather(const Sweep& sweep, const SweepLabels& labels)
{
  Cloud& c = *cloud;
  c.points.clear();
  refs.clear();
  const std::size_t beams = sweep.beamCount();
  for (std::size_t beam = 0; beam < beams; ++beam)
  {
    for (std::uint8_t echo = 0; echo < 2; ++echo)
    {
      if (labels.echoes[echo][beam] != Label::errorSurface)
        continue;
      const Eigen::Vector3f& p = sweep.echoes[echo].points[beam];
      if (!p.allFinite())
        continue;
      c.points.push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
      refs.push_back(PointRef{ static_cast<std::uint32_t>(beam), echo });
    }
  }
  c.width = static_cast<std::uint32_t>(c.points.size());
  c.height = 1;
  c.is_dense = true;
  assigned.assign(refs.size(), 0);
  remaining.resize(refs.size());
  for (std::size_t i = 0; i < refs.size(); ++i)
    remaining[i] = static_cast<int>(i);
}

bool ObjectExtractor::Workspace::anyPairCloser(std::uint32_t a, std::uint32_t b, float squared_distance) const
{
  const std::uint32_t* ids = index.sortedId();
  const std::uint32_t a_end = index.cellBegin(a) + index.cellSize(a);
  const std::uint32_t b_end = index.cellBegin(b) + index.cellSize(b);
  for (std::uint32_t i = index.cellBegin(a); i < a_end; ++i)
  {
    const Eigen::Vector3f& p = inlier_points[ids[i]];
    for (std::uint32_t j = index.cellBegin(b); j < b_end; ++j)
      if ((inlier_points[ids[j]] - p).squaredNorm() < squared_distance)
        return true;
  }
  return false;
}

// Splits `inliers` (ascending) into connected patches; patch k is
// patch_members[patch_start[k] .. patch_start[k + 1]), patches numbered in the order of their
// first point. Returns the number of patches.
std::size_t ObjectExtractor::Workspace::splitPatches(double connection_distance)
{
  static const std::array<std::int64_t, 62> kOffsets = forwardCellOffsets();
  const std::size_t n = inliers.size();
  // Cell diagonal 0.87 * distance; the floor only guards a zero radius from direct callers.
  const double cell_size = std::max(0.5 * connection_distance, 1e-6);

  inlier_points.resize(n);
  index.reservePoints(n);
  for (std::size_t k = 0; k < n; ++k)
  {
    const pcl::PointXYZ& q = cloud->points[static_cast<std::size_t>(inliers[k])];
    inlier_points[k] = Eigen::Vector3f(q.x, q.y, q.z);
    index.pointX()[k] = q.x;
    index.pointY()[k] = q.y;
    index.pointZ()[k] = q.z;
    index.pointId()[k] = static_cast<std::uint32_t>(k);
  }
  index.setPointCount(n);
  if (n == 0)
  {
    patch_start.assign(1, 0);
    return 0;
  }
  SpatialIndex::Options options;
  options.lookup = true;
  index.build(AnchoredGrid(inlier_points[0], cell_size, 2), options);

  const std::size_t cell_count = index.cellCount();
  const std::uint64_t* keys = index.cellKeys();
  parent.resize(cell_count);
  for (std::uint32_t c = 0; c < cell_count; ++c)
    parent[c] = c;
  const float squared_distance = static_cast<float>(connection_distance * connection_distance);
  for (std::uint32_t a = 0; a < cell_count; ++a)
  {
    for (const std::int64_t offset : kOffsets)
    {
      const std::uint32_t b = index.findCell(static_cast<std::uint64_t>(static_cast<std::int64_t>(keys[a]) + offset));
      if (b == SpatialIndex::kNoCell)
        continue;
      const std::uint32_t root_a = find(a);
      const std::uint32_t root_b = find(b);
      // All points of a cell are already connected, so one close pair joins two cells.
      if (root_a == root_b || !anyPairCloser(a, b, squared_distance))
        continue;
      parent[std::max(root_a, root_b)] = std::min(root_a, root_b);
    }
  }

  // Number patches by first point and group the points by patch.
  return groupByRoot(
      static_cast<std::uint32_t>(n), cell_count, [&](std::uint32_t k) { return find(index.cellOfPoint(k)); },
      grouping, patch_start, patch_members);
}

// Median distance from each projected point to its nearest other one: the sampling
// spacing of the patch. Nearest neighbours by a sweep over the points sorted along
// `sweep_direction` (the patch's long axis, so the band searched around a point crosses
// the short side); stops once the sorted distance alone exceeds the best found.
double ObjectExtractor::Workspace::typicalSpacing(const Eigen::Vector2d& sweep_direction)
{
  const std::size_t n = projected.size();
  if (n < 2)
    return 0.0;
  sweep_order.resize(n);
  for (std::uint32_t i = 0; i < n; ++i)
    sweep_order[i] = { projected[i].dot(sweep_direction), i };
  std::sort(sweep_order.begin(), sweep_order.end());
  // A median needs no more than a couple of thousand samples: on large patches query every
  // stride-th point (against all of them).
  const std::size_t stride = (n + kSpacingSamples - 1) / kSpacingSamples;
  nearest.clear();
  for (std::size_t a = 0; a < n; a += stride)
  {
    const double key = sweep_order[a].first;
    const Eigen::Vector2d& p = projected[sweep_order[a].second];
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t b = a + 1; b < n && sweep_order[b].first - key < best; ++b)
      best = std::min(best, (projected[sweep_order[b].second] - p).norm());
    for (std::size_t b = a; b-- > 0 && key - sweep_order[b].first < best;)
      best = std::min(best, (projected[sweep_order[b].second] - p).norm());
    nearest.push_back(best);
  }
  const auto middle = nearest.begin() + static_cast<std::ptrdiff_t>(nearest.size() / 2);
  std::nth_element(nearest.begin(), middle, nearest.end());
  return *middle;
}

// Least median of squares (Rousseeuw) on a sample of the patch: planes through three sample
// points, spread over the patch so that each is well defined, scored by the median distance of
// the sample to them. Its 50 % breakdown point is what the least-squares start lacks. A fixed
// generator seed keeps the extraction deterministic.
void ObjectExtractor::Workspace::leastMedianPlane(std::uint32_t begin, std::uint32_t count, Eigen::Vector3d& normal,
                                                  Eigen::Vector3d& point)
{
  if (count < 3)
    return;
  const std::uint32_t stride = (count + kMedianSamples - 1) / kMedianSamples;
  median_sample.clear();
  for (std::uint32_t k = 0; k < count; k += stride)
    median_sample.push_back(inlier_points[patch_members[begin + k]].cast<double>());
  const std::size_t n = median_sample.size();
  if (n < 3)
    return;
  const auto medianDistance = [&](const Eigen::Vector3d& plane_normal, const Eigen::Vector3d& plane_point) {
    sample_distance.resize(n);
    for (std::size_t k = 0; k < n; ++k)
      sample_distance[k] = std::fabs((median_sample[k] - plane_point).dot(plane_normal));
    const auto middle = sample_distance.begin() + static_cast<std::ptrdiff_t>(n / 2);
    std::nth_element(sample_distance.begin(), middle, sample_distance.end());
    return *middle;
  };
  double best = medianDistance(normal, point);
  // The spread of the sample: a triple counts when the area of its triangle is at least a
  // tenth of the sample's extent squared (three points side by side fix no plane).
  Eigen::Vector3d low = median_sample[0], high = median_sample[0];
  for (const Eigen::Vector3d& x : median_sample)
  {
    low = low.cwiseMin(x);
    high = high.cwiseMax(x);
  }
  const double min_double_area = 0.1 * (high - low).squaredNorm();
  std::mt19937 generator(kMedianSeed);
  std::uniform_int_distribution<std::size_t> pick(0, n - 1);
  for (int trial = 0; trial < kMedianTrials; ++trial)
  {
    const Eigen::Vector3d& a = median_sample[pick(generator)];
    const Eigen::Vector3d& b = median_sample[pick(generator)];
    const Eigen::Vector3d& c = median_sample[pick(generator)];
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    const double double_area = cross.norm();
    if (!(double_area > min_double_area))
      continue;
    const Eigen::Vector3d candidate = cross / double_area;
    const double distance = medianDistance(candidate, a);
    if (distance < best)
    {
      best = distance;
      normal = candidate;
      point = a;
    }
  }
}

double ObjectExtractor::Workspace::buildObject(const Eigen::Vector3f& ransac_normal, const Eigen::Vector3f& origin,
                                               double footprint_angle, std::uint32_t patch, ReflectiveObject& object)
{
  const std::uint32_t begin = patch_start[patch];
  const std::uint32_t end = patch_start[patch + 1];

  // Plane of the patch, robust to the points of other surfaces within RANSAC's band (a frame
  // or a wall 2-4 cm in front of a pane, echoes from just behind the glass): least squares,
  // then again on the points within kPlaneTrimSigmas robust sigma of that plane, until the
  // plane settles. A hard cut and plain least squares on what is kept, rather than a smooth
  // M-estimator weight: measured on random scenes 1000-1011 (all four families, objects with
  // >= 50 surface echoes, before the mirror refinement), Tukey's biweight at 3 sigma made the
  // noise-limited planes of narrow patches worse (Hesai median 0.24 -> 0.26 deg), the cut made
  // every family better (Hesai 0.24 -> 0.19, Ouster 0.18 -> 0.08, Velodyne 0.19 -> 0.17 deg;
  // Velodyne 90th percentile 1.13 -> 0.49 deg).
  const std::uint32_t count_points = end - begin;
  kept.assign(count_points, 1);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = ransac_normal.cast<double>().normalized();
  Eigen::Vector3d long_axis = Eigen::Vector3d::UnitX();
  bool fitted = false;
  for (int iteration = 0; iteration <= kPlaneTrimIterations; ++iteration)
  {
    std::uint32_t kept_count = 0;
    Eigen::Vector3d kept_centroid = Eigen::Vector3d::Zero();
    for (std::uint32_t k = 0; k < count_points; ++k)
    {
      if (kept[k] == 0)
        continue;
      kept_centroid += inlier_points[patch_members[begin + k]].cast<double>();
      ++kept_count;
    }
    // Fewer than three points kept: keep the last plane.
    if (kept_count < 3)
      break;
    kept_centroid /= static_cast<double>(kept_count);
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (std::uint32_t k = 0; k < count_points; ++k)
    {
      if (kept[k] == 0)
        continue;
      const Eigen::Vector3d d = inlier_points[patch_members[begin + k]].cast<double>() - kept_centroid;
      covariance += d * d.transpose();
    }
    covariance /= static_cast<double>(kept_count);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
    const Eigen::Vector3d eigenvalues = solver.eigenvalues();  // ascending
    const Eigen::Vector3d candidate = solver.eigenvectors().col(0);
    // Collinear points (one scan line across the object) do not fix a plane: keep RANSAC's
    // (or the last one).
    if (!(eigenvalues[1] > 1e-6 * eigenvalues[2]) || !candidate.allFinite())
    {
      if (!fitted)
        centroid = kept_centroid;
      break;
    }
    centroid = kept_centroid;
    normal = candidate.normalized();
    long_axis = solver.eigenvectors().col(2);
    // A strip (one or two scan lines across a pane's specular spot, a few centimetres wide)
    // is no wider than the range noise along its beams: its two smaller spreads are alike, and
    // the smallest may lie across the strip instead of along the beam, a plane at grazing
    // incidence. Neither glass nor a mirror returns a surface echo there (glass within a few
    // degrees of perpendicular, a mirror within about 20), so such a plane is the noise's: take
    // the plane through the strip's axis that faces the beam instead.
    if (eigenvalues[1] < kStripEigenvalueRatio * eigenvalues[0])
    {
      const Eigen::Vector3d view = (origin.cast<double>() - kept_centroid).normalized();
      const Eigen::Vector3d facing = view - view.dot(long_axis) * long_axis;
      if (std::fabs(view.dot(normal)) < kMinStripIncidenceCosine && facing.norm() > 1e-6)
        normal = facing.normalized();
    }
    fitted = true;
    if (iteration == kPlaneTrimIterations)
      break;
    // The first cut is made around the least-median plane: a frame at the patch's edge has
    // the leverage to tilt the least-squares plane towards itself, until its points are as near
    // to it as the pane's own edge, and no cut around that plane separates them.
    Eigen::Vector3d cut_normal = normal;
    Eigen::Vector3d cut_point = centroid;
    if (iteration == 0)
      leastMedianPlane(begin, count_points, cut_normal, cut_point);
    // The scale of the residuals: 1.4826 x their median absolute value is sigma for Gaussian
    // noise, so the cut follows the sensor's noise at the patch's range.
    abs_residuals.resize(count_points);
    for (std::uint32_t k = 0; k < count_points; ++k)
      abs_residuals[k] =
          std::fabs((inlier_points[patch_members[begin + k]].cast<double>() - cut_point).dot(cut_normal));
    sorted_residuals = abs_residuals;
    const auto middle = sorted_residuals.begin() + static_cast<std::ptrdiff_t>(count_points / 2);
    std::nth_element(sorted_residuals.begin(), middle, sorted_residuals.end());
    const double cutoff = std::max(kPlaneTrimSigmas * 1.4826 * *middle, kPlaneTrimMinCutoff);
    bool changed = false;
    for (std::uint32_t k = 0; k < count_points; ++k)
    {
      const std::uint8_t keep = abs_residuals[k] < cutoff ? 1 : 0;
      changed = changed || keep != kept[k];
      kept[k] = keep;
    }
    if (!changed)
      break;
  }
  // A cut that left fewer than three points (a tiny patch) did not fit a plane: keep them all.
  if (std::count(kept.begin(), kept.end(), std::uint8_t{ 1 }) < 3)
    kept.assign(count_points, 1);
  if (normal.dot(origin.cast<double>() - centroid) < 0.0)
    normal = -normal;

  // Orthonormal basis of the plane with u x v = normal.
  const Eigen::Vector3d helper = std::fabs(normal.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d u = normal.cross(helper).normalized();
  const Eigen::Vector3d v = normal.cross(u);

  // The outline and the surface points are those of the plane's own points: the points cut off
  // are another surface (a frame along the pane) and stay errorSurface without an object.
  projected.clear();
  for (std::uint32_t m = begin; m < end; ++m)
  {
    if (kept[m - begin] == 0)
      continue;
    const Eigen::Vector3d d = inlier_points[patch_members[m]].cast<double>() - centroid;
    projected.emplace_back(d.dot(u), d.dot(v));
  }
  Eigen::Vector2d sweep_direction(long_axis.dot(u), long_axis.dot(v));
  sweep_direction = sweep_direction.norm() > 1e-9 ? sweep_direction.normalized() : Eigen::Vector2d::UnitX();
  const double spacing = typicalSpacing(sweep_direction);

  convexHull(projected, hull);  // reorders `projected`
  Rectangle2D rectangle = minAreaRectangle(hull);
  // Sampling bias: thin beams at spacing s on an object of extent L span L - s on average
  // (the first and last sample fall anywhere within s of the edges; half a spacing missing
  // on each side). A real beam has a footprint of width f (divergence x range): it returns
  // from the surface while any of its footprint is on it, and its point lies on the beam's
  // centre, up to f / 2 beyond the edge (the UTM-30LX-EW's 0.25 deg are 1.1 cm at 2.5 m, as
  // much as its spacing there). The samples then span L + f - s: grow both extents by the
  // part of the spacing the footprint does not cover, s - f when positive. Not shrunk when
  // f > s: the typical spacing is the one along the densest direction, and across the
  // sparser one the hull is short by more than that.
  const double footprint = footprint_angle * (centroid - origin.cast<double>()).norm();
  const double growth = std::max(0.0, spacing - footprint);
  rectangle.length += growth;
  rectangle.breadth += growth;

  const Eigen::Vector3d axis_a = u * rectangle.axis.x() + v * rectangle.axis.y();
  const Eigen::Vector3d axis_b = u * rectangle.perpendicular().x() + v * rectangle.perpendicular().y();
  const Eigen::Vector3d centre = centroid + u * rectangle.centre.x() + v * rectangle.centre.y();

  // Width: the more horizontal side; on a horizontal plane the longer side.
  bool a_is_width;
  if (std::fabs(normal.z()) > kHorizontalNormalZ)
    a_is_width = rectangle.length >= rectangle.breadth;
  else
    a_is_width = std::fabs(axis_a.z()) <= std::fabs(axis_b.z());
  Eigen::Vector3d width_axis = a_is_width ? axis_a : axis_b;
  Eigen::Vector3d height_axis = normal.cross(width_axis);  // so width x height = normal
  // Signs: the height axis points up; on a horizontal plane, where no side is up, away from
  // the sensor (the far side of a floor mirror is its "top"), else along +x, else +y.
  double up;
  if (std::fabs(normal.z()) > kHorizontalNormalZ)
  {
    Eigen::Vector3d away = centre - origin.cast<double>();
    away.z() = 0.0;
    up = height_axis.dot(away);
    if (std::fabs(up) < 1e-9)
      up = std::fabs(height_axis.x()) > 1e-9 ? height_axis.x() : height_axis.y();
  }
  else
  {
    up = height_axis.z();
  }
  if (up < 0.0)
  {
    width_axis = -width_axis;
    height_axis = -height_axis;
  }

  object.type = ObjectType::unknown;
  object.plane.head<3>() = normal.cast<float>();
  object.plane[3] = static_cast<float>(-normal.dot(centroid));
  object.centre = centre.cast<float>();
  object.width_axis = width_axis.cast<float>();
  object.height_axis = height_axis.cast<float>();
  object.width = static_cast<float>(a_is_width ? rectangle.length : rectangle.breadth);
  object.height = static_cast<float>(a_is_width ? rectangle.breadth : rectangle.length);
  object.footprint = static_cast<float>(footprint);
  object.surface_inliers.clear();
  for (std::uint32_t m = begin; m < end; ++m)
    if (kept[m - begin] != 0)
      object.surface_inliers.push_back(refs[static_cast<std::size_t>(inliers[patch_members[m]])]);
  return spacing;
}

ObjectExtractor::ObjectExtractor(const ObjectExtractionConfig& config) : config_(config)
{
}

// Groups `members` (candidate indices) into connected groups on the grid: group_start /
// group_members (positions into members, ascending within a group), groups numbered in the
// order of their first member. Returns the number of groups.
std::size_t ObjectExtractor::Workspace::groupOnGrid(const Sweep& sweep, const BeamNeighbourhood& neighbourhood,
                                                    const IndexVector& members)
{
  const std::size_t n = members.size();
  const std::size_t cols = neighbourhood.cols();
  member_of_beam.resize(sweep.beamCount(), -1);
  member_parent.resize(n);
  for (std::uint32_t i = 0; i < n; ++i)
  {
    member_parent[i] = i;
    member_of_beam[refs[static_cast<std::size_t>(members[i])].beam] = static_cast<std::int32_t>(i);
  }
  for (std::uint32_t i = 0; i < n; ++i)
  {
    const PointRef ref = refs[static_cast<std::size_t>(members[i])];
    const Eigen::Vector3f& p = sweep.echoes[ref.echo].points[ref.beam];
    const float range = sweep.echoes[ref.echo].ranges[ref.beam];
    neighbourhood.anyNeighbour(ref.beam / cols, ref.beam % cols, [&](std::size_t other, std::size_t k) {
      const std::int32_t j = member_of_beam[other];
      if (j < 0)
        return false;
      const PointRef q = refs[static_cast<std::size_t>(members[static_cast<std::size_t>(j)])];
      if ((sweep.echoes[q.echo].points[q.beam] - p).squaredNorm() > neighbourhood.limitSquared(range, k))
        return false;
      const std::uint32_t a = findMember(i);
      const std::uint32_t b = findMember(static_cast<std::uint32_t>(j));
      if (a != b)
        member_parent[std::max(a, b)] = std::min(a, b);
      return false;
    });
  }
  for (std::uint32_t i = 0; i < n; ++i)
    member_of_beam[refs[static_cast<std::size_t>(members[i])].beam] = -1;

  return groupByRoot(
      static_cast<std::uint32_t>(n), n, [&](std::uint32_t i) { return findMember(i); }, grouping, group_start,
      group_members);
}

// The patches of the plane's inliers connected on the grid, in splitPatches' layout.
void ObjectExtractor::Workspace::patchesFromGroups(const Sweep& sweep, const BeamNeighbourhood& neighbourhood)
{
  const std::size_t n = inliers.size();
  inlier_points.resize(n);
  for (std::size_t k = 0; k < n; ++k)
  {
    const pcl::PointXYZ& q = cloud->points[static_cast<std::size_t>(inliers[k])];
    inlier_points[k] = Eigen::Vector3f(q.x, q.y, q.z);
  }
  groupOnGrid(sweep, neighbourhood, inliers);
  patch_start = group_start;
  patch_members = group_members;
}

// Median over the points (members[positions[0 .. count)]) of the shorter of the two runs of
// these points through it, along its row and along its column of the grid.
std::size_t ObjectExtractor::Workspace::beamsAcross(const SweepSampling& sampling, const IndexVector& members,
                                                    const std::uint32_t* positions, std::size_t count)
{
  if (count == 0)
    return 0;
  const std::uint64_t cols = sampling.cols;
  const std::uint64_t rows = sampling.rows;
  run_along_row.resize(count);
  across.resize(count);
  // Pass 0 walks the points in row-major order (runs along a row), pass 1 in column-major order.
  for (int pass = 0; pass < 2; ++pass)
  {
    grid_order.resize(count);
    for (std::uint32_t i = 0; i < count; ++i)
    {
      const std::uint64_t beam = refs[static_cast<std::size_t>(members[positions[i]])].beam;
      const std::uint64_t row = beam / cols;
      const std::uint64_t col = beam % cols;
      grid_order[i] = { pass == 0 ? row * cols + col : col * rows + row, i };
    }
    std::sort(grid_order.begin(), grid_order.end());
    std::size_t first = 0;
    for (std::size_t k = 1; k <= count; ++k)
    {
      // A run continues while the next point is the next cell of the same row (column).
      const bool continues = k < count && grid_order[k].first == grid_order[k - 1].first + 1 &&
                             (pass == 0 ? grid_order[k].first % cols != 0 : grid_order[k].first % rows != 0);
      if (continues)
        continue;
      const std::uint32_t length = static_cast<std::uint32_t>(k - first);
      for (std::size_t m = first; m < k; ++m)
      {
        const std::uint32_t point = grid_order[m].second;
        if (pass == 0)
          run_along_row[point] = length;
        else
          across[point] = std::min(run_along_row[point], length);
      }
      first = k;
    }
  }
  const auto middle = across.begin() + static_cast<std::ptrdiff_t>(count / 2);
  std::nth_element(across.begin(), middle, across.end());
  return *middle;
}

void ObjectExtractor::Workspace::fitPlanes(const Sweep& sweep, const SweepSampling& sampling,
                                           const Eigen::Vector3f& origin, const ObjectExtractionConfig& config,
                                           const BeamNeighbourhood* neighbourhood,
                                           std::vector<ReflectiveObject>& objects)
{
  // Three points span a plane; Params::validate() refuses fewer, this guards direct callers.
  const std::size_t min_points = static_cast<std::size_t>(std::max(config.min_object_points, 3));
  const std::size_t min_across = static_cast<std::size_t>(std::max(config.min_beams_across, 0));
  const bool on_grid = sampling.hasGrid() && sampling.rows * sampling.cols == sweep.beamCount();
  const double footprint_angle = config.footprint_steps * sampling.col_step;
  // Every pass assigns at least min_points (>= 3) points or stops, so the loop ends.
  while (remaining.size() >= min_points)
  {
    // A fresh model and RANSAC per plane: both seed their generators with PCL's fixed seed
    // (12345) when not asked for a random one, so the same sweep gives the same planes,
    // whatever the extractor did before. Single-threaded (PCL's default).
    remaining_x.resize(remaining.size());
    remaining_y.resize(remaining.size());
    remaining_z.resize(remaining.size());
    for (std::size_t i = 0; i < remaining.size(); ++i)
    {
      const pcl::PointXYZ& q = cloud->points[static_cast<std::size_t>(remaining[i])];
      remaining_x[i] = q.x;
      remaining_y[i] = q.y;
      remaining_z[i] = q.z;
    }
    pcl::SampleConsensusModelPlane<pcl::PointXYZ>::Ptr model(
        new CountingPlaneModel(cloud, remaining, remaining_x, remaining_y, remaining_z));
    pcl::RandomSampleConsensus<pcl::PointXYZ> ransac(model, config.plane_threshold);
    ransac.setMaxIterations(kRansacMaxIterations);
    if (!ransac.computeModel())
      break;
    ransac.getInliers(inliers);
    ransac.getModelCoefficients(coefficients);
    // Least-squares polish of the plane on its inliers, and the inliers of the polished
    // plane when there are at least as many (RANSAC's plane through three noisy points is
    // a little tilted and misses the edges of a large patch).
    if (inliers.size() >= 3)
    {
      model->optimizeModelCoefficients(inliers, coefficients, refined_coefficients);
      model->selectWithinDistance(refined_coefficients, config.plane_threshold, refined_inliers);
      if (refined_inliers.size() >= inliers.size() && refined_coefficients.allFinite())
      {
        std::swap(inliers, refined_inliers);
        std::swap(coefficients, refined_coefficients);
      }
    }
    if (inliers.size() < min_points)
      break;
    std::sort(inliers.begin(), inliers.end());
    std::size_t newly_assigned = 0;
    for (const int index : inliers)
    {
      newly_assigned += assigned[static_cast<std::size_t>(index)] == 0 ? 1 : 0;
      assigned[static_cast<std::size_t>(index)] = 1;
    }
    // PCL only returns points among `remaining`; should it ever not, stop rather than spin.
    if (newly_assigned == 0)
      break;

    const Eigen::Vector3f ransac_normal = coefficients.head<3>();
    std::size_t patch_count = 0;
    if (neighbourhood != nullptr)
    {
      patchesFromGroups(sweep, *neighbourhood);
      patch_count = patch_start.size() - 1;
    }
    else
    {
      patch_count = splitPatches(config.connection_distance);
    }
    for (std::uint32_t patch = 0; patch < patch_count; ++patch)
    {
      const std::size_t size = patch_start[patch + 1] - patch_start[patch];
      if (size < min_points)
        continue;
      if (on_grid && beamsAcross(sampling, inliers, &patch_members[patch_start[patch]], size) < min_across)
        continue;
      objects.emplace_back();
      ReflectiveObject& object = objects.back();
      object.id = static_cast<std::uint32_t>(objects.size() - 1);
      const double spacing = buildObject(ransac_normal, origin, footprint_angle, patch, object);
      // Without a grid the rectangle says how wide the patch is, in sample spacings.
      if (!on_grid && std::min(object.width, object.height) < static_cast<double>(min_across) * spacing)
        objects.pop_back();
    }

    remaining.erase(std::remove_if(remaining.begin(), remaining.end(),
                                   [this](int index) { return assigned[static_cast<std::size_t>(index)] != 0; }),
                    remaining.end());
  }
}

void ObjectExtractor::extract(const Sweep& sweep, const Eigen::Vector3f& sensor_origin, const SweepLabels& labels,
                              std::vector<ReflectiveObject>& objects)
{
  if (!workspace_)
    workspace_.reset(new Workspace);
  const SweepSampling sampling = workspace_->sampling_estimator.estimate(sweep, sensor_origin);
  extract(sweep, sampling, sensor_origin, labels, objects);
}

void ObjectExtractor::extract(const Sweep& sweep, const SweepSampling& sampling, const Eigen::Vector3f& sensor_origin,
                              const SweepLabels& labels, std::vector<ReflectiveObject>& objects)
{
  objects.clear();
  if (!workspace_)
    workspace_.reset(new Workspace);
  Workspace& ws = *workspace_;
  ws.gather(sweep, labels);
  const bool on_grid = sampling.hasGrid() && sampling.rows * sampling.cols == sweep.beamCount();
  if (!config_.follows_sampling || !on_grid)
  {
    ws.fitPlanes(sweep, sampling, sensor_origin, config_, nullptr, objects);
    return;
  }
  // Connected groups of surface points first: a plane is fitted to each group on its own, and
  // a group too small or too thin to hold an object (a line of mixed pixels) costs no RANSAC.
  const BeamNeighbourhood neighbourhood(sampling, config_.neighbourhood);
  const std::size_t min_points = static_cast<std::size_t>(std::max(config_.min_object_points, 3));
  const std::size_t min_across = static_cast<std::size_t>(std::max(config_.min_beams_across, 0));
  ws.candidates = ws.remaining;
  const IndexVector& all = ws.candidates;
  const std::size_t groups = ws.groupOnGrid(sweep, neighbourhood, all);
  std::swap(ws.candidate_group_start, ws.group_start);
  std::swap(ws.candidate_group_members, ws.group_members);
  const std::vector<std::uint32_t>& starts = ws.candidate_group_start;
  const std::vector<std::uint32_t>& members = ws.candidate_group_members;
  for (std::size_t g = 0; g < groups; ++g)
  {
    const std::size_t size = starts[g + 1] - starts[g];
    if (size < min_points || ws.beamsAcross(sampling, all, &members[starts[g]], size) < min_across)
      continue;
    ws.remaining.clear();
    for (std::uint32_t m = starts[g]; m < starts[g + 1]; ++m)
      ws.remaining.push_back(all[members[m]]);
    std::sort(ws.remaining.begin(), ws.remaining.end());
    ws.fitPlanes(sweep, sampling, sensor_origin, config_, &neighbourhood, objects);
  }
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
