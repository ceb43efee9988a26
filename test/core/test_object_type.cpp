#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "ohm_mirror_detector3d/core/object_type.h"
#include "ohm_mirror_detector3d/core/stage_configs.h"
#include "object_fixtures.h"
#include "sweep_fixtures.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::Label;
using core::ObjectType;

// A scene around a 1 x 1 m object in the plane x = 2 (facing the sensor at the origin), built
// beam by beam with the labels the echo comparison would give.
struct Scene
{
  std::vector<test::Beam> beams;
  std::vector<std::pair<Label, Label>> labels;
  std::mt19937 noise_source{ 7 };

  // A real diffuse wall in the plane x = wall_x, |y| <= half_width, |z| <= 1, seen directly.
  void addRealWall(float wall_x, float half_width)
  {
    for (float y = -half_width; y <= half_width; y += 0.02f)
      for (float z = -1.0f; z <= 1.0f; z += 0.02f)
        addSingleReturn(Eigen::Vector3f(wall_x, y, z));
  }

  void addSingleReturn(const Eigen::Vector3f& p)
  {
    beams.push_back({ p, p });
    labels.emplace_back(Label::unchecked, Label::unchecked);
  }

  // A beam with a surface echo on the object and a far echo at `far` along the same ray.
  void addDoubleEcho(const Eigen::Vector3f& far)
  {
    std::normal_distribution<float> noise(0.0f, 0.005f);
    const Eigen::Vector3f direction = far.normalized();
    const Eigen::Vector3f surface = direction * (2.0f / direction.x());
    beams.push_back({ surface, far + direction * noise(noise_source) });
    labels.emplace_back(Label::errorSurface, Label::error);
  }

  // Double echoes on ordinary geometry, as a sensor that resolves two echoes `separation` apart
  // gives them where its footprint straddles a depth edge: `count` beams at the wall x = -1 beside
  // the room (2 <= y <= 3), their second echo `separation` beyond the first.
  void addMixedPixels(std::size_t count, float separation)
  {
    for (std::size_t k = 0; k < count; ++k)
    {
      const Eigen::Vector3f first(-1.0f, 2.0f + 0.01f * static_cast<float>(k), 0.0f);
      beams.push_back({ first, first + separation * first.normalized() });
      labels.emplace_back(Label::unchecked, Label::unchecked);
    }
  }

  // Single echoes `behind` beyond the object's plane, at |y|, |z| <= 0.18 (8 mm apart): reflected,
  // they land within the directions of the double echoes' surface echoes.
  void addEchoesJustBehind(float behind)
  {
    for (float y = -0.18f; y <= 0.18f; y += 0.008f)
      for (float z = -0.18f; z <= 0.18f; z += 0.008f)
        addSingleReturn(Eigen::Vector3f(2.0f + behind, y, z));
  }

  // Double echoes through the object of every point of a wall at x = far_x (|y| <= 1.2, |z| <= 1).
  void addDoubleEchoesSeeing(float far_x)
  {
    for (float y = -1.2f; y <= 1.2f; y += 0.03f)
      for (float z = -1.0f; z <= 1.0f; z += 0.03f)
        addDoubleEcho(Eigen::Vector3f(far_x, y, z));
  }

  ObjectType analyze(core::ReflectiveObject& object) const
  {
    const core::Sweep sweep = test::makeSweep(beams);
    core::SweepLabels sweep_labels;
    sweep_labels.reset(sweep.beamCount());
    for (std::size_t i = 0; i < labels.size(); ++i)
    {
      sweep_labels.echoes[0][i] = labels[i].first;
      sweep_labels.echoes[1][i] = labels[i].second;
    }
    core::ReflectionEvidence evidence;
    evidence.build(sweep, sweep_labels, Eigen::Vector3f::Zero());
    core::ObjectTypeAnalyzer analyzer(core::stageConfigs(core::Params()).object_type);
    analyzer.analyze(sweep, Eigen::Vector3f::Zero(), sweep_labels, evidence, object);
    return object.type;
  }
};

core::ReflectiveObject objectAtTwoMetres()
{
  return test::wallObject(2.0f, 1.0f, 1.0f);
}

