#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "ohm_mirror_detector3d/core/reflection_evidence.h"
#include "sweep_fixtures.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::ReflectionOutcome;

using test::everywhere;
using test::evidenceOf;
using test::rangeImage;
using test::Wall;

constexpr float kDegree = static_cast<float>(M_PI) / 180.0f;

// A surface in the plane x = 2, facing the sensor at the origin.
const Eigen::Vector4f kPlane(-1.0f, 0.0f, 0.0f, 2.0f);
const core::LandingTolerance kTolerance;

core::ReflectionTestOptions withPathCheck()
{
  core::ReflectionTestOptions options;
  options.check_path = true;
  return options;
}
core::ReflectionTestOptions withWideNormal()
{
  core::ReflectionTestOptions options;
  options.wide_normal = true;
  return options;
}
const core::ReflectionTestOptions kPathCheck = withPathCheck();
const core::ReflectionTestOptions kWideNormal = withWideNormal();

// A point 3 m behind the surface, 0.3 m above the sensor: reflected, it lands at x = -1.
const Eigen::Vector3f kBehind(5.0f, 0.4f, 0.3f);

TEST(ReflectionEvidence, TheAngularStepIsTheSweepsOwn)
{
  const core::ReflectionEvidence evidence = evidenceOf(rangeImage({ { 0, -1.0f, everywhere }, { 0, 4.0f, everywhere } }));
  EXPECT_NEAR(evidence.angularStep(), 1.0f * kDegree, 0.05f * kDegree);
}

TEST(ReflectionEvidence, APointThatLandsOnWhatTheSensorSawInFrontIsAPhantom)
{
  // The sensor saw a wall at x = -1: exactly where the point lands.
  const core::ReflectionEvidence evidence = evidenceOf(rangeImage({ { 0, -1.0f, everywhere } }));
  const core::ReflectionTest test = evidence.test(kPlane, kBehind, kTolerance);
  EXPECT_EQ(test.outcome, ReflectionOutcome::phantom) << core::reflectionOutcomeName(test.outcome);
  EXPECT_LT(std::fabs(test.range_difference), 0.02f);
}

TEST(ReflectionEvidence, APointWhereTheSensorSawFurtherIsSeenThrough)
{
  // The sensor saw through where the point would land, to a wall at x = -3: the point is real.
  const core::ReflectionEvidence evidence = evidenceOf(rangeImage({ { 0, -3.0f, everywhere } }));
  const core::ReflectionTest test = evidence.test(kPlane, kBehind, kTolerance);
  EXPECT_EQ(test.outcome, ReflectionOutcome::transmitted) << core::reflectionOutcomeName(test.outcome);
  EXPECT_GT(test.range_difference, 1.5f);
}

// A post at x = `post_x` (where `post` says: |z| <= 0.5 and a band of y) before a wall at x = -3.
core::Sweep postBeforeAFarWall(float post_x, bool (*post)(const Eigen::Vector3f&))
{
  return rangeImage({ { 0, -3.0f, everywhere }, { 0, post_x, post } });
}

TEST(ReflectionEvidence, APointLandsClearOnlyWithNothingSeenAtItsRangeInTheWindowAroundIt)
{
  // Reflected, the point lands at (-1, 0.4, 0.3), where the sensor saw the wall at x = -3.
  EXPECT_TRUE(evidenceOf(rangeImage({ { 0, -3.0f, everywhere } })).landsClear(kPlane, kBehind, 0.1f));
  // A post 1.5 cm beside where it lands, at its range (within the test's window of 1.25 degrees):
  // where the point lands is no proof of free space.
  EXPECT_FALSE(evidenceOf(postBeforeAFarWall(-1.0f, [](const Eigen::Vector3f& x) {
                 return x.y() > 0.415f && x.y() < 0.44f && std::fabs(x.z()) < 0.5f;
               })).landsClear(kPlane, kBehind, 0.1f));
  // The same post 5 degrees away, or 0.3 m further than where the point lands: clear.
  EXPECT_TRUE(evidenceOf(postBeforeAFarWall(-1.0f, [](const Eigen::Vector3f& x) {
                return x.y() > 0.5f && x.y() < 0.55f && std::fabs(x.z()) < 0.5f;
              })).landsClear(kPlane, kBehind, 0.1f));
  EXPECT_TRUE(evidenceOf(postBeforeAFarWall(-1.3f, [](const Eigen::Vector3f& x) {
                return x.y() > 0.54f && x.y() < 0.57f && std::fabs(x.z()) < 0.7f;
              })).landsClear(kPlane, kBehind, 0.1f));
  // No index, no proof.
  EXPECT_FALSE(evidenceOf(rangeImage(std::vector<Wall>())).landsClear(kPlane, kBehind, 0.1f));
}

