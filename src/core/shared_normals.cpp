#include "ohm_mirror_detector3d/core/shared_normals.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// An object's surface echoes as moments about their centroid: the scatter of parallel planes is
// the sum of each one's own, so a pane and a panel a centimetre in front of it share a normal
// without the offset between them tilting it.
struct EchoMoments
{
  std::size_t count = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();  // sum of (x - centroid)(x - centroid)^T
};

EchoMoments momentsOf(const Sweep& sweep, const ReflectiveObject& object)
{
  EchoMoments moments;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (const PointRef& ref : object.surface_inliers)
  {
    if (ref.echo >= sweep.echoes.size() || ref.beam >= sweep.echoes[ref.echo].points.size())
      continue;
    const Eigen::Vector3f& x = sweep.echoes[ref.echo].points[ref.beam];
    if (!x.allFinite())
      continue;
    // About the object's centre, so that the sums stay well conditioned far from the sensor.
    const Eigen::Vector3d d = (x - object.centre).cast<double>();
    sum += d;
    second += d * d.transpose();
    ++moments.count;
  }
  if (moments.count == 0)
    return moments;
  const Eigen::Vector3d mean = sum / static_cast<double>(moments.count);
  moments.centroid = object.centre.cast<double>() + mean;
  moments.scatter = second - static_cast<double>(moments.count) * mean * mean.transpose();
  return moments;
}

// A plane needs three echoes; fewer add nothing to the shared normal.
constexpr std::size_t kMinEchoes = 3;

bool inOneWall(const ReflectiveObject& a, const ReflectiveObject& b, float min_cosine)
{
  return a.sharesPlaneWith(b, min_cosine, kMaxSharedPlaneDistance) &&
         b.sharesPlaneWith(a, min_cosine, kMaxSharedPlaneDistance);
}

// The object with its plane turned to `normal` (flipped to face the sensor as its plane did)
// through `point`, and its rectangle moved onto it: the centres projected, the axes made
// perpendicular to the new normal again.
void setPlane(ReflectiveObject& object, Eigen::Vector3f normal, const Eigen::Vector3f& point)
{
  if (normal.dot(object.plane.head<3>()) < 0.0f)
    normal = -normal;
  object.plane.head<3>() = normal;
  object.plane[3] = -normal.dot(point);
  object.centre -= object.signedDistance(object.centre) * normal;
  object.patch_centre -= object.signedDistance(object.patch_centre) * normal;
  const Eigen::Vector3f width = object.width_axis - object.width_axis.dot(normal) * normal;
  if (!(width.norm() > 0.0f))
    return;
  Eigen::Vector3f height = normal.cross(width.normalized());
  if (height.dot(object.height_axis) < 0.0f)
    height = -height;
  object.width_axis = width.normalized();
  object.height_axis = height;
}
}  // namespace

void SharedNormals::process(const Sweep& sweep, const SweepContext&, const ReflectionEvidence&, SweepLabels&,
                            std::vector<ReflectiveObject>& objects)
{
  if (!config_.enabled || objects.size() < 2)
    return;
  std::vector<EchoMoments> moments;
  moments.reserve(objects.size());
  for (const ReflectiveObject& object : objects)
    moments.push_back(momentsOf(sweep, object));
  struct NewPlane
  {
    std::size_t object;
    Eigen::Vector3f normal;
    Eigen::Vector3f through;
  };
  std::vector<NewPlane> planes;
  for (std::size_t a = 0; a < objects.size(); ++a)
  {
    if (moments[a].count < kMinEchoes)
      continue;
    Eigen::Matrix3d scatter = moments[a].scatter;
    bool shared = false;
    for (std::size_t b = 0; b < objects.size(); ++b)
      if (b != a && moments[b].count > moments[a].count && inOneWall(objects[a], objects[b], config_.min_cosine))
      {
        scatter += moments[b].scatter;
        shared = true;
      }
    if (!shared)
      continue;
    // The direction of least scatter (eigenvalues ascending).
    const Eigen::Vector3d normal = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvectors().col(0);
    planes.push_back(NewPlane{ a, normal.cast<float>(), moments[a].centroid.cast<float>() });
  }
  for (const NewPlane& plane : planes)
    setPlane(objects[plane.object], plane.normal, plane.through);
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