TEST(ObjectType, PhantomsThatMirrorOntoTheRealSceneMakeAMirror)
{
  Scene scene;
  scene.addRealWall(-1.0f, 1.5f);
  // What the mirror shows: the wall at x = -1 reflected across x = 2, i.e. at x = 5.
  scene.addDoubleEchoesSeeing(5.0f);
  core::ReflectiveObject object = objectAtTwoMetres();
  EXPECT_EQ(scene.analyze(object), ObjectType::mirror);
  EXPECT_GT(object.evidence.mirrored_points, 1000u);
  EXPECT_GT(object.evidence.inlier_fraction, 0.9f);
  EXPECT_LT(object.evidence.landing_fitness, 0.001f);
  EXPECT_TRUE(object.evidence.plane_refined);
}

TEST(ObjectType, RealPointsBehindThatDoNotMirrorOntoTheSceneMakeGlass)
{
  Scene scene;
  // Behind the pane a wall at x = 5; in front the sensor sees a wall at x = -2, so the space
  // at x = -1 where the mirrored points would land is free.
  scene.addRealWall(-2.0f, 3.0f);
  scene.addDoubleEchoesSeeing(5.0f);
  core::ReflectiveObject object = objectAtTwoMetres();
  EXPECT_EQ(scene.analyze(object), ObjectType::glass);
  EXPECT_LT(object.evidence.inlier_fraction, 0.5f);
}

TEST(ObjectType, AWallNearWhereThePhantomsShouldLandIsNoMirror)
{
  Scene scene;
  // A real wall 30 cm beyond where a mirror image would be, tilted: no good registration.
  for (float y = -1.5f; y <= 1.5f; y += 0.02f)
    for (float z = -1.0f; z <= 1.0f; z += 0.02f)
      scene.addSingleReturn(Eigen::Vector3f(-1.3f - 0.3f * y, y, z));
  scene.addDoubleEchoesSeeing(5.0f);
  core::ReflectiveObject object = objectAtTwoMetres();
  // Some mirrored points land near the tilted wall: no mirror, but no clear glass either.
  EXPECT_NE(scene.analyze(object), ObjectType::mirror);
}

TEST(ObjectType, RefinesAMirrorsPlaneToWhereItsPhantomsLandOnTheRealScene)
{
  // The plane fitted to the surface echoes is 0.5 deg and 1 cm off; the phantoms 3 m behind
  // the mirror would come back 5 cm off. The refined plane must put them back.
  Scene scene;
  scene.addRealWall(-1.0f, 1.5f);
  scene.addDoubleEchoesSeeing(5.0f);
  core::ReflectiveObject object = objectAtTwoMetres();
  const float tilt = 0.5f * static_cast<float>(M_PI) / 180.0f;
  object.plane = Eigen::Vector4f(-std::cos(tilt), std::sin(tilt), 0.0f, 2.01f);
  ASSERT_EQ(scene.analyze(object), ObjectType::mirror);
  const float angle_error = std::acos(std::min(1.0f, -object.plane.x()));
  EXPECT_LT(angle_error, 0.05f * static_cast<float>(M_PI) / 180.0f);
  EXPECT_NEAR(object.plane[3], 2.0f, 0.003f);
  EXPECT_NEAR(object.signedDistance(object.centre), 0.0f, 1e-4f);
  const Eigen::Vector3f phantom(5.0f, 0.5f, 0.3f);
  EXPECT_LT((object.reflect(phantom) - Eigen::Vector3f(-1.0f, 0.5f, 0.3f)).norm(), 0.01f);
}

TEST(ObjectType, TooFewPointsBehindLeaveTheTypeUnknown)
{
  Scene scene;
  scene.addRealWall(-1.0f, 1.5f);
  for (int i = 0; i < 10; ++i)
    scene.addDoubleEcho(Eigen::Vector3f(5.0f, 0.05f * i, 0.0f));
  core::ReflectiveObject object = objectAtTwoMetres();
  EXPECT_EQ(scene.analyze(object), ObjectType::unknown);
  EXPECT_EQ(object.evidence.mirrored_points, 10u);
}

