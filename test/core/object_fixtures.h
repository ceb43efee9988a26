// Hand-made objects for the core tests.
#pragma once

#include "ohm_mirror_detector3d/core/reflective_object.h"

namespace ohm_mirror_detector3d
{
namespace test
{
// A vertical rectangle in the plane x = distance, facing the origin, centred on the x axis.
inline core::ReflectiveObject wallObject(float distance, float width, float height,
                                         core::ObjectType type = core::ObjectType::unknown, std::uint32_t id = 0)
{
  core::ReflectiveObject object;
  object.id = id;
  object.type = type;
  object.plane = Eigen::Vector4f(-1.0f, 0.0f, 0.0f, distance);
  object.centre = Eigen::Vector3f(distance, 0.0f, 0.0f);
  object.width_axis = Eigen::Vector3f::UnitY();
  object.height_axis = Eigen::Vector3f::UnitZ();
  object.width = width;
  object.height = height;
  return object;
}

}  // namespace test
}  // namespace ohm_mirror_detector3d
