#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <random>

#include "ohm_mirror_detector3d/core/cleaned_output.h"
#include "ohm_mirror_detector3d/core/cone_labelling.h"
#include "ohm_mirror_detector3d/core/merged_echoes.h"
#include "ohm_mirror_detector3d/core/phantom_planes.h"
#include "ohm_mirror_detector3d/core/reflection_chains.h"
#include "ohm_mirror_detector3d/core/stage_configs.h"
#include "ohm_mirror_detector3d/core/vision_cone.h"
#include "object_fixtures.h"
#include "sweep_fixtures.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::ConeRelation;
using core::Label;
using core::ObjectType;
using test::wallObject;

ConeRelation relationOf(const Eigen::Vector3f& p, float margin = 0.05f)
{
  return core::locateInCone(wallObject(2.0f, 0.6f, 0.4f), Eigen::Vector3f::Zero(), p, 0.05f, margin).relation;
}

TEST(VisionCone, LocatesPointsOnBehindInFrontAndOutside)
{
  EXPECT_EQ(relationOf({ 2.0f, 0.1f, 0.1f }), ConeRelation::onSurface);
  EXPECT_EQ(relationOf({ 2.04f, 0.0f, 0.0f }), ConeRelation::onSurface);
  EXPECT_EQ(relationOf({ 1.96f, 0.0f, 0.0f }), ConeRelation::onSurface);
  EXPECT_EQ(relationOf({ 3.0f, 0.1f, 0.05f }), ConeRelation::behind);
  EXPECT_EQ(relationOf({ 1.0f, 0.0f, 0.0f }), ConeRelation::inFront);
  // The ray to (3, 0.6, 0) crosses the plane at y = 0.4 > 0.3 + 0.05.
  EXPECT_EQ(relationOf({ 3.0f, 0.6f, 0.0f }), ConeRelation::outside);
}

TEST(VisionCone, TheMarginGrowsTheRectangle)
{
  // Crosses the plane at y = 0.34: outside the 0.6 m wide rectangle, inside it grown by 5 cm.
  const Eigen::Vector3f p(4.0f, 0.68f, 0.0f);
  EXPECT_EQ(relationOf(p, 0.05f), ConeRelation::behind);
  EXPECT_EQ(relationOf(p, 0.0f), ConeRelation::outside);
}

TEST(VisionCone, HalfTheBeamFootprintGrowsTheRectangleBeforeTheMargin)
{
  // Beams whose centre passes up to half a footprint beside the edge still return from the
  // object: with a 2 cm footprint, the ray crossing the plane at y = 0.305 is in the cone
  // without any margin, the one at y = 0.315 only with a margin.
  core::ReflectiveObject object = wallObject(2.0f, 0.6f, 0.4f);
  object.footprint = 0.02f;
  auto relation = [&](float y, float margin) {
    return core::locateInCone(object, Eigen::Vector3f::Zero(), Eigen::Vector3f(4.0f, 2.0f * y, 0.0f), 0.05f, margin)
        .relation;
  };
  EXPECT_EQ(relation(0.305f, 0.0f), ConeRelation::behind);
  EXPECT_EQ(relation(0.315f, 0.0f), ConeRelation::outside);
  EXPECT_EQ(relation(0.315f, 0.01f), ConeRelation::behind);
  object.footprint = 0.0f;
  EXPECT_EQ(relation(0.305f, 0.0f), ConeRelation::outside);
}

TEST(ConeLabelling, PointsBesideTheRectangleWithinHalfTheFootprintAreLabelledBehind)
{
  // The culling of blocks of beams (ConeBounds) must reach as far as the cone does.
  core::ReflectiveObject object = wallObject(2.0f, 0.6f, 0.4f);
  object.type = ObjectType::mirror;
  object.footprint = 0.04f;
  // Crosses the plane at y = 0.318, 1.8 cm beside the edge (more than the culling's rounding
  // slack); every beam of the block the same, so that its box is that point.
  const Eigen::Vector3f beside(4.0f, 0.636f, 0.0f);
  const std::vector<test::Beam> beams(64, test::Beam{ beside, beside });
  const core::Sweep sweep = test::makeSweep(beams);
  core::SweepLabels labels;
  labels.reset(sweep.beamCount(), Label::valid);
  std::vector<core::ReflectiveObject> objects{ object };
  core::ReflectionEvidence evidence;
  evidence.build(sweep, labels, Eigen::Vector3f::Zero());
  core::ConeLabellingConfig config;
  config.plane_threshold = 0.05;
  config.cone_margin = 0.0;
  core::ObjectAssignment assignment;
  core::ConeLabelling(config).apply(sweep, Eigen::Vector3f::Zero(), evidence, objects, labels, assignment);
  EXPECT_EQ(assignment.echoes[0][40], 0);
  EXPECT_GE(objects[0].behind_points, 1u);
}

TEST(VisionCone, TheConeIsFromTheSensorOriginNotAlongTheNormal)
{
  // Behind the plane and beyond the rectangle's edge along the normal, but seen through it.
  EXPECT_EQ(relationOf({ 6.0f, 0.8f, 0.0f }), ConeRelation::behind);
}

TEST(VisionCone, ASensorBehindThePlaneSeesNoSurface)
{
  const core::ReflectiveObject object = wallObject(2.0f, 0.6f, 0.4f);
  EXPECT_EQ(core::locateInCone(object, Eigen::Vector3f(3.0f, 0.0f, 0.0f), Eigen::Vector3f(1.0f, 0.0f, 0.0f), 0.05f,
                               0.05f)
                .relation,
            ConeRelation::outside);
}

struct Labelled
{
  core::SweepLabels labels;
  core::ObjectAssignment assignment;
};

Labelled label(const core::Sweep& sweep, std::vector<core::ReflectiveObject>& objects,
               const std::vector<std::pair<Label, Label>>& before = {})
{
  Labelled out;
  out.labels.reset(sweep.beamCount());
  for (std::size_t i = 0; i < before.size(); ++i)
  {
    out.labels.echoes[0][i] = before[i].first;
    out.labels.echoes[1][i] = before[i].second;
  }
  core::ReflectionEvidence evidence;
  evidence.build(sweep, out.labels, Eigen::Vector3f::Zero());
  core::ConeLabelling(core::stageConfigs(core::Params()).cone_labelling)
      .apply(sweep, Eigen::Vector3f::Zero(), evidence, objects, out.labels, out.assignment);
  return out;
}

TEST(ConeLabelling, TheEvidenceIsAskedForOnlyWhenAPointLiesBehindAnObject)
{
  // Issue 17: a sweep whose (map) objects have nothing behind them never builds the evidence;
  // one with a point behind asks for it once and labels as the eager apply does.
  const core::ReflectiveObject object = wallObject(2.0f, 0.6f, 0.4f, ObjectType::mirror);
  core::ConeLabellingConfig config;
  config.plane_threshold = 0.05;
  config.cone_margin = 0.0;
  const core::ConeLabelling labelling(config);
  for (const bool behind : { false, true })
  {
    // First echo on the surface; the second either on it too or 1 m behind it.
    const Eigen::Vector3f on(2.0f, 0.1f, 0.1f), back(3.0f, 0.15f, 0.15f);
    const std::vector<test::Beam> beams(100, test::Beam{ on, behind ? back : on });
    const core::Sweep sweep = test::makeSweep(beams);
    core::SweepLabels labels;
    labels.reset(sweep.beamCount(), Label::valid);
    core::ReflectionEvidence evidence;
    evidence.build(sweep, labels, Eigen::Vector3f::Zero());
    int asked = 0;
    std::vector<core::ReflectiveObject> lazy_objects{ object };
    core::SweepLabels lazy_labels = labels;
    core::ObjectAssignment lazy_assignment;
    labelling.apply(
        sweep, Eigen::Vector3f::Zero(),
        [&]() -> const core::ReflectionEvidence& {
          ++asked;
          return evidence;
        },
        lazy_objects, lazy_labels, lazy_assignment);
    std::vector<core::ReflectiveObject> eager_objects{ object };
    core::SweepLabels eager_labels = labels;
    core::ObjectAssignment eager_assignment;
    labelling.apply(sweep, Eigen::Vector3f::Zero(), evidence, eager_objects, eager_labels, eager_assignment);
    EXPECT_EQ(asked, behind ? 1 : 0);
    EXPECT_EQ(lazy_objects[0].behind_points, behind ? 100u : 0u);
    EXPECT_EQ(lazy_objects[0].behind_points, eager_objects[0].behind_points);
    for (std::size_t k = 0; k < 2; ++k)
    {
      EXPECT_EQ(lazy_labels.echoes[k], eager_labels.echoes[k]);
      EXPECT_EQ(lazy_assignment.echoes[k], eager_assignment.echoes[k]);
    }
  }
}

TEST(ConeLabelling, LabelsSurfaceAndBehindPointsByTheObjectsType)
{
  const core::Sweep sweep = test::makeSweep({ { { 2.0f, 0.1f, 0.1f }, { 3.0f, 0.1f, 0.05f } } });
  const std::pair<ObjectType, std::pair<Label, Label>> cases[] = {
    { ObjectType::unknown, { Label::errorSurface, Label::behindErrorS } },
    { ObjectType::mirror, { Label::reflectiveSurface, Label::behindReflective } },
    { ObjectType::glass, { Label::transparentSurface, Label::behindTransparent } },
  };
  for (const auto& c : cases)
  {
    std::vector<core::ReflectiveObject> objects{ wallObject(2.0f, 0.6f, 0.4f, c.first) };
    const Labelled out = label(sweep, objects, { { Label::errorSurface, Label::error } });
    EXPECT_EQ(out.labels.echoes[0][0], c.second.first) << core::objectTypeName(c.first);
    EXPECT_EQ(out.labels.echoes[1][0], c.second.second) << core::objectTypeName(c.first);
    EXPECT_EQ(out.assignment.echoes[0][0], 0);
    EXPECT_EQ(out.assignment.echoes[1][0], 0);
  }
}