TEST(ObjectType, NothingSeenWhereThePhantomsLandLeavesTheTypeUnknown)
{
  // A mirror facing open space: the sensor saw nothing in the directions of the mirrored
  // points, so neither a match nor a contradiction is possible.
  Scene scene;
  for (float z = -1.0f; z <= 1.0f; z += 0.02f)
    for (float x = -1.0f; x <= 1.0f; x += 0.02f)
      scene.addSingleReturn(Eigen::Vector3f(x, 4.0f, z));  // a wall off to the side only
  scene.addDoubleEchoesSeeing(5.0f);
  core::ReflectiveObject object = objectAtTwoMetres();
  EXPECT_EQ(scene.analyze(object), ObjectType::unknown);
  EXPECT_GT(object.evidence.mirrored_points, 1000u);
}

TEST(ObjectType, OnlyPointsInsideTheVisionConeCount)
{
  Scene scene;
  scene.addRealWall(-1.0f, 1.5f);
  // Far echoes beside the object (outside its cone) are not its phantoms.
  for (float z = -1.0f; z <= 1.0f; z += 0.03f)
    scene.addDoubleEcho(Eigen::Vector3f(5.0f, 3.0f, z));
  core::ReflectiveObject object = objectAtTwoMetres();
  EXPECT_EQ(scene.analyze(object), ObjectType::unknown);
  EXPECT_EQ(object.evidence.mirrored_points, 0u);
}

// The types of `objects` in a sweep seen from the origin, every point unchecked, analysed together
// as the pipeline does (each sees the others).
void typesIn(const core::Sweep& sweep, std::vector<core::ReflectiveObject>& objects)
{
  core::SweepLabels labels;
  labels.reset(sweep.beamCount());
  core::ReflectionEvidence evidence;
  evidence.build(sweep, labels, Eigen::Vector3f::Zero());
  core::ObjectTypeAnalyzer analyzer(core::stageConfigs(core::Params()).object_type);
  analyzer.analyzeAll(sweep, Eigen::Vector3f::Zero(), labels, evidence, objects);
}

// The type of `object` alone in a sweep seen from the origin, every point unchecked.
ObjectType typeIn(const core::Sweep& sweep, core::ReflectiveObject& object)
{
  std::vector<core::ReflectiveObject> objects{ object };
  typesIn(sweep, objects);
  object = objects[0];
  return object.type;
}

TEST(ObjectType, GlassThatAlsoReflectsIsGlass)
{
  // A wall at x = -1 behind the sensor. Behind the pane at x = 2: where y > 0 its reflection in
  // the pane (at x = 5), where y < 0 a real wall at x = 3.5 seen through it.
  const core::Sweep sweep =
      test::rangeImage({ { 0, -1.0f, test::everywhere },
                         { 0, 5.0f, [](const Eigen::Vector3f& x) { return x.y() > 0.0f; } },
                         { 0, 3.5f, [](const Eigen::Vector3f& x) { return x.y() <= 0.0f; } } });
  core::ReflectiveObject object = objectAtTwoMetres();
  EXPECT_EQ(typeIn(sweep, object), ObjectType::glass);
  EXPECT_GT(object.evidence.phantom_points, 100u);
  EXPECT_GT(object.evidence.transmitted_points, 100u);
  EXPECT_GT(object.evidence.real_fraction, 0.3f);
}

TEST(ObjectType, ASurfaceThatOnlyReflectsIsAMirror)
{
  // Shiny metal or a mirror: everything behind it is the reflection of the wall at x = -1.
  const core::Sweep sweep = test::rangeImage({ { 0, -1.0f, test::everywhere }, { 0, 5.0f, test::everywhere } });
  core::ReflectiveObject object = objectAtTwoMetres();
  EXPECT_EQ(typeIn(sweep, object), ObjectType::mirror);
  EXPECT_EQ(object.evidence.transmitted_points, 0u);
  EXPECT_TRUE(object.evidence.plane_refined);
  // The sweep has no intensities: the phantoms' brightness is no evidence.
  EXPECT_EQ(object.evidence.phantom_share_points, 0u);
  EXPECT_TRUE(std::isnan(object.evidence.dim_phantom_fraction));
}

