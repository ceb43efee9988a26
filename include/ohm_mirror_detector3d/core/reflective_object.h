// A planar specular or transparent object found in a sweep.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
enum class ObjectType : std::uint8_t
{
  unknown = 0,  // discontinuous echoes on a plane, too little evidence to decide
  mirror = 1,   // the points behind the plane are a reflection of the scene in front of it
  glass = 2,    // the points behind the plane are real
};

const char* objectTypeName(ObjectType type);

// How far from the surface the sensor saw in its direction a point reflected across an object's
// plane (q) may lie and still lie on it [m]: base + per metre of q's range (noise, sampling) +
// per metre the point lies behind the plane (the plane's angular uncertainty: an error of the
// plane's tilt moves q by twice the tilt times the distance behind).
struct LandingTolerance
{
  float base = 0.1f;
  float per_range = 0.005f;
  float per_behind = 0.0f;

  float at(float range, float behind) const { return base + per_range * range + per_behind * behind; }
};

// Why the type decision came out as it did (see analyzeObjectType).
struct TypeEvidence
{
  std::size_t mirrored_points = 0;  // points behind the plane reflected across it
  std::size_t matched_points = 0;   // of those, within icp_max_distance of the real scene after ICP
                                    // (estimated on a sample of at most 512 of them)
  float inlier_fraction = std::numeric_limits<float>::quiet_NaN();
  float icp_fitness = std::numeric_limits<float>::quiet_NaN();  // mean squared distance of matches [m^2]
  bool icp_converged = false;
  Eigen::Matrix4f icp_correction = Eigen::Matrix4f::Identity();
};

struct ReflectiveObject
{
  std::uint32_t id = 0;
  ObjectType type = ObjectType::unknown;

  // Plane n.x + d = 0, (n, d) = plane.head<3>(), plane[3]; n is a unit normal pointing
  // towards the sensor origin.
  Eigen::Vector4f plane = Eigen::Vector4f::Zero();

  // Rectangle: centre, unit axes in the plane (width_axis the more horizontal one, i.e.
  // with the smaller |z|; for a horizontal plane the longer side), full extents along them.
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  Eigen::Vector3f width_axis = Eigen::Vector3f::UnitX();
  Eigen::Vector3f height_axis = Eigen::Vector3f::UnitY();
  float width = 0.0f;
  float height = 0.0f;

  // The errorSurface points the plane was fitted to.
  std::vector<PointRef> surface_inliers;

  // Filled by cone labelling: points of both echoes on the surface and behind it.
  std::size_t surface_points = 0;
  std::size_t behind_points = 0;
  float mean_surface_intensity = std::numeric_limits<float>::quiet_NaN();

  TypeEvidence evidence;

  // Corners in order around the rectangle: centre -+ w/2 -+ h/2.
  std::array<Eigen::Vector3f, 4> corners() const;

  // Signed distance of p from the plane, positive on the sensor's side.
  float signedDistance(const Eigen::Vector3f& p) const { return plane.head<3>().dot(p) + plane[3]; }

  // p reflected across the plane.
  Eigen::Vector3f reflect(const Eigen::Vector3f& p) const
  {
    return p - 2.0f * signedDistance(p) * plane.head<3>();
  }

};

}  // namespace core
}  // namespace ohm_mirror_detector3d
