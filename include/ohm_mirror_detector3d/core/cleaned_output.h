// Stage sendScanTuple of the paper: the points that go on to mapping.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "ohm_mirror_detector3d/core/reflection_chains.h"
#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct OutputPoint
{
  Eigen::Vector3f position;
  float intensity;
  Label label;
  std::uint8_t echo;   // 1 or 2
  std::uint32_t beam;  // index of the beam in the sweep
};

// Fills `cleaned` (cleared first, capacity kept) with every point whose label is kept
// for mapping, in beam order, echo 1 before echo 2; a behindReflective point is
// back-projected to where the object it shows really is: reflected across the mirrors of its
// chain (paths, reflection_chains.h) in order. A single-return beam that repeats its return in
// echo 2 (same position, as the Hokuyo3D driver and the simulator publish it) contributes it
// once, so mapping does not count it twice.
void collectCleaned(const Sweep& sweep, const SweepLabels& labels, const std::vector<ReflectiveObject>& objects,
                    const ReflectionPaths& paths, std::vector<OutputPoint>& cleaned);

}  // namespace core
}  // namespace ohm_mirror_detector3d