// The sweep of ASurfaceThatOnlyReflectsIsAMirror with the intensities of a Lambertian wall at
// x = -1 (cos(incidence) / r^2), seen directly in front of the surface at x = 2 and, behind it,
// through a reflector that returns `reflected` (R^2) of the light.
core::Sweep reflectionWithIntensities(float reflected)
{
  core::Sweep sweep = test::rangeImage({ { 0, -1.0f, test::everywhere }, { 0, 5.0f, test::everywhere } });
  sweep.has_intensity = true;
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t i = 0; i < sweep.beamCount(); ++i)
    {
      const Eigen::Vector3f& p = sweep.echoes[k].points[i];
      const float range = p.norm();
      const float lambert = 1000.0f * std::fabs(p.x()) / range / (range * range);
      sweep.echoes[k].intensities[i] = p.x() > 2.0f ? reflected * lambert : lambert;
    }
  return sweep;
}

TEST(ObjectType, PhantomsTooDimForAMirrorAreReflectionsInGlass)
{
  // A pane reflects 8 % at perpendicular incidence: its phantoms come back with R^2 = 0.6 % of
  // the light. The geometry alone (every point behind lands on the wall) says mirror.
  const core::Sweep sweep = reflectionWithIntensities(0.08f * 0.08f);
  core::ReflectiveObject object = objectAtTwoMetres();
  EXPECT_EQ(typeIn(sweep, object), ObjectType::glass);
  EXPECT_TRUE(object.evidence.typed_by_dim_phantoms);
  EXPECT_EQ(object.evidence.transmitted_points, 0u);
  EXPECT_GT(object.evidence.phantom_share_points, 100u);
  EXPECT_NEAR(object.evidence.phantom_intensity_share, 0.0064f, 0.001f);
  EXPECT_GT(object.evidence.dim_phantom_fraction, 0.95f);
}

TEST(ObjectType, PhantomsAsBrightAsAMirrorsOrShinyMetalsStayAMirror)
{
  // R = 0.9 (a mirror) and R = 0.5 (shiny metal).
  for (const float reflectance : { 0.9f, 0.5f })
  {
    const core::Sweep sweep = reflectionWithIntensities(reflectance * reflectance);
    core::ReflectiveObject object = objectAtTwoMetres();
    EXPECT_EQ(typeIn(sweep, object), ObjectType::mirror) << "reflectance " << reflectance;
    EXPECT_FALSE(object.evidence.typed_by_dim_phantoms);
    EXPECT_NEAR(object.evidence.phantom_intensity_share, reflectance * reflectance, 0.02f);
    EXPECT_LT(object.evidence.dim_phantom_fraction, 0.05f);
  }
}

TEST(ObjectType, AnObjectLeftUnknownWhosePhantomsAreTooBrightForGlassIsAMirror)
{
  // A narrow mirror: inside its rectangle, away from the border, too few points are decided for a
  // type, though all of its phantoms land on the wall at x = -1. Brighter than any reflection in
  // glass below 80 deg incidence (R^2 >= 0.15), they make it a mirror; without intensities, or as
  // dim as glass's, they do not.
  core::ReflectiveObject plain = test::wallObject(2.0f, 0.12f, 0.5f);
  const core::Sweep geometry = test::rangeImage({ { 0, -1.0f, test::everywhere }, { 0, 5.0f, test::everywhere } });
  ASSERT_EQ(typeIn(geometry, plain), ObjectType::unknown);
  ASSERT_GE(plain.evidence.inlier_fraction, 0.9f);

  core::ReflectiveObject bright = test::wallObject(2.0f, 0.12f, 0.5f);
  EXPECT_EQ(typeIn(reflectionWithIntensities(0.5f * 0.5f), bright), ObjectType::mirror);
  EXPECT_TRUE(bright.evidence.typed_by_bright_phantoms);
  EXPECT_GE(bright.evidence.phantom_share_points, 10u);

  core::ReflectiveObject dim = test::wallObject(2.0f, 0.12f, 0.5f);
  EXPECT_EQ(typeIn(reflectionWithIntensities(0.3f * 0.3f), dim), ObjectType::unknown);
  EXPECT_FALSE(dim.evidence.typed_by_bright_phantoms);
}

// A reflecting surface at x = 2 whose phantoms land on the wall at x = -1, seen by a sensor that
// resolves two echoes 0.9 m apart (its mixed pixels show it), with single echoes `behind` beyond
// its plane over its inside: the object's type and evidence.
core::ReflectiveObject surfaceWithEchoesBehind(float behind)
{
  Scene scene;
  scene.addRealWall(-1.0f, 1.5f);
  scene.addDoubleEchoesSeeing(5.0f);
  scene.addMixedPixels(150, 0.9f);
  scene.addEchoesJustBehind(behind);
  core::ReflectiveObject object = objectAtTwoMetres();
  scene.analyze(object);
  return object;
}

