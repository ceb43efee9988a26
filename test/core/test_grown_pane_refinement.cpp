#include <gtest/gtest.h>

#include <cmath>

#include "growth_fixtures.h"
#include "traced_scene.h"

#include "ohm_mirror_detector3d/core/glass_growth.h"
#include "ohm_mirror_detector3d/core/grown_pane_refinement.h"
#include "ohm_mirror_detector3d/core/object_type.h"
#include "ohm_mirror_detector3d/core/stage_configs.h"

namespace ohm_mirror_detector3d
{
namespace
{
using test::Panel;
using test::Surface;

constexpr float kWall = 3.0f;  // the wall x = 3 with the pane in it; a room behind it to x = 6
constexpr float kDegree = static_cast<float>(M_PI) / 180.0f;

// A 2.4 x 1.9 m pane in the wall x = 3 (y in [-1.4, 1], z in [-0.9, 1]), the wall around it,
// the rooms in front and behind (floor z = -1, ceiling z = 1.5, side walls y = +-3): through the
// pane the sensor sees the floor and the ceiling of the room behind.
test::TracedScene paneInAWall()
{
  test::TracedScene scene;
  scene.panels = test::room(2.5f, 6.0f, 3.0f, 1.0f, 1.5f);
  scene.panels.push_back({ 0, kWall, { -3.0f, -1.0f }, { -1.4f, 1.5f }, Surface::wall });
  scene.panels.push_back({ 0, kWall, { 1.0f, -1.0f }, { 3.0f, 1.5f }, Surface::wall });
  scene.panels.push_back({ 0, kWall, { -1.4f, -1.0f }, { 1.0f, -0.9f }, Surface::wall });
  scene.panels.push_back({ 0, kWall, { -1.4f, 1.0f }, { 1.0f, 1.5f }, Surface::wall });
  scene.panels.push_back({ 0, kWall, { -1.4f, -0.9f }, { 1.0f, 1.0f }, Surface::glass });
  return scene;
}

// The pane's 0.2 m patch at its perpendicular foot, its plane through the patch's centre but
// tilted by `tilt` [rad] about the horizontal axis in the wall (as a plane fitted to a small
// spot of surface echoes may be).
core::ReflectiveObject tiltedPatch(float tilt, core::ObjectType type)
{
  core::ReflectiveObject patch = test::patchAt(kWall, 0.0f, 0.0f, 0.2f, type);
  const Eigen::Vector3f normal(-std::cos(tilt), 0.0f, std::sin(tilt));
  patch.plane.head<3>() = normal;
  patch.plane[3] = -normal.dot(patch.centre);
  patch.height_axis = normal.cross(patch.width_axis).normalized();
  if (patch.height_axis.z() < 0.0f)
    patch.height_axis = -patch.height_axis;
  return patch;
}

struct Refined
{
  core::ReflectiveObject object;
  float error_deg;  // between the object's plane and the wall's
};

// The traced sweep with the pane's surface echoes moved onto the patch's plane along their beams
// (their noise over a small spot, as if correlated, tilts the plane fitted to them), the detect
// phase's labels and evidence, the glass growth, then the stage. The patch's surface inliers are
// those echoes.
Refined growAndRefine(core::ReflectiveObject patch, bool grow = true)
{
  core::Sweep sweep = paneInAWall().sweep(-55.0f, 55.0f, -60.0f, 60.0f, 0.4f);
  {
    const test::Detected traced(sweep);
    for (std::size_t i = 0; i < sweep.beamCount(); ++i)
      if (traced.labels.echoes[0][i] == core::Label::errorSurface)
      {
        Eigen::Vector3f& p = sweep.echoes[0].points[i];
        p *= -patch.plane[3] / patch.plane.head<3>().dot(p);
        patch.surface_inliers.push_back(core::PointRef{ static_cast<std::uint32_t>(i), 0 });
      }
    sweep.computeRanges(Eigen::Vector3f::Zero());
  }
  const test::Detected detected(sweep);
  core::SweepLabels labels = detected.labels;
  std::vector<core::ReflectiveObject> objects{ patch };
  if (grow)
    core::GlassGrowth(test::growthConfig()).process(sweep, core::SweepContext(), detected.evidence, labels, objects);
  core::ObjectTypeAnalyzer analyzer(core::stageConfigs(core::Params()).object_type);
  analyzer.beginSweep(sweep);
  core::GrownPaneRefinement(analyzer).process(sweep, core::SweepContext(), detected.evidence, labels, objects);
  const float cosine = std::fabs(objects[0].plane.head<3>().dot(-Eigen::Vector3f::UnitX()));
  return { objects[0], std::acos(std::min(1.0f, cosine)) / kDegree };
}

TEST(GrownPaneRefinement, AGrownPanesPlaneFittedADegreeOffIsSetSquareByWhatLiesBehindIt)
{
  // The floor, the ceiling and the side walls seen through the pane land, reflected across the
  // true plane, on the floor, the ceiling and the side walls in front: only a plane square to
  // them makes them land.
  const Refined refined = growAndRefine(tiltedPatch(1.5f * kDegree, core::ObjectType::glass));
  ASSERT_TRUE(refined.object.grown);
  EXPECT_TRUE(refined.object.evidence.plane_refined);
  EXPECT_LT(refined.error_deg, 0.1f);
  EXPECT_NEAR(refined.object.evidence.plane_correction / kDegree, 1.5f, 0.15f);
  // The plane still goes through the wall at the patch.
  EXPECT_NEAR(refined.object.signedDistance(Eigen::Vector3f(kWall, 0.0f, 0.0f)), 0.0f, 0.01f);
}

TEST(GrownPaneRefinement, APatchThatDidNotGrowKeepsItsPlane)
{
  // Without the growth the stage has nothing to do: analyze() already looked behind the patch.
  const core::ReflectiveObject patch = tiltedPatch(1.5f * kDegree, core::ObjectType::glass);
  const Refined refined = growAndRefine(patch, false);
  EXPECT_FALSE(refined.object.evidence.plane_refined);
  EXPECT_TRUE(refined.object.plane.isApprox(patch.plane));
  EXPECT_FALSE(refined.object.surface_inliers.empty());
}

TEST(GrownPaneRefinement, APlaneTheTypeDecisionRefinedIsLeftAlone)
{
  core::ReflectiveObject patch = tiltedPatch(1.5f * kDegree, core::ObjectType::glass);
  patch.evidence.plane_refined = true;
  const Refined refined = growAndRefine(patch);
  ASSERT_TRUE(refined.object.grown);
  EXPECT_NEAR(refined.error_deg, 1.5f, 1e-3f);
}

}  // namespace
}  // namespace ohm_mirror_detector3d
