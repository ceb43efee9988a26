#include <gtest/gtest.h>

#include "ohm_mirror_detector3d/core/cleaned_output.h"
#include "ohm_mirror_detector3d/core/reflection_chains.h"
#include "object_fixtures.h"
#include "sweep_fixtures.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::Label;
using core::ObjectType;

// Two mirrors facing each other across the sensor (origin) in a room 4 m x 4 m x 3 m, on the walls
// x = 2 (mirror A) and x = -2 (mirror B), each 4 m wide and 1 m high.
// A beam at slope 1/4 in the x-y plane meets A at (2, 0.5, 0), B at (-2, 1.5, 0) and the wall
// y = 2 at (0, 2, 0) after a path of 8 / cos: the sensor puts it at (8, 2, 0), behind A; reflected
// across A it lies at (-4, 2, 0), still behind B.
const Eigen::Vector3f kTwiceReflected(8.0f, 2.0f, 0.0f);
const Eigen::Vector3f kWhereItIs(0.0f, 2.0f, 0.0f);

std::vector<core::ReflectiveObject> facingMirrors()
{
  core::ReflectiveObject a = test::wallObject(2.0f, 4.0f, 1.0f, ObjectType::mirror, 0);
  core::ReflectiveObject b = test::wallObject(2.0f, 4.0f, 1.0f, ObjectType::mirror, 1);
  b.plane = Eigen::Vector4f(1.0f, 0.0f, 0.0f, 2.0f);
  b.centre = Eigen::Vector3f(-2.0f, 0.0f, 0.0f);
  return { a, b };
}

bool awayFromTheDoor(const Eigen::Vector3f& x)
{
  return std::fabs(x.x()) > 0.5f;
}

// The room's walls as the sensor sees them (the mirrors' walls too); with a door in the wall
// y = 2 around x = 0, the sensor sees through it to a wall at y = 5.
core::Sweep room(bool door)
{
  std::vector<test::Wall> walls{ { 0, 2.0f, test::everywhere },  { 0, -2.0f, test::everywhere },
                                 { 1, -2.0f, test::everywhere }, { 2, 1.5f, test::everywhere },
                                 { 2, -1.5f, test::everywhere } };
  walls.push_back(door ? test::Wall{ 1, 2.0f, awayFromTheDoor } : test::Wall{ 1, 2.0f, test::everywhere });
  if (door)
    walls.push_back({ 1, 5.0f, test::everywhere });
  return test::rangeImage(walls);
}

struct Chained
{
  core::SweepLabels labels;
  core::ReflectionPaths paths;
  core::ReflectionChainCounts counts;
  std::vector<core::OutputPoint> cleaned;
};

// The cone labelling's outcome for `phantom` (echo 2 of beam 0): behindReflective, behind mirror
// A; every other point valid. Then the chain stage and the cleaned output.
Chained chain(const Eigen::Vector3f& phantom, int max_reflections, bool door = false)
{
  core::Sweep sweep = room(door);
  sweep.echoes[1].points[0] = phantom;
  sweep.computeRanges(Eigen::Vector3f::Zero());
  const std::vector<core::ReflectiveObject> objects = facingMirrors();
  Chained out;
  out.labels.reset(sweep.beamCount(), Label::valid);
  out.labels.echoes[1][0] = Label::behindReflective;
  core::ObjectAssignment assignment;
  assignment.reset(sweep.beamCount());
  assignment.echoes[1][0] = 0;
  core::ReflectionEvidence evidence;
  evidence.build(sweep, out.labels, Eigen::Vector3f::Zero());
  core::ReflectionChainConfig config;
  config.max_reflections = max_reflections;
  out.counts = core::ReflectionChains(config).apply(sweep, Eigen::Vector3f::Zero(), evidence, objects, assignment,
                                                    out.labels, out.paths);
  core::collectCleaned(sweep, out.labels, objects, out.paths, out.cleaned);
  return out;
}

const core::OutputPoint* cleanedPhantom(const Chained& out)
{
  for (const core::OutputPoint& point : out.cleaned)
    if (point.beam == 0 && point.echo == 2)
      return &point;
  return nullptr;
}

