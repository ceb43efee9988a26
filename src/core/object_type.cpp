#include "ohm_mirror_detector3d/core/object_type.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>

#include <Eigen/Eigenvalues>
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
using Point = pcl::PointXYZ;
using Cloud = pcl::PointCloud<Point>;

// A mirror's phantoms, reflected across a plane fitted to its surface echoes, already land
// on the real scene; ICP only takes out the small error of the fitted plane. A larger
// correction means ICP slid them onto some other structure.
constexpr float kMaxCorrectionAngle = 5.0f * static_cast<float>(M_PI) / 180.0f;
constexpr int kIcpIterations = 30;
constexpr int kPlaneRefinementIterations = 10;
constexpr int kNormalNeighbours = 20;
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

  std::vector<Eigen::Vector3f> behind;   // the points behind the object, as measured
  std::vector<Eigen::Vector3f> surface;  // the surface echoes its plane was fitted to
  struct Correspondence
  {
    Eigen::Vector3d jacobian;
    float residual;
  };
  std::vector<Correspondence> correspondences;
  std::vector<float> absolute_residuals;
  std::vector<Eigen::Vector3f> real_normals;  // NaN: not computed yet; infinite: no surface there
  std::vector<int> neighbourhood;
  std::vector<float> neighbourhood_distances;

  // The surface normal of the real scene at real point `index`, from its nearest neighbours.
  const Eigen::Vector3f& realNormal(std::size_t index);

  // Points within max_distance of a real point (ICP's target), and their squared distances' sum.
  std::size_t countMatches(const Cloud& points, float max_distance, double& squared_sum);
  void refineMirrorPlane(const Eigen::Vector3f& origin, float max_distance, ReflectiveObject& object);
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
  b.behind.clear();
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
      b.behind.push_back(p);
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
  double squared_sum = 0.0;
  evidence.matched_points = b.countMatches(b.aligned, max_distance, squared_sum);
  evidence.inlier_fraction = static_cast<float>(evidence.matched_points) / evidence.mirrored_points;
  evidence.icp_fitness = evidence.matched_points > 0 ? static_cast<float>(squared_sum / evidence.matched_points) :
                                                        std::numeric_limits<float>::infinity();
  double unused = 0.0;
  const float fraction_before_icp =
      static_cast<float>(b.countMatches(*b.mirrored, max_distance, unused)) / evidence.mirrored_points;

  const Eigen::Affine3f correction(evidence.icp_correction);
  const float correction_angle = Eigen::AngleAxisf(correction.rotation()).angle();
  const bool small_correction =
      correction.translation().norm() <= max_distance && correction_angle <= kMaxCorrectionAngle;
  const float min_fraction = static_cast<float>(params.icp_min_inlier_fraction);
  const bool fits = evidence.icp_converged && small_correction && evidence.inlier_fraction >= min_fraction &&
                    evidence.icp_fitness <= static_cast<float>(params.icp_fitness_threshold);
  if (fits)
  {
    object.type = ObjectType::mirror;
    b.surface.clear();
    for (const PointRef& ref : object.surface_inliers)
      b.surface.push_back(sweep.echoes[ref.echo].points[ref.beam]);
    b.refineMirrorPlane(sweep.origin, max_distance, object);
  }
  else if (std::max(fraction_before_icp, evidence.inlier_fraction) < kGlassFractionOfRequired * min_fraction)
    object.type = ObjectType::glass;
}

void ObjectTypeAnalyzer::Buffers::refineMirrorPlane(const Eigen::Vector3f& origin, float max_distance,
                                                   ReflectiveObject& object)
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
  // weight): where the phantoms constrain the plane poorly (all on one floor, say), the
  // surface echoes keep it.
  Eigen::Vector3f normal = object.plane.head<3>();
  float offset = object.plane[3];
  const float max_squared = max_distance * max_distance;
  real_normals.assign(real->size(), Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
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
      Point mirrored;
      mirrored.getVector3fMap() = p - 2.0f * side * normal;
      if (icp.getSearchMethodTarget()->nearestKSearch(mirrored, 1, neighbour, squared_distance) != 1 ||
          squared_distance[0] > max_squared)
        continue;
      const std::size_t nearest = static_cast<std::size_t>(neighbour[0]);
      const Eigen::Vector3f& surface_normal = realNormal(nearest);
      if (!surface_normal.allFinite())
        continue;
      const float residual =
          surface_normal.dot(mirrored.getVector3fMap() - real->points[nearest].getVector3fMap());
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
      const double weight = magnitude <= huber ? 1.0 : huber / magnitude;
      hessian += weight * c.jacobian * c.jacobian.transpose();
      gradient += weight * c.jacobian * static_cast<double>(c.residual);
    }
    if (used < 3)
      return;
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
  // Computed on first use: only the real points phantoms land on need one.
  icp.getSearchMethodTarget()->nearestKSearch(real->points[index], kNormalNeighbours, neighbourhood,
                                              neighbourhood_distances);
  normal.setConstant(std::numeric_limits<float>::infinity());  // too few neighbours: no surface
  if (neighbourhood.size() < 3)
    return normal;
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  for (int n : neighbourhood)
    centroid += real->points[static_cast<std::size_t>(n)].getVector3fMap();
  centroid /= static_cast<float>(neighbourhood.size());
  Eigen::Matrix3f covariance = Eigen::Matrix3f::Zero();
  for (int n : neighbourhood)
  {
    const Eigen::Vector3f d = real->points[static_cast<std::size_t>(n)].getVector3fMap() - centroid;
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

std::size_t ObjectTypeAnalyzer::Buffers::countMatches(const Cloud& points, float max_distance, double& squared_sum)
{
  const float max_squared = max_distance * max_distance;
  std::size_t matched = 0;
  squared_sum = 0.0;
  for (const pcl::PointXYZ& p : points.points)
  {
    if (icp.getSearchMethodTarget()->nearestKSearch(p, 1, neighbour, squared_distance) == 1 &&
        squared_distance[0] <= max_squared)
    {
      ++matched;
      squared_sum += squared_distance[0];
    }
  }
  return matched;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