// A range image: a wall at x = -1 behind the sensor; beyond the surface at x = 2 a wall at
// x = 5 where y > 0 (reflected across x = 2 it lands on the wall at x = -1: phantoms) and at
// x = 3.5 where y < 0 (reflected it lands at x = 0.5, in front of the surface, where the sensor
// saw further, through to the walls behind: real).
core::Sweep phantomsAndRealPointsBehind()
{
  return test::rangeImage({ { 0, -1.0f, test::everywhere },
                            { 0, 5.0f, [](const Eigen::Vector3f& x) { return x.y() > 0.0f; } },
                            { 0, 3.5f, [](const Eigen::Vector3f& x) { return x.y() <= 0.0f; } } });
}

TEST(ConeLabelling, EveryPointBehindIsLabelledByItsOwnEvidence)
{
  const core::Sweep sweep = phantomsAndRealPointsBehind();
  for (ObjectType type : { ObjectType::glass, ObjectType::mirror, ObjectType::unknown })
  {
    // 0.6 m high: every reflection lies within the sweep's 60 degrees of elevation.
    std::vector<core::ReflectiveObject> objects{ wallObject(2.0f, 1.0f, 0.6f, type) };
    const Labelled out = label(sweep, objects);
    std::size_t phantoms = 0, real = 0;
    for (std::size_t i = 0; i < sweep.beamCount(); ++i)
    {
      if (out.assignment.echoes[0][i] != 0)
        continue;
      const Eigen::Vector3f& p = sweep.echoes[0].points[i];
      const Label expected = p.y() > 0.0f ? Label::behindReflective : Label::behindTransparent;
      const Label got = out.labels.echoes[0][i];
      EXPECT_EQ(got, expected) << core::objectTypeName(type) << " at " << p.transpose();
      phantoms += got == Label::behindReflective ? 1 : 0;
      real += got == Label::behindTransparent ? 1 : 0;
    }
    EXPECT_GT(phantoms, 50u) << core::objectTypeName(type);
    EXPECT_GT(real, 50u) << core::objectTypeName(type);
    EXPECT_GE(objects[0].phantom_points, phantoms);
    EXPECT_GE(objects[0].transmitted_points, real);
    EXPECT_EQ(objects[0].phantom_points + objects[0].transmitted_points + objects[0].ambiguous_points +
                  objects[0].undecided_points,
              objects[0].behind_points);
  }
}

// Expects every point of `sweep` assigned to objects[0] (behind it: nothing lies on its
// surface in these sweeps) to be labelled `expected`; how many there are.
std::size_t expectBehindLabelled(const core::Sweep& sweep, std::vector<core::ReflectiveObject>& objects,
                                 Label expected, const char* what)
{
  const Labelled out = label(sweep, objects);
  std::size_t behind = 0;
  for (std::size_t i = 0; i < sweep.beamCount(); ++i)
    if (out.assignment.echoes[0][i] == 0)
    {
      EXPECT_EQ(out.labels.echoes[0][i], expected) << what;
      ++behind;
    }
  return behind;
}

TEST(ConeLabelling, BehindGlassTypedByItsFaintPhantomsPointsWithoutEvidenceTakeWhatItsPointsSaid)
{
  // Glass whose points behind, by their geometry, were reflections with nothing proved real (a
  // mirror to the geometry), typed glass by its phantoms' faintness: its surface is glass, but a
  // point without evidence of its own is taken for a reflection, as its other points said. Glass
  // that the geometry left unknown keeps it as real.
  const core::Sweep sweep = test::rangeImage({ { 0, 5.0f, test::everywhere } });
  const std::pair<ObjectType, Label> cases[] = { { ObjectType::mirror, Label::behindReflective },
                                                 { ObjectType::unknown, Label::behindTransparent } };
  for (const auto& c : cases)
  {
    std::vector<core::ReflectiveObject> objects{ wallObject(2.0f, 1.0f, 1.0f, ObjectType::glass) };
    objects[0].evidence.typed_by_dim_phantoms = true;
    objects[0].evidence.geometric_type = c.first;
    EXPECT_GT(expectBehindLabelled(sweep, objects, c.second, core::objectTypeName(c.first)), 100u);
    EXPECT_EQ(objects[0].type, ObjectType::glass);
  }
}

// Behind a mirror at x = 2: a wall at x = 6 (a 0.8 x 0.8 m patch, 49 beams at 1 deg). Reflected, its points would
// lie at x = -2, behind the wall at x = -1 the sensor saw all round.
core::Sweep wallBehindAMirrorFacingAWall()
{
  return test::rangeImage(
      { { 0, -1.0f, test::everywhere },
        { 0, 6.0f, [](const Eigen::Vector3f& x) { return std::fabs(x.y()) < 0.4f && std::fabs(x.z()) < 0.4f; } } });
}

// Labels of the points at x = 6 behind object 0.
std::map<Label, std::size_t> behindTheMirror(const core::Sweep& sweep, std::vector<core::ReflectiveObject>& objects)
{
  const Labelled out = label(sweep, objects);
  std::map<Label, std::size_t> counts;
  for (std::size_t i = 0; i < sweep.beamCount(); ++i)
    if (out.assignment.echoes[0][i] == 0 && sweep.echoes[0].points[i].x() > 5.0f)
      ++counts[out.labels.echoes[0][i]];
  return counts;
}

TEST(ConeLabelling, APointWhosePhantomLightWouldPierceASeenWallIsReal)
{
  // The light of a phantom would have come from the mirror to x = -2 through the wall at x = -1:
  // the points are real, whatever the object's type says.
  const core::Sweep sweep = wallBehindAMirrorFacingAWall();
  std::vector<core::ReflectiveObject> objects{ wallObject(2.0f, 1.0f, 1.0f, ObjectType::mirror) };
  std::map<Label, std::size_t> counts = behindTheMirror(sweep, objects);
  EXPECT_GT(counts[Label::behindTransparent], 40u);
  EXPECT_EQ(counts[Label::behindReflective], 0u);
  EXPECT_EQ(objects[0].transmitted_points, objects[0].behind_points);
}

TEST(ConeLabelling, APathThatMayGoOnThroughAnotherMirrorProvesNothing)
{
  // A second mirror in the wall at x = -1, facing the first: the light may have been reflected
  // there again (a reflection chain), so the wall no longer proves the points real; behind a
  // mirror they take its type.
  const core::Sweep sweep = wallBehindAMirrorFacingAWall();
  core::ReflectiveObject facing = wallObject(-1.0f, 1.5f, 1.5f, ObjectType::mirror, 1);
  facing.plane = Eigen::Vector4f(1.0f, 0.0f, 0.0f, 1.0f);  // facing +x, towards the sensor
  std::vector<core::ReflectiveObject> objects{ wallObject(2.0f, 1.0f, 1.0f, ObjectType::mirror), facing };
  std::map<Label, std::size_t> counts = behindTheMirror(sweep, objects);
  EXPECT_GT(counts[Label::behindReflective], 40u);
  EXPECT_EQ(counts[Label::behindTransparent], 0u);
}

// The sweep's returns given intensities of brightness (intensity x r^2) 5 where y > 0 and 900
// elsewhere: reflections in a pane against what is seen through it.
void faintWhereYIsPositive(core::Sweep& sweep)
{
  sweep.has_intensity = true;
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t i = 0; i < sweep.beamCount(); ++i)
    {
      const Eigen::Vector3f& p = sweep.echoes[k].points[i];
      sweep.echoes[k].intensities[i] = (p.y() > 0.0f ? 5.0f : 900.0f) / p.squaredNorm();
    }
}

// Nothing seen in front of a pane at x = 2: no point behind it can be told by its geometry. Its
// sampled phantoms came back with a brightness (intensity x r^2) of `phantom`, what was seen
// through it with `seen_through`; behind it, where y > 0, points of brightness 5, elsewhere of
// 900. Labels the points behind the pane (`glass`, its evidence set so) and checks each against
// expected(is_faint).
void expectLabelledByBrightness(core::ReflectiveObject glass, float seen_through,
                                const std::function<Label(bool is_faint)>& expected, float phantom = 10.0f)
{
  core::Sweep sweep = test::rangeImage({ { 0, 5.0f, test::everywhere } });
  faintWhereYIsPositive(sweep);
  glass.evidence.phantom_brightness = phantom;
  glass.evidence.transmitted_brightness = seen_through;
  std::vector<core::ReflectiveObject> objects{ glass };
  const Labelled out = label(sweep, objects);
  std::size_t faint = 0, bright = 0;
  for (std::size_t i = 0; i < sweep.beamCount(); ++i)
    if (out.assignment.echoes[0][i] == 0)
    {
      const bool is_faint = sweep.echoes[0].points[i].y() > 0.0f;
      EXPECT_EQ(out.labels.echoes[0][i], expected(is_faint)) << "seen through " << seen_through;
      (is_faint ? faint : bright) += 1;
    }
  EXPECT_GT(faint, 50u);
  EXPECT_GT(bright, 50u);
}

