// Stage analyzeObjectType of the paper: mirror or glass, by registering the mirrored
// points behind the plane to the real scene in front of it.
#pragma once

#include <Eigen/Core>
#include <memory>

#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct ObjectTypeConfig
{
  double plane_threshold;          // d_thres_plane [m]: half thickness of the surface
  double cone_margin;              // d_thres_visionCone [m]: growth of the vision cone
  double icp_max_distance;         // [m]
  double icp_fitness_threshold;    // [m^2]
  int icp_min_points;
  double icp_min_inlier_fraction;
};

class ObjectTypeAnalyzer
{
public:
  explicit ObjectTypeAnalyzer(const ObjectTypeConfig& config);
  ~ObjectTypeAnalyzer();
  ObjectTypeAnalyzer(ObjectTypeAnalyzer&&) noexcept;
  ObjectTypeAnalyzer& operator=(ObjectTypeAnalyzer&&) noexcept;

  // Reflects the points behind the object (inside its vision cone from sensor_origin, both
  // echoes, nanPoint excluded) across its plane and registers them by ICP (max correspondence distance
  // icp_max_distance) to the real points in front of the plane near where they land
  // (labels unchecked or valid; error and errorSurface points are echoes of this or
  // another surface, not real geometry). For speed (see object_type.cpp) the registered
  // points are an even, deterministic sample of at most 512 of them, and the real scene is
  // taken only near where that sample lands, one point per 2 cm voxel; the shares and means
  // below are the sample's, matched_points is the sample's share times mirrored_points.
  // Sets object.type and object.evidence:
  // - unknown when fewer than icp_min_points points are behind it, or when the sensor saw
  //   fewer than that many real points in the directions where the mirrored points land
  //   (nothing to compare with, e.g. a mirror facing open space: no confident decision);
  // - mirror when ICP converged, at least icp_min_inlier_fraction of the mirrored points lie
  //   within icp_max_distance of a real point after ICP, their mean squared distance is at
  //   most icp_fitness_threshold, and ICP moved them only a little (a real mirror's phantoms
  //   land on the real scene already: a large correction means ICP fitted something else);
  //   the mirror's plane is then refined to the pure reflection nearest to what ICP found,
  //   which back-projects phantoms far more accurately than the plane of the surface echoes;
  // - glass when fewer than half of icp_min_inlier_fraction match, before and after ICP: the
  //   sensor looked where the mirrored points land and saw something else there (free space
  //   or other geometry);
  // - unknown in between: ambiguous evidence is not turned into a confident call.
  void analyze(const Sweep& sweep, const Eigen::Vector3f& sensor_origin, const SweepLabels& labels,
               ReflectiveObject& object);

  // Optional, for speed: bounding boxes of blocks of 64 beams of this sweep, so that analyze()
  // skips blocks that cannot hold a point it looks for (same result). Valid for this sweep
  // object until its points change: call it again for every sweep (Pipeline does).
  void beginSweep(const Sweep& sweep);

private:
  ObjectTypeConfig config_;
  struct Buffers;
  std::unique_ptr<Buffers> buffers_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
