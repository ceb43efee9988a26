#include "ohm_mirror_detector3d/core/vision_cone.h"

namespace ohm_mirror_detector3d
{
namespace core
{
ConeHit locateInCone(const ReflectiveObject& object, const Eigen::Vector3f& origin, const Eigen::Vector3f& point,
                     float plane_threshold, float margin)
{
  return VisionCone(object, origin, plane_threshold, margin).locate(point);
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