TEST(ConeLabelling, BehindGlassAPointWithoutEvidenceFarFainterThanWhatIsSeenThroughIsAReflection)
{
  // Only ten times fainter than seen through or more is the contrast enough to tell.
  for (const float seen_through : { 1000.0f, 50.0f })
    expectLabelledByBrightness(wallObject(2.0f, 1.0f, 1.0f, ObjectType::glass), seen_through, [&](bool is_faint) {
      return is_faint && seen_through >= 100.0f ? Label::behindReflective : Label::behindTransparent;
    });
}

TEST(ConeLabelling, BehindGlassAPointTwentyTimesFainterThanWhatIsSeenThroughIsAReflectionWhateverItsPhantoms)
{
  // The pane's sampled phantoms as bright as what is seen through it (real points that landed on
  // seen geometry by coincidence): no contrast between the two. A point without evidence 200
  // times fainter than what is seen through is still a reflection; 10 times fainter, it may be a
  // dark surface seen through.
  for (const float seen_through : { 1000.0f, 50.0f })
    expectLabelledByBrightness(
        wallObject(2.0f, 1.0f, 1.0f, ObjectType::glass), seen_through,
        [&](bool is_faint) {
          return is_faint && seen_through >= 1000.0f ? Label::behindReflective : Label::behindTransparent;
        },
        seen_through);
}

// A pane at x = 2 whose sampled points told no brightness (its evidence's are NaN). Behind it,
// where y > 0, faint reflections at x = 5 (brightness 5): reflected they land at x = -1, on the
// wall behind the sensor where z < 0 (their own test: phantom) and where nothing was seen above
// it (no return). Where y <= 0, bright points seen through at x = 3.5 (brightness 900): reflected
// to x = 0.5, where the sensor saw further (transmitted) below z = 0, nothing above.
core::Sweep faintReflectionsAndBrightPointsBehindAPane()
{
  core::Sweep sweep = test::rangeImage({ { 0, -1.0f, [](const Eigen::Vector3f& x) { return x.z() < 0.0f; } },
                                         { 0, 5.0f, [](const Eigen::Vector3f& x) { return x.y() > 0.0f; } },
                                         { 0, 3.5f, [](const Eigen::Vector3f& x) { return x.y() <= 0.0f; } } });
  faintWhereYIsPositive(sweep);
  return sweep;
}

TEST(ConeLabelling, BehindAPaneWhoseSampleToldNoBrightnessWhatItsConeToldTellsThePointsWithoutEvidence)
{
  const core::Sweep sweep = faintReflectionsAndBrightPointsBehindAPane();
  // Well above z = 0, where no reflection lands on anything seen: no evidence of their own.
  const auto withoutEvidence = [](const Eigen::Vector3f& p) { return p.z() > 0.1f * p.norm(); };
  for (const bool sample_told : { false, true })
  {
    core::ReflectiveObject glass = wallObject(2.0f, 1.0f, 0.6f, ObjectType::glass);
    if (sample_told)
    {
      // A sample that told: what was seen through it no brighter than its phantoms (no contrast).
      glass.evidence.phantom_brightness = 50.0f;
      glass.evidence.transmitted_brightness = 50.0f;
    }
    std::vector<core::ReflectiveObject> objects{ glass };
    const Labelled out = label(sweep, objects);
    std::size_t faint_without = 0, bright_without = 0;
    for (std::size_t i = 0; i < sweep.beamCount(); ++i)
    {
      const Eigen::Vector3f& p = sweep.echoes[0].points[i];
      if (out.assignment.echoes[0][i] != 0 || !withoutEvidence(p))
        continue;
      const bool faint = p.y() > 0.0f;
      // The cone's reference only where the sample gave none: the sample's is not second-guessed.
      const Label expected = faint && !sample_told ? Label::behindReflective : Label::behindTransparent;
      EXPECT_EQ(out.labels.echoes[0][i], expected) << "sample told: " << sample_told << " at " << p.transpose();
      (faint ? faint_without : bright_without) += 1;
    }
    EXPECT_GT(faint_without, 20u);
    EXPECT_GT(bright_without, 20u);
    // The points that told, by their own test.
    EXPECT_GT(objects[0].phantom_points, 20u);
    EXPECT_GT(objects[0].transmitted_points, 20u);
  }
}

TEST(ConeLabelling, BehindGlassTypedByItsFaintPhantomsAPointAsBrightAsWhatIsSeenThroughIsReal)
{
  // The pane typed glass by its faint phantoms where the geometry said mirror: its points without
  // evidence are reflections, as its other points said, except those at least as bright as the
  // geometric mean of its phantoms (10) and what is seen through it, or, with too little contrast
  // between the two to tell by that mean, at least as bright as what is seen through. The bright
  // points are 900, the faint ones 5.
  core::ReflectiveObject glass = wallObject(2.0f, 1.0f, 1.0f, ObjectType::glass);
  glass.evidence.typed_by_dim_phantoms = true;
  glass.evidence.geometric_type = ObjectType::mirror;
  for (const float seen_through : { 1000.0f, 50.0f })
    expectLabelledByBrightness(glass, seen_through, [&](bool is_faint) {
      return !is_faint ? Label::behindTransparent : Label::behindReflective;
    });
  // Seen through at 2000, its phantoms at 1000: the bright points are fainter than what is seen
  // through and there is no contrast to tell by; they stay reflections.
  expectLabelledByBrightness(
      glass, 2000.0f, [&](bool) { return Label::behindReflective; }, 1000.0f);
}

TEST(ConeLabelling, WhatIsSeenThroughIsThePointsSeenThroughUnlessTheyAreFainterThanThePhantoms)
{
  core::TypeEvidence evidence;
  EXPECT_TRUE(std::isnan(evidence.seenThroughBrightness()));
  evidence.landing_brightness = 800.0f;
  EXPECT_EQ(evidence.seenThroughBrightness(), 800.0f);  // nothing sampled seen through
  evidence.phantom_brightness = 23.0f;
  evidence.transmitted_brightness = 300.0f;
  EXPECT_EQ(evidence.seenThroughBrightness(), 300.0f);  // brighter than the phantoms: the reference
  evidence.transmitted_brightness = 14.0f;
  EXPECT_EQ(evidence.seenThroughBrightness(), 800.0f);  // fainter: reflections themselves
  evidence.landing_brightness = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(evidence.seenThroughBrightness(), 14.0f);   // nothing better known
}

TEST(ConeLabelling, BehindGlassWhosePointsSeenThroughAreFaintWhatItsPhantomsLandOnTells)
{
  // A pane close by: its sampled "seen through" points were reflections too (fainter than its
  // phantoms), but what the phantoms land on, seen directly, is bright. Against that, the bright
  // points behind it are real and the faint ones reflections; without it nothing could be told
  // and all would stay what the geometry said (reflections).
  core::ReflectiveObject glass = wallObject(2.0f, 1.0f, 1.0f, ObjectType::glass);
  glass.evidence.typed_by_dim_phantoms = true;
  glass.evidence.geometric_type = ObjectType::mirror;
  for (const float landing : { 1000.0f, std::numeric_limits<float>::quiet_NaN() })
  {
    glass.evidence.landing_brightness = landing;
    expectLabelledByBrightness(glass, 8.0f, [&](bool is_faint) {
      return !is_faint && std::isfinite(landing) ? Label::behindTransparent : Label::behindReflective;
    });
  }
}

TEST(ConeLabelling, PointsWithoutEvidenceOfTheirOwnTakeTheObjectsType)
{
  // Nothing seen in front of the surface: no point behind can be told by itself.
  const core::Sweep sweep = test::rangeImage({ { 0, 5.0f, test::everywhere } });
  const std::pair<ObjectType, Label> cases[] = { { ObjectType::unknown, Label::behindErrorS },
                                                 { ObjectType::mirror, Label::behindReflective },
                                                 { ObjectType::glass, Label::behindTransparent } };
  for (const auto& c : cases)
  {
    std::vector<core::ReflectiveObject> objects{ wallObject(2.0f, 1.0f, 1.0f, c.first) };
    EXPECT_GT(expectBehindLabelled(sweep, objects, c.second, core::objectTypeName(c.first)), 100u);
    EXPECT_EQ(objects[0].undecided_points, objects[0].behind_points);
  }
}

// A 128-ring lidar's sampling (0.35 deg rings, 0.18 deg columns) of a floor 1 m below the
// sensor, 1 cm range noise, through a pane reaching down to it 2 m ahead (x = 2). With
// `behind_share` > 0 every return has a Lambertian intensity (1000 cos(incidence) / r^2), those
// beyond the pane times behind_share (what the pane lets through, or reflects); 0: none.
core::Sweep floorThroughAPane(float behind_share)
{
  std::mt19937 generator(5);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  return test::gridSweep(172, 445, -60.0f, 0.35f, 0.0f, -40.0f, 0.18f, [&](const Eigen::Vector3f& direction) {
    const bool floor = direction.z() < -0.05f;
    const float range = -1.0f / direction.z();
    const Eigen::Vector3f point =
        floor ? Eigen::Vector3f((range + noise(generator)) * direction) : Eigen::Vector3f::Constant(nan);
    float intensity = nan;
    if (floor && behind_share > 0.0f)
      intensity = 1000.0f * -direction.z() / (range * range) * (point.x() > 2.0f ? behind_share : 1.0f);
    return std::make_pair(point, intensity);
  });
}

