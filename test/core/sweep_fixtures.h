// Tiny hand-made sweeps for the core tests.
#pragma once

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "ohm_mirror_detector3d/core/reflection_evidence.h"
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

// An axis-aligned wall: the points x with x[axis] == at, seen only where `seen(x)` holds.
struct Wall
{
  int axis;
  float at;
  bool (*seen)(const Eigen::Vector3f&);
};

inline bool everywhere(const Eigen::Vector3f&)
{
  return true;
}

// A lidar's sweep at the origin on a grid of directions [deg]: row r at elevation
// elevation0 + r elevation_step, column c at azimuth heading + (azimuth0 + c azimuth_step).
// beam(direction) gives each beam's return as (point, intensity), both echoes alike (a
// non-finite point: none); it is called row by row, so that a noise generator it draws from
// gives the same sweep every time.
template <typename Beam>
core::Sweep gridSweep(std::size_t rows, std::size_t cols, float elevation0, float elevation_step, float heading,
                      float azimuth0, float azimuth_step, Beam beam)
{
  const float degree = static_cast<float>(M_PI) / 180.0f;
  core::Sweep sweep;
  sweep.resize(rows, cols);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c)
    {
      const float elevation = elevation0 * degree + elevation_step * degree * static_cast<float>(r);
      const float azimuth = heading * degree + (azimuth0 + azimuth_step * static_cast<float>(c)) * degree;
      const Eigen::Vector3f direction(std::cos(elevation) * std::cos(azimuth),
                                      std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
      const std::pair<Eigen::Vector3f, float> point_and_intensity = beam(direction);
      for (core::EchoCloud& echo : sweep.echoes)
      {
        echo.points[r * cols + c] = point_and_intensity.first;
        echo.intensities[r * cols + c] = point_and_intensity.second;
      }
    }
  sweep.computeRanges(Eigen::Vector3f::Zero());
  return sweep;
}

// A sweep of a spinning lidar at the origin: 1 degree steps in azimuth (all around) and in
// elevation (-60 to 60 degrees), each beam's single return on the nearest wall it hits (none:
// a non-finite point).
inline core::Sweep rangeImage(const std::vector<Wall>& walls)
{
  const float degree = static_cast<float>(M_PI) / 180.0f;
  core::Sweep sweep;
  const std::size_t rows = 121, cols = 360;
  sweep.resize(rows, cols);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c)
    {
      const float elevation = (static_cast<float>(r) - 60.0f) * degree;
      const float azimuth = static_cast<float>(c) * degree;
      const Eigen::Vector3f direction(std::cos(elevation) * std::cos(azimuth),
                                      std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
      float nearest = std::numeric_limits<float>::infinity();
      for (const Wall& wall : walls)
      {
        const float t = wall.at / direction[wall.axis];
        if (t > 0.0f && t < nearest && wall.seen(t * direction))
          nearest = t;
      }
      const Eigen::Vector3f point =
          std::isfinite(nearest) ? Eigen::Vector3f(nearest * direction)
                               : Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
      sweep.echoes[0].points[r * cols + c] = point;
      sweep.echoes[1].points[r * cols + c] = point;
    }
  sweep.computeRanges(Eigen::Vector3f::Zero());
  return sweep;
}

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

// The reflection evidence of a sweep whose echoes are all unchecked (before the echo comparison),
// seen from the origin.
inline core::ReflectionEvidence evidenceOf(const core::Sweep& sweep)
{
  core::SweepLabels labels;
  labels.reset(sweep.beamCount());
  core::ReflectionEvidence evidence;
  evidence.build(sweep, labels, Eigen::Vector3f::Zero());
  return evidence;
}

}  // namespace test
}  // namespace ohm_mirror_detector3d
