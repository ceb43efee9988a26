#include <gtest/gtest.h>

#include "growth_fixtures.h"
#include "traced_scene.h"

#include "ohm_mirror_detector3d/core/cone_labelling.h"
#include "ohm_mirror_detector3d/core/intensity_evidence.h"
#include "ohm_mirror_detector3d/core/params.h"
#include "ohm_mirror_detector3d/core/phantom_planes.h"
#include "ohm_mirror_detector3d/core/stage_configs.h"

#include <cmath>
#include <limits>
#include <random>

namespace ohm_mirror_detector3d
{
namespace
{
using core::Label;
using core::ObjectType;
using test::Panel;
using test::Surface;

constexpr float kBack = 2.5f;     // the back wall, x = -2.5
constexpr float kMirror = 1.99f;  // the mirror, 1 cm in front of the front wall at x = 2
// The back wall's phantom in the mirror: its mirror image across x = kMirror.
constexpr float kPhantomWall = kMirror + (kMirror + kBack);

// A room with a large mirror on its front wall: through most of the mirror the sensor sees the
// back wall's phantom, single returns at x = kPhantomWall.
test::TracedScene mirrorRoom()
{
  test::TracedScene scene;
  scene.panels = test::room(kBack, 2.0f, 2.5f, 1.0f, 1.5f);
  scene.panels.push_back({ 0, kMirror, { -1.5f, -0.8f }, { 1.5f, 1.2f }, Surface::mirror });
  return scene;
}

// A free-standing pane at x = 2 in a room whose front wall is at x = 4: through it the sensor
// sees the front wall itself.
test::TracedScene paneRoom()
{
  test::TracedScene scene;
  scene.panels = test::room(kBack, 4.0f, 2.5f, 1.0f, 1.5f);
  scene.panels.push_back({ 0, 2.0f, { -1.5f, -0.8f }, { 1.5f, 1.2f }, Surface::glass });
  return scene;
}

core::Sweep sweepOf(const test::TracedScene& scene)
{
  return scene.sweep(-180.0f, 179.5f, -60.0f, 60.0f, 0.5f);
}

// An object on the plane x = distance (centred at y, z, `size` across) made of the first echoes
// of the sweep that lie on it inside its rectangle, as object extraction would have fitted it.
core::ReflectiveObject objectOfEchoes(const core::Sweep& sweep, float distance, float y, float z, float size,
                                      ObjectType type)
{
  core::ReflectiveObject object = test::patchAt(distance, y, z, size, type);
  for (std::size_t b = 0; b < sweep.beamCount(); ++b)
  {
    const Eigen::Vector3f& p = sweep.echoes[0].points[b];
    if (p.allFinite() && std::fabs(p.x() - distance) < 0.02f && std::fabs(p.y() - y) <= 0.5f * size &&
        std::fabs(p.z() - z) <= 0.5f * size)
      object.surface_inliers.push_back(core::PointRef{ static_cast<std::uint32_t>(b), 0 });
  }
  return object;
}

core::PhantomPlaneConfig phantomPlaneConfig()
{
  return core::stageConfigs(core::Params()).phantom_planes;
}

std::vector<core::ReflectiveObject> afterStage(const core::Sweep& sweep, std::vector<core::ReflectiveObject> objects)
{
  const test::Detected detected(sweep);
  core::SweepLabels labels = detected.labels;
  core::PhantomPlanes(phantomPlaneConfig()).process(sweep, core::SweepContext(), detected.evidence, labels, objects);
  return objects;
}

struct Labelled
{
  core::SweepLabels labels;
  core::ObjectAssignment assignment;
};

// The sweep labelled by the objects' cones with the default parameters, after the detect phase.
Labelled labelWith(const core::Sweep& sweep, const test::Detected& detected, std::vector<core::ReflectiveObject>& objects)
{
  Labelled out{ detected.labels, core::ObjectAssignment() };
  core::ConeLabelling(core::stageConfigs(core::Params()).cone_labelling)
      .apply(sweep, Eigen::Vector3f::Zero(), detected.evidence, objects, out.labels, out.assignment);
  return out;
}

// The sweep labelled with one object, `host`, that keeps `plane` among its phantom planes.
Labelled labelWithPhantomPlane(const core::Sweep& sweep, const test::Detected& detected, core::ReflectiveObject host,
                               const core::ReflectiveObject& plane)
{
  host.phantom_planes.push_back(plane);
  std::vector<core::ReflectiveObject> objects{ host };
  return labelWith(sweep, detected, objects);
}

TEST(PhantomPlanes, TheDefaultsSwitchTheStageOn)
{
  const core::PhantomPlaneConfig config = phantomPlaneConfig();
  EXPECT_TRUE(config.enabled);
  EXPECT_FLOAT_EQ(config.min_share, 0.5f);
  core::Params off;
  off.phantom_plane_share = 0.0;
  EXPECT_FALSE(core::stageConfigs(off).phantom_planes.enabled);
}

TEST(PhantomPlanes, AnObjectMadeOfAMirrorsPhantomsIsHandedToTheMirror)
{
  const core::Sweep sweep = sweepOf(mirrorRoom());
  // The mirror's surface echoes: its near-perpendicular patch.
  const core::ReflectiveObject mirror = objectOfEchoes(sweep, kMirror, 0.0f, 0.0f, 0.2f, ObjectType::mirror);
  // The back wall's phantom seen through the mirror up and to the side of its patch.
  const core::ReflectiveObject phantom = objectOfEchoes(sweep, kPhantomWall, 1.2f, 0.6f, 0.8f, ObjectType::glass);
  ASSERT_GE(mirror.surface_inliers.size(), 50u);
  ASSERT_GE(phantom.surface_inliers.size(), 50u);

  const test::Detected detected(sweep);
  const Eigen::Vector3f origin = Eigen::Vector3f::Zero();
  const core::PhantomPlanes stage(phantomPlaneConfig());
  EXPECT_GE(stage.shares(sweep, origin, detected.evidence, phantom, mirror).phantom, 0.9f);
  EXPECT_LE(stage.shares(sweep, origin, detected.evidence, mirror, phantom).phantom, 0.0f);

  // In either order: the phantom plane goes, the mirror stays, renumbered, and keeps it.
  for (const bool mirror_first : { true, false })
  {
    const std::vector<core::ReflectiveObject> objects =
        afterStage(sweep, mirror_first ? std::vector<core::ReflectiveObject>{ mirror, phantom } :
                                         std::vector<core::ReflectiveObject>{ phantom, mirror });
    ASSERT_EQ(objects.size(), 1u);
    EXPECT_EQ(objects[0].type, ObjectType::mirror);
    EXPECT_EQ(objects[0].id, 0u);
    ASSERT_EQ(objects[0].phantom_planes.size(), 1u);
    EXPECT_NEAR(objects[0].phantom_planes[0].centre.x(), kPhantomWall, 1e-4f);
  }
}

TEST(PhantomPlanes, AnObjectOfFarMoreEchoesIsNoPhantomPlaneOfAnother)
{
  // A "mirror" of only a few surface echoes does not take an object of many more.
  const core::Sweep sweep = sweepOf(mirrorRoom());
  core::ReflectiveObject speck = objectOfEchoes(sweep, kMirror, 0.0f, 0.0f, 0.2f, ObjectType::mirror);
  const core::ReflectiveObject phantom = objectOfEchoes(sweep, kPhantomWall, 1.2f, 0.6f, 0.8f, ObjectType::glass);
  speck.surface_inliers.resize(phantom.surface_inliers.size() / 5);
  const std::vector<core::ReflectiveObject> objects = afterStage(sweep, { speck, phantom });
  EXPECT_EQ(objects.size(), 2u);
}

TEST(PhantomPlanes, AWallSeenThroughGlassIsNoPhantom)
{
  // The front wall behind the pane, reflected across it, lands where the sensor saw further.
  const core::Sweep sweep = sweepOf(paneRoom());
  core::ReflectiveObject pane = test::patchAt(2.0f, 0.0f, 0.0f, 0.2f, ObjectType::glass);
  pane.surface_inliers.resize(200, core::PointRef{ 0, 0 });  // as many surface echoes as a pane's patch
  const core::ReflectiveObject wall = objectOfEchoes(sweep, 4.0f, 1.0f, 0.4f, 0.8f, ObjectType::unknown);
  ASSERT_GE(wall.surface_inliers.size(), 50u);
  const std::vector<core::ReflectiveObject> objects = afterStage(sweep, { pane, wall });
  ASSERT_EQ(objects.size(), 2u);
  EXPECT_TRUE(objects[0].phantom_planes.empty());
  EXPECT_TRUE(objects[1].phantom_planes.empty());
}

TEST(PhantomPlanes, APatchJustBehindAnotherObjectsPlaneIsNoPhantomOfIt)
{
  // Reflected across a plane they (nearly) lie on, points land next to themselves: that is no
  // evidence of a reflection. A patch of the front wall, and another object whose plane lies 4 cm
  // in front of it (a pane in a frame, or a fragment of one surface fitted a little apart).
  test::TracedScene scene;
  scene.panels = test::room(kBack, 2.0f, 2.5f, 1.0f, 1.5f);
  const core::Sweep sweep = sweepOf(scene);
  const core::ReflectiveObject patch = objectOfEchoes(sweep, 2.0f, 0.0f, 0.0f, 0.4f, ObjectType::unknown);
  ASSERT_GE(patch.surface_inliers.size(), 50u);
  const core::ReflectiveObject other = test::patchAt(1.96f, 0.8f, 0.5f, 0.3f, ObjectType::glass);
  const std::vector<core::ReflectiveObject> objects = afterStage(sweep, { other, patch });
  EXPECT_EQ(objects.size(), 2u);
}

TEST(PhantomPlanes, TheConeLabellingLabelsThePhantomPlanesPointsAgainstTheirMirror)
{
  // The mirror's patch is small; its phantom plane's cone is outside its own. The points there
  // are the mirror's phantoms, labelled so and assigned to it (back-projected across its plane).
  const core::Sweep sweep = sweepOf(mirrorRoom());
  core::ReflectiveObject mirror = test::patchAt(kMirror, 0.0f, 0.0f, 0.2f, ObjectType::mirror);
  mirror.phantom_planes.push_back(objectOfEchoes(sweep, kPhantomWall, 1.2f, 0.6f, 0.8f, ObjectType::glass));
  std::vector<core::ReflectiveObject> objects{ mirror };
  const test::Detected detected(sweep);
  const Labelled out = labelWith(sweep, detected, objects);
  std::size_t phantoms = 0, others = 0;
  for (const core::PointRef& ref : mirror.phantom_planes[0].surface_inliers)
  {
    EXPECT_EQ(out.assignment.echoes[ref.echo][ref.beam], 0);
    ++(out.labels.echoes[ref.echo][ref.beam] == Label::behindReflective ? phantoms : others);
  }
  EXPECT_GE(phantoms, 9 * (phantoms + others) / 10);
  EXPECT_GE(objects[0].phantom_points, phantoms);

  // Without the phantom plane, the same points are outside every cone.
  std::vector<core::ReflectiveObject> alone{ test::patchAt(kMirror, 0.0f, 0.0f, 0.2f, ObjectType::mirror) };
  const Labelled plain = labelWith(sweep, detected, alone);
  const core::PointRef first = mirror.phantom_planes[0].surface_inliers.front();
  EXPECT_EQ(plain.labels.echoes[first.echo][first.beam], Label::valid);
}

TEST(PhantomPlanes, APointBeyondAPhantomPlaneIsNoPhantomOfItsObject)
{
  // A phantom plane is the image of a wall; what lies beyond it would be behind that wall, which no
  // reflection shows. Here the phantom plane is taken 1.5 m nearer than the back wall's phantoms:
  // those, beyond it, land on the back wall across the mirror all the same, but prove nothing.
  const core::Sweep sweep = sweepOf(mirrorRoom());
  const core::ReflectiveObject mirror = test::patchAt(kMirror, 0.0f, 0.0f, 0.2f, ObjectType::mirror);
  const core::ReflectiveObject on_it = objectOfEchoes(sweep, kPhantomWall, 1.2f, 0.6f, 0.8f, ObjectType::glass);
  core::ReflectiveObject nearer = on_it;
  nearer.plane[3] -= 1.5f;
  nearer.centre.x() -= 1.5f;
  const test::Detected detected(sweep);
  const Labelled out = labelWithPhantomPlane(sweep, detected, mirror, nearer);
  std::size_t in_cone = 0, phantoms = 0;
  for (const core::PointRef& ref : on_it.surface_inliers)
  {
    if (out.assignment.echoes[ref.echo][ref.beam] != 0)
      continue;
    ++in_cone;
    phantoms += out.labels.echoes[ref.echo][ref.beam] == Label::behindReflective ? 1 : 0;
  }
  ASSERT_GE(in_cone, 50u);
  EXPECT_EQ(phantoms, 0u);  // (phantoms in the cone nearer than the phantom plane are still taken)
}

// The wall seen through a reflecting pane: a pane at x = kMirror (its near-perpendicular patch
// gives surface echoes) reflects the back wall and lets the sensor see a wall at x = seen_wall
// (kSeenWall, or just behind the pane). Up and to the side of the patch, where the transmitted
// path is the shorter, a beam's near echo lies on that wall and its far echo is the back wall's
// phantom at x = kPhantomWall.
constexpr float kSeenWall = 3.0f;

core::Sweep seenThroughSweep(float seen_wall)
{
  core::Sweep sweep = sweepOf(mirrorRoom());
  for (std::size_t b = 0; b < sweep.beamCount(); ++b)
  {
    const Eigen::Vector3f phantom = sweep.echoes[0].points[b];
    if (!phantom.allFinite() || std::fabs(phantom.x() - kPhantomWall) > 0.02f || phantom.y() < 0.6f ||
        phantom.z() < 0.1f)
      continue;
    sweep.echoes[0].points[b] = phantom * (seen_wall / phantom.x());
    sweep.echoes[1].points[b] = phantom;
  }
  sweep.computeRanges(Eigen::Vector3f::Zero());
  return sweep;
}

// The pane at kMirror (its 0.1 m patch) and the wall at `distance` seen through it, objects of
// seenThroughSweep(distance)'s echoes as object extraction would have fitted them.
struct PaneAndWall
{
  explicit PaneAndWall(float wall_distance)
    : distance(wall_distance)
    , sweep(seenThroughSweep(wall_distance))
    , pane(objectOfEchoes(sweep, kMirror, 0.0f, 0.0f, 0.1f, ObjectType::glass))
    , wall(objectOfEchoes(sweep, wall_distance, 1.0f, 0.5f, 0.6f, ObjectType::glass))
    , detected(sweep)
  {
  }