TEST(ReflectionChains, ATwiceReflectedPhantomIsBackProjectedThroughBothMirrors)
{
  const Chained out = chain(kTwiceReflected, 3);
  EXPECT_EQ(out.labels.echoes[1][0], Label::behindReflective);
  EXPECT_EQ(out.paths.mirrors(out.paths.path(1, 0)), (std::vector<std::int32_t>{ 0, 1 }));
  EXPECT_EQ(out.counts.multiply_reflected, 1u);
  EXPECT_EQ(out.counts.unexplained, 0u);
  const core::OutputPoint* cleaned = cleanedPhantom(out);
  ASSERT_NE(cleaned, nullptr);
  EXPECT_LT((cleaned->position - kWhereItIs).norm(), 1e-4f);
  EXPECT_EQ(cleaned->label, Label::behindReflective);
}

TEST(ReflectionChains, APhantomWhoseReflectionMissesTheOtherMirrorKeepsOneMirror)
{
  // Reflected across A it lands at (1, 0.5, 0), in front of B: a phantom of one reflection.
  const Chained out = chain(Eigen::Vector3f(3.0f, 0.5f, 0.0f), 3);
  EXPECT_EQ(out.paths.mirrors(out.paths.path(1, 0)), (std::vector<std::int32_t>{ 0 }));
  EXPECT_EQ(out.counts.multiply_reflected, 0u);
  const core::OutputPoint* cleaned = cleanedPhantom(out);
  ASSERT_NE(cleaned, nullptr);
  EXPECT_LT((cleaned->position - Eigen::Vector3f(1.0f, 0.5f, 0.0f)).norm(), 1e-4f);
}

TEST(ReflectionChains, APhantomNoChainExplainsIsDroppedAsError)
{
  // Where the chain ends the sensor saw through a door to the wall 3 m further: nothing is there.
  const Chained out = chain(kTwiceReflected, 3, true);
  EXPECT_EQ(out.labels.echoes[1][0], Label::error);
  EXPECT_EQ(out.counts.unexplained, 1u);
  EXPECT_EQ(cleanedPhantom(out), nullptr);
}

TEST(ReflectionChains, APathCrossingMoreMirrorsThanTheLimitIsDroppedAsError)
{
  const Chained limited = chain(kTwiceReflected, 1);
  EXPECT_EQ(limited.labels.echoes[1][0], Label::error);
  EXPECT_EQ(limited.counts.unexplained, 1u);
  EXPECT_EQ(cleanedPhantom(limited), nullptr);
  const Chained enough = chain(kTwiceReflected, 2);
  EXPECT_EQ(enough.labels.echoes[1][0], Label::behindReflective);
  ASSERT_NE(cleanedPhantom(enough), nullptr);
  EXPECT_LT((cleanedPhantom(enough)->position - kWhereItIs).norm(), 1e-4f);
}

TEST(ReflectionChains, WithoutFollowingChainsAPhantomIsReflectedAcrossItsFirstMirrorOnly)
{
  const Chained out = chain(kTwiceReflected, 0);
  EXPECT_EQ(out.labels.echoes[1][0], Label::behindReflective);
  const core::OutputPoint* cleaned = cleanedPhantom(out);
  ASSERT_NE(cleaned, nullptr);
  EXPECT_LT((cleaned->position - Eigen::Vector3f(-4.0f, 2.0f, 0.0f)).norm(), 1e-4f);
}

TEST(ReflectionChains, AThriceReflectedPhantomCrossesTheFirstMirrorAgain)
{
  // Slope 1/6: A at (2, 1/3), B at (-2, 1), A again at (2, 5/3), then the wall y = 2 at (0, 2, 0)
  // after a path of 12 / cos: found at (12, 2, 0), reflected across A, B and A.
  const Eigen::Vector3f thrice(12.0f, 2.0f, 0.0f);
  const Chained out = chain(thrice, 3);
  EXPECT_EQ(out.paths.mirrors(out.paths.path(1, 0)), (std::vector<std::int32_t>{ 0, 1, 0 }));
  const core::OutputPoint* cleaned = cleanedPhantom(out);
  ASSERT_NE(cleaned, nullptr);
  EXPECT_LT((cleaned->position - kWhereItIs).norm(), 1e-4f);
  EXPECT_EQ(chain(thrice, 2).labels.echoes[1][0], Label::error);
}

}  // namespace
}  // namespace ohm_mirror_detector3d