TEST(ReflectionEvidence, APointHiddenFromTheSensorButNotFromThePlaneCannotBeTold)
{
  // A box face at x = -0.5 (0.2 x 0.2 m) hides where the point lands on the wall at x = -1, but
  // not the path from where the beam met the plane to there: the point may be a phantom of the
  // wall behind the box.
  const core::ReflectionEvidence evidence = evidenceOf(rangeImage(
      { { 0, -1.0f, everywhere },
        { 0, -0.5f, [](const Eigen::Vector3f& x) {
           return x.y() > 0.1f && x.y() < 0.3f && x.z() > 0.05f && x.z() < 0.25f;
         } } }));
  const core::ReflectionTest test = evidence.test(kPlane, kBehind, kTolerance, kPathCheck);
  EXPECT_EQ(test.outcome, ReflectionOutcome::occluded) << core::reflectionOutcomeName(test.outcome);
  EXPECT_FALSE(test.path_blocked);
}

TEST(ReflectionEvidence, APointWhosePathFromThePlanePiercesASeenWallIsSeenThrough)
{
  // A wall at x = -0.5 hides where the point lands, and the light of a phantom would have had to
  // cross it on its way from the plane: the point is real, seen through the plane (what lies
  // behind a pane in a wall, reflected, lies beyond the room's walls).
  const core::ReflectionEvidence evidence = evidenceOf(rangeImage({ { 0, -0.5f, everywhere } }));
  const core::ReflectionTest test = evidence.test(kPlane, kBehind, kTolerance, kPathCheck);
  EXPECT_EQ(test.outcome, ReflectionOutcome::transmitted) << core::reflectionOutcomeName(test.outcome);
  EXPECT_TRUE(test.path_blocked);
  EXPECT_LT(test.range_difference, -0.3f);
  // Without the check it cannot be told.
  const core::ReflectionTest unchecked = evidence.test(kPlane, kBehind, kTolerance);
  EXPECT_EQ(unchecked.outcome, ReflectionOutcome::occluded) << core::reflectionOutcomeName(unchecked.outcome);
  EXPECT_FALSE(unchecked.path_blocked);
}

TEST(ReflectionEvidence, APointWhereTheSensorSawNothingCannotBeTold)
{
  // The wall at x = -1 is seen only on the other side (y < -1).
  const core::ReflectionEvidence evidence =
      evidenceOf(rangeImage({ { 0, -1.0f, [](const Eigen::Vector3f& x) { return x.y() < -1.0f; } } }));
  const core::ReflectionTest test = evidence.test(kPlane, kBehind, kTolerance);
  EXPECT_EQ(test.outcome, ReflectionOutcome::noReturn);
  EXPECT_TRUE(std::isnan(test.range_difference));
}

TEST(ReflectionEvidence, APointOnAFloorThroughThePlaneIsAmbiguous)
{
  // The floor z = -1 continues through the plane: a real floor point behind glass lands on the
  // floor in front as a mirror's phantom of the floor would.
  const core::ReflectionEvidence evidence = evidenceOf(rangeImage({ { 2, -1.0f, everywhere } }));
  const core::ReflectionTest test = evidence.test(kPlane, Eigen::Vector3f(3.0f, 0.4f, -1.0f), kTolerance);
  EXPECT_EQ(test.outcome, ReflectionOutcome::ambiguous) << core::reflectionOutcomeName(test.outcome);
}

// A 128-ring lidar's sampling near the sensor (0.35 deg rings, 0.18 deg columns over +-60 deg of
// azimuth, -40 .. 0 deg of elevation) of a floor at z = -1 and a wall at x = `wall_x` beyond it,
// with 1 cm Gaussian range noise.
core::Sweep noisyFloorAndWall(float wall_x)
{
  std::mt19937 generator(3);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  return test::gridSweep(115, 667, -40.0f, 0.35f, 180.0f, -60.0f, 0.18f, [&](const Eigen::Vector3f& direction) {
    float range = direction.z() < 0.0f ? -1.0f / direction.z() : std::numeric_limits<float>::infinity();
    range = std::min(range, wall_x / direction.x());
    return std::make_pair(Eigen::Vector3f((range + noise(generator)) * direction), std::numeric_limits<float>::quiet_NaN());
  });
}

TEST(ReflectionEvidence, TheWideNormalTellsANoisyFloorThroughThePlaneFromAWallFacingIt)
{
  // Glass in the plane x = 2 behind the sensor's back (it looks towards -x: the floor, and a
  // wall at x = -3). Real floor points behind the glass (x = 5.1 .. 6.5) land on the floor in
  // view (x = -1.1 .. -2.5, clear of the wall's corner): ambiguous, though the test window's
  // few returns, a ring (1-3 cm) apart with 1 cm noise, give no trustworthy normal. Points half a metre above the floor at
  // x = 7 land on the wall, which faces the plane: phantoms.
  const core::ReflectionEvidence evidence = evidenceOf(noisyFloorAndWall(-3.0f));
  int floor_ambiguous = 0, floor_landed = 0, wall_phantom = 0, wall_landed = 0;
  for (float x = 5.1f; x <= 6.5f; x += 0.1f)
    for (float y = -1.0f; y <= 1.0f; y += 0.1f)
    {
      const core::ReflectionTest floor = evidence.test(kPlane, Eigen::Vector3f(x, y, -1.0f), kTolerance, kWideNormal);
      floor_landed += floor.outcome == ReflectionOutcome::phantom || floor.outcome == ReflectionOutcome::ambiguous;
      floor_ambiguous += floor.outcome == ReflectionOutcome::ambiguous;
      // Reflected to x = -3 (on the wall), 0.5 m above the floor.
      const core::ReflectionTest wall = evidence.test(kPlane, Eigen::Vector3f(7.0f, 0.5f * y, -0.5f), kTolerance, kWideNormal);
      wall_landed += wall.outcome == ReflectionOutcome::phantom || wall.outcome == ReflectionOutcome::ambiguous;
      wall_phantom += wall.outcome == ReflectionOutcome::phantom;
    }
  // (The window's normal alone: 214 of the 291 floor points ambiguous.)
  ASSERT_GT(floor_landed, 250);
  EXPECT_GE(floor_ambiguous, floor_landed * 98 / 100);
  ASSERT_GT(wall_landed, 250);
  EXPECT_GE(wall_phantom, wall_landed * 98 / 100);
}