TEST(ObjectType, MergedEchoesJustBehindShinyMetalDoNotMakeItGlass)
{
  // Shiny metal: over its inside single echoes lie 0.15 m behind it (its diffuse echo merged with
  // its reflection off something just in front of it). Reflected, they would lie in front of the
  // metal, where the sensor saw the metal itself: seen through, were they not so near the plane
  // for the sensor's echo separation. Enough of them to make it glass otherwise.
  const core::ReflectiveObject metal = surfaceWithEchoesBehind(0.15f);
  EXPECT_EQ(metal.type, ObjectType::mirror);
  EXPECT_LT(metal.evidence.real_fraction, 0.05f);

  // The same echoes 0.6 m behind the plane are real, seen through it: no merged echo lies that
  // far behind (kMergedEchoReach of the separation).
  const core::ReflectiveObject pane = surfaceWithEchoesBehind(0.6f);
  EXPECT_EQ(pane.type, ObjectType::glass);
  EXPECT_GT(pane.evidence.real_fraction, 0.2f);
}

// A mirror at x = 2 showing the wall at x = -1 (double echoes: its surface echo and the phantom
// at x = 5) and thin posts 0.6 m in front of it (x = 1.4, 2 cm wide, 10 cm apart, |z| <= 1, seen
// directly), with mixed pixels showing an echo separation of 0.9 m when `mixed_pixels`.
// add_phantom(scene, r) adds the echoes a post point's reflection r (at x = 2.6) comes back as.
template <typename AddPhantom>
core::ReflectiveObject mirrorWithPosts(bool mixed_pixels, AddPhantom add_phantom)
{
  Scene scene;
  scene.addRealWall(-1.0f, 1.5f);
  scene.addDoubleEchoesSeeing(5.0f);
  if (mixed_pixels)
    scene.addMixedPixels(150, 0.9f);
  for (float post = -0.5f; post < 0.45f; post += 0.1f)
    for (float y = post; y <= post + 0.02f; y += 0.0075f)
      for (float z = -1.0f; z <= 1.0f; z += 0.01f)
      {
        scene.addSingleReturn(Eigen::Vector3f(1.4f, y, z));
        add_phantom(scene, Eigen::Vector3f(2.6f, y, z));
      }
  core::ReflectiveObject object = objectAtTwoMetres();
  scene.analyze(object);
  return object;
}

// The posts' reflections lie 0.6 m behind the mirror, within the separation: each comes back as
// one echo merged with the mirror's surface echo, `shortfall` of its depth short of the
// reflection along the beam.
core::ReflectiveObject mirrorWithMergedPosts(float shortfall)
{
  return mirrorWithPosts(true, [shortfall](Scene& scene, const Eigen::Vector3f& reflection) {
    const Eigen::Vector3f crossing = reflection * (2.0f / 2.6f);
    scene.addSingleReturn(crossing + (1.0f - shortfall) * (reflection - crossing));
  });
}

TEST(ObjectType, AMirrorsMergedEchoesLandingBesideWhatTheyShowDoNotMakeItGlass)
{
  // Reflected as measured, the merged echoes land in front of the posts, beside them as the
  // sensor sees them, where it saw the mirror further away: seen through, by their own test, and
  // a quarter of what the inside decides (glass, were they counted). Moved a little along their
  // beams (the mirror's reflection outshines its surface echo), they land on the posts, or behind
  // them: as likely merged echoes, not counted.
  const core::ReflectiveObject mirror = mirrorWithMergedPosts(0.2f);
  EXPECT_EQ(mirror.type, ObjectType::mirror);
  EXPECT_LT(mirror.evidence.real_fraction, 0.1f);
  EXPECT_GT(mirror.evidence.surface_backed_share, 0.5f);
  // Measured where they are (no shortfall), they land on the posts: phantoms.
  EXPECT_EQ(mirrorWithMergedPosts(0.0f).type, ObjectType::mirror);
}

