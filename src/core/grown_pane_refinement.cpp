#include "ohm_mirror_detector3d/core/grown_pane_refinement.h"

namespace ohm_mirror_detector3d
{
namespace core
{
void GrownPaneRefinement::process(const Sweep& sweep, const SweepContext& context, const ReflectionEvidence& evidence,
                                  SweepLabels& labels, std::vector<ReflectiveObject>& objects)
{
  for (ReflectiveObject& object : objects)
    if (object.type == ObjectType::glass && object.grown && !object.evidence.plane_refined)
      analyzer_.refineGrownPlane(sweep, context.sensorOrigin(), labels, evidence, object);
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
