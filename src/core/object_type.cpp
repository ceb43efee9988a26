#include "ohm_mirror_detector3d/core/object_type.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "ohm_mirror_detector3d/core/vision_cone.h"

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
using Cloud = pcl::PointCloud<pcl::PointXYZ>;

// A mirror's phantoms, reflected across a plane fitted to its surface echoes, already land
// on the real scene; ICP only takes out the small error of the fitted plane. A larger
// correction means ICP slid them onto some other structure.
constexpr float kMaxCorrectionAngle = 5.0f * static_cast<float>(M_PI) / 180.0f;
constexpr int kIcpIterations = 30;

// Point i of echo 2 repeating echo 1 (a single return) is one measurement, not two.
bool isRepeatedReturn(const Sweep& sweep, std::size_t k, std::size_t i)
{
  return k == 1 && sweep.echoes[1].points[i] == sweep.echoes[0].points[i];
}

pcl::PointXYZ toPcl(const Eigen::Vector3f& p)
{
  return pcl::PointXYZ(p.x(), p.y(), p.z());
}
}  // namespace

struct ObjectTypeAnalyzer::Buffers
{
  Cloud::Ptr mirrored{ new Cloud };
  Cloud::Ptr real{ new Cloud };
  Cloud aligned;
  pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
  std::vector<int> neighbour;
  std::vector<float> squared_distance;
};

ObjectTypeAnalyzer::ObjectTypeAnalyzer() : buffers_(new Buffers)
{
}
ObjectTypeAnalyzer::~ObjectTypeAnalyzer() = default;
ObjectTypeAnalyzer::ObjectTypeAnalyzer(ObjectTypeAnalyzer&&) noexcept = default;
ObjectTypeAnalyzer& ObjectTypeAnalyzer::operator=(ObjectTypeAnalyzer&&) noexcept = default;

void ObjectTypeAnalyzer::analyze(const Sweep& sweep, const Params& params, const SweepLabels& labels,
                                 ReflectiveObject& object)
{
  Buffers& b = *buffers_;
  TypeEvidence& evidence = object.evidence;
  evidence = TypeEvidence();
  object.type = ObjectType::unknown;

  const float plane_threshold = static_cast<float>(params.plane_threshold);
  const float margin = static_cast<float>(params.vision_cone_margin);
  const float max_distance = static_cast<float>(params.icp_max_distance);
  const std::size_t min_points = static_cast<std::size_t>(params.icp_min_points);

  b.mirrored->clear();
  Eigen::AlignedBox3f landing_zone;
  Eigen::Vector3f direction_sum = Eigen::Vector3f::Zero();
  for (std::size_t k = 0; k < 2; ++k)
  {
    for (std::size_t i = 0; i < sweep.beamCount(); ++i)
    {
      if (labels.echoes[k][i] == Label::nanPoint || isRepeatedReturn(sweep, k, i))
        continue;
      const Eigen::Vector3f& p = sweep.echoes[k].points[i];
      if (locateInCone(object, sweep.origin, p, plane_threshold, margin).relation != ConeRelation::behind)
        continue;
      const Eigen::Vector3f mirrored = object.reflect(p);
      b.mirrored->push_back(toPcl(mirrored));
      landing_zone.extend(mirrored);
      direction_sum += (mirrored - sweep.origin).normalized();
    }
  }
  evidence.mirrored_points = b.mirrored->size();
  if (evidence.mirrored_points < min_points)
    return;

  // The directions in which the mirrored points lie, as a cone around their mean direction:
  // real points seen in it tell that the sensor looked there.
  const Eigen::Vector3f mean_direction = direction_sum.normalized();
  float min_cosine = 1.0f;
  for (const pcl::PointXYZ& q : b.mirrored->points)
    min_cosine = std::min(min_cosine, (q.getVector3fMap() - sweep.origin).normalized().dot(mean_direction));

  landing_zone.min().array() -= max_distance;
  landing_zone.max().array() += max_distance;
  b.real->clear();
  std::size_t seen_in_their_directions = 0;
  for (std::size_t k = 0; k < 2; ++k)
  {
    for (std::size_t i = 0; i < sweep.beamCount(); ++i)
    {
      const Label label = labels.echoes[k][i];
      if ((label != Label::unchecked && label != Label::valid) || isRepeatedReturn(sweep, k, i))
        continue;
      const Eigen::Vector3f& p = sweep.echoes[k].points[i];
      if (!(object.signedDistance(p) > plane_threshold))
        continue;
      if ((p - sweep.origin).normalized().dot(mean_direction) >= min_cosine)
        ++seen_in_their_directions;
      if (landing_zone.contains(p))
        b.real->push_back(toPcl(p));
    }
  }
  if (seen_in_their_directions < min_points)
    return;
  if (b.real->size() < 3)
  {
    // The sensor looked there and nothing real lies where the mirrored points land.
    evidence.inlier_fraction = 0.0f;
    object.type = ObjectType::glass;
    return;
  }

  b.icp.setInputSource(b.mirrored);
  b.icp.setInputTarget(b.real);
  b.icp.setMaxCorrespondenceDistance(max_distance);
  b.icp.setMaximumIterations(kIcpIterations);
  b.icp.setTransformationEpsilon(1e-9);
  b.icp.align(b.aligned);
  evidence.icp_converged = b.icp.hasConverged();
  evidence.icp_correction = b.icp.getFinalTransformation();

  // Matches after ICP, counted on ICP's own kd-tree of the real points.
  const float max_squared = max_distance * max_distance;
  double squared_sum = 0.0;
  for (const pcl::PointXYZ& p : b.aligned.points)
  {
    if (b.icp.getSearchMethodTarget()->nearestKSearch(p, 1, b.neighbour, b.squared_distance) == 1 &&
        b.squared_distance[0] <= max_squared)
    {
      ++evidence.matched_points;
      squared_sum += b.squared_distance[0];
    }
  }
  evidence.inlier_fraction = static_cast<float>(evidence.matched_points) / evidence.mirrored_points;
  evidence.icp_fitness = evidence.matched_points > 0 ? static_cast<float>(squared_sum / evidence.matched_points) :
                                                        std::numeric_limits<float>::infinity();

  const Eigen::Affine3f correction(evidence.icp_correction);
  const float correction_angle = Eigen::AngleAxisf(correction.rotation()).angle();
  const bool small_correction =
      correction.translation().norm() <= max_distance && correction_angle <= kMaxCorrectionAngle;
  const bool fits = evidence.icp_converged && small_correction &&
                    evidence.inlier_fraction >= static_cast<float>(params.icp_min_inlier_fraction) &&
                    evidence.icp_fitness <= static_cast<float>(params.icp_fitness_threshold);
  object.type = fits ? ObjectType::mirror : ObjectType::glass;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