// The labels of the points behind a glass pane in `sweep` (not its surface) up to x = max_x:
// (behind, kept as behindTransparent, taken for phantoms).
struct BehindTheFloorPane
{
  std::size_t behind = 0, kept = 0, phantoms = 0;
};

BehindTheFloorPane labelBehindTheFloorPane(const core::Sweep& sweep, float max_x = 100.0f)
{
  std::vector<std::pair<Label, Label>> before;
  for (std::size_t i = 0; i < sweep.beamCount(); ++i)
  {
    const Label label = sweep.echoes[0].points[i].allFinite() ? Label::unchecked : Label::nanPoint;
    before.emplace_back(label, label);
  }
  std::vector<core::ReflectiveObject> objects{ wallObject(2.0f, 1.2f, 2.2f, ObjectType::glass) };
  const Labelled out = label(sweep, objects, before);
  BehindTheFloorPane result;
  for (std::size_t i = 0; i < sweep.beamCount(); ++i)
    if (out.assignment.echoes[0][i] == 0 && out.labels.echoes[0][i] != Label::transparentSurface &&
        sweep.echoes[0].points[i].x() <= max_x)
    {
      ++result.behind;
      result.kept += out.labels.echoes[0][i] == Label::behindTransparent ? 1 : 0;
      result.phantoms += out.labels.echoes[0][i] == Label::behindReflective ? 1 : 0;
    }
  return result;
}

TEST(ConeLabelling, TheFloorSeenThroughGlassStaysRealThoughItsReflectionLandsOnTheFloor)
{
  // Reflected across the pane, a floor point behind it lands on the floor in front, as a phantom
  // of the floor would: without intensities it cannot be told, and behind glass it is kept.
  const BehindTheFloorPane out = labelBehindTheFloorPane(floorThroughAPane(0.0f));
  ASSERT_GT(out.behind, 2000u);
  // (With the test window's normal alone, 14 % of them were taken for phantoms.)
  EXPECT_GE(out.kept, out.behind * 99 / 100) << out.kept << " of " << out.behind;
}

TEST(ConeLabelling, BehindGlassTheIntensityTellsTheFloorSeenThroughFromItsReflection)
{
  // The same floor points behind the pane, once as light the pane let through (90 %), once as
  // its reflection of the floor in front (10 %): against the floor seen where they land, only
  // the reflection is too weak.
  const BehindTheFloorPane seen_through = labelBehindTheFloorPane(floorThroughAPane(0.9f));
  ASSERT_GT(seen_through.behind, 2000u);
  EXPECT_GE(seen_through.kept, seen_through.behind * 99 / 100) << seen_through.kept << " of " << seen_through.behind;
  // Up to 3.3 m (beyond, the reflection lands nearer than 0.7 m, under the sensor's view, and
  // only glass's default is left).
  const BehindTheFloorPane reflected = labelBehindTheFloorPane(floorThroughAPane(0.1f), 3.3f);
  ASSERT_GT(reflected.behind, 1000u);
  EXPECT_GE(reflected.phantoms, reflected.behind * 90 / 100) << reflected.phantoms << " of " << reflected.behind;
  const BehindTheFloorPane near_seen_through = labelBehindTheFloorPane(floorThroughAPane(0.9f), 3.3f);
  EXPECT_GE(near_seen_through.kept, near_seen_through.behind * 99 / 100);
}

TEST(ConeLabelling, PointsOutsideEveryConeBecomeValidExceptErrorAndNanPoints)
{
  const core::Sweep sweep = test::makeSweep({ { { 1.0f, 0.0f, 0.0f }, { 5.0f, 3.0f, 0.0f } },
                                              { { 4.0f, 3.0f, 0.0f }, { 4.0f, 3.0f, 0.0f } },
                                              { { 1.5f, 2.0f, 0.0f }, { 6.0f, 4.0f, 0.0f } } });
  std::vector<core::ReflectiveObject> objects{ wallObject(2.0f, 0.6f, 0.4f, ObjectType::mirror) };
  const Labelled out = label(sweep, objects,
                             { { Label::unchecked, Label::nanPoint },
                               { Label::unchecked, Label::unchecked },
                               { Label::errorSurface, Label::error } });
  EXPECT_EQ(out.labels.echoes[0][0], Label::valid);  // in front of the mirror
  EXPECT_EQ(out.labels.echoes[1][0], Label::nanPoint);
  EXPECT_EQ(out.labels.echoes[0][1], Label::valid);
  EXPECT_EQ(out.labels.echoes[0][2], Label::valid);  // a discontinuity with no object
  EXPECT_EQ(out.labels.echoes[1][2], Label::error);
  EXPECT_EQ(out.assignment.echoes[0][0], core::ObjectAssignment::kNoObject);
}

TEST(ConeLabelling, WhereConesOverlapTheNearerSurfaceWins)
{
  std::vector<core::ReflectiveObject> objects{ wallObject(3.0f, 1.0f, 1.0f, ObjectType::glass, 0),
                                               wallObject(2.0f, 1.0f, 1.0f, ObjectType::mirror, 1) };
  // On the far glass and behind the near mirror: the mirror decides, in either object order.
  const core::Sweep sweep = test::makeSweep({ { { 3.0f, 0.0f, 0.0f }, { 4.0f, 0.0f, 0.0f } } });
  for (int order = 0; order < 2; ++order)
  {
    const Labelled out = label(sweep, objects);
    EXPECT_EQ(out.labels.echoes[0][0], Label::behindReflective);
    EXPECT_EQ(out.labels.echoes[1][0], Label::behindReflective);
    EXPECT_EQ(objects[static_cast<std::size_t>(out.assignment.echoes[0][0])].type, ObjectType::mirror);
    std::swap(objects[0], objects[1]);
  }
}

TEST(ConeLabelling, AMirrorSeenThroughAPaneTakesItsSurfaceAndItsPhantoms)
{
  // A pane at 2 m, a mirror 1 m behind it: on the mirror's surface and behind it, the points are
  // the mirror's, in either object order (the pane let the beam through, the mirror turned it).
  std::vector<core::ReflectiveObject> objects{ wallObject(2.0f, 1.0f, 1.0f, ObjectType::glass, 0),
                                               wallObject(3.0f, 1.0f, 1.0f, ObjectType::mirror, 1) };
  const core::Sweep sweep = test::makeSweep({ { { 2.0f, 0.0f, 0.0f }, { 3.0f, 0.0f, 0.0f } },
                                              { { 2.5f, 0.1f, 0.0f }, { 4.0f, 0.4f, 0.3f } } });
  for (int order = 0; order < 2; ++order)
  {
    const Labelled out = label(sweep, objects);
    const auto typeOf = [&](std::int32_t j) { return objects[static_cast<std::size_t>(j)].type; };
    EXPECT_EQ(out.labels.echoes[0][0], Label::transparentSurface);
    EXPECT_EQ(out.labels.echoes[1][0], Label::reflectiveSurface);
    EXPECT_EQ(typeOf(out.assignment.echoes[1][0]), ObjectType::mirror);
    // Between the two planes: seen through the pane.
    EXPECT_EQ(out.labels.echoes[0][1], Label::behindTransparent);
    EXPECT_EQ(out.labels.echoes[1][1], Label::behindReflective);
    EXPECT_EQ(typeOf(out.assignment.echoes[1][1]), ObjectType::mirror);
    std::swap(objects[0], objects[1]);
  }
  // A mirror only a few centimetres behind the pane's plane is the same wall, and a fragment
  // narrower than 20 cm is no mirror seen through it: the nearer surface wins.
  for (const core::ReflectiveObject& mirror : { wallObject(2.1f, 1.0f, 1.0f, ObjectType::mirror, 1),
                                                wallObject(3.0f, 0.15f, 1.0f, ObjectType::mirror, 1) })
  {
    objects = { wallObject(2.0f, 1.0f, 1.0f, ObjectType::glass, 0), mirror };
    const Labelled out = label(sweep, objects);
    EXPECT_EQ(out.labels.echoes[1][1], Label::behindTransparent);
    EXPECT_EQ(out.assignment.echoes[1][1], 0);
  }
}

// A pane at x = distance grown (glass_growth.h) to width x height from a patch of
// patch x patch around its centre.
core::ReflectiveObject grownPane(float distance, float width, float height, float patch)
{
  core::ReflectiveObject pane = wallObject(distance, width, height, ObjectType::glass);
  pane.grown = true;
  pane.patch_centre = pane.centre;
  pane.patch_width = pane.patch_height = patch;
  return pane;
}

TEST(ConeLabelling, AReturnOnAGrownPanesPlaneBeyondItsPatchIsNoEchoOfThePane)
{
  // Glass echoes only near perpendicular incidence, in its patch; beyond it a return on the plane
  // is the frame, the wall or the floor.
  const core::Sweep sweep = test::makeSweep({ { { 2.0f, 0.05f, 0.0f }, { 2.0f, 0.05f, 0.0f } },
                                              { { 2.0f, 0.6f, 0.3f }, { 2.0f, 0.6f, 0.3f } } });
  std::vector<core::ReflectiveObject> objects{ grownPane(2.0f, 2.0f, 1.5f, 0.2f) };
  Labelled out = label(sweep, objects);
  EXPECT_EQ(out.labels.echoes[0][0], Label::transparentSurface);
  EXPECT_EQ(out.labels.echoes[0][1], Label::valid);
  EXPECT_EQ(out.assignment.echoes[0][1], core::ObjectAssignment::kNoObject);
  EXPECT_EQ(objects[0].surface_points, 2u);  // both echoes of the first beam
  // A pane of that extent that did not grow (its rectangle is its patch) echoes all over it.
  objects[0].grown = false;
  out = label(sweep, objects);
  EXPECT_EQ(out.labels.echoes[0][1], Label::transparentSurface);
}