// A wall 4 m away all around, with `count` double echoes (mixed pixels) whose second echo lies
// `separation` + k cm beyond the first (k = 0, 1, ...).
core::Sweep wallWithDoubleEchoes(std::size_t count, float separation)
{
  core::Sweep sweep = rangeImage({ { 0, 4.0f, everywhere }, { 0, -4.0f, everywhere }, { 1, 4.0f, everywhere },
                                   { 1, -4.0f, everywhere } });
  for (std::size_t k = 0; k < count; ++k)
  {
    const std::size_t beam = 60 * 360 + 3 * k;  // along the horizon, every third degree
    const Eigen::Vector3f& first = sweep.echoes[0].points[beam];
    sweep.echoes[1].points[beam] = first + (separation + 0.01f * static_cast<float>(k)) * first.normalized();
  }
  sweep.computeRanges(Eigen::Vector3f::Zero());
  return sweep;
}

TEST(ReflectionEvidence, TheEchoSeparationIsTheSmallestTheSensorResolved)
{
  // 110 double echoes 0.9 to 1.99 m apart: the third smallest distance (0.92 m).
  EXPECT_NEAR(evidenceOf(wallWithDoubleEchoes(110, 0.9f)).echoSeparation(), 0.92f, 1e-3f);
  // One odd pair closer together does not decide it.
  core::Sweep odd = wallWithDoubleEchoes(110, 0.9f);
  const std::size_t beam = 60 * 360 + 1;
  odd.echoes[1].points[beam] = odd.echoes[0].points[beam] * 1.02f;
  odd.computeRanges(Eigen::Vector3f::Zero());
  EXPECT_NEAR(evidenceOf(odd).echoSeparation(), 0.91f, 1e-3f);
  // Too few double echoes to tell: none.
  EXPECT_EQ(evidenceOf(wallWithDoubleEchoes(90, 0.9f)).echoSeparation(), 0.0f);
}

TEST(ReflectionEvidence, ASweepWithoutReturnsHasNoEvidence)
{
  const core::ReflectionEvidence evidence = evidenceOf(rangeImage({}));
  EXPECT_EQ(evidence.angularStep(), 0.0f);
  EXPECT_EQ(evidence.test(kPlane, kBehind, kTolerance).outcome, ReflectionOutcome::noReturn);
}

TEST(ReflectionEvidence, NanPointsAreNoEvidence)
{
  // The wall at x = -1 was seen, but every return was gated (nanPoint): nothing to compare with.
  const core::Sweep sweep = rangeImage({ { 0, -1.0f, everywhere } });
  core::SweepLabels labels;
  labels.reset(sweep.beamCount(), core::Label::nanPoint);
  core::ReflectionEvidence evidence;
  evidence.build(sweep, labels, Eigen::Vector3f::Zero());
  EXPECT_EQ(evidence.test(kPlane, kBehind, kTolerance).outcome, ReflectionOutcome::noReturn);
}

TEST(ReflectionEvidence, TheSensorOriginIsTheApex)
{
  // The same scene seen from (0, 0, 1): the sweep's points moved with it, the test as before.
  core::Sweep sweep = rangeImage({ { 0, -1.0f, everywhere } });
  const Eigen::Vector3f origin(0.0f, 0.0f, 1.0f);
  for (auto& echo : sweep.echoes)
    for (Eigen::Vector3f& p : echo.points)
      p += origin;
  core::SweepLabels labels;
  labels.reset(sweep.beamCount());
  core::ReflectionEvidence evidence;
  evidence.build(sweep, labels, origin);
  EXPECT_EQ(evidence.test(kPlane, kBehind + origin, kTolerance).outcome, ReflectionOutcome::phantom);
  // A point whose reflection misses the wall by half a metre is no phantom.
  EXPECT_EQ(evidence.test(Eigen::Vector4f(-1.0f, 0.0f, 0.0f, 2.25f), kBehind + origin, kTolerance).outcome,
            ReflectionOutcome::transmitted);
}

}  // namespace
}  // namespace ohm_mirror_detector3d
