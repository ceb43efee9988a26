// Where a point lies relative to an object's vision cone: the cone from the sensor origin
// through the object's rectangle, grown by the vision-cone margin.
#pragma once

#include <Eigen/Core>

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
};

// `margin` grows the rectangle on every side; `plane_threshold` is the surface's half thickness.
ConeHit locateInCone(const ReflectiveObject& object, const Eigen::Vector3f& origin, const Eigen::Vector3f& point,
                     float plane_threshold, float margin);

}  // namespace core
}  // namespace ohm_mirror_detector3d
