// Object stage: the multi-sweep post-filter (post_filter = 1). With the sweep's place in the
// fixed frame (SweepContext::fixed_from_sweep) it merges the sweep's objects into the object map
// (object_map.h) and then hands the cone labelling the map's objects instead of the sweep's, in
// the sweep's frame: every map object the sweep's objects merged into (once, however many of
// them did: an object never labels twice) with its full extent and its type over the sweeps,
// and every other map object that may label from where the sensor is, so that points behind a
// known pane or mirror are labelled in sweeps where it gave no double echo. A sweep without a
// fixed pose is left as it is (single-sweep); the front ends say why.
#pragma once

#include <cstdint>
#include <vector>

#include "ohm_mirror_detector3d/core/object_map.h"
#include "ohm_mirror_detector3d/core/object_stage.h"

namespace ohm_mirror_detector3d
{
namespace core
{
class PostFilter : public ObjectStage
{
public:
  // `map` outlives the stage (the pipeline owns both; the map survives new parameters).
  explicit PostFilter(ObjectMap& map) : map_(map) {}

  const char* name() const override { return "post_filter"; }
  // Known objects label sweeps that found none.
  bool runsWithoutObjects() const override { return true; }
  // It merges and places objects; the cone labelling asks for the evidence when it needs it.
  bool needsEvidence() const override { return false; }

  void process(const Sweep& sweep, const SweepContext& context, const ReflectionEvidence& evidence,
               SweepLabels& labels, std::vector<ReflectiveObject>& objects) override;

private:
  ObjectMap& map_;
  std::vector<std::uint32_t> merged_ids_;
  std::vector<ReflectiveObject> labelling_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