TEST(ConeLabelling, BeyondAGrownPanesPatchAMirrorInItsPlaneTakesThePoint)
{
  // A metal panel 3 cm behind the pane's plane, beside its patch (y from 0.4 to 0.8), which the
  // pane's growth reached over. Nothing is seen in front: the points take their object's type.
  std::vector<core::ReflectiveObject> objects{ grownPane(2.0f, 2.0f, 1.5f, 0.2f),
                                               wallObject(2.03f, 0.4f, 0.6f, ObjectType::mirror, 1) };
  objects[1].centre.y() = 0.6f;
  // Behind both, crossing the pane's plane at y = 0.6; behind the pane's patch only.
  const core::Sweep sweep = test::makeSweep({ { { 4.0f, 1.2f, 0.0f }, { 4.0f, 1.2f, 0.0f } },
                                              { { 4.0f, 0.1f, 0.0f }, { 4.0f, 0.1f, 0.0f } } });
  Labelled out = label(sweep, objects);
  EXPECT_EQ(out.assignment.echoes[0][0], 1);
  EXPECT_EQ(out.labels.echoes[0][0], Label::behindReflective);
  EXPECT_EQ(out.assignment.echoes[0][1], 0);
  EXPECT_EQ(out.labels.echoes[0][1], Label::behindTransparent);
  // Where the pane's own patch reaches, the nearer surface wins as everywhere else.
  objects[0].patch_width = 2.0f;
  out = label(sweep, objects);
  EXPECT_EQ(out.assignment.echoes[0][0], 0);
  EXPECT_EQ(out.labels.echoes[0][0], Label::behindTransparent);
}

TEST(ConeLabelling, BeyondAGrownPanesPatchAnotherPatchOfThePaneTakesThePoint)
{
  // A pane found as two patches, both grown over the whole pane: where the ray crosses the plane
  // in the second's patch, the second takes the point, though the first's plane lies nearer.
  core::ReflectiveObject second = grownPane(2.02f, 2.0f, 1.5f, 0.4f);
  second.id = 1;
  second.patch_centre = Eigen::Vector3f(2.02f, 0.6f, 0.0f);
  std::vector<core::ReflectiveObject> objects{ grownPane(2.0f, 2.0f, 1.5f, 0.2f), second };
  const core::Sweep sweep = test::makeSweep({ { { 4.0f, 1.2f, 0.0f }, { 4.0f, 1.2f, 0.0f } } });
  Labelled out = label(sweep, objects);
  EXPECT_EQ(out.assignment.echoes[0][0], 1);
  // Another pane 30 cm behind is no patch of the same one: the nearer surface wins.
  objects[1].plane[3] = 2.3f;
  objects[1].centre.x() = objects[1].patch_centre.x() = 2.3f;
  out = label(sweep, objects);
  EXPECT_EQ(out.assignment.echoes[0][0], 0);
}

TEST(ConeLabelling, BeyondTwoGrownPatchesOfOnePaneTheWiderPatchTakesThePoint)
{
  // Both patches grown over the whole pane, the point beyond both: the plane fitted to the wider
  // patch (more surface echoes) back-projects its reflections more exactly. A plane 6 degrees off
  // is no patch of the same pane: the nearer surface wins.
  core::ReflectiveObject wide = grownPane(2.02f, 2.0f, 1.5f, 0.5f);
  wide.id = 1;
  wide.patch_centre = Eigen::Vector3f(2.02f, -0.6f, 0.0f);
  std::vector<core::ReflectiveObject> objects{ grownPane(2.0f, 2.0f, 1.5f, 0.2f), wide };
  const core::Sweep sweep = test::makeSweep({ { { 4.0f, 1.2f, 0.0f }, { 4.0f, 1.2f, 0.0f } } });
  Labelled out = label(sweep, objects);
  EXPECT_EQ(out.assignment.echoes[0][0], 1);
  const float turn = 6.0f * static_cast<float>(M_PI) / 180.0f;
  objects[1].plane.head<3>() = Eigen::Vector3f(-std::cos(turn), std::sin(turn), 0.0f);
  objects[1].plane[3] = -objects[1].plane.head<3>().dot(objects[1].centre);
  out = label(sweep, objects);
  EXPECT_EQ(out.assignment.echoes[0][0], 0);
}

TEST(ConeLabelling, APaneGrownOverAMirrorsPointDoesNotLeaveItsPathUnchecked)
{
  // The points behind the mirror are real by their paths (the seen wall at x = -1 blocks a
  // phantom's light). A pane 30 cm behind the mirror, grown over it from a patch off to the side,
  // claims them too; that claim makes them no points another reflection may explain. A pane whose
  // own patch covers them does.
  const core::Sweep sweep = wallBehindAMirrorFacingAWall();
  core::ReflectiveObject pane = grownPane(2.3f, 3.0f, 3.0f, 0.2f);
  pane.id = 1;
  pane.patch_centre = Eigen::Vector3f(2.3f, 1.2f, 0.0f);
  std::vector<core::ReflectiveObject> objects{ wallObject(2.0f, 1.0f, 1.0f, ObjectType::mirror), pane };
  std::map<Label, std::size_t> counts = behindTheMirror(sweep, objects);
  EXPECT_GT(counts[Label::behindTransparent], 40u);
  EXPECT_EQ(counts[Label::behindReflective], 0u);
  objects[1].grown = false;
  counts = behindTheMirror(sweep, objects);
  EXPECT_GT(counts[Label::behindReflective], 40u);
}

// All around the sensor, 1 degree steps, elevations -45 to 45 degrees: a wall at x = -3 behind it
// and one at x = 5 ahead (behind a pane at x = 1, reflected across it, a point of that wall lands
// on the wall behind the sensor, as a phantom's would). Lambertian intensities (1000 cos / r^2),
// those of the wall ahead times `ahead_share`: what it keeps against the wall it lands on.
core::Sweep wallsAheadAndBehind(float ahead_share)
{
  return test::gridSweep(91, 360, -45.0f, 1.0f, 0.0f, 0.0f, 1.0f, [&](const Eigen::Vector3f& direction) {
    const float at = direction.x() > 0.0f ? 5.0f : -3.0f;
    const float range = at / direction.x();
    const float share = direction.x() > 0.0f ? ahead_share : 1.0f;
    return std::make_pair(Eigen::Vector3f(range * direction),
                          share * 1000.0f * std::fabs(direction.x()) / (range * range));
  });
}

TEST(ConeLabelling, BehindAGrownPanesPartALandingPointIsAReflectionOnlyWhenFaint)
{
  // A pane grown to 2 x 1 m from a 0.2 m patch. Away from perpendicular incidence real points
  // behind a pane land on seen geometry by coincidence, and reflections in glass keep a few per
  // cent of the light: there a landing point is a reflection only when it kept less than 0.08 of
  // what it lands on. In the patch the landing alone decides, as behind every object.
  for (const float share : { 0.5f, 0.03f })
  {
    const core::Sweep sweep = wallsAheadAndBehind(share);
    std::vector<core::ReflectiveObject> objects{ grownPane(1.0f, 2.0f, 1.0f, 0.2f) };
    const Labelled out = label(sweep, objects);
    std::size_t in_patch = 0, beyond = 0;
    for (std::size_t i = 0; i < sweep.beamCount(); ++i)
    {
      if (out.assignment.echoes[0][i] != 0)
        continue;
      const Eigen::Vector3f crossing = sweep.echoes[0].points[i] / sweep.echoes[0].points[i].x();
      const bool through_patch = std::fabs(crossing.y()) <= 0.1f && std::fabs(crossing.z()) <= 0.1f;
      const bool clearly_beyond = std::fabs(crossing.y()) > 0.2f || std::fabs(crossing.z()) > 0.2f;
      if (through_patch)
      {
        ++in_patch;
        EXPECT_EQ(out.labels.echoes[0][i], Label::behindReflective) << "share " << share;
      }
      else if (clearly_beyond)
      {
        ++beyond;
        EXPECT_EQ(out.labels.echoes[0][i], share < 0.08f ? Label::behindReflective : Label::behindTransparent)
            << "share " << share << " crossing " << crossing.transpose();
      }
    }
    EXPECT_GT(in_patch, 20u);
    EXPECT_GT(beyond, 1000u);
  }
}

TEST(ConeLabelling, CountsSurfaceAndBehindPointsAndAveragesSurfaceIntensity)
{
  core::Sweep sweep = test::makeSweep({ { { 2.0f, 0.0f, 0.0f }, { 3.0f, 0.0f, 0.0f } },
                                        { { 2.0f, 0.1f, 0.0f }, { 3.0f, 0.15f, 0.0f } },
                                        { { 1.0f, 0.0f, 0.0f }, { 1.0f, 0.0f, 0.0f } } });
  sweep.echoes[0].intensities = { 10.0f, 20.0f, 99.0f };
  std::vector<core::ReflectiveObject> objects{ wallObject(2.0f, 0.6f, 0.4f) };
  label(sweep, objects);
  EXPECT_EQ(objects[0].surface_points, 2u);
  EXPECT_EQ(objects[0].behind_points, 2u);
  EXPECT_FLOAT_EQ(objects[0].mean_surface_intensity, 15.0f);
}

