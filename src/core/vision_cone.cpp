#include "ohm_mirror_detector3d/core/vision_cone.h"

#include <cmath>

namespace ohm_mirror_detector3d
{
namespace core
{
ConeHit locateInCone(const ReflectiveObject& object, const Eigen::Vector3f& origin, const Eigen::Vector3f& point,
                     float plane_threshold, float margin)
{
  ConeHit hit;
  const float origin_side = object.signedDistance(origin);
  const float point_side = object.signedDistance(point);
  // A sensor behind the plane does not see this surface at all.
  if (!(origin_side > 0.0f))
    return hit;
  if (point_side > plane_threshold)
  {
    // Whether such a point is inside the cone matters to no caller: it is not affected.
    hit.relation = ConeRelation::inFront;
    return hit;
  }
  // Where the ray origin -> point crosses the plane; for points in the surface band that
  // lie slightly in front of the plane, extend the ray to it.
  const float denominator = origin_side - point_side;
  const Eigen::Vector3f crossing =
      denominator > 0.0f ? Eigen::Vector3f(origin + (origin_side / denominator) * (point - origin)) : point;
  const Eigen::Vector3f offset = crossing - object.centre;
  if (std::fabs(offset.dot(object.width_axis)) > 0.5f * object.width + margin ||
      std::fabs(offset.dot(object.height_axis)) > 0.5f * object.height + margin)
    return hit;
  hit.relation = point_side >= -plane_threshold ? ConeRelation::onSurface : ConeRelation::behind;
  hit.plane_range = (crossing - origin).norm();
  return hit;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