// The posts' phantoms (double echoes: the mirror's surface echo and the phantom) lie `aside` [m]
// off in y from their reflections, as a plane tilted by a fraction of a degree or a merged echo
// would put them.
core::ReflectiveObject mirrorWithPostPhantomsAside(float aside)
{
  return mirrorWithPosts(false, [aside](Scene& scene, const Eigen::Vector3f& reflection) {
    scene.addDoubleEcho(reflection + Eigen::Vector3f(0.0f, aside, 0.0f));
  });
}

TEST(ObjectType, PhantomsLandingJustBesideWhatTheyShowDoNotMakeAMirrorGlass)
{
  // 2.5 cm aside, the posts' phantoms land beside the posts as the sensor sees them, where it saw
  // the mirror further away: seen through, by their own test, and enough of them to make the
  // mirror glass. The posts lie within the test's window around where they land: no proof of
  // free space there, and they are not counted.
  const core::ReflectiveObject mirror = mirrorWithPostPhantomsAside(0.025f);
  EXPECT_EQ(mirror.type, ObjectType::mirror);
  EXPECT_LT(mirror.evidence.real_fraction, 0.1f);
  // Where they belong they are phantoms of the posts.
  EXPECT_EQ(mirrorWithPostPhantomsAside(0.0f).type, ObjectType::mirror);
  // 5 cm aside, midway between two posts, they land clear of them and are seen through: glass
  // (a pane with thin things behind it, whose surface echoes came back everywhere).
  const core::ReflectiveObject pane = mirrorWithPostPhantomsAside(0.05f);
  EXPECT_EQ(pane.type, ObjectType::glass);
}

TEST(ObjectType, TheShareOfPointsBehindWithASurfaceEchoInFrontLeavesMergedEchoesOut)
{
  // Every double echo through the inside has its surface echo on the plane; the single echoes
  // 0.15 m behind are within the reach of merged echoes (0.2 of the 0.9 m separation) and do not
  // count: shiny metal, seen over its whole face.
  EXPECT_FLOAT_EQ(surfaceWithEchoesBehind(0.15f).evidence.surface_backed_share, 1.0f);
  // 0.6 m behind they are points seen through without a surface echo in front, as behind glass
  // (about 2100 single echoes beside about 4700 double echoes through the inside).
  const float pane = surfaceWithEchoesBehind(0.6f).evidence.surface_backed_share;
  EXPECT_GT(pane, 0.5f);
  EXPECT_LT(pane, 0.8f);
  // Nothing behind the inside: no share.
  Scene empty;
  empty.addRealWall(-1.0f, 1.5f);
  core::ReflectiveObject object = objectAtTwoMetres();
  empty.analyze(object);
  EXPECT_TRUE(std::isnan(object.evidence.surface_backed_share));
}

TEST(ObjectType, WithNothingSeenInFrontTheTypeStaysUnknown)
{
  // Only the wall behind the surface was seen: no point behind it can be told by itself.
  const core::Sweep sweep = test::rangeImage({ { 0, 5.0f, test::everywhere } });
  core::ReflectiveObject object = objectAtTwoMetres();
  EXPECT_EQ(typeIn(sweep, object), ObjectType::unknown);
  EXPECT_GT(object.evidence.undecided_points, 100u);
}

// Behind the surface at x = 2 the reflection (at x = 5) of a wall at x = -1 behind the sensor,
// which a box 5 cm behind the sensor hides from it except through a small opening at its corner:
// the surface's phantoms land where the sensor saw the box in front, occluded, but their light's
// path from the surface to the wall passes beside the box. With `seen_through`, a wall 1.5 m
// behind the surface is seen through it where y < -0.6 instead of the reflection.
core::Sweep phantomsHiddenByABox(bool seen_through)
{
  const auto box = [](const Eigen::Vector3f& x) {
    const bool opening = x.y() > 0.04f && x.z() > 0.04f;
    return std::fabs(x.y()) <= 0.05f && std::fabs(x.z()) <= 0.05f && !opening;
  };
  std::vector<test::Wall> walls{ { 0, -0.05f, box }, { 0, -1.0f, test::everywhere } };
  if (seen_through)
    walls.push_back({ 0, 3.5f, [](const Eigen::Vector3f& x) { return x.y() < -0.6f; } });
  walls.push_back({ 0, 5.0f, test::everywhere });
  return test::rangeImage(walls);
}

