#include "ohm_mirror_detector3d/core/object_type.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "ohm_mirror_detector3d/core/block_box.h"
#include "ohm_mirror_detector3d/core/mirror_plane_refinement.h"
#include "ohm_mirror_detector3d/core/mirror_registration.h"
#include "ohm_mirror_detector3d/core/real_scene.h"
#include "ohm_mirror_detector3d/core/spatial_index.h"
#include "ohm_mirror_detector3d/core/vision_cone.h"

// The type decision. Why this is not pcl::IterativeClosestPoint on the whole scene (which it
// was, and which the bench still runs as its baseline): the registration only has to answer
// "do the phantoms land on the real scene near where a pure reflection puts them?". So
// - the phantoms are a deterministic sample of at most kMaxSamples points (evenly spread
//   over the behind points in beam order): the inlier fraction and fitness are shares and
//   means, and a few hundred points estimate them to a few percent;
// - the target is only the real scene where they can land (the box of the mirrored points
//   grown by icp_max_distance, and there only the cells near a sampled phantom), thinned to
//   one point per small voxel, so that a dense scanner does not pay for points that add no
//   information at the ICP's 10 cm scale;
// - nearest neighbours come from the spatial index over that target (RealScene: cells
//   icp_max_distance wide, queried over 3 x 3 columns of 3 cells, bounded by the
//   correspondence distance) instead of a kd-tree: a far point costs 9 short scans, where an
//   unbounded kd-tree search for it walks much of the tree;
// - ICP stops once an iteration moves the phantoms by less than a micrometre
//   (mirror_registration.h); a mirror's plane is then refined (mirror_plane_refinement.h).
// Together they take the type decision from seconds to about a millisecond per object on a
// 1080 x 1000 sweep, with the same decisions.

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// At most this many of the points behind an object are registered (see the top of the file).
constexpr std::size_t kMaxSamples = 512;
// The real scene is thinned to one point per voxel of icp_max_distance / kVoxelsPerDistance,
// at most kMaxVoxel wide: the 1 cm noise of the scanner stays the largest error.
constexpr float kVoxelsPerDistance = 5.0f;
constexpr float kMaxVoxel = 0.02f;
// Most cells of the landing cells' grid; a larger landing box gets larger cells.
constexpr std::size_t kMaxLandingCells = std::size_t(1) << 20;
// Glass needs a clear contradiction: fewer than this share of the inlier fraction a mirror
// needs, before and after ICP. Between the two the evidence is ambiguous and the type stays
// unknown rather than being a confident wrong call (e.g. a mirror reflecting mostly sky).
constexpr float kGlassFractionOfRequired = 0.5f;

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

// Cells of the landing box (at least icp_max_distance wide) within two cells of a sampled
// mirrored point: the only places where ICP (which moves the phantoms by at most
// icp_max_distance for a mirror) and the refinement look for real points. A room-sized box
// holds a hundred times more real points than these cells.
class LandingCells
{
public:
  void build(const Eigen::AlignedBox3f& box, float min_cell, const std::vector<Eigen::Vector3f>& mirrored)
  {
    grid_ = BoxGrid(box, min_cell, 0, kMaxLandingCells);
    for (int a = 0; a < 3; ++a)
      n_[a] = static_cast<std::int64_t>(grid_.cells(a));
    marked_.assign(static_cast<std::size_t>(n_.prod()), 0);
    for (const Eigen::Vector3f& p : mirrored)
    {
      const Eigen::Array3f c = grid_.coordinates(p).array().floor();
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
    const Eigen::Vector3f c = grid_.coordinates(p);
    const std::int64_t x = std::min<std::int64_t>(static_cast<std::int64_t>(c.x()), n_[0] - 1);
    const std::int64_t y = std::min<std::int64_t>(static_cast<std::int64_t>(c.y()), n_[1] - 1);
    const std::int64_t z = std::min<std::int64_t>(static_cast<std::int64_t>(c.z()), n_[2] - 1);
    return marked_[static_cast<std::size_t>((x * n_[1] + y) * n_[2] + z)] != 0;
  }

private:
  BoxGrid grid_;
  Eigen::Array<std::int64_t, 3, 1> n_ = Eigen::Array<std::int64_t, 3, 1>::Ones();
  std::vector<char> marked_;
};
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
  std::vector<Eigen::Vector3f> candidates;    // real points where the sample can land
  LandingCells landing;
  std::vector<Eigen::Vector3f> real;          // candidates thinned to one per voxel
  CellKeySet voxels;
  RealScene scene;                            // of `real`
  MirrorRegistration registration;
  std::vector<Eigen::Vector3f> surface;       // the surface echoes its plane was fitted to
  MirrorPlaneRefinement refinement;
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
    if (b.voxels.insert(cell_key::of(p, landing_zone.min(), 1.0f / voxel)))
      b.real.push_back(p);
  if (b.candidates.size() < 3)
  {
    // The sensor looked there and nothing real lies where the mirrored points land.
    evidence.inlier_fraction = 0.0f;
    object.type = ObjectType::glass;
    return;
  }
  b.scene.build(b.real, max_distance);

  // Shares of the sample within max_distance of a real point before ICP, and after it.
  double unused = 0.0;
  const float fraction_before_icp = static_cast<float>(countMatches(b.scene, b.mirrored, unused)) / samples;
  const float min_fraction = static_cast<float>(config_.icp_min_inlier_fraction);
  // Once ICP has moved the phantoms further than a mirror's may move, the object is no
  // mirror; if enough of them matched before ICP it is no glass either, and nothing ICP does
  // next can change that: it may stop there (on scenes where it slides along a floor, most of
  // its iterations).
  const bool may_stop_when_too_far = !(fraction_before_icp < kGlassFractionOfRequired * min_fraction);
  evidence.icp_converged =
      b.registration.align(b.scene, b.mirrored, may_stop_when_too_far, max_distance, evidence.icp_correction);

  double squared_sum = 0.0;
  const std::size_t matched = countMatches(b.scene, b.registration.aligned(), squared_sum);
  evidence.inlier_fraction = static_cast<float>(matched) / static_cast<float>(samples);
  evidence.matched_points =
      static_cast<std::size_t>(std::lround(static_cast<double>(evidence.inlier_fraction) * total));
  evidence.icp_fitness =
      matched > 0 ? static_cast<float>(squared_sum / matched) : std::numeric_limits<float>::infinity();
  const Eigen::Affine3f correction(evidence.icp_correction);
  const float correction_angle = Eigen::AngleAxisf(correction.rotation()).angle();
  const bool small_correction =
      correction.translation().norm() <= max_distance && correction_angle <= kMaxMirrorCorrectionAngle;
  const bool fits = evidence.icp_converged && small_correction && evidence.inlier_fraction >= min_fraction &&
                    evidence.icp_fitness <= static_cast<float>(config_.icp_fitness_threshold);
  if (fits)
  {
    object.type = ObjectType::mirror;
    b.surface.clear();
    for (const PointRef& ref : object.surface_inliers)
      b.surface.push_back(sweep.echoes[ref.echo].points[ref.beam]);
    b.refinement.refine(b.scene, b.surface, b.behind, sensor_origin, phantom_weight, object);
  }
  else if (std::max(fraction_before_icp, evidence.inlier_fraction) < kGlassFractionOfRequired * min_fraction)
    object.type = ObjectType::glass;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