// The cleaned output after the reflection chains (default parameters), as the pipeline runs them.
std::vector<core::OutputPoint> cleanedOf(const core::Sweep& sweep, const std::vector<core::ReflectiveObject>& objects,
                                         Labelled& out)
{
  core::ReflectionEvidence evidence;
  evidence.build(sweep, out.labels, Eigen::Vector3f::Zero());
  core::ReflectionPaths paths;
  core::ReflectionChains(core::stageConfigs(core::Params()).reflection_chains)
      .apply(sweep, Eigen::Vector3f::Zero(), evidence, objects, out.assignment, out.labels, paths);
  std::vector<core::OutputPoint> cleaned;
  core::collectCleaned(sweep, out.labels, objects, paths, cleaned);
  return cleaned;
}

TEST(CleanedOutput, BackProjectsPhantomsAcrossTheirOwnMirror)
{
  // Two mirrors side by side; each phantom reflects across its own plane.
  core::ReflectiveObject left = wallObject(2.0f, 1.0f, 1.0f, ObjectType::mirror, 0);
  left.centre.y() = 1.0f;
  core::ReflectiveObject right = wallObject(2.5f, 1.0f, 1.0f, ObjectType::mirror, 1);
  right.centre.y() = -1.0f;
  std::vector<core::ReflectiveObject> objects{ left, right };
  const core::Sweep sweep = test::makeSweep({ { { 2.0f, 1.0f, 0.0f }, { 3.0f, 1.5f, 0.0f } },
                                              { { 2.5f, -1.0f, 0.0f }, { 3.0f, -1.2f, 0.0f } } });
  Labelled out = label(sweep, objects, { { Label::errorSurface, Label::error }, { Label::errorSurface, Label::error } });
  ASSERT_EQ(out.labels.echoes[1][0], Label::behindReflective);
  ASSERT_EQ(out.labels.echoes[1][1], Label::behindReflective);
  const std::vector<core::OutputPoint> cleaned = cleanedOf(sweep, objects, out);
  ASSERT_EQ(cleaned.size(), 4u);
  EXPECT_TRUE(cleaned[1].position.isApprox(Eigen::Vector3f(1.0f, 1.5f, 0.0f)));
  EXPECT_EQ(cleaned[1].label, Label::behindReflective);
  EXPECT_TRUE(cleaned[3].position.isApprox(Eigen::Vector3f(2.0f, -1.2f, 0.0f)));
  // Surface points stay where they were measured.
  EXPECT_TRUE(cleaned[0].position.isApprox(Eigen::Vector3f(2.0f, 1.0f, 0.0f)));
}

TEST(CleanedOutput, KeepsPointsBehindGlassInPlace)
{
  std::vector<core::ReflectiveObject> objects{ wallObject(2.0f, 1.0f, 1.0f, ObjectType::glass) };
  const core::Sweep sweep = test::makeSweep({ { { 2.0f, 0.0f, 0.0f }, { 3.0f, 0.0f, 0.0f } } });
  Labelled out = label(sweep, objects, { { Label::errorSurface, Label::error } });
  const std::vector<core::OutputPoint> cleaned = cleanedOf(sweep, objects, out);
  ASSERT_EQ(cleaned.size(), 2u);
  EXPECT_EQ(cleaned[1].label, Label::behindTransparent);
  EXPECT_TRUE(cleaned[1].position.isApprox(Eigen::Vector3f(3.0f, 0.0f, 0.0f)));
}

// A pane at x = 2 (3 m wide, 1 m high), a pillar 0.5 m in front of it (a face at x = 1.5 with y
// in [0.6, 1.2], |z| <= 0.2), seen directly (brightness 100), and the room seen through the pane
// at x = 6 (brightness 900). Each beam through the pane that shows the pillar's reflection
// (0.5 m behind the pane, within the sensor's echo separation) returns one echo of the pane's
// surface merged with that reflection, `shortfall` short of the reflection along the beam, with
// `brightness`; its second echo is the room seen through. A hundred and twenty beams elsewhere
// are mixed pixels 0.9 m apart: the sweep's echo separation. `real` holds, per merged echo's
// beam, where the pillar point it shows really is.
struct MergedEchoes
{
  core::Sweep sweep;
  std::map<std::size_t, Eigen::Vector3f> real;
};

bool onThePillar(const Eigen::Vector3f& x)
{
  return x.y() >= 0.6f && x.y() <= 1.2f && std::fabs(x.z()) <= 0.2f;
}

MergedEchoes mergedEchoesBehindAPane(float shortfall, float brightness)
{
  MergedEchoes out;
  out.sweep = test::rangeImage({ { 0, 1.5f, onThePillar }, { 0, 6.0f, test::everywhere } });
  core::Sweep& sweep = out.sweep;
  sweep.has_intensity = true;
  std::size_t mixed = 0;
  for (std::size_t i = 0; i < sweep.beamCount(); ++i)
  {
    const Eigen::Vector3f p = sweep.echoes[0].points[i];
    if (!p.allFinite())
      continue;
    const float seen = p.x() > 5.9f ? 900.0f : 100.0f;
    sweep.echoes[0].intensities[i] = sweep.echoes[1].intensities[i] = seen / p.squaredNorm();
    const Eigen::Vector3f d = p.normalized();
    if (p.x() > 5.9f && d.y() < -0.2f && mixed < 120)
    {
      // A mixed pixel: the far echo 0.9 m behind the near one.
      sweep.echoes[1].points[i] = p + 0.9f * d;
      ++mixed;
      continue;
    }
    if (!(p.x() > 5.9f))
      continue;  // the pillar, seen directly
    const Eigen::Vector3f crossing = d * (2.0f / d.x());
    if (std::fabs(crossing.y()) > 1.5f || std::fabs(crossing.z()) > 0.5f)
      continue;
    const float behind = 0.5f / d.x();  // along the reflected ray, to the pillar's face
    const Eigen::Vector3f real = crossing + behind * Eigen::Vector3f(-d.x(), d.y(), d.z());
    if (!onThePillar(real))
      continue;
    out.real[i] = real;
    sweep.echoes[0].points[i] = crossing + (behind - shortfall) * d;
    sweep.echoes[0].intensities[i] = brightness / sweep.echoes[0].points[i].squaredNorm();
  }
  sweep.computeRanges(Eigen::Vector3f::Zero());
  return out;
}

// The pane at x = 2 as object extraction would report it (its 0.6 m surface-echo patch, seeing
// through it as bright as the room), with as many surface echoes of its own as its phantom plane
// has (a phantom plane has about as many as its pane's patch, PhantomPlaneConfig::max_echo_ratio;
// only their count matters), and the object fitted to the merged echoes (typed mirror, as on the
// 128-ring lidar's random_11), with the largest x among them.
struct PaneAndMergedPlane
{
  core::ReflectiveObject pane;
  core::ReflectiveObject merged;
  float deepest = 0.0f;
};

PaneAndMergedPlane paneAndMergedPlane(const MergedEchoes& scene)
{
  PaneAndMergedPlane out;
  out.pane = wallObject(2.0f, 0.6f, 1.0f, ObjectType::glass, 0);
  out.pane.evidence.transmitted_brightness = 900.0f;
  Eigen::Vector3f low = Eigen::Vector3f::Constant(1e9f), high = -low;
  std::vector<core::PointRef> echoes;
  for (const auto& beam_and_real : scene.real)
  {
    const auto beam = static_cast<std::uint32_t>(beam_and_real.first);
    out.pane.surface_inliers.push_back(core::PointRef{ beam, 1 });
    const Eigen::Vector3f& p = scene.sweep.echoes[0].points[beam];
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
    echoes.push_back(core::PointRef{ beam, 0 });
  }
  out.merged = wallObject(0.5f * (low.x() + high.x()), high.y() - low.y() + 0.1f, high.z() - low.z() + 0.1f,
                          ObjectType::mirror, 1);
  out.merged.centre = 0.5f * (low + high);
  out.merged.surface_inliers = echoes;
  out.deepest = high.x();
  return out;
}

TEST(ConeLabelling, AnEchoOfThePaneMergedWithAReflectionIsBackProjectedToWhatItShows)
{
  // Short of the reflection by 0.2 m, each merged echo, reflected, lies between the pillar and
  // the pane: behind the pillar as the sensor sees it (occluded), or beside it, where the sensor
  // saw further (seen through). Faint against what is seen through the pane, it is taken for the
  // reflection it is merged with and back-projected to the pillar, where it lands when moved
  // along its beam. Short by 0.08 m, less than the landing tolerance, it lands as measured, and
  // would be back-projected 8 cm off: it is moved to where it lands exactly.
  for (const float shortfall : { 0.2f, 0.08f })
  {
    const MergedEchoes scene = mergedEchoesBehindAPane(shortfall, 20.0f);
    ASSERT_GT(scene.real.size(), 20u);
    ASSERT_LT(scene.real.size(), 100u);
    core::ReflectiveObject pane = wallObject(2.0f, 3.0f, 1.0f, ObjectType::glass);
    pane.evidence.transmitted_brightness = 900.0f;
    std::vector<core::ReflectiveObject> objects{ pane };
    Labelled out = label(scene.sweep, objects);
    core::ReflectionEvidence evidence;
    evidence.build(scene.sweep, out.labels, Eigen::Vector3f::Zero());
    ASSERT_NEAR(evidence.echoSeparation(), 0.9f, 0.01f);
    EXPECT_GE(out.assignment.merged_echoes[0].size(), scene.real.size() * 9 / 10) << "short by " << shortfall;
    const std::vector<core::OutputPoint> cleaned = cleanedOf(scene.sweep, objects, out);
    std::size_t near = 0;
    for (const core::OutputPoint& point : cleaned)
    {
      const auto real = scene.real.find(point.beam);
      if (point.echo != 1 || real == scene.real.end())
        continue;
      EXPECT_EQ(point.label, Label::behindReflective) << "short by " << shortfall;
      near += (point.position - real->second).norm() < 0.03f ? 1 : 0;
    }
    EXPECT_GE(near, scene.real.size() * 9 / 10) << near << " of " << scene.real.size() << ", short by " << shortfall;
  }
}

