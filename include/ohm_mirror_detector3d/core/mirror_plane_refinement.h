// The plane of a reflecting surface, refined to the pure reflection that puts its phantoms onto
// the real scene they show (part of the type decision, for every object with enough phantoms:
// mirrors, shiny metal, glass that reflects).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "ohm_mirror_detector3d/core/real_scene.h"
#include "ohm_mirror_detector3d/core/reflective_object.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// A reflecting surface's phantoms, reflected across a plane fitted to its surface echoes,
// already land near the real scene; the refinement only takes out the small error of the fitted
// plane. A refinement that turns it further fitted something else.
constexpr float kMaxPlaneRefinementAngle = 5.0f * static_cast<float>(M_PI) / 180.0f;

struct PlaneRefinement
{
  bool refined = false;
  float angle_uncertainty = 0.0f;  // standard deviation of the refined plane's tilt [rad]
};

class MirrorPlaneRefinement
{
public:
  // The plane fitted to a mirror's surface echoes is good to a few tenths of a degree (a
  // thousand echoes with 1 cm noise on 60 x 40 cm); reflection multiplies that by the
  // phantoms' distance behind the mirror: 0.1 deg is 2 cm at 5 m. The phantoms and the real
  // scene they show pin the plane down far better: this finds the plane whose reflection puts
  // the phantoms `behind` (a sample, each standing for `phantom_weight` of them) onto the real
  // surfaces of `scene`, with the `surface` echoes' distances to the plane in the same least
  // squares. On success it moves object.plane, centre and axes into the refined plane and says
  // how uncertain its tilt still is; a refinement that turned the plane away from
  // sensor_origin, or by more than kMaxPlaneRefinementAngle, keeps the object as it was.
  PlaneRefinement refine(RealScene& scene, const std::vector<Eigen::Vector3f>& surface,
                         const std::vector<Eigen::Vector3f>& behind, const Eigen::Vector3f& sensor_origin,
                         double phantom_weight, ReflectiveObject& object);

private:
  struct Correspondence
  {
    Eigen::Vector3d jacobian;
    float residual;
  };
  std::vector<Correspondence> correspondences_;
  std::vector<float> absolute_residuals_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
