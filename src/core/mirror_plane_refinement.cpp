#include "ohm_mirror_detector3d/core/mirror_plane_refinement.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>


namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
constexpr int kPlaneRefinementIterations = 10;
// Tukey biweight of the refinement: correspondences beyond this many robust sigmas (1.4826 MAD)
// weigh nothing, and the cut is never below three times the scanner's noise.
constexpr float kTukeyScale = 3.0f;
constexpr float kMadToSigma = 1.4826f;
constexpr float kMinTukeyThreshold = 0.03f;
}  // namespace

PlaneRefinement MirrorPlaneRefinement::refine(RealScene& scene, const std::vector<Eigen::Vector3f>& surface,
                                              const std::vector<Eigen::Vector3f>& behind,
                                              const Eigen::Vector3f& sensor_origin, double phantom_weight,
                                              ReflectiveObject& object)
{
  PlaneRefinement result;
  // Only the mirror's 3 degrees of freedom (normal tilt, offset) are estimated, by
  // Gauss-Newton; residuals are point-to-plane distances to the real surface at the nearest
  // real point, because point-to-point residuals carry the offset between two samplings of a
  // wall, which biases the tilt by as much again. The surface echoes' distances to the plane
  // stay in the same least squares (same noise, same weight; each sampled phantom weighs for
  // the phantoms it stands for): where the phantoms constrain the plane poorly (all on one
  // floor, say), the surface echoes keep it.
  Eigen::Vector3f normal = object.plane.head<3>();
  float offset = object.plane[3];
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  double weighted_squares = 0.0, weights = 0.0;
  for (int iteration = 0; iteration < kPlaneRefinementIterations; ++iteration)
  {
    const Eigen::Vector3f helper = std::fabs(normal.z()) < 0.9f ? Eigen::Vector3f::UnitZ() : Eigen::Vector3f::UnitX();
    const Eigen::Vector3f u = normal.cross(helper).normalized();
    const Eigen::Vector3f v = normal.cross(u);
    Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
    Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
    weighted_squares = weights = 0.0;
    for (const Eigen::Vector3f& s : surface)
    {
      const Eigen::Vector3d jacobian(u.dot(s), v.dot(s), 1.0);
      const double residual = static_cast<double>(normal.dot(s) + offset);
      hessian += jacobian * jacobian.transpose();
      gradient += jacobian * residual;
      weighted_squares += residual * residual;
      weights += 1.0;
    }
    // Phantom residuals first, then a robust (Tukey) weight from their spread: a phantom
    // matched to the wrong surface (a corner, a part of the room the sensor did not see)
    // must not drag the mirror.
    correspondences_.clear();
    for (const Eigen::Vector3f& p : behind)
    {
      const float side = normal.dot(p) + offset;
      const Eigen::Vector3f mirrored = p - 2.0f * side * normal;
      float squared = 0.0f;
      const std::uint32_t nearest = scene.nearest(mirrored, squared);
      if (nearest == RealScene::kNone)
        continue;
      const Eigen::Vector3f& surface_normal = scene.surfaceNormal(nearest);
      if (!surface_normal.allFinite())
        continue;
      const float residual = surface_normal.dot(mirrored - scene.points()[nearest]);
      // Derivatives of p - 2 (n.p + d) n for n tilted towards u, towards v, and for d,
      // projected on the real surface's normal.
      const Eigen::Vector3d jacobian(surface_normal.dot(-2.0f * (u.dot(p) * normal + side * u)),
                                     surface_normal.dot(-2.0f * (v.dot(p) * normal + side * v)),
                                     surface_normal.dot(-2.0f * normal));
      correspondences_.push_back({ jacobian, residual });
    }
    const std::size_t used = correspondences_.size();
    if (used < 3)
      return result;
    absolute_residuals_.resize(used);
    for (std::size_t c = 0; c < used; ++c)
      absolute_residuals_[c] = std::fabs(correspondences_[c].residual);
    std::nth_element(absolute_residuals_.begin(), absolute_residuals_.begin() + used / 2, absolute_residuals_.end());
    const float tukey = std::max(kTukeyScale * kMadToSigma * absolute_residuals_[used / 2], kMinTukeyThreshold);
    for (const Correspondence& c : correspondences_)
    {
      const float magnitude = std::fabs(c.residual);
      const double ratio = static_cast<double>(magnitude / tukey);
      const double weight = phantom_weight * (ratio < 1.0 ? (1.0 - ratio * ratio) * (1.0 - ratio * ratio) : 0.0);
      hessian += weight * c.jacobian * c.jacobian.transpose();
      gradient += weight * c.jacobian * static_cast<double>(c.residual);
      weighted_squares += weight * static_cast<double>(c.residual) * static_cast<double>(c.residual);
      weights += weight;
    }
    information = hessian;
    const Eigen::Vector3d step = -hessian.ldlt().solve(gradient);
    if (!step.allFinite())
      return result;
    normal = (normal + static_cast<float>(step[0]) * u + static_cast<float>(step[1]) * v).normalized();
    offset += static_cast<float>(step[2]);
    if (step.head<2>().norm() < 1e-6 && std::fabs(step[2]) < 1e-5)
      break;
  }
  // A refinement that turned the plane away from the sensor, or by more than ICP may move
  // the phantoms, fitted something else: keep the surface plane.
  if (!(normal.dot(sensor_origin) + offset > 0.0f) ||
      normal.dot(object.plane.head<3>()) < std::cos(kMaxPlaneRefinementAngle))
    return result;
  // The tilt's standard deviation: residual variance times the inverse information, its larger
  // tilt axis.
  const Eigen::Matrix2d tilt_covariance = (weighted_squares / std::max(weights, 1.0)) *
                                          information.inverse().topLeftCorner<2, 2>();
  const double largest = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(tilt_covariance).eigenvalues()[1];
  result.refined = true;
  result.angle_uncertainty = static_cast<float>(std::sqrt(std::max(largest, 0.0)));
  object.plane.head<3>() = normal;
  object.plane[3] = offset;
  object.centre -= object.signedDistance(object.centre) * normal;
  // Keep the rectangle's axes in the refined plane (they turn by a fraction of a degree).
  object.width_axis = (object.width_axis - object.width_axis.dot(normal) * normal).normalized();
  object.height_axis = normal.cross(object.width_axis);
  return result;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
