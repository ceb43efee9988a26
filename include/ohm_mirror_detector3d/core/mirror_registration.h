// The registration behind the type decision: do a plane's phantoms, reflected across it, land on
// the real scene? Point-to-point ICP of the reflected points onto the real scene (RealScene),
// with the correspondences within the scene's reach.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <vector>

#include "ohm_mirror_detector3d/core/real_scene.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// A mirror's phantoms, reflected across a plane fitted to its surface echoes, already land on
// the real scene; ICP only takes out the small error of the fitted plane. A larger correction
// means ICP slid them onto some other structure.
constexpr float kMaxMirrorCorrectionAngle = 5.0f * static_cast<float>(M_PI) / 180.0f;

// Of `points`, how many lie within the scene's reach of a real point; the sum of their squared
// distances in `squared_sum`.
std::size_t countMatches(const RealScene& scene, const std::vector<Eigen::Vector3f>& points, double& squared_sum);

class MirrorRegistration
{
public:
  // Point-to-point ICP of `mirrored` onto the scene: the correspondences within reach, the
  // rigid motion that best aligns them (Umeyama), repeated until an iteration hardly moves
  // them, the mean squared distance stops changing, or 30 iterations; like PCL's ICP, it has
  // converged unless fewer than 3 correspondences were found. With stop_when_too_far it also
  // stops once the accumulated correction moves them further than max_distance or turns them
  // by more than kMaxMirrorCorrectionAngle (no mirror's phantoms need that). Returns whether
  // it converged; `correction` is the accumulated motion, aligned() the moved points.
  bool align(const RealScene& scene, const std::vector<Eigen::Vector3f>& mirrored, bool stop_when_too_far,
             float max_distance, Eigen::Matrix4f& correction);

  const std::vector<Eigen::Vector3f>& aligned() const { return aligned_; }

private:
  std::vector<Eigen::Vector3f> aligned_;
  Eigen::Matrix3Xf source_matches_;
  Eigen::Matrix3Xf target_matches_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
