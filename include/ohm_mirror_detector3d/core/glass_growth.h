// Object stage: a pane grows from its surface-echo patch to its real extent. Glass returns a
// surface echo only near perpendicular incidence; elsewhere the sensor sees through it with no
// echo on it. A pane sits in a wall, a frame or between mullions: its extent is the region of
// its plane around the patch that the rays cross (points behind the plane, no return on it),
// bounded by returns on the plane. An opening (a doorway) has no surface echo and so no patch:
// it is never grown from, and the frame or wall between a pane and a doorway beside it stops
// the growth. A growth that reaches growth_max_extent beyond the patch on some side found no
// boundary there: it is refused (the object keeps its patch and says growth_capped).
#pragma once

#include <vector>

#include "ohm_mirror_detector3d/core/object_stage.h"
#include "ohm_mirror_detector3d/core/plane_crossings.h"

namespace ohm_mirror_detector3d
{
namespace core
{
class GlassGrowth : public ObjectStage
{
public:
  explicit GlassGrowth(const ObjectGrowthConfig& config);

  const char* name() const override { return "glass_growth"; }

  // Grows every object of type glass over the crossed cells (PlaneCrossings::grow).
  void process(const Sweep& sweep, const SweepContext& context, const ReflectionEvidence& evidence,
               SweepLabels& labels, std::vector<ReflectiveObject>& objects) override;

private:
  ObjectGrowthConfig config_;
  PlaneCrossings crossings_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
