#include <gtest/gtest.h>

#include "growth_fixtures.h"
#include "traced_scene.h"

#include "ohm_mirror_detector3d/core/mirror_growth.h"
#include "ohm_mirror_detector3d/core/pipeline.h"

#include <map>

namespace ohm_mirror_detector3d
{
namespace
{
using test::growthConfig;
using test::Panel;
using test::Surface;

constexpr float kWall = 2.0f;     // the wall the mirror hangs on, x = 2
constexpr float kMirror = 1.99f;  // the mirror, 1 cm in front of it

// A 1.0 x 0.8 m mirror on the front wall of a room (y in [-0.6, 0.4], z in [-0.3, 0.5]: the
// surface echoes near the perpendicular foot at y = z = 0 are off its centre), plus `more`.
test::TracedScene wallMirror(std::vector<Panel> more = {})
{
  test::TracedScene scene;
  scene.panels = test::room(2.5f, kWall, 2.5f, 1.0f, 1.5f);
  scene.panels.push_back({ 0, kMirror, { -0.6f, -0.3f }, { 0.4f, 0.5f }, Surface::mirror });
  for (const Panel& panel : more)
    scene.panels.push_back(panel);
  return scene;
}

struct Grown
{
  core::ReflectiveObject object;
  test::Sides sides;
};

Grown grow(const core::Sweep& sweep, core::ReflectiveObject object, const core::ObjectGrowthConfig& config)
{
  const test::Detected detected(sweep);
  std::vector<core::ReflectiveObject> objects{ object };
  core::SweepLabels labels = detected.labels;
  core::MirrorGrowth(config).process(sweep, core::SweepContext(), detected.evidence, labels, objects);
  return { objects[0], test::sidesOf(objects[0]) };
}

// All around: the reflections land on walls behind the sensor too, which it must have seen.
core::Sweep sweepOf(const test::TracedScene& scene)
{
  return scene.sweep(-180.0f, 179.5f, -60.0f, 60.0f, 0.5f);
}

TEST(MirrorGrowth, AMirrorGrowsFromItsPatchToItsFrameAndKeepsThePatch)
{
  const Grown grown = grow(sweepOf(wallMirror()), test::patchAt(kMirror, 0.0f, 0.0f, 0.2f, core::ObjectType::mirror),
                           growthConfig());
  EXPECT_NEAR(grown.sides.y_low, -0.6f, 0.05f);
  EXPECT_NEAR(grown.sides.y_high, 0.4f, 0.05f);
  EXPECT_NEAR(grown.sides.z_low, -0.3f, 0.05f);
  EXPECT_NEAR(grown.sides.z_high, 0.5f, 0.05f);
  EXPECT_TRUE(grown.object.grown);
  EXPECT_FALSE(grown.object.growth_capped);
  EXPECT_FLOAT_EQ(grown.object.patch_width, 0.2f);
  EXPECT_FLOAT_EQ(grown.object.patch_height, 0.2f);
  EXPECT_TRUE(grown.object.patch_centre.isApprox(Eigen::Vector3f(kMirror, 0.0f, 0.0f)));
}

TEST(MirrorGrowth, ADoorwayBesideTheMirrorIsNotSwallowed)
{
  // The front wall with a doorway at y in [0.5, 1.3] (10 cm of wall from the mirror), a
  // corridor behind it: through the doorway the sensor sees real points, not phantoms.
  test::TracedScene scene;
  scene.panels = test::room(2.5f, 6.0f, 2.5f, 1.0f, 1.5f);
  scene.panels.push_back({ 0, kWall, { -2.5f, -1.0f }, { 0.5f, 1.5f }, Surface::wall });
  scene.panels.push_back({ 0, kWall, { 1.3f, -1.0f }, { 2.5f, 1.5f }, Surface::wall });
  scene.panels.push_back({ 0, kWall, { 0.5f, 0.9f }, { 1.3f, 1.5f }, Surface::wall });
  scene.panels.push_back({ 0, kMirror, { -0.6f, -0.3f }, { 0.4f, 0.5f }, Surface::mirror });
  const Grown grown =
      grow(sweepOf(scene), test::patchAt(kMirror, 0.0f, 0.0f, 0.2f, core::ObjectType::mirror), growthConfig());
  EXPECT_NEAR(grown.sides.y_high, 0.4f, 0.05f);
  EXPECT_NEAR(grown.sides.y_low, -0.6f, 0.05f);
}

TEST(MirrorGrowth, AFreeHangingMirrorStopsWhereRealPointsAreSeenBesideIt)
{
  // No wall around it: beside the mirror the sensor sees the far wall directly. Floor and
  // ceiling far enough that the whole mirror shows the wall behind the sensor.
  test::TracedScene scene;
  scene.panels = test::room(2.5f, 4.0f, 2.5f, 2.0f, 2.5f);
  scene.panels.push_back({ 0, 1.5f, { -0.6f, -0.3f }, { 0.4f, 0.5f }, Surface::mirror });
  const Grown grown =
      grow(sweepOf(scene), test::patchAt(1.5f, 0.0f, 0.0f, 0.2f, core::ObjectType::mirror), growthConfig());
  EXPECT_NEAR(grown.sides.y_low, -0.6f, 0.05f);
  EXPECT_NEAR(grown.sides.y_high, 0.4f, 0.05f);
  EXPECT_NEAR(grown.sides.z_low, -0.3f, 0.05f);
  EXPECT_NEAR(grown.sides.z_high, 0.5f, 0.05f);
}

TEST(MirrorGrowth, TheCapBoundsTheGrowthAndIsReported)
{
  core::ObjectGrowthConfig config = growthConfig();
  config.max_growth = 0.2f;
  const Grown grown =
      grow(sweepOf(wallMirror()), test::patchAt(kMirror, 0.0f, 0.0f, 0.2f, core::ObjectType::mirror), config);
  EXPECT_TRUE(grown.object.growth_capped);
  EXPECT_LE(grown.object.width, 0.2f + 2.0f * 0.2f + 1e-3f);
  EXPECT_GT(grown.object.width, 0.5f);
}

TEST(MirrorGrowth, OnlyMirrorsGrow)
{
  const core::ReflectiveObject unknown = test::patchAt(kMirror, 0.0f, 0.0f, 0.2f, core::ObjectType::unknown);
  const Grown grown = grow(sweepOf(wallMirror()), unknown, growthConfig());
  EXPECT_FALSE(grown.object.grown);
  EXPECT_FLOAT_EQ(grown.object.width, 0.2f);
}

TEST(MirrorGrowth, APatchInAPlainWallDoesNotGrow)
{
  // A "mirror" patch on a wall without a mirror: every cell around is a return on the plane.
  test::TracedScene scene;
  scene.panels = test::room(2.5f, kWall, 2.5f, 1.0f, 1.5f);
  const Grown grown =
      grow(sweepOf(scene), test::patchAt(kWall, 0.0f, 0.0f, 0.2f, core::ObjectType::mirror), growthConfig());
  EXPECT_FALSE(grown.object.grown);
  EXPECT_FALSE(grown.object.growth_capped);
}

}  // namespace
}  // namespace ohm_mirror_detector3d