TEST(ObjectType, AMirrorWhosePhantomsABoxHidesFromTheSensorIsNoGlass)
{
  // A few phantoms land where the sensor saw the wall, none is seen through: the occluded ones
  // are no real points, and too few are decided to type it.
  core::ReflectiveObject object = objectAtTwoMetres();
  EXPECT_EQ(typeIn(phantomsHiddenByABox(false), object), ObjectType::unknown);
  EXPECT_GT(object.evidence.undecided_points, 300u);
  EXPECT_GT(object.evidence.phantom_points, object.evidence.transmitted_points);
  // With a wall seen through it, it is glass.
  object = objectAtTwoMetres();
  EXPECT_EQ(typeIn(phantomsHiddenByABox(true), object), ObjectType::glass);
  EXPECT_GT(object.evidence.transmitted_points, 100u);
}

// A corridor along x (floor and ceiling at z = -+0.8, side walls at y = -+1.2, no ends): every
// surface in it is perpendicular to a surface across it at x = 2, which maps it onto itself.
std::vector<test::Wall> corridor()
{
  return { { 2, -0.8f, test::everywhere }, { 2, 0.8f, test::everywhere }, { 1, -1.2f, test::everywhere },
           { 1, 1.2f, test::everywhere } };
}

TEST(ObjectType, GlassAcrossACorridorIsGlassThoughItsFloorLandsOnItself)
{
  // A wall 3 m beyond the pane, seen through it: its reflection would lie at x = -1, where the
  // sensor sees down the corridor further. The floor and walls behind the pane land on
  // themselves (ambiguous) and must not outweigh it.
  std::vector<test::Wall> walls = corridor();
  walls.push_back({ 0, 5.0f, test::everywhere });
  const core::Sweep sweep = test::rangeImage(walls);
  core::ReflectiveObject object = objectAtTwoMetres();
  EXPECT_EQ(typeIn(sweep, object), ObjectType::glass);
  EXPECT_GT(object.evidence.ambiguous_points, 50u);
  EXPECT_GT(object.evidence.transmitted_points, 100u);
}


TEST(ObjectType, AnUnknownObjectCountsTheOccludedPointsWhosePhantomLightAWallWouldHaveStopped)
{
  // A 4 cm sliver of a window at x = 2 in a room whose back wall (x = -0.5) the sensor sees; outside,
  // a wall at x = 8. Reflected across the window, the outside lands behind the back wall (occluded),
  // and a phantom's light would have had to cross that wall. Through the sliver's inside hardly a
  // beam passes: the type stays unknown, and the points count as path-blocked, as the cone
  // labelling will keep them (real, seen through).
  const core::Sweep sweep = test::rangeImage({ { 0, -0.5f, test::everywhere }, { 0, 8.0f, test::everywhere } });
  core::ReflectiveObject sliver = test::wallObject(2.0f, 0.04f, 1.0f);
  EXPECT_EQ(typeIn(sweep, sliver), ObjectType::unknown);
  EXPECT_EQ(sliver.evidence.transmitted_points, 0u);
  EXPECT_GT(sliver.evidence.undecided_points, 30u);
  // Most of them: the rest land beyond the sweep's +-60 deg of elevation, where nothing was seen.
  EXPECT_GT(2 * sliver.evidence.path_blocked_points, sliver.evidence.undecided_points);
  EXPECT_LE(sliver.evidence.path_blocked_points, sliver.evidence.undecided_points);

  // Without the back wall nothing is seen where they land: no path is blocked.
  const core::Sweep open = test::rangeImage({ { 0, 8.0f, test::everywhere } });
  core::ReflectiveObject open_sliver = test::wallObject(2.0f, 0.04f, 1.0f);
  EXPECT_EQ(typeIn(open, open_sliver), ObjectType::unknown);
  EXPECT_EQ(open_sliver.evidence.path_blocked_points, 0u);

  // An object the geometry typed (the whole window: its inside decides) is not looked at again.
  core::ReflectiveObject window = test::wallObject(2.0f, 1.0f, 1.0f);
  EXPECT_NE(typeIn(sweep, window), ObjectType::unknown);
  EXPECT_EQ(window.evidence.path_blocked_points, 0u);
}

