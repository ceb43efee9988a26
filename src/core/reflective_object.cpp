#include "ohm_mirror_detector3d/core/reflective_object.h"

namespace ohm_mirror_detector3d
{
namespace core
{
const char* objectTypeName(ObjectType type)
{
  switch (type)
  {
    case ObjectType::unknown: return "unknown";
    case ObjectType::mirror: return "mirror";
    case ObjectType::glass: return "glass";
  }
  return "invalid-type";
}

namespace
{
std::array<Eigen::Vector3f, 4> rectangleCorners(const Eigen::Vector3f& centre, const Eigen::Vector3f& width_axis,
                                                const Eigen::Vector3f& height_axis, float width, float height)
{
  const Eigen::Vector3f half_width = 0.5f * width * width_axis;
  const Eigen::Vector3f half_height = 0.5f * height * height_axis;
  return { centre - half_width - half_height, centre + half_width - half_height,
           centre + half_width + half_height, centre - half_width + half_height };
}
}  // namespace

std::array<Eigen::Vector3f, 4> ReflectiveObject::corners() const
{
  return rectangleCorners(centre, width_axis, height_axis, width, height);
}

std::array<Eigen::Vector3f, 4> ReflectiveObject::patchCorners() const
{
  if (!grown)
    return corners();
  return rectangleCorners(patch_centre, width_axis, height_axis, patch_width, patch_height);
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
