// Label-phase stage between the cone labelling and the cleaned output: where each phantom really
// is. A beam reflected by one mirror gives a phantom behind it that one reflection back-projects;
// a beam reflected again by a second mirror (facing mirrors, a mirror seen in a mirror) gives a
// phantom that, reflected across the first mirror, still lies behind the second. Its real place
// is at the end of the chain of mirrors its path crosses: reflected across the first mirror, the
// rest of the path is a straight ray from the sensor's image in that mirror, and the next mirror
// is the one that ray crosses (from its front, inside its rectangle) before the point.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ohm_mirror_detector3d/core/cone_labelling.h"
#include "ohm_mirror_detector3d/core/reflection_evidence.h"
#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// The longest chain of mirrors followed (the upper bound of max_reflections in parameters.def).
constexpr int kMaxReflections = 8;

struct ReflectionChainConfig
{
  // max_reflections: how many mirrors a phantom's path may cross, the first included; a phantom
  // whose path crosses more is `error`. 0: back-project across the first mirror only, without
  // looking further (the paper's method).
  int max_reflections = 3;
  float plane_threshold = 0.05f;  // d_thres_plane [m]: a point this near a plane is on it, not behind
  float cone_margin = 0.05f;      // d_thres_visionCone [m]: a mirror's rectangle grown as its vision cone is
};

// The one place that says where a phantom really is: per point of both echoes the chain of
// mirrors its beam met, in order (the first is the object the cone labelling put it behind).
// Chains are the nodes of a tree: node j < objects is the one-mirror chain [j], every other node
// is a chain one mirror longer than its parent's.
class ReflectionPaths
{
public:
  static constexpr std::int32_t kNoPath = -1;

  // Every point without a chain, and the one-mirror chains of `objects` objects.
  void reset(std::size_t beam_count, std::size_t objects);

  // The chain `parent` followed by mirror `object` (added the first time it is asked for);
  // kNoPath when `parent` holds kMaxReflections mirrors already.
  std::int32_t extend(std::int32_t parent, std::int32_t object);

  std::int32_t path(std::size_t echo, std::size_t beam) const { return echoes_[echo][beam]; }
  void setPath(std::size_t echo, std::size_t beam, std::int32_t path) { echoes_[echo][beam] = path; }

  // The mirrors of a chain, first to last.
  std::vector<std::int32_t> mirrors(std::int32_t path) const;

  // The points the cone labelling took for a surface echo merged with a reflection
  // (ObjectAssignment::merged_echoes): their chains start from the reflection's own echo.
  void setMergedEchoes(const std::array<std::vector<ObjectAssignment::MergedEcho>, 2>& merged) { merged_ = merged; }
  // Where the reflection that p shows was measured from: p itself, or for a merged echo the
  // reflection's own echo along the beam.
  Eigen::Vector3f reflectionEcho(std::size_t echo, std::size_t beam, const Eigen::Vector3f& p) const;

  // p reflected across every mirror of the point's chain in order: where it really is (p itself
  // for a point without a chain). A merged echo starts from its reflection's own echo.
  Eigen::Vector3f backProject(const std::vector<ReflectiveObject>& objects, std::size_t echo, std::size_t beam,
                              const Eigen::Vector3f& p) const;

private:
  struct Node
  {
    std::int32_t parent;  // kNoPath for a one-mirror chain
    std::int32_t object;
    int length;           // mirrors in the chain
  };
  std::size_t objects_ = 0;
  std::vector<Node> nodes_;
  std::vector<std::int32_t> children_;  // nodes_.size() x objects_: the chain one mirror longer, or kNoPath
  std::array<std::vector<std::int32_t>, 2> echoes_;
  std::array<std::vector<ObjectAssignment::MergedEcho>, 2> merged_;
};

struct ReflectionChainCounts
{
  std::size_t multiply_reflected = 0;  // phantoms back-projected through two mirrors or more
  std::size_t unexplained = 0;         // phantoms no chain explains, labelled error
};

class ReflectionChains
{
public:
  explicit ReflectionChains(const ReflectionChainConfig& config);

  // Gives every behindReflective point (the cone labelling's phantoms, behind object
  // assignment) its chain: from the first mirror, as long as the reflected ray crosses another
  // mirror (type mirror, its front, inside its rectangle grown as its vision cone, the point more
  // than plane_threshold behind it), that mirror too. A point whose chain grows beyond
  // max_reflections, or whose chain of two or more ends where the sensor saw through (evidence:
  // transmitted, nothing is there), is labelled error (dropped from `cleaned`). With
  // max_reflections 0 every phantom keeps its one mirror.
  ReflectionChainCounts apply(const Sweep& sweep, const Eigen::Vector3f& sensor_origin,
                              const ReflectionEvidence& evidence, const std::vector<ReflectiveObject>& objects,
                              const ObjectAssignment& assignment, SweepLabels& labels, ReflectionPaths& paths) const;

private:
  ReflectionChainConfig config_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
