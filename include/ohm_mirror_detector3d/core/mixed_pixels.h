// Double echoes at depth edges of ordinary geometry (mixed pixels). A beam whose footprint
// straddles the edge of a table top or a box returns from both sides of it: the near echo on
// the edge of the nearer surface, the far echo on the surface behind. The echo comparison marks
// such a beam discontinuous like a beam through glass, and real frames are full of them (about
// a fifth of a 64-ring lidar's second returns indoors: SENSORS.md). Along an edge they make a
// line one beam wide, which object extraction refuses as a surface; this stage then gives both
// their echoes back to the scene, where otherwise the far one would be dropped as `error`.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ohm_mirror_detector3d/core/beam_neighbourhood.h"
#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/sweep.h"
#include "ohm_mirror_detector3d/core/sweep_sampling.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct MixedPixelConfig
{
  // Its noise floor is also the range difference below which two echoes of a beam are one
  // surface (d_thres).
  BeamNeighbourhoodConfig neighbourhood;
};

class MixedPixels
{
public:
  explicit MixedPixels(const MixedPixelConfig& config) : config_(config) {}

  // On a sweep with a grid, for every beam whose echoes are errorSurface and error and whose
  // errorSurface echo belongs to no object (surface_inliers): when one of the beams around it
  // returns from one surface only (no two echoes further apart than the noise floor) at a
  // point within the neighbourhood's limit of the near echo (the near echo continues a surface
  // seen in front), and one of the beams around has a return within the limit of the far echo
  // (it continues a surface seen behind), both echoes become unchecked: both are real. Judged
  // on the labels before the call. Returns the number of beams released.
  std::size_t release(const Sweep& sweep, const SweepSampling& sampling, const std::vector<ReflectiveObject>& objects,
                      SweepLabels& labels);

private:
  MixedPixelConfig config_;
  std::vector<std::uint8_t> on_object_;  // per beam
  std::vector<std::uint32_t> released_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
