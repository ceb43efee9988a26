// The seam of the pipeline: a stage between the type decision and the cone labelling that works
// on whole objects (the detect phase's objects and the labels behind them) before they label
// the sweep. What goes here: growing an object over the part of its plane through which
// points behind it are seen, multiple reflections, fusing objects over sweeps in a fixed frame.
#pragma once

#include <vector>

#include "ohm_mirror_detector3d/core/reflection_evidence.h"
#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/sweep.h"
#include "ohm_mirror_detector3d/core/sweep_context.h"

namespace ohm_mirror_detector3d
{
namespace core
{
class ObjectStage
{
public:
  virtual ~ObjectStage() = default;

  // A short name for timing and messages.
  virtual const char* name() const = 0;

  // Whether the stage runs on sweeps in which the detect phase found no object (the others are
  // skipped there, and the per-point evidence is not built for them).
  virtual bool runsWithoutObjects() const { return false; }
  // Whether process() reads the evidence; a stage that does not (the post-filter) gets it
  // unbuilt, so that a sweep whose objects leave nothing behind them never builds it.
  virtual bool needsEvidence() const { return true; }

  // Called once per sweep, after the detect phase and the object stages before it. `labels`
  // hold the detect phase's evidence per point (nanPoint: gated or outlier; errorSurface / error:
  // near and far echo of a discontinuous beam; unchecked: everything else); `evidence` answers
  // for any point behind any plane whether, reflected across it, it lands on what the sensor
  // saw (reflection_evidence.h; the test the type decision and the cone labelling use);
  // `objects` are the objects so far (plane, rectangle, type, evidence, landing tolerance,
  // surface_inliers). A stage may change, add or remove objects and change labels; the cone
  // labelling then labels the sweep by the objects it leaves, from context.sensorOrigin(), each
  // point behind by its own evidence against its object's plane. Objects keep their index as id
  // (the stage renumbers what it adds or removes).
  virtual void process(const Sweep& sweep, const SweepContext& context, const ReflectionEvidence& evidence,
                       SweepLabels& labels, std::vector<ReflectiveObject>& objects) = 0;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
