// Object stage: objects in one wall share its normal. The panes of a glass partition or of a
// window, a mirror or a metal panel beside them, stand in one plane (or in parallel planes a
// frame's depth apart), but each is detected on its own, and a small or oblique one's plane
// comes from few surface echoes whose noise is not independent over a spot: a few tenths of a
// degree off, which puts its phantoms 2-10 cm from where they belong 3 m behind it. An object
// whose plane lies within `min_cosine` (and its centre within kMaxSharedPlaneDistance) of
// objects with more surface echoes takes the normal fitted to the surface echoes of all of
// them together (each about its own centroid: parallel planes, not one plane, so that a panel
// a centimetre in front of a pane keeps its own offset), and keeps its offset through its own
// surface echoes' centroid and its rectangle. An object with no sibling with more surface
// echoes keeps its plane (its own refinement from its phantoms included).
//
// Measured (double-echo phantoms at a wrong place, the stage off -> on): random scenes
// 34000-34024 of the 32-ring lidar 52.1 -> 39.6 % (random_34012: a partition's pane 0.33 deg off
// beside a pane of 2305 echoes, its phantoms more than 5 cm off 2224 -> 2), of the 128-ring lidar
// 28.3 -> 25.1 %; make evaluate's 64-ring lidar 15.2 -> 13.9 %, 32-ring 23.4 -> 22.7 %; no sweep
// worse by more than 100 points. Only larger siblings count: pooled with every sibling, a small
// fragment 0.3 deg off in a metal panel's plane turned the panel that much (128-ring lidar, make
// evaluate's random_10: 378 phantoms more at a wrong place). Its cost is a pass over the objects'
// surface echoes.
#pragma once

#include <vector>

#include "ohm_mirror_detector3d/core/object_stage.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct SharedNormalConfig
{
  bool enabled = true;
  // Two objects are in one wall when their normals are within acos(min_cosine) of each other
  // and each one's centre within kMaxSharedPlaneDistance of the other's plane.
  float min_cosine = 0.99863f;  // 3 deg
};

// How far each object's centre may lie from the other's plane for the two to be in one wall [m]
// (a frame's depth, a panel mounted in front of the wall).
constexpr float kMaxSharedPlaneDistance = 0.1f;

class SharedNormals : public ObjectStage
{
public:
  explicit SharedNormals(const SharedNormalConfig& config) : config_(config) {}

  const char* name() const override { return "shared_normals"; }
  bool needsEvidence() const override { return false; }

  // Every object with a sibling in its wall that has more surface echoes (surface_inliers):
  // its plane turned to the normal fitted to them and its own surface echoes, through its own
  // echoes' centroid; its rectangle (centre, axes, patch) moved onto the new plane. The
  // decisions are made on the planes as they came in, so the order of the objects does not matter.
  void process(const Sweep& sweep, const SweepContext& context, const ReflectionEvidence& evidence,
               SweepLabels& labels, std::vector<ReflectiveObject>& objects) override;

private:
  SharedNormalConfig config_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
