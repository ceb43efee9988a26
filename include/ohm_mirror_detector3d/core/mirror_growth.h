// Object stage: a mirror grows from its surface-echo patch to its real extent. A mirror gives
// surface echoes only near perpendicular incidence; elsewhere its phantoms come as single
// echoes behind its plane, outside the patch's vision cone, and stay in `cleaned`. The mirror's
// extent is the part of its plane, around the patch, through which the sensor sees points that,
// reflected across the plane, land on what it saw in front (phantoms; beside them ambiguous
// ones too: a floor or a side wall that the reflection maps onto itself). The growth stops at returns on the plane (a
// frame, the wall the mirror hangs on), at cells through which real points are seen (seen
// through, or where the sensor could not see or saw nothing), and at growth_max_extent. The
// cone labelling then labels the phantoms of the grown part behindReflective and back-projects
// them.
#pragma once

#include <vector>

#include "ohm_mirror_detector3d/core/object_stage.h"
#include "ohm_mirror_detector3d/core/plane_crossings.h"

namespace ohm_mirror_detector3d
{
namespace core
{
class MirrorGrowth : public ObjectStage
{
public:
  explicit MirrorGrowth(const ObjectGrowthConfig& config);

  const char* name() const override { return "mirror_growth"; }

  // Grows every object of type mirror (PlaneCrossings::grow); a cell is taken when at least half
  // of (at most kTestedPerCell of) the points behind crossing it land on what the sensor saw, at
  // least one of them a phantom (not only ambiguous). The test stops as soon as the answer is
  // known: the evidence test is the stage's cost.
  void process(const Sweep& sweep, const SweepContext& context, const ReflectionEvidence& evidence,
               SweepLabels& labels, std::vector<ReflectiveObject>& objects) override;

  static constexpr std::size_t kTestedPerCell = 2;

private:
  ObjectGrowthConfig config_;
  PlaneCrossings crossings_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
