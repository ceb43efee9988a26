#include "ohm_mirror_detector3d/core/mirror_registration.h"

#include <Eigen/Geometry>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
constexpr int kIcpIterations = 30;
// ICP has converged when an iteration turns by less than this [rad] and moves by less than
// this [m] (0.5 mm at 5 m; the scanner's noise is 1 cm), or when the mean squared distance of
// the correspondences changed by less than this share.
constexpr float kIcpStepRotation = 1e-4f;
constexpr float kIcpStepTranslation = 1e-4f;
constexpr double kIcpRelativeMseChange = 1e-5;
}  // namespace

std::size_t countMatches(const RealScene& scene, const std::vector<Eigen::Vector3f>& points, double& squared_sum)
{
  std::size_t matched = 0;
  squared_sum = 0.0;
  for (const Eigen::Vector3f& p : points)
  {
    float squared = 0.0f;
    if (scene.nearest(p, squared) != RealScene::kNone)
    {
      ++matched;
      squared_sum += squared;
    }
  }
  return matched;
}

bool MirrorRegistration::align(const RealScene& scene, const std::vector<Eigen::Vector3f>& mirrored,
                               bool stop_when_too_far, float max_distance, Eigen::Matrix4f& correction)
{
  correction.setIdentity();
  aligned_ = mirrored;
  bool converged = false;
  double previous_mse = -1.0;
  for (int iteration = 0; iteration < kIcpIterations; ++iteration)
  {
    std::size_t used = 0;
    double squared_sum = 0.0;
    source_matches_.resize(3, static_cast<Eigen::Index>(aligned_.size()));
    target_matches_.resize(3, static_cast<Eigen::Index>(aligned_.size()));
    for (const Eigen::Vector3f& p : aligned_)
    {
      float squared = 0.0f;
      const std::uint32_t nearest = scene.nearest(p, squared);
      if (nearest == RealScene::kNone)
        continue;
      squared_sum += squared;
      source_matches_.col(static_cast<Eigen::Index>(used)) = p;
      target_matches_.col(static_cast<Eigen::Index>(used)) = scene.points()[nearest];
      ++used;
    }
    // Like PCL's ICP: fewer than 3 correspondences cannot fix a rigid motion.
    if (used < 3)
      return false;
    converged = true;
    const Eigen::Matrix4f step = Eigen::umeyama(source_matches_.leftCols(static_cast<Eigen::Index>(used)),
                                                target_matches_.leftCols(static_cast<Eigen::Index>(used)), false);
    if (!step.allFinite())
      return false;
    const Eigen::Affine3f motion(step);
    for (Eigen::Vector3f& p : aligned_)
      p = motion * p;
    correction = step * correction;
    const double mse = squared_sum / static_cast<double>(used);
    if ((Eigen::AngleAxisf(motion.linear()).angle() < kIcpStepRotation &&
         motion.translation().norm() < kIcpStepTranslation) ||
        (previous_mse >= 0.0 && std::fabs(mse - previous_mse) <= kIcpRelativeMseChange * previous_mse))
    {
      break;
    }
    previous_mse = mse;
    if (stop_when_too_far)
    {
      const Eigen::Affine3f total(correction);
      if (total.translation().norm() > max_distance ||
          Eigen::AngleAxisf(total.linear()).angle() > kMaxMirrorCorrectionAngle)
        break;
    }
  }
  // Reaching the iteration cap counts as converged, as in PCL.
  return converged;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