namespace ohm_mirror_detector3d
{
namespace
{
// The parameters switch the stage on in the pipeline itself (what every front end builds):
// the mirror's phantoms beyond its patch are then labelled behindReflective, not valid.
TEST(MirrorGrowth, GrowObjectsSwitchesItOnInThePipeline)
{
  const core::Sweep sweep = sweepOf(wallMirror());
  // A phantom seen through the mirror far from the patch: the beam through (y, z) = (-0.5, 0.4) on it.
  const Eigen::Vector3f through(kMirror, -0.5f, 0.4f);
  std::size_t beam = 0;
  float best = -1.0f;
  for (std::size_t b = 0; b < sweep.beamCount(); ++b)
  {
    const Eigen::Vector3f& p = sweep.echoes[0].points[b];
    const float alignment = p.allFinite() ? p.normalized().dot(through.normalized()) : -1.0f;
    if (alignment > best)
    {
      best = alignment;
      beam = b;
    }
  }
  ASSERT_GT(sweep.echoes[0].points[beam].x(), kWall);  // a phantom behind the wall
  std::map<int, core::Label> label_of;
  std::map<int, core::ReflectiveObject> mirror_of;
  for (const int grow : { 0, 1 })
  {
    core::Params params;
    params.grow_objects = grow;
    core::Pipeline pipeline(params);
    const core::PipelineResult& result = pipeline.process(sweep, core::SweepContext());
    label_of[grow] = result.labels.echoes[0][beam];
    for (const core::ReflectiveObject& object : result.objects)
      if (object.type == core::ObjectType::mirror)
        mirror_of[grow] = object;
  }
  ASSERT_EQ(mirror_of.size(), 2u);
  EXPECT_FALSE(mirror_of[0].grown);
  EXPECT_LT(mirror_of[0].width, 0.5f);
  EXPECT_TRUE(mirror_of[1].grown);
  EXPECT_NEAR(mirror_of[1].width, 1.0f, 0.1f);
  EXPECT_NEAR(mirror_of[1].height, 0.8f, 0.1f);
  EXPECT_EQ(label_of[0], core::Label::valid);
  EXPECT_EQ(label_of[1], core::Label::behindReflective);
}

}  // namespace
}  // namespace ohm_mirror_detector3d