TEST(MergedEchoes, APointInFrontOfThePlaneHoldsNoMergedReflection)
{
  // A merged echo lies behind the pane. Asked about a point 2.4 m in front of it, with a landing
  // tolerance that grows with the depth behind the plane, the search for the reflection stepped
  // by a negative tolerance and never ended; now there is none to find.
  const MergedEchoes scene = mergedEchoesBehindAPane(0.2f, 20.0f);
  const core::ReflectionEvidence evidence = test::evidenceOf(scene.sweep);
  ASSERT_GT(evidence.echoSeparation(), 0.0f);
  core::ReflectiveObject pane = wallObject(2.0f, 3.0f, 1.0f, ObjectType::glass);
  pane.landing_tolerance.per_behind = 0.05f;
  EXPECT_FALSE(core::mergedReflection(evidence, pane, Eigen::Vector3f(0.2f, 0.18f, 0.0f)).allFinite());
  EXPECT_FALSE(core::mergedReflection(evidence, pane, Eigen::Vector3f(1.5f, 0.9f, 0.0f)).allFinite());
}

TEST(MergedEchoes, AnEchoSeenThroughOnlyAsMeasuredMayBeAMirrorsMergedEcho)
{
  // The pane at x = 2 as a mirror that returns its surface echo everywhere: merged with the
  // pillar's reflection, each echo lies 0.15 m short of it (the reflection outshines the surface
  // echo). Those that land beside the pillar as measured (seen through, by their own test) are no
  // longer seen through once moved a tenth to a third of their depth along their beams: they may
  // be merged echoes.
  const MergedEchoes scene = mergedEchoesBehindAPane(0.15f, 900.0f);
  const core::ReflectionEvidence evidence = test::evidenceOf(scene.sweep);
  ASSERT_NEAR(evidence.echoSeparation(), 0.9f, 0.01f);
  const core::ReflectiveObject mirror = wallObject(2.0f, 3.0f, 1.0f, ObjectType::mirror);
  std::size_t seen_through = 0, merged = 0;
  for (const auto& beam_and_real : scene.real)
  {
    const Eigen::Vector3f& p = scene.sweep.echoes[0].points[beam_and_real.first];
    if (evidence.test(mirror.plane, p, mirror.landing_tolerance).outcome != core::ReflectionOutcome::transmitted)
      continue;
    ++seen_through;
    merged += core::mayBeMergedReflection(evidence, mirror, p) ? 1 : 0;
  }
  ASSERT_GE(seen_through, 5u);
  EXPECT_GE(merged, seen_through * 9 / 10) << merged << " of " << seen_through;

  // Seen through and still seen through when moved: 0.4 m behind the pane, reflected into the
  // open room beside the pillar (y = -0.4), or 1.2 m behind it, beyond the echo separation.
  for (const Eigen::Vector3f& p : { Eigen::Vector3f(2.4f, -0.4f, 0.0f), Eigen::Vector3f(3.2f, -0.4f, 0.0f) })
  {
    ASSERT_EQ(evidence.test(mirror.plane, p, mirror.landing_tolerance).outcome, core::ReflectionOutcome::transmitted);
    EXPECT_FALSE(core::mayBeMergedReflection(evidence, mirror, p)) << p.transpose();
  }
}

TEST(ConeLabelling, APointSeenThroughAPaneAsBrightAsTheRestStaysWhereItWasMeasured)
{
  // The same echoes as bright as what is seen through the pane: real points just behind it,
  // however their reflections land when moved along their beams.
  const MergedEchoes scene = mergedEchoesBehindAPane(0.2f, 900.0f);
  core::ReflectiveObject pane = wallObject(2.0f, 3.0f, 1.0f, ObjectType::glass);
  pane.evidence.transmitted_brightness = 900.0f;
  std::vector<core::ReflectiveObject> objects{ pane };
  const Labelled out = label(scene.sweep, objects);
  EXPECT_TRUE(out.assignment.merged_echoes[0].empty());
  for (const auto& beam_and_real : scene.real)
    EXPECT_EQ(out.labels.echoes[0][beam_and_real.first], Label::behindTransparent);
}

TEST(ConeLabelling, WithoutDoubleEchoesToShowTheSeparationNoEchoIsTakenForMerged)
{
  // The sensor's echo separation unknown (fewer than a hundred double echoes: only the merged
  // echoes' beams, the mixed pixels removed), nothing says how far a merged echo may lie short.
  MergedEchoes scene = mergedEchoesBehindAPane(0.2f, 20.0f);
  for (std::size_t i = 0; i < scene.sweep.beamCount(); ++i)
    if (scene.real.count(i) == 0)
      scene.sweep.echoes[1].points[i] = scene.sweep.echoes[0].points[i];
  core::ReflectiveObject pane = wallObject(2.0f, 3.0f, 1.0f, ObjectType::glass);
  pane.evidence.transmitted_brightness = 900.0f;
  std::vector<core::ReflectiveObject> objects{ pane };
  const Labelled out = label(scene.sweep, objects);
  EXPECT_TRUE(out.assignment.merged_echoes[0].empty());
}

TEST(ConeLabelling, APlaneOfMergedEchoesBehindAPaneIsItsPhantomPlaneAndBackProjected)
{
  // The merged echoes 0.2 m short of the pillar's reflection lie on a plane 0.33 m behind the pane:
  // object extraction fits an object to them (typed mirror here, as on the 128-ring lidar's
  // random_11). Reflected
  // as measured they land nowhere, so they would not be the pane's phantoms; moved along their
  // beams they are, and the object becomes the pane's phantom plane. The pane's own rectangle (its
  // surface-echo patch, 0.6 m wide) does not reach them: its phantom plane's cone does, and they
  // are back-projected from there.
  const MergedEchoes scene = mergedEchoesBehindAPane(0.2f, 20.0f);
  const PaneAndMergedPlane fitted = paneAndMergedPlane(scene);
  const core::ReflectiveObject& pane = fitted.pane;
  const core::ReflectiveObject& merged = fitted.merged;
  std::vector<core::ReflectiveObject> objects{ pane, merged };
  core::SweepLabels labels;
  labels.reset(scene.sweep.beamCount());
  core::ReflectionEvidence evidence;
  evidence.build(scene.sweep, labels, Eigen::Vector3f::Zero());
  core::PhantomPlanes(core::stageConfigs(core::Params()).phantom_planes)
      .process(scene.sweep, core::SweepContext(), evidence, labels, objects);
  ASSERT_EQ(objects.size(), 1u);
  ASSERT_EQ(objects[0].phantom_planes.size(), 1u);

  // In front of an object not typed glass, the echoes are nobody's merged echoes (moved along
  // their beams, a real pane's surface echoes behind a small unknown object land too): the object
  // stays one of its own.
  core::ReflectiveObject speck = pane;
  speck.type = ObjectType::unknown;
  std::vector<core::ReflectiveObject> not_a_pane{ speck, merged };
  core::PhantomPlanes(core::stageConfigs(core::Params()).phantom_planes)
      .process(scene.sweep, core::SweepContext(), evidence, labels, not_a_pane);
  EXPECT_EQ(not_a_pane.size(), 2u);

  Labelled out = label(scene.sweep, objects);
  const std::vector<core::OutputPoint> cleaned = cleanedOf(scene.sweep, objects, out);
  std::size_t near = 0;
  for (const core::OutputPoint& point : cleaned)
  {
    const auto real = scene.real.find(point.beam);
    if (point.echo == 1 && real != scene.real.end())
      near += point.label == Label::behindReflective && (point.position - real->second).norm() < 0.05f ? 1 : 0;
  }
  EXPECT_GE(near, scene.real.size() * 9 / 10) << near << " of " << scene.real.size();
}

