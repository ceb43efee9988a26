// Tiny hand-made sweeps for the core tests.
#pragma once

#include <limits>
#include <vector>

#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace test
{
// One beam: its two echoes as points in the sensor frame (origin at 0).
struct Beam
{
  Eigen::Vector3f echo1;
  Eigen::Vector3f echo2;
};

// A 1 x N sweep from hand-written beams; intensities are the beam index.
inline core::Sweep makeSweep(const std::vector<Beam>& beams)
{
  core::Sweep sweep;
  sweep.resize(1, beams.size());
  sweep.has_intensity = true;
  for (std::size_t i = 0; i < beams.size(); ++i)
  {
    sweep.echoes[0].points[i] = beams[i].echo1;
    sweep.echoes[1].points[i] = beams[i].echo2;
    sweep.echoes[0].intensities[i] = static_cast<float>(i);
    sweep.echoes[1].intensities[i] = static_cast<float>(i);
  }
  sweep.computeRanges(Eigen::Vector3f::Zero());
  return sweep;
}

// A point at `range` metres straight ahead (+x).
inline Eigen::Vector3f ahead(float range)
{
  return Eigen::Vector3f(range, 0.0f, 0.0f);
}

inline Eigen::Vector3f filled(float value)
{
  return Eigen::Vector3f::Constant(value);
}

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

}  // namespace test
}  // namespace ohm_mirror_detector3d