// A room seen by a lidar at the origin with 1 cm of range noise, 1 degree steps: a floor at
// z = -0.8 that runs on through the plane x = 2, the room's back wall at x = -0.5, and a wall at
// x = far_wall beyond the plane. With far_wall = 4.5 the part beyond x = 2 is the room's mirror
// image (a mirror at x = 2); further out, it is what a window at x = 2 shows.
core::Sweep noisyRoomAndBeyond(float far_wall)
{
  std::mt19937 noise_source{ 11 };
  std::normal_distribution<float> noise(0.0f, 0.01f);
  const std::vector<test::Wall> walls{ { 2, -0.8f, test::everywhere },
                                       { 0, -0.5f, test::everywhere },
                                       { 0, far_wall, test::everywhere } };
  return test::gridSweep(121, 360, -60.0f, 1.0f, 0.0f, 0.0f, 1.0f, [&](const Eigen::Vector3f& direction) {
    float nearest = test::kInf;
    for (const test::Wall& wall : walls)
    {
      const float t = wall.at / direction[wall.axis];
      if (t > 0.0f && t < nearest)
        nearest = t;
    }
    const float range = nearest + noise(noise_source);
    // No intensities: only the geometry decides.
    return std::make_pair(std::isfinite(nearest) ? Eigen::Vector3f(range * direction) : Eigen::Vector3f::Constant(test::kNaN),
                          test::kNaN);
  });
}

TEST(ObjectType, AWindowWhoseOutsideFloorLandsOnTheRoomsFloorIsGlass)
{
  // Through a window at x = 2 the ground outside (the floor's plane) lands, reflected, on the
  // room's floor, which the noisy returns around where it lands make out only roughly: as a
  // mirror's phantoms of the floor would. Beyond x = 4.5 the ground and the wall at x = 8 land
  // behind the room's back wall, where a phantom's light could not have come from. The window
  // reaches down to the floor (-0.8 <= z <= 0.2).
  core::ReflectiveObject window = objectAtTwoMetres();
  window.centre.z() = -0.3f;
  EXPECT_EQ(typeIn(noisyRoomAndBeyond(8.0f), window), ObjectType::glass);
  EXPECT_EQ(window.evidence.geometric_type, ObjectType::glass);
  EXPECT_TRUE(window.evidence.typed_by_blocked_paths);
  EXPECT_GT(window.evidence.path_blocked_points, window.evidence.phantom_points);

  // A mirror at x = 2 in the same room: its phantoms of the back wall land on it, and no point
  // is path-blocked.
  core::ReflectiveObject mirror = objectAtTwoMetres();
  mirror.centre.z() = -0.3f;
  EXPECT_EQ(typeIn(noisyRoomAndBeyond(4.5f), mirror), ObjectType::mirror);
  EXPECT_FALSE(mirror.evidence.typed_by_blocked_paths);
  EXPECT_GT(mirror.evidence.phantom_points, 100u);
}

TEST(ObjectType, PointsSeenThroughWhereAnotherObjectMayHaveReflectedThemDoNotMakeGlass)
{
  // Behind the surface at x = 2, a wall at x = 5.5. Reflected across the surface it lies at
  // x = -1.5, where the sensor sees further, to x = -6: seen through, alone.
  const core::Sweep sweep = test::rangeImage({ { 0, 5.5f, test::everywhere }, { 0, -6.0f, test::everywhere } });
  core::ReflectiveObject alone = objectAtTwoMetres();
  EXPECT_EQ(typeIn(sweep, alone), ObjectType::glass);
  EXPECT_GT(alone.evidence.transmitted_points, 100u);

  // With a mirror at x = -1 facing it, the reflections lie behind that mirror as the sensor's
  // image in the surface sees it: what the sensor saw beyond may be that mirror's phantoms, and
  // the points behind the surface its phantoms reflected again. They prove nothing.
  core::ReflectiveObject facing = test::wallObject(1.0f, 3.0f, 3.0f, ObjectType::unknown, 1);
  facing.plane = Eigen::Vector4f(1.0f, 0.0f, 0.0f, 1.0f);
  facing.centre = Eigen::Vector3f(-1.0f, 0.0f, 0.0f);
  std::vector<core::ReflectiveObject> objects{ objectAtTwoMetres(), facing };
  typesIn(sweep, objects);
  EXPECT_EQ(objects[0].type, ObjectType::unknown);
  EXPECT_EQ(objects[0].evidence.transmitted_points, 0u);
}

}  // namespace
}  // namespace ohm_mirror_detector3d
