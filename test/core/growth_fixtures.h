// The detect phase's labels of a traced sweep and a hand-made patch, for the growth stages' tests.
#pragma once

#include "ohm_mirror_detector3d/core/echo_comparison.h"
#include "ohm_mirror_detector3d/core/plane_crossings.h"
#include "ohm_mirror_detector3d/core/range_gate.h"
#include "ohm_mirror_detector3d/core/reflection_evidence.h"
#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace test
{
// What the object stages get from the detect phase: nanPoint out of range, errorSurface / error
// on the discontinuous beams, unchecked elsewhere; and the per-point evidence over it.
struct Detected
{
  core::SweepLabels labels;
  core::ReflectionEvidence evidence;

  explicit Detected(const core::Sweep& sweep)
  {
    labels.reset(sweep.beamCount());
    core::RangeGate(core::RangeGateConfig{ 0.05, 60.0 }).apply(sweep, labels);
    core::EchoComparison(core::EchoComparisonConfig{ 0.05 }).apply(sweep, labels);
    evidence.build(sweep, labels, Eigen::Vector3f::Zero());
  }
};

// The growth stages switched on with the defaults' cap, 5 cm plane threshold.
inline core::ObjectGrowthConfig growthConfig()
{
  core::ObjectGrowthConfig config;
  config.panes = true;
  config.mirrors = true;
  config.plane_threshold = 0.05f;
  config.max_growth = 1.5f;
  return config;
}

// A patch (the surface-echo rectangle) on the plane x = distance, facing the origin, centred at
// (distance, y, z), `size` across both ways.
inline core::ReflectiveObject patchAt(float distance, float y, float z, float size, core::ObjectType type)
{
  core::ReflectiveObject object;
  object.type = type;
  object.plane = Eigen::Vector4f(-1.0f, 0.0f, 0.0f, distance);
  object.centre = Eigen::Vector3f(distance, y, z);
  object.width_axis = Eigen::Vector3f::UnitY();
  object.height_axis = Eigen::Vector3f::UnitZ();
  object.width = size;
  object.height = size;
  return object;
}

// The grown rectangle's sides along y (width) and z (height).
struct Sides
{
  float y_low, y_high, z_low, z_high;
};

inline Sides sidesOf(const core::ReflectiveObject& object)
{
  return { object.centre.y() - 0.5f * object.width, object.centre.y() + 0.5f * object.width,
           object.centre.z() - 0.5f * object.height, object.centre.z() + 0.5f * object.height };
}

}  // namespace test
}  // namespace ohm_mirror_detector3d
