// Where a point lies relative to an object's vision cone: the cone from the sensor origin
// through the object's rectangle, grown by half the beam footprint (ReflectiveObject::footprint)
// and the vision-cone margin.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "ohm_mirror_detector3d/core/reflective_object.h"

namespace ohm_mirror_detector3d
{
namespace core
{
enum class ConeRelation
{
  outside,    // the ray from the origin to the point misses the grown rectangle
  inFront,    // inside the cone, nearer to the sensor than the surface
  onSurface,  // inside the cone, within plane_threshold of the plane
  behind,     // inside the cone, beyond the surface
};

struct ConeHit
{
  ConeRelation relation = ConeRelation::outside;
  float plane_range = 0.0f;  // distance from the origin to where the ray crosses the plane
  Eigen::Vector3f crossing = Eigen::Vector3f::Zero();  // that crossing (onSurface and behind only)
};

// One object's vision cone with everything that does not depend on the point worked out
// once: the stages that test every point of a sweep against every object call it inline
// (a function call and the origin's side per point cost as much as the test itself).
class VisionCone
{
public:
  // `margin` grows the rectangle on every side beyond half the footprint; `plane_threshold` is
  // the surface's half thickness.
  VisionCone(const ReflectiveObject& object, const Eigen::Vector3f& origin, float plane_threshold, float margin)
    : normal_(object.plane.head<3>())
    , offset_(object.plane[3])
    , origin_(origin)
    , centre_(object.centre)
    , width_axis_(object.width_axis)
    , height_axis_(object.height_axis)
    , half_width_(0.5f * (object.width + object.footprint) + margin)
    , half_height_(0.5f * (object.height + object.footprint) + margin)
    , plane_threshold_(plane_threshold)
    , origin_side_(object.signedDistance(origin))
  {
  }

  // Signed distance of p from the plane, positive on the sensor's side.
  float side(const Eigen::Vector3f& p) const { return normal_.dot(p) + offset_; }

  ConeHit locate(const Eigen::Vector3f& point) const
  {
    ConeHit hit;
    const float point_side = side(point);
    // A sensor behind the plane does not see this surface at all.
    if (!(origin_side_ > 0.0f))
      return hit;
    if (point_side > plane_threshold_)
    {
      // Whether such a point is inside the cone matters to no caller: it is not affected.
      hit.relation = ConeRelation::inFront;
      return hit;
    }
    // Where the ray origin -> point crosses the plane; for points in the surface band that
    // lie slightly in front of the plane, extend the ray to it.
    const float denominator = origin_side_ - point_side;
    const Eigen::Vector3f crossing =
        denominator > 0.0f ? Eigen::Vector3f(origin_ + (origin_side_ / denominator) * (point - origin_)) : point;
    const Eigen::Vector3f offset = crossing - centre_;
    if (std::fabs(offset.dot(width_axis_)) > half_width_ || std::fabs(offset.dot(height_axis_)) > half_height_)
      return hit;
    hit.relation = point_side >= -plane_threshold_ ? ConeRelation::onSurface : ConeRelation::behind;
    hit.plane_range = (crossing - origin_).norm();
    hit.crossing = crossing;
    return hit;
  }

private:
  Eigen::Vector3f normal_;
  float offset_;
  Eigen::Vector3f origin_;
  Eigen::Vector3f centre_;
  Eigen::Vector3f width_axis_;
  Eigen::Vector3f height_axis_;
  float half_width_;
  float half_height_;
  float plane_threshold_;
  float origin_side_;
};

// The same test for a single point (builds the VisionCone each call).
ConeHit locateInCone(const ReflectiveObject& object, const Eigen::Vector3f& origin, const Eigen::Vector3f& point,
                     float plane_threshold, float margin);

}  // namespace core
}  // namespace ohm_mirror_detector3d
