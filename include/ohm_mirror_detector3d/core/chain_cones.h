// Whether a point behind one object, reflected across it, lies behind another object as the
// sensor's image in the first sees it (the test of reflection_chains.cpp): then the light that
// reached it may have come by a second reflection, or through that other surface, and where it
// lands proves nothing about the first object. The cone labelling asks it before it checks a
// point's light path; the type decision before it counts a point as seen through.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/vision_cone.h"

namespace ohm_mirror_detector3d
{
namespace core
{
class ChainCones
{
public:
  // Every object's cone from every other's image of the origin (n^2 cones: a few dozen objects at
  // most), built before the stage's threads start so that they only read them. The objects are
  // copied as they are now: the type decision refines their planes while it asks.
  ChainCones(const std::vector<ReflectiveObject>& objects, const Eigen::Vector3f& origin, float plane_threshold,
             float margin)
    : plane_threshold_(plane_threshold), cones_(objects.size())
  {
    if (objects.size() < 2)
      return;
    planes_.reserve(objects.size());
    for (std::size_t from = 0; from < objects.size(); ++from)
    {
      planes_.push_back(objects[from].plane);
      const Eigen::Vector3f image = objects[from].reflect(origin);
      for (const ReflectiveObject& object : objects)
        cones_[from].emplace_back(object, image, plane_threshold, margin);
    }
  }

  // Whether a point behind object `from`, reflected across it to `reflected`, its beam crossing
  // the plane at `crossing`, lies behind another object in front of which that crossing is.
  bool mayContinue(std::size_t from, const Eigen::Vector3f& reflected, const Eigen::Vector3f& crossing) const
  {
    if (planes_.size() < 2)
      return false;
    const std::vector<VisionCone>& cones = cones_[from];
    for (std::size_t j = 0; j < planes_.size(); ++j)
      if (j != from && planes_[j].head<3>().dot(crossing) + planes_[j][3] > plane_threshold_ &&
          cones[j].locate(reflected).relation == ConeRelation::behind)
        return true;
    return false;
  }

private:
  std::vector<Eigen::Vector4f, Eigen::aligned_allocator<Eigen::Vector4f>> planes_;
  float plane_threshold_;
  std::vector<std::vector<VisionCone>> cones_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
