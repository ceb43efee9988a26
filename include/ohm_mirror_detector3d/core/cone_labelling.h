// Stage cleanScanTuple of the paper: label every point by the objects' vision cones.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "ohm_mirror_detector3d/core/reflection_evidence.h"
#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// For each point of both echoes, the index of the object whose surface it lies on or
// behind, or kNoObject.
struct ObjectAssignment
{
  static constexpr std::int32_t kNoObject = -1;
  std::array<std::vector<std::int32_t>, 2> echoes;
  // Per echo, in beam order: the points taken for one echo of an object's surface merged with a
  // reflection in it (merged_echoes.h), each with where the reflection's
  // own echo lies along its beam (what the reflection chains and the back-projection start from).
  struct MergedEcho
  {
    std::uint32_t beam;
    Eigen::Vector3f reflection;
  };
  std::array<std::vector<MergedEcho>, 2> merged_echoes;

  void reset(std::size_t beam_count);
};

struct ConeLabellingConfig
{
  double plane_threshold;  // d_thres_plane [m]: half thickness of a surface
  double cone_margin;      // d_thres_visionCone [m]: growth of the vision cone on every side
  int threads = 1;         // core/parallel.h: ranges of beams are labelled side by side
};

class ConeLabelling
{
public:
  explicit ConeLabelling(const ConeLabellingConfig& config);

  // Labels every point that is not nanPoint: on the surface of an object (within
  // plane_threshold, inside its vision cone from sensor_origin grown by cone_margin) or behind
  // it. A point on the surface gets the object's surface label by its type (errorSurface,
  // reflectiveSurface, transparentSurface). A point behind is labelled by its own evidence
  // (evidence.test with the object's plane and landing tolerance): behindReflective when,
  // reflected across the plane, it lands on what the sensor saw in front (a phantom),
  // behindTransparent when the sensor saw through where it lands (real, seen through the
  // surface); a point without evidence of its own (ambiguous, occluded, out of view, no return)
  // takes the object's type (behindReflective behind a mirror, behindTransparent behind glass,
  // behindErrorS behind an unknown surface). Where cones overlap the surface nearest to the
  // sensor wins. Points outside every cone (or in front of the surface) become valid, except
  // `error` points, which stay error. The points in the cones of an object's phantom planes and
  // of the surfaces seen through it (phantom_planes.h) are labelled against it; a pane's phantom
  // planes' own echoes are its reflections unless they land where the sensor looked through.
  // Fills each object's surface_points, behind_points, the counts of what the points behind
  // said, and mean_surface_intensity.
  void apply(const Sweep& sweep, const Eigen::Vector3f& sensor_origin, const ReflectionEvidence& evidence,
             std::vector<ReflectiveObject>& objects, SweepLabels& labels, ObjectAssignment& assignment) const;
  // The same with the evidence asked for only when the first point behind an object needs it
  // (the pipeline then builds it): a sweep in which no point lies behind any object (map
  // objects all round, none of them with anything behind it) never builds it.
  void apply(const Sweep& sweep, const Eigen::Vector3f& sensor_origin,
             const std::function<const ReflectionEvidence&()>& evidence, std::vector<ReflectiveObject>& objects,
             SweepLabels& labels, ObjectAssignment& assignment) const;

private:
  float plane_threshold_;
  float cone_margin_;
  int threads_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