TEST(ConeLabelling, FaintEchoesJustBehindAPaneAreItsPhantomPlaneByTheirBrightness)
{
  // Short of the pillar's reflection by 0.3 m, the merged echoes lie on a plane 0.2 m behind the
  // pane, nearer than phantom_planes' min_depth (0.3 m): reflected across a plane they nearly lie
  // on they land next to themselves, and moved along their beams they need not land either (the
  // shortfall is a third of the echo separation). Faint against what the pane lets through, they
  // are its reflections all the same, and the object fitted to them is its phantom plane.
  const MergedEchoes scene = mergedEchoesBehindAPane(0.3f, 20.0f);
  ASSERT_GT(scene.real.size(), 20u);
  const PaneAndMergedPlane fitted = paneAndMergedPlane(scene);
  const core::ReflectiveObject& pane = fitted.pane;
  const core::ReflectiveObject& merged = fitted.merged;
  const float depth = fitted.deepest - 2.0f;
  const core::PhantomPlaneConfig config = core::stageConfigs(core::Params()).phantom_planes;
  ASSERT_LT(depth, config.min_depth);
  ASSERT_GT(depth, core::PhantomPlanes::kMinFaintDepth + 0.05f);
  core::SweepLabels labels;
  labels.reset(scene.sweep.beamCount());
  core::ReflectionEvidence evidence;
  evidence.build(scene.sweep, labels, Eigen::Vector3f::Zero());
  core::PhantomPlanes stage(config);
  const core::PhantomPlanes::Shares shares = stage.shares(scene.sweep, Eigen::Vector3f::Zero(), evidence, merged, pane);
  EXPECT_GE(shares.phantom, 0.9f);
  EXPECT_LT(shares.landed, config.min_share);
  std::vector<core::ReflectiveObject> objects{ pane, merged };
  stage.process(scene.sweep, core::SweepContext(), evidence, labels, objects);
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_EQ(objects[0].phantom_planes.size(), 1u);

  // As bright as what is seen through the pane: something real just behind it.
  const MergedEchoes bright = mergedEchoesBehindAPane(0.3f, 900.0f);
  core::ReflectionEvidence bright_evidence;
  bright_evidence.build(bright.sweep, labels, Eigen::Vector3f::Zero());
  EXPECT_LT(stage.shares(bright.sweep, Eigen::Vector3f::Zero(), bright_evidence, merged, pane).phantom, config.min_share);
  // Behind an object not typed glass brightness says nothing: nothing is seen through a mirror.
  core::ReflectiveObject mirror = pane;
  mirror.type = ObjectType::mirror;
  EXPECT_LT(stage.shares(scene.sweep, Eigen::Vector3f::Zero(), evidence, merged, mirror).phantom, config.min_share);
  // Far more echoes than the pane's: a pane's own surface echoes are faint too, and its larger
  // part just behind a speck of it is no reflection.
  core::ReflectiveObject speck = pane;
  speck.surface_inliers.resize(scene.real.size() / 5);
  EXPECT_LT(stage.shares(scene.sweep, Eigen::Vector3f::Zero(), evidence, merged, speck).phantom, config.min_share);
}


TEST(ConeLabelling, APaneGrownToItsExtentTakesTheFaintPhantomPlaneItsFewSurfaceEchoesCouldNot)
{
  // The pane's surface echoes only a fifth of the merged plane's (a patch at its mullion): by the
  // echo ratio it cannot hold the plane. Grown to its extent (0.6 x 1 m, larger than the plane's
  // rectangle), it is measured by that and takes the plane in.
  const MergedEchoes scene = mergedEchoesBehindAPane(0.3f, 20.0f);
  ASSERT_GT(scene.real.size(), 20u);
  const PaneAndMergedPlane fitted = paneAndMergedPlane(scene);
  core::ReflectiveObject patch = fitted.pane;
  patch.surface_inliers.resize(scene.real.size() / 5);
  const core::ReflectiveObject& merged = fitted.merged;
  ASSERT_LT(merged.width * merged.height, patch.width * patch.height);
  core::SweepLabels labels;
  labels.reset(scene.sweep.beamCount());
  core::ReflectionEvidence evidence;
  evidence.build(scene.sweep, labels, Eigen::Vector3f::Zero());
  const core::PhantomPlaneConfig config = core::stageConfigs(core::Params()).phantom_planes;
  core::PhantomPlanes stage(config);
  EXPECT_LT(stage.shares(scene.sweep, Eigen::Vector3f::Zero(), evidence, merged, patch).phantom, config.min_share);
  core::ReflectiveObject grown = patch;
  grown.grown = true;
  EXPECT_GE(stage.shares(scene.sweep, Eigen::Vector3f::Zero(), evidence, merged, grown).phantom, 0.9f);
  // Grown, but smaller than the plane: no reflection of something in front of it fills more than it.
  core::ReflectiveObject small = grown;
  small.width = 0.5f * merged.width;
  small.height = merged.height;
  EXPECT_LT(stage.shares(scene.sweep, Eigen::Vector3f::Zero(), evidence, merged, small).phantom, config.min_share);

  // The run after growth (grown_hosts_only, as the pipeline adds it) looks only at grown hosts.
  core::PhantomPlaneConfig after_growth = config;
  after_growth.grown_hosts_only = true;
  core::PhantomPlanes second(after_growth);
  core::ReflectiveObject whole = fitted.pane;  // all its surface echoes: within the echo ratio
  EXPECT_GE(stage.shares(scene.sweep, Eigen::Vector3f::Zero(), evidence, merged, whole).phantom, 0.9f);
  EXPECT_FLOAT_EQ(second.shares(scene.sweep, Eigen::Vector3f::Zero(), evidence, merged, whole).phantom, 0.0f);
  std::vector<core::ReflectiveObject> objects{ grown, merged };
  second.process(scene.sweep, core::SweepContext(), evidence, labels, objects);
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_EQ(objects[0].phantom_planes.size(), 1u);
}

// Near echoes on the plane x = 2 over y in [2.6, 3.4] and z in [-0.2, 0.2] (incidence 52-60 deg),
// each with a far echo 1 m further along its beam; even beams faint (brightness, intensity x r^2:
// 5), odd ones bright (2000), against a sweep reference of 1000. Labels them (near errorSurface,
// far error) with `object` and returns (near labels of the faint beams, of the bright ones):
// 17 x 9 beams, kObliqueFaint faint and kObliqueBright bright.
constexpr std::size_t kObliqueFaint = 77;
constexpr std::size_t kObliqueBright = 76;
std::pair<std::map<Label, std::size_t>, std::map<Label, std::size_t>>
labelObliqueLayer(core::ReflectiveObject& object)
{
  std::vector<test::Beam> beams;
  for (float y = 2.6f; y <= 3.4f + 1e-4f; y += 0.05f)
    for (float z = -0.2f; z <= 0.2f + 1e-4f; z += 0.05f)
    {
      const Eigen::Vector3f near(2.0f, y, z);
      beams.push_back(test::Beam{ near, near + near.normalized() });
    }
  core::Sweep sweep = test::makeSweep(beams);
  for (std::size_t i = 0; i < beams.size(); ++i)
    for (std::size_t k = 0; k < 2; ++k)
      sweep.echoes[k].intensities[i] = (i % 2 == 0 ? 5.0f : 2000.0f) / sweep.echoes[k].points[i].squaredNorm();
  object.intensity.scale.reference = 1000.0f;
  std::vector<core::ReflectiveObject> objects{ object };
  const Labelled out =
      label(sweep, objects, std::vector<std::pair<Label, Label>>(beams.size(), { Label::errorSurface, Label::error }));
  object = objects[0];
  std::map<Label, std::size_t> faint, bright;
  for (std::size_t i = 0; i < beams.size(); ++i)
    ++(i % 2 == 0 ? faint : bright)[out.labels.echoes[0][i]];
  return { faint, bright };
}

// A pane 2 m ahead whose rectangle spans y in [2.5, 3.5]: no beam meets it within 50 deg of
// perpendicular.
core::ReflectiveObject obliquePane(ObjectType type, float faint_share)
{
  core::ReflectiveObject object = wallObject(2.0f, 1.0f, 0.6f, type);
  object.centre = Eigen::Vector3f(2.0f, 3.0f, 0.0f);
  object.intensity.faint_share = faint_share;
  return object;
}

TEST(ConeLabelling, FaintEchoesOfGlassSeenOnlyFarFromPerpendicularAreDroppedAsReflections)
{
  // Glass returns a surface echo only near perpendicular incidence: a layer of faint near echoes
  // at 52-60 deg is the reflection, in a pane not found, of a surface in the room. Its faint
  // echoes are dropped; what is bright on the plane (a frame) stays glass's surface.
  core::ReflectiveObject glass = obliquePane(ObjectType::glass, 0.9f);
  const auto labels = labelObliqueLayer(glass);
  EXPECT_TRUE(glass.intensity.oblique_faint_surface);
  EXPECT_EQ(labels.first, (std::map<Label, std::size_t>{ { Label::error, kObliqueFaint } }));
  EXPECT_EQ(labels.second, (std::map<Label, std::size_t>{ { Label::transparentSurface, kObliqueBright } }));
  EXPECT_EQ(glass.surface_points, kObliqueBright);
}

TEST(ConeLabelling, FaintEchoesOnAnObjectMetNearPerpendicularOrOnAMirrorOrMostlyBrightStay)
{
  // The same layer on: glass whose rectangle reaches the sensor's perpendicular (its faint echoes
  // are its haze), a mirror (a mirror's silvered back hazes faintly at any angle), and glass whose
  // echoes off the specular peak are mostly bright. None of them drops an echo.
  core::ReflectiveObject wide = obliquePane(ObjectType::glass, 0.9f);
  wide.centre.y() = 1.5f;
  wide.width = 4.0f;
  const std::pair<core::ReflectiveObject, Label> cases[] = {
    { wide, Label::transparentSurface },
    { obliquePane(ObjectType::mirror, 0.9f), Label::reflectiveSurface },
    { obliquePane(ObjectType::glass, 0.3f), Label::transparentSurface },
  };
  for (const auto& c : cases)
  {
    core::ReflectiveObject object = c.first;
    const auto labels = labelObliqueLayer(object);
    EXPECT_FALSE(object.intensity.oblique_faint_surface);
    EXPECT_EQ(labels.first, (std::map<Label, std::size_t>{ { c.second, kObliqueFaint } }));
    EXPECT_EQ(labels.second, (std::map<Label, std::size_t>{ { c.second, kObliqueBright } }));
  }
}

}  // namespace
}  // namespace ohm_mirror_detector3d