  core::PhantomPlanes::Shares shares(const core::ReflectiveObject& object, const core::ReflectiveObject& host) const
  {
    return core::PhantomPlanes(phantomPlaneConfig()).shares(sweep, Eigen::Vector3f::Zero(), detected.evidence, object, host);
  }

  float distance;
  core::Sweep sweep;
  core::ReflectiveObject pane, wall;
  test::Detected detected;
};

// The wall's sample was seen through the pane (none of it the pane's phantoms), and the stage hands
// the wall to the pane as a surface seen through it.
void expectSeenThroughThePane(const PaneAndWall& scene)
{
  const core::PhantomPlanes::Shares shares = scene.shares(scene.wall, scene.pane);
  EXPECT_GE(shares.seen_through, 0.9f);
  EXPECT_LE(shares.phantom, 0.0f);
  const std::vector<core::ReflectiveObject> objects = afterStage(scene.sweep, { scene.wall, scene.pane });
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_TRUE(objects[0].phantom_planes.empty());
  ASSERT_EQ(objects[0].seen_through_surfaces.size(), 1u);
  EXPECT_NEAR(objects[0].seen_through_surfaces[0].centre.x(), scene.distance, 1e-4f);
}

TEST(PhantomPlanes, AWallSeenThroughAPaneIsHandedToThePaneAndItsFarEchoesAreThePanesPhantoms)
{
  const PaneAndWall scene(kSeenWall);
  const core::Sweep& sweep = scene.sweep;
  const core::ReflectiveObject& pane = scene.pane;
  // The near echoes on the wall behind: more than max_echo_ratio times the pane's (no phantom plane
  // could be that much larger than its pane's patch; a surface seen through it can).
  const core::ReflectiveObject& wall = scene.wall;
  ASSERT_GE(pane.surface_inliers.size(), 20u);
  ASSERT_GE(wall.surface_inliers.size(), 4 * pane.surface_inliers.size());
  expectSeenThroughThePane(scene);
  // The pane is seen through nothing; nothing is seen through a mirror.
  EXPECT_LE(scene.shares(pane, wall).seen_through, 0.0f);
  core::ReflectiveObject mirror = pane;
  mirror.type = ObjectType::mirror;
  EXPECT_LE(scene.shares(wall, mirror).seen_through, 0.0f);
  // An object typed mirror showed reflections of its own: it is no wall seen through another.
  core::ReflectiveObject shiny = wall;
  shiny.type = ObjectType::mirror;
  EXPECT_LE(scene.shares(shiny, pane).seen_through, 0.0f);

  const test::Detected& detected = scene.detected;
  std::vector<core::ReflectiveObject> objects = afterStage(sweep, { wall, pane });

  // Labelled against the pane: the wall's points are seen through it (kept), the beams' far echoes
  // are its phantoms (back-projected across it).
  const Labelled out = labelWith(sweep, detected, objects);
  std::size_t kept = 0, reflections = 0, others = 0;
  for (const core::PointRef& ref : wall.surface_inliers)
  {
    EXPECT_EQ(out.assignment.echoes[0][ref.beam], 0);
    EXPECT_EQ(out.assignment.echoes[1][ref.beam], 0);
    ++(out.labels.echoes[0][ref.beam] == Label::behindTransparent ? kept : others);
    ++(out.labels.echoes[1][ref.beam] == Label::behindReflective ? reflections : others);
  }
  EXPECT_EQ(kept, wall.surface_inliers.size());
  EXPECT_GE(reflections, 9 * wall.surface_inliers.size() / 10);
}

// A wall just behind a pane (nearer than min_depth: a partition's next pane, seen at an angle
// that returns no surface echo, with the wall right behind it): reflected across the pane its
// echoes land next to themselves, which proves nothing, but their beams' far echoes are the
// pane's phantoms, not the wall's. Random scene 46008, rotating Hokuyo: such a wall 0.17 m
// behind a partition was typed glass and its plane, 7 deg off the partition's, took the
// partition's reflections for points seen through it (7931 double-echo phantoms at a wrong place).
TEST(PhantomPlanes, AWallJustBehindAPaneIsSeenThroughItByItsFarEchoes)
{
  const PaneAndWall scene(kMirror + 0.18f);
  ASSERT_LT(scene.distance - kMirror, phantomPlaneConfig().min_depth);
  ASSERT_GE(scene.wall.surface_inliers.size(), 4 * scene.pane.surface_inliers.size());
  expectSeenThroughThePane(scene);
  // Only a pane is looked through this close: behind an object whose type nothing decided (most
  // often no reflecting surface at all) the far echoes' landing is no evidence.
  core::ReflectiveObject undecided = scene.pane;
  undecided.type = ObjectType::unknown;
  EXPECT_LE(scene.shares(scene.wall, undecided).seen_through, 0.0f);
}

// A metal panel on a side wall that runs through a glass partition: behind the partition at
// x = 2, on the wall y = -kSideWall. Reflected across the partition, the panel's echoes land on
// the same wall in front of it, a surface the reflection maps onto itself, which proves nothing.
// With a centimetre and more of range noise the plane through the four returns around where an
// echo lands (a beam step apart) points anywhere, and most of them seemed to land on a surface
// that the reflection does not map onto itself. An echo as bright as a wall is no reflection in
// glass: its landing surface's normal comes from a ball of returns. Random scene 48007, rotating
// Hokuyo: such a panel (typed mirror) was taken for the partition's phantom plane, 4303
// double-echo phantoms at a wrong place (1880 with the ball's normal for bright echoes).
constexpr float kSideWall = 2.5f;

struct PanelBehindAPane
{
  core::Sweep sweep;
  core::ReflectiveObject pane, panel;
};

// The panel's echoes `panel_brightness` times as bright as the walls'.
PanelBehindAPane panelBehindAPane(float panel_brightness)
{
  PanelBehindAPane scene;
  core::Sweep& sweep = scene.sweep;
  sweep = sweepOf(paneRoom());
  std::mt19937 random(7);
  std::normal_distribution<float> noise(0.0f, 0.015f);
  sweep.has_intensity = true;
  for (std::size_t k = 0; k < 2; ++k)
  {
    sweep.echoes[k].intensities.assign(sweep.beamCount(), std::numeric_limits<float>::quiet_NaN());
    for (std::size_t b = 0; b < sweep.beamCount(); ++b)
    {
      Eigen::Vector3f& p = sweep.echoes[k].points[b];
      if (!p.allFinite())
        continue;
      p *= 1.0f + noise(random) / p.norm();
      // A wall's echo falls with the square of the range (the scale finds that out).
      sweep.echoes[k].intensities[b] = 1000.0f / p.squaredNorm();
    }
  }
  sweep.computeRanges(Eigen::Vector3f::Zero());
  scene.pane = objectOfEchoes(sweep, 2.0f, 0.0f, 0.0f, 0.2f, ObjectType::glass);

  core::ReflectiveObject& panel = scene.panel;
  panel.type = ObjectType::mirror;
  panel.plane = Eigen::Vector4f(0.0f, 1.0f, 0.0f, kSideWall);
  panel.centre = Eigen::Vector3f(2.8f, -kSideWall, 0.2f);
  panel.width_axis = Eigen::Vector3f::UnitX();
  panel.height_axis = Eigen::Vector3f::UnitZ();
  panel.width = 0.8f;
  panel.height = 1.0f;
  for (std::size_t b = 0; b < sweep.beamCount(); ++b)
  {
    const Eigen::Vector3f& p = sweep.echoes[0].points[b];
    if (p.allFinite() && std::fabs(p.y() + kSideWall) < 0.05f && std::fabs(p.x() - panel.centre.x()) <= 0.4f &&
        std::fabs(p.z() - panel.centre.z()) <= 0.5f)
    {
      panel.surface_inliers.push_back(core::PointRef{ static_cast<std::uint32_t>(b), 0 });
      sweep.echoes[0].intensities[b] *= panel_brightness;
    }
  }
  return scene;
}

TEST(PhantomPlanes, ABrightPanelOnAWallThatRunsThroughAPaneIsNoPhantomPlaneOfIt)
{
  const PanelBehindAPane scene = panelBehindAPane(1.0f);
  ASSERT_GE(scene.pane.surface_inliers.size(), 20u);
  ASSERT_GE(scene.panel.surface_inliers.size(), 100u);
  const test::Detected detected(scene.sweep);
  const core::IntensityScale scale = core::intensityScale(scene.sweep);
  const core::PhantomPlanes stage(phantomPlaneConfig());
  EXPECT_LT(stage.shares(scene.sweep, Eigen::Vector3f::Zero(), detected.evidence, scene.panel, scene.pane, &scale).phantom,
            0.5f * phantomPlaneConfig().min_share);
  EXPECT_EQ(afterStage(scene.sweep, { scene.panel, scene.pane }).size(), 2u);
  // Without intensities the few returns' normal decides, and most of the panel's echoes seem to land
  // on the wall in front (the test of the ball's normal is not asked: a reflection's echo is faint).
  EXPECT_GE(stage.shares(scene.sweep, Eigen::Vector3f::Zero(), detected.evidence, scene.panel, scene.pane).phantom,
            phantomPlaneConfig().min_share);
}

TEST(PhantomPlanes, AFaintImageOnAWallThatRunsThroughAPaneIsStillItsPhantomPlane)
{
  // As faint as a reflection in glass: the pane's image of the wall in front of it, for all its
  // landing says; left to the few returns' normal, as before.
  const PanelBehindAPane scene = panelBehindAPane(0.02f);
  const test::Detected detected(scene.sweep);
  const core::IntensityScale scale = core::intensityScale(scene.sweep);
  EXPECT_GE(core::PhantomPlanes(phantomPlaneConfig())
                .shares(scene.sweep, Eigen::Vector3f::Zero(), detected.evidence, scene.panel, scene.pane, &scale)
                .phantom,
            phantomPlaneConfig().min_share);
}

// The hidden side of something between the sensor and a pane: a box stands 1.4 m from the sensor,
// its front (seen) at x = kBoxFront, its back (not seen) at x = kBoxBack. The pane at x = kMirror
// reflects the back: its image lies at x = kHiddenImage, as far behind the pane as the back is in
// front. Beams that pass the box and meet the pane there return that image as their near echo
// and the front wall seen through the pane as their far echo.
constexpr float kBoxFront = 1.4f;
constexpr float kBoxBack = 1.6f;
constexpr float kHiddenImage = kMirror + (kMirror - kBoxBack);

core::Sweep hiddenSideSweep()
{
  test::TracedScene scene;
  scene.panels = test::room(kBack, 4.0f, 2.5f, 1.0f, 1.5f);
  scene.panels.push_back({ 0, kMirror, { -1.5f, -0.8f }, { 1.5f, 1.2f }, Surface::glass });
  scene.panels.push_back({ 0, kBoxFront, { 0.85f, -0.5f }, { 2.0f, 0.8f }, Surface::wall });
  core::Sweep sweep = sweepOf(scene);
  for (std::size_t b = 0; b < sweep.beamCount(); ++b)
  {
    const Eigen::Vector3f seen_through = sweep.echoes[0].points[b];
    if (!seen_through.allFinite() || std::fabs(seen_through.x() - 4.0f) > 0.02f)
      continue;
    const Eigen::Vector3f image = seen_through * (kHiddenImage / seen_through.x());
    // Where the box's back, reflected, is seen: the image's reflection lies behind the box's front.
    if (image.y() < 1.0f || image.y() > 1.4f || image.z() < 0.0f || image.z() > 0.5f)
      continue;
    sweep.echoes[0].points[b] = image;
    sweep.echoes[1].points[b] = seen_through;
  }
  sweep.computeRanges(Eigen::Vector3f::Zero());
  return sweep;
}

TEST(PhantomPlanes, AnImageOfAHiddenSideInAPaneIsThePanesPhantomPlane)
{
  const core::Sweep sweep = hiddenSideSweep();
  // The pane's patch is small: its phantom plane holds more than max_echo_ratio times its echoes.
  core::ReflectiveObject pane = test::patchAt(kMirror, 0.0f, 0.0f, 0.2f, ObjectType::glass);
  pane.surface_inliers.resize(50, core::PointRef{ 0, 0 });
  const core::ReflectiveObject image = objectOfEchoes(sweep, kHiddenImage, 1.2f, 0.25f, 0.4f, ObjectType::mirror);
  ASSERT_GT(image.surface_inliers.size(), 4 * pane.surface_inliers.size());

  const test::Detected detected(sweep);
  const Eigen::Vector3f origin = Eigen::Vector3f::Zero();
  // Reflected across the pane its echoes land behind the box's front: occluded, not on a surface.
  std::size_t occluded = 0;
  for (const core::PointRef& ref : image.surface_inliers)
    occluded += detected.evidence.test(pane.plane, sweep.echoes[0].points[ref.beam], pane.landing_tolerance).outcome ==
                        core::ReflectionOutcome::occluded ?
                    1 :
                    0;
  EXPECT_GE(occluded, 9 * image.surface_inliers.size() / 10);

  const core::PhantomPlanes stage(phantomPlaneConfig());
  EXPECT_GE(stage.shares(sweep, origin, detected.evidence, image, pane).phantom, 0.9f);
  const std::vector<core::ReflectiveObject> objects = afterStage(sweep, { image, pane });
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_EQ(objects[0].type, ObjectType::glass);
  ASSERT_EQ(objects[0].phantom_planes.size(), 1u);
  EXPECT_NEAR(objects[0].phantom_planes[0].centre.x(), kHiddenImage, 1e-4f);

  // A mirror lets nothing through: behind it no far echo is seen through, and the image is no
  // phantom plane of a mirror's small patch.
  core::ReflectiveObject mirror = pane;
  mirror.type = ObjectType::mirror;
  EXPECT_LE(stage.shares(sweep, origin, detected.evidence, image, mirror).phantom, 0.0f);
  // Landing further behind a seen surface than things are deep is no evidence (a real mirror
  // behind the pane lands there): the box is 0.2 m deep.
  core::PhantomPlaneConfig shallow = phantomPlaneConfig();
  shallow.max_hidden_depth = 0.1f;
  EXPECT_LT(core::PhantomPlanes(shallow).shares(sweep, origin, detected.evidence, image, pane).phantom, 0.5f);
  // Whose far echoes are its own reflections is a real mirror seen through the pane, not an image.
  core::Sweep with_own_phantoms = sweep;
  for (const core::PointRef& ref : image.surface_inliers)
  {
    // The box's front seen in the object's mirror: its image across x = kHiddenImage.
    const Eigen::Vector3f p = sweep.echoes[0].points[ref.beam];
    with_own_phantoms.echoes[1].points[ref.beam] = p * ((2.0f * kHiddenImage - kBoxFront) / p.x());
  }
  with_own_phantoms.computeRanges(origin);
  const test::Detected mirrored(with_own_phantoms);
  EXPECT_LT(stage.shares(with_own_phantoms, origin, mirrored.evidence, image, pane).phantom, 0.5f);
}

TEST(PhantomPlanes, TheConeLabellingLabelsAPanesImageOfAHiddenSideAsItsReflections)
{
  // Reflected across the pane, the image's echoes land behind the box's front: no evidence of
  // their own, which behind glass keeps a point as seen through. On the pane's phantom plane they
  // are its reflections; the far echoes behind them were seen through the pane.
  const core::Sweep sweep = hiddenSideSweep();
  const core::ReflectiveObject pane = test::patchAt(kMirror, 0.0f, 0.0f, 0.2f, ObjectType::glass);
  const core::ReflectiveObject image = objectOfEchoes(sweep, kHiddenImage, 1.2f, 0.25f, 0.4f, ObjectType::mirror);
  ASSERT_GE(image.surface_inliers.size(), 50u);
  const test::Detected detected(sweep);
  const Labelled out = labelWithPhantomPlane(sweep, detected, pane, image);
  std::size_t reflections = 0, seen_through = 0;
  for (const core::PointRef& ref : image.surface_inliers)
  {
    EXPECT_EQ(out.assignment.echoes[0][ref.beam], 0);
    reflections += out.labels.echoes[0][ref.beam] == Label::behindReflective ? 1 : 0;
    seen_through += out.labels.echoes[1][ref.beam] == Label::behindTransparent ? 1 : 0;
  }
  EXPECT_GE(reflections, 9 * image.surface_inliers.size() / 10);
  EXPECT_GE(seen_through, 9 * image.surface_inliers.size() / 10);

  // Without the phantom plane the same echoes are kept (nothing proves them reflections).
  std::vector<core::ReflectiveObject> alone{ test::patchAt(kMirror, 0.0f, 0.0f, 0.2f, ObjectType::glass) };
  alone[0].width = alone[0].height = 4.0f;  // a pane grown over the image's beams
  const Labelled plain = labelWith(sweep, detected, alone);
  std::size_t kept = 0;
  for (const core::PointRef& ref : image.surface_inliers)
    kept += plain.labels.echoes[0][ref.beam] == Label::behindTransparent ? 1 : 0;
  EXPECT_GE(kept, 9 * image.surface_inliers.size() / 10);
}

}  // namespace
}  // namespace ohm_mirror_detector3d
