// Stage analyzeObjectType of the paper: mirror or glass, from what the points behind the plane
// say one by one when reflected across it (reflection_evidence.h), instead of the paper's ICP
// of all of them at once.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "ohm_mirror_detector3d/core/block_box.h"
#include "ohm_mirror_detector3d/core/mirror_plane_refinement.h"
#include "ohm_mirror_detector3d/core/reflection_evidence.h"
#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
class ChainCones;
struct ObjectTypeConfig
{
  double plane_threshold;          // d_thres_plane [m]: half thickness of the surface
  double cone_margin;              // d_thres_visionCone [m]: growth of the vision cone
  double icp_max_distance;         // [m]: landing tolerance at the sensor, reach of the plane refinement
  double icp_fitness_threshold;    // [m^2]: mean squared landing distance of a mirror's phantoms
  int icp_min_points;              // fewest phantoms to refine a plane, and decided points to type it
  double icp_min_inlier_fraction;  // share of the decided points that must be phantoms for a mirror
  int threads = 1;                 // core/parallel.h: analyzeAll() decides objects side by side
};

class ObjectTypeAnalyzer
{
public:
  explicit ObjectTypeAnalyzer(const ObjectTypeConfig& config);
  ~ObjectTypeAnalyzer();
  ObjectTypeAnalyzer(ObjectTypeAnalyzer&&) noexcept;
  ObjectTypeAnalyzer& operator=(ObjectTypeAnalyzer&&) noexcept;

  // Decides the object's type from what its points behind say (ReflectionEvidence): the points
  // behind it (inside its vision cone from sensor_origin, both echoes, nanPoint excluded), an
  // even sample of at most 512 of them, each reflected across the plane and tested against
  // what the sensor saw in front (tolerance icp_max_distance, growing with range and the
  // plane's uncertainty). Sets object.landing_tolerance, object.type and object.evidence:
  // - when at least icp_min_points of them (estimated) land on seen geometry, the plane is
  //   first refined so that they land exactly (a mirror's, shiny metal's or reflecting glass's
  //   plane, fitted to its surface echoes, is good to a few tenths of a degree; reflection
  //   multiplies that by the distance behind), and the sample tested again;
  // - unknown when fewer than icp_min_points of the points inside its rectangle (away from its
  //   border, where points beside the surface are seen through the grown cone) are phantoms or
  //   real (transmitted, or, only when too few are transmitted or phantoms and the transmitted
  //   are at least as many as the phantoms, occluded: their reflection lies behind what the
  //   sensor saw there; a mirror's phantoms hidden from the sensor by furniture are occluded
  //   too): nothing to tell (a mirror facing open space);
  // - glass when a clear share of those is real: the surface lets the sensor through
  //   (reflections in it are its phantoms; a pane at an oblique angle has many);
  // - mirror otherwise, if its phantoms land within icp_fitness_threshold (mean squared) of what
  //   the sensor saw; unknown if not.
  void analyze(const Sweep& sweep, const Eigen::Vector3f& sensor_origin, const SweepLabels& labels,
               const ReflectionEvidence& evidence, ReflectiveObject& object);
  // beginSweep(sweep), then analyze() for every object, the objects shared among config.threads
  // threads (the same result as one after the other: an object's decision reads only the sweep,
  // its labels, the evidence and the other objects as they were before any was analysed). Here a
  // point seen through an object does not count where its reflection lies behind another object
  // (chain_cones.h): it may be the other's phantom reflected again.
  void analyzeAll(const Sweep& sweep, const Eigen::Vector3f& sensor_origin, const SweepLabels& labels,
                  const ReflectionEvidence& evidence, std::vector<ReflectiveObject>& objects);

  // Optional, for speed: bounding boxes of blocks of 64 beams of this sweep, so that analyze()
  // skips blocks that cannot hold a point it looks for (same result). Valid for this sweep
  // object until its points change: call it again for every sweep (Pipeline does).
  void beginSweep(const Sweep& sweep);

  // Beams per block of those boxes.
  static constexpr std::size_t kBlockBoxBeams = 64;
  // Those boxes of echo 0 and echo 1 (all their finite points) when beginSweep was called for
  // this sweep, else null: the intensity evidence reads them too instead of a pass of its own.
  const SweepBlockBoxes* blockBoxes(const Sweep& sweep) const;

  // Refines the plane of an object that an object stage grew, the way analyze() does (the same
  // sample, landing test and refinement, surface echoes and all), from the points behind its
  // grown rectangle: a pane's patch of surface echoes is often a small spot, its plane fitted a
  // degree or more off, and analyze() sees only what lies behind that spot. Leaves the object
  // as it is, and returns false, when too few of those points land on seen geometry or the
  // refinement is refused (MirrorPlaneRefinement). Its type is not decided again.
  bool refineGrownPlane(const Sweep& sweep, const Eigen::Vector3f& sensor_origin, const SweepLabels& labels,
                        const ReflectionEvidence& evidence, ReflectiveObject& object);

private:
  struct Buffers;
  struct SweepBoxes;
  // `chains` (null: none) tells where a point behind object `index` may continue through another.
  void analyzeWith(Buffers& buffers, const Sweep& sweep, const Eigen::Vector3f& sensor_origin,
                   const SweepLabels& labels, const ReflectionEvidence& evidence, ReflectiveObject& object,
                   const ChainCones* chains, std::size_t index);
  // With enough of buffers.landed (their estimated count, `weight` points each, at least
  // icp_min_points, and 3 sampled), refines object's plane from them and records it: the
  // evidence's plane_refined and plane_correction, the landing tolerance's tilt term. False
  // (the object as it was) otherwise or when the refinement is refused.
  bool refineFromLanded(Buffers& buffers, const Sweep& sweep, const SweepLabels& labels, const Eigen::Vector3f& sensor_origin,
                        double weight, ReflectiveObject& object);
  // Refines object's plane from buffers.landed (points behind that land on seen geometry).
  PlaneRefinement refinePlane(Buffers& buffers, const Sweep& sweep, const SweepLabels& labels, const Eigen::Vector3f& sensor_origin,
                              double weight, ReflectiveObject& object);

  ObjectTypeConfig config_;
  std::unique_ptr<SweepBoxes> boxes_;
  // One per worker of analyzeAll(); the first serves the single-object calls.
  std::vector<std::unique_ptr<Buffers>> buffers_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
