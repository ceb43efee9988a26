#include <gtest/gtest.h>

#include <cmath>
#include <limits>
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
using test::rangeImage;
using test::Wall;

constexpr float kDegree = static_cast<float>(M_PI) / 180.0f;

core::ReflectionEvidence evidenceOf(const core::Sweep& sweep)
{
  core::SweepLabels labels;
  labels.reset(sweep.beamCount());
  core::ReflectionEvidence evidence;
  evidence.build(sweep, labels, Eigen::Vector3f::Zero());
  return evidence;
}

// A surface in the plane x = 2, facing the sensor at the origin.
const Eigen::Vector4f kPlane(-1.0f, 0.0f, 0.0f, 2.0f);
const core::LandingTolerance kTolerance;

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

TEST(ReflectionEvidence, APointWhereTheSensorSawNearerCannotBeTold)
{
  // A wall at x = -0.5 hides where the point lands.
  const core::ReflectionEvidence evidence = evidenceOf(rangeImage({ { 0, -0.5f, everywhere } }));
  EXPECT_EQ(evidence.test(kPlane, kBehind, kTolerance).outcome, ReflectionOutcome::occluded);
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

// A near sensor's sweep of one wall (axis, at), at the origin: 0.25 degree steps in azimuth
// (-60 to 60 degrees) and 0.5 degree steps in elevation (-60 to 30), each return 1 cm of range
// noise off the wall. At 1-2 m its returns are 4-9 mm apart: the noise turns a plane through a
// few neighbouring returns every way.
core::Sweep noisyNearSweep(int axis, float at)
{
  const std::size_t rows = 181, cols = 481;
  core::Sweep sweep;
  sweep.resize(rows, cols);
  std::mt19937 random(14);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c)
    {
      const float elevation = (0.5f * static_cast<float>(r) - 60.0f) * kDegree;
      const float azimuth = (0.25f * static_cast<float>(c) - 60.0f) * kDegree;
      const Eigen::Vector3f direction(std::cos(elevation) * std::cos(azimuth),
                                      std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
      const float t = at / direction[axis];
      const Eigen::Vector3f point = t > 0.0f && t < 20.0f ?
                                        Eigen::Vector3f((t + noise(random)) * direction) :
                                        Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
      sweep.echoes[0].points[r * cols + c] = point;
      sweep.echoes[1].points[r * cols + c] = point;
    }
  sweep.computeRanges(Eigen::Vector3f::Zero());
  return sweep;
}

// The share of `points` whose test says `outcome`.
float shareOf(const core::ReflectionEvidence& evidence, const Eigen::Vector4f& plane,
              const std::vector<Eigen::Vector3f>& points, ReflectionOutcome outcome)
{
  std::size_t hits = 0;
  for (const Eigen::Vector3f& p : points)
    hits += evidence.test(plane, p, kTolerance).outcome == outcome ? 1 : 0;
  return static_cast<float>(hits) / static_cast<float>(points.size());
}

TEST(ReflectionEvidence, ANoisyFloorThroughThePlaneIsAmbiguousAndANoisyWallFacingItIsNot)
{
  // The pane x = 2 and the floor z = -0.5 through it, seen by a near sensor: the floor behind
  // the pane (x 2.4 to 3.4) reflects onto the floor in front (x 1.6 to 0.6, 0.8-1.7 m away).
  // Its normal, from a patch of returns some 15 cm apart, is the floor's: ambiguous.
  std::vector<Eigen::Vector3f> floor_behind, wall_behind;
  for (int k = 0; k < 200; ++k)
  {
    const float across = -0.1f + 0.0015f * static_cast<float>(k);
    floor_behind.emplace_back(2.4f + 0.005f * static_cast<float>(k), across, -0.5f);
    wall_behind.emplace_back(3.0f, across, -0.3f + 0.003f * static_cast<float>(k));
  }
  const core::ReflectionEvidence floor_evidence = evidenceOf(noisyNearSweep(2, -0.5f));
  EXPECT_GE(shareOf(floor_evidence, kPlane, floor_behind, ReflectionOutcome::ambiguous), 0.95f);

  // A wall facing the pane (x = 1): points 1 m behind it land there as a mirror's phantoms do,
  // and the same noise must not make them ambiguous.
  const core::ReflectionEvidence wall_evidence = evidenceOf(noisyNearSweep(0, 1.0f));
  EXPECT_GE(shareOf(wall_evidence, kPlane, wall_behind, ReflectionOutcome::phantom), 0.95f);
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
