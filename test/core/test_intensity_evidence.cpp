#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "ohm_mirror_detector3d/core/intensity_evidence.h"
#include "ohm_mirror_detector3d/core/stage_configs.h"
#include "ohm_mirror_detector3d/core/vision_cone.h"

namespace ohm_mirror_detector3d
{
namespace
{
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kPlaneX = 2.0f;  // the object: the plane x = 2, y and z in [-0.5, 0.5], facing the sensor

core::ReflectiveObject object(core::ObjectType type = core::ObjectType::unknown)
{
  core::ReflectiveObject o;
  o.type = type;
  o.plane = Eigen::Vector4f(-1.0f, 0.0f, 0.0f, kPlaneX);
  o.centre = Eigen::Vector3f(kPlaneX, 0.0f, 0.0f);
  o.width_axis = Eigen::Vector3f::UnitY();
  o.height_axis = Eigen::Vector3f::UnitZ();
  o.width = o.height = 1.0f;
  return o;
}

struct Echo
{
  Eigen::Vector3f point;
  float intensity;
};

// A 1 x N sweep: per beam its near and far echo (far NaN: a single echo).
core::Sweep sweepOf(const std::vector<std::pair<Echo, Echo>>& beams)
{
  core::Sweep sweep;
  sweep.resize(1, beams.size());
  sweep.has_intensity = true;
  for (std::size_t i = 0; i < beams.size(); ++i)
  {
    sweep.echoes[0].points[i] = beams[i].first.point;
    sweep.echoes[0].intensities[i] = beams[i].first.intensity;
    sweep.echoes[1].points[i] = beams[i].second.point;
    sweep.echoes[1].intensities[i] = beams[i].second.intensity;
  }
  sweep.computeRanges(Eigen::Vector3f::Zero());
  return sweep;
}

const Echo kNone{ Eigen::Vector3f::Constant(kNaN), kNaN };

// Walls far away whose intensity * range^2 is 1: the sweep's reference (most of the beams).
void addWalls(std::vector<std::pair<Echo, Echo>>& beams, int count)
{
  for (int i = 0; i < count; ++i)
  {
    const Eigen::Vector3f p(-4.0f, -3.0f + 0.01f * i, 1.0f);
    beams.push_back({ Echo{ p, 1.0f / p.squaredNorm() }, kNone });
  }
}

// A point on the object seen at incidence beyond the specular peak (y = 0.4: atan(0.4 / 2) = 11 deg).
Eigen::Vector3f offPeak(int i)
{
  return Eigen::Vector3f(kPlaneX, 0.4f, -0.45f + 0.03f * i);
}

float cosIncidence(const Eigen::Vector3f& p)
{
  return p.x() / p.norm();
}

core::IntensityEvidenceConfig config()
{
  return core::stageConfigs(core::Params()).intensity;
}

core::SweepContext origin()
{
  return core::SweepContext();
}

// The stage with the default configuration over the objects of a sweep.
void runStage(const core::Sweep& sweep, std::vector<core::ReflectiveObject>& objects)
{
  core::SweepLabels labels;
  core::IntensityEvidence(config()).process(sweep, origin(), core::ReflectionEvidence(), labels, objects);
}

TEST(IntensityEvidence, MirrorHazeOverTheWholeFaceTypesAnUnknownObjectMirror)
{
  std::vector<std::pair<Echo, Echo>> beams;
  addWalls(beams, 200);
  // A mirror's haze: off the peak, 2 % of the reference (over cos(incidence)), each with a phantom behind.
  for (int i = 0; i < 30; ++i)
  {
    const Eigen::Vector3f p = offPeak(i);
    const float haze = 0.02f * cosIncidence(p) / p.squaredNorm();
    beams.push_back({ Echo{ p, haze }, Echo{ p * 2.0f, 4.0f * haze } });
  }
  const core::Sweep sweep = sweepOf(beams);
  const core::IntensityFeatures f =
      core::intensityFeatures(sweep, Eigen::Vector3f::Zero(), object(), core::intensityScale(sweep), config());
  EXPECT_EQ(f.echoes, 30u);
  EXPECT_EQ(f.off_peak, 30u);
  EXPECT_FLOAT_EQ(f.faint_share, 1.0f);
  EXPECT_NEAR(f.haze, 0.02f, 1e-4f);
  EXPECT_NEAR(f.echo_ratio, 4.0f, 1e-4f);
  EXPECT_GT(f.log_odds, config().type_log_odds);
  EXPECT_LE(f.log_odds, core::kMaxLogOdds);

  std::vector<core::ReflectiveObject> objects{ object() };
  runStage(sweep, objects);
  EXPECT_EQ(objects[0].type, core::ObjectType::mirror);
  EXPECT_TRUE(objects[0].intensity.typed);
}

// A pane's frame off the specular peak: 20 echoes as bright as a wall, nothing behind them.
void addFrame(std::vector<std::pair<Echo, Echo>>& beams)
{
  for (int i = 0; i < 20; ++i)
  {
    const Eigen::Vector3f p = offPeak(i);
    beams.push_back({ Echo{ p, 0.8f / p.squaredNorm() }, kNone });
  }
}

TEST(IntensityEvidence, BrightFrameOffThePeakAndFaintReflectionsTypeAnUnknownObjectGlass)
{
  std::vector<std::pair<Echo, Echo>> beams;
  addWalls(beams, 200);
  // Off the peak only the frame, as bright as a wall; near the perpendicular the saturated peak with what
  // is seen through behind it.
  addFrame(beams);
  for (int i = 0; i < 10; ++i)
  {
    const Eigen::Vector3f p(kPlaneX, 0.0f, -0.05f + 0.01f * i);
    beams.push_back({ Echo{ p, 50.0f }, Echo{ p * 3.0f, 50.0f * 0.001f } });
  }
  const core::Sweep sweep = sweepOf(beams);
  std::vector<core::ReflectiveObject> objects{ object(), object(core::ObjectType::mirror) };
  runStage(sweep, objects);
  const core::IntensityFeatures& f = objects[0].intensity;
  EXPECT_EQ(f.echoes, 30u);
  EXPECT_EQ(f.off_peak, 20u);
  EXPECT_FLOAT_EQ(f.faint_share, 0.0f);
  EXPECT_TRUE(std::isnan(f.haze)) << "no faint echo";
  EXPECT_NEAR(f.echo_ratio, 0.001f, 1e-6f);
  EXPECT_EQ(f.bright_off_peak, 20u);
  EXPECT_FLOAT_EQ(f.bright_backed_share, 0.0f) << "nothing behind the frame";
  EXPECT_FALSE(core::diffuseReflector(f));
  EXPECT_LT(f.log_odds, -config().type_log_odds);
  EXPECT_EQ(objects[0].type, core::ObjectType::glass);
  EXPECT_TRUE(objects[0].intensity.typed);
  // The geometry's verdict stands against the log-odds: they type only what it left unknown.
  EXPECT_EQ(objects[1].type, core::ObjectType::mirror);
  EXPECT_FALSE(objects[1].intensity.typed);
  EXPECT_FLOAT_EQ(objects[1].intensity.log_odds, f.log_odds);
}

TEST(IntensityEvidence, TooFewEchoesOrNoIntensitiesSayNothing)
{
  std::vector<std::pair<Echo, Echo>> beams;
  addWalls(beams, 50);
  for (int i = 0; i < 4; ++i)  // fewer than kMinFeatureEchoes off the peak
  {
    const Eigen::Vector3f p = offPeak(i);
    beams.push_back({ Echo{ p, 0.02f * cosIncidence(p) / p.squaredNorm() }, kNone });
  }
  core::Sweep sweep = sweepOf(beams);
  std::vector<core::ReflectiveObject> objects{ object() };
  runStage(sweep, objects);
  EXPECT_EQ(objects[0].intensity.echoes, 4u);
  EXPECT_TRUE(std::isnan(objects[0].intensity.faint_share));
  EXPECT_FLOAT_EQ(objects[0].intensity.log_odds, 0.0f);
  EXPECT_EQ(objects[0].type, core::ObjectType::unknown);

  sweep.has_intensity = false;
  objects = { object() };
  runStage(sweep, objects);
  EXPECT_EQ(objects[0].intensity.echoes, 0u);
  EXPECT_EQ(objects[0].type, core::ObjectType::unknown);
}

TEST(IntensityEvidence, FeatureLogLikelihoodRatioFavoursTheNearerMean)
{
  const core::FeatureModel model{ -1.6f, -2.7f, 0.35f };
  EXPECT_GT(model.logLikelihoodRatio(-1.6f), 0.0f);
  EXPECT_LT(model.logLikelihoodRatio(-2.7f), 0.0f);
  EXPECT_NEAR(model.logLikelihoodRatio(-2.15f), 0.0f, 1e-5f);
  EXPECT_NEAR(model.logLikelihoodRatio(-1.6f), 0.5f * (1.1f / 0.35f) * (1.1f / 0.35f), 1e-3f);
}

TEST(IntensityEvidence, OnByDefaultWithTheModelFromTheTableAndTheGrowthCapAsItsReach)
{
  core::Params params;
  EXPECT_TRUE(core::stageConfigs(params).intensity.enabled);
  params.intensity_evidence = 0;
  EXPECT_FALSE(core::stageConfigs(params).intensity.enabled);
  params.intensity_evidence = 1;
  params.intensity_haze_mirror = -1.2;
  params.growth_max_extent = 0.7;
  const core::IntensityEvidenceConfig c = core::stageConfigs(params).intensity;
  EXPECT_TRUE(c.enabled);
  EXPECT_FLOAT_EQ(c.model.haze.mirror, -1.2f);
  EXPECT_FLOAT_EQ(c.model.faint_share.glass, static_cast<float>(params.intensity_faint_share_glass));
  EXPECT_FLOAT_EQ(c.plane_threshold, static_cast<float>(params.plane_threshold));
  EXPECT_FLOAT_EQ(c.reach, 0.7f);
}

// Walls at ranges from 1 to 10 m of reflectivities from 0.6 to 1.4: a raw signal falls with
// range squared, a reflectivity does not.
void addRoom(std::vector<std::pair<Echo, Echo>>& beams, int count, bool range_compensated)
{
  for (int i = 0; i < count; ++i)
  {
    const float range = 1.0f + 9.0f * static_cast<float>(i % 37) / 36.0f;
    const float reflectivity = 0.6f + 0.8f * static_cast<float>(i % 11) / 10.0f;
    const Eigen::Vector3f p = range * Eigen::Vector3f(-0.8f, 0.6f, 0.0f);
    beams.push_back({ Echo{ p, range_compensated ? reflectivity : reflectivity / (range * range) }, kNone });
  }
}

// A mirror's haze off the peak with a phantom behind each echo (phantom_gain times as bright), as a
// raw signal or compensated.
void addMirrorHaze(std::vector<std::pair<Echo, Echo>>& beams, bool range_compensated, float phantom_gain = 4.0f)
{
  for (int i = 0; i < 30; ++i)
  {
    const Eigen::Vector3f p = offPeak(i);
    const float haze = 0.02f * cosIncidence(p) / p.squaredNorm();
    const Eigen::Vector3f phantom = p * 2.0f;
    const float scale_near = range_compensated ? p.squaredNorm() : 1.0f;
    const float scale_far = range_compensated ? phantom.squaredNorm() : 1.0f;
    beams.push_back({ Echo{ p, haze * scale_near }, Echo{ phantom, phantom_gain * haze * scale_far } });
  }
}

TEST(IntensityEvidence, ARangeCompensatedReflectivityIsToldFromTheSweepAndGivesTheSameFeatures)
{
  core::IntensityFeatures features[2];
  for (const bool compensated : { false, true })
  {
    std::vector<std::pair<Echo, Echo>> beams;
    addRoom(beams, 400, compensated);
    addMirrorHaze(beams, compensated);
    const core::Sweep sweep = sweepOf(beams);
    const core::IntensityScale scale = core::intensityScale(sweep);
    EXPECT_EQ(scale.range_compensated, compensated);
    features[compensated ? 1 : 0] = core::intensityFeatures(sweep, Eigen::Vector3f::Zero(), object(), scale, config());
  }
  const core::IntensityFeatures& raw = features[0];
  const core::IntensityFeatures& compensated = features[1];
  EXPECT_EQ(raw.off_peak, 30u);
  EXPECT_FLOAT_EQ(raw.faint_share, 1.0f);
  EXPECT_GT(raw.log_odds, config().type_log_odds);
  EXPECT_EQ(compensated.off_peak, raw.off_peak);
  EXPECT_FLOAT_EQ(compensated.faint_share, raw.faint_share);
  EXPECT_NEAR(compensated.haze, raw.haze, 1e-3f * raw.haze);
  EXPECT_NEAR(compensated.echo_ratio, raw.echo_ratio, 1e-3f * raw.echo_ratio);
  EXPECT_NEAR(compensated.log_odds, raw.log_odds, 1e-3f);
}

// 200 walls and a mirror's haze on the object (beams 200-229).
core::Sweep hazeSweep()
{
  std::vector<std::pair<Echo, Echo>> beams;
  addWalls(beams, 200);
  addMirrorHaze(beams, false);
  return sweepOf(beams);
}

// The object of hazeSweep, its haze echoes as its surface inliers.
core::ReflectiveObject hazeObject()
{
  core::ReflectiveObject o = object();
  for (std::size_t beam = 200; beam < 230; ++beam)
    o.surface_inliers.push_back(core::PointRef{ static_cast<std::uint32_t>(beam), 0 });
  return o;
}

TEST(IntensityEvidence, AnObjectSeenBehindAnotherIsNotTypedByItsIntensities)
{
  const core::Sweep sweep = hazeSweep();

  // A pane 1 m in front of the object, 0.2 m wide, beside the object's echoes: they lie behind its
  // plane 0.2 m and more beside its rectangle (seen through it, when the pane is larger than its patch).
  core::ReflectiveObject pane = object(core::ObjectType::glass);
  pane.plane = Eigen::Vector4f(-1.0f, 0.0f, 0.0f, 1.0f);
  pane.centre = Eigen::Vector3f(1.0f, -0.2f, 0.0f);
  pane.width = 0.2f;
  const core::ReflectiveObject behind = hazeObject();

  core::IntensityEvidenceConfig c = config();
  core::SweepLabels labels;
  for (const float reach : { 1.5f, 0.1f })
  {
    c.reach = reach;
    std::vector<core::ReflectiveObject> objects{ behind, pane };
    core::IntensityEvidence(c).process(sweep, origin(), core::ReflectionEvidence(), labels, objects);
    EXPECT_GT(objects[0].intensity.log_odds, c.type_log_odds) << "the features are computed all the same";
    if (reach > 1.0f)
    {
      EXPECT_EQ(objects[0].type, core::ObjectType::unknown) << "within reach of the pane";
      EXPECT_FALSE(objects[0].intensity.typed);
    }
    else
    {
      EXPECT_EQ(objects[0].type, core::ObjectType::mirror) << "beyond the reach of the pane's rectangle";
      EXPECT_TRUE(objects[0].intensity.typed);
    }
  }
}

TEST(IntensityEvidence, AFragmentJustOffTheObjectsPlaneDoesNotHideIt)
{
  const core::Sweep sweep = hazeSweep();
  const core::ReflectiveObject haze = hazeObject();

  // A 10 x 10 cm patch 0.6 m beside the object's centre, its plane turned 10 deg from the object's:
  // the object's echoes lie 0.17 m behind that plane, within the reach of its rectangle, but the
  // object's centre only 0.10 m (under kMinDepthBehindAnother): the same surface, not one seen
  // through the patch.
  const float turn = 10.0f * static_cast<float>(M_PI) / 180.0f;
  core::ReflectiveObject patch = object(core::ObjectType::glass);
  patch.centre = Eigen::Vector3f(kPlaneX, -0.6f, 0.0f);
  const Eigen::Vector3f normal(-std::cos(turn), -std::sin(turn), 0.0f);
  patch.plane = Eigen::Vector4f(normal.x(), normal.y(), normal.z(), -normal.dot(patch.centre));
  patch.width_axis = Eigen::Vector3f(-normal.y(), normal.x(), 0.0f);
  patch.width = patch.height = 0.1f;
  ASSERT_LT(patch.signedDistance(sweep.echoes[0].points[200]), -0.15f);
  ASSERT_GT(patch.signedDistance(haze.centre), -core::kMinDepthBehindAnother);

  std::vector<core::ReflectiveObject> objects{ haze, patch };
  runStage(sweep, objects);
  EXPECT_EQ(objects[0].type, core::ObjectType::mirror);
  EXPECT_TRUE(objects[0].intensity.typed);
}

TEST(IntensityEvidence, AnObjectWhosePlanePassesNextToTheSensorHidesNothing)
{
  const core::Sweep sweep = hazeSweep();
  const core::ReflectiveObject haze = hazeObject();

  // A mirror 0.7 m away whose plane passes 4 cm from the sensor, seen edge-on: grown by the
  // reach, its rectangle takes in the part of its plane beside the sensor, through which every
  // ray to the object crosses it. Nothing is seen through a plane from that close.
  core::ReflectiveObject edge_on = object(core::ObjectType::mirror);
  const Eigen::Vector3f normal(-0.6f, 0.8f, 0.0f);
  edge_on.plane = Eigen::Vector4f(normal.x(), normal.y(), normal.z(), 0.04f);
  edge_on.centre = Eigen::Vector3f(0.6f, 0.4f, 0.0f);
  edge_on.width_axis = Eigen::Vector3f(0.8f, 0.6f, 0.0f);
  edge_on.width = 0.5f;
  edge_on.height = 0.7f;
  ASSERT_NEAR(edge_on.signedDistance(edge_on.centre), 0.0f, 1e-6f);
  ASSERT_LT(edge_on.signedDistance(haze.centre), -core::kMinDepthBehindAnother);
  ASSERT_LT(edge_on.signedDistance(Eigen::Vector3f::Zero()), core::kMinSeenThroughPlaneDistance);
  ASSERT_EQ(core::locateInCone(edge_on, Eigen::Vector3f::Zero(), sweep.echoes[0].points[200], config().plane_threshold,
                               config().reach)
                .relation,
            core::ConeRelation::behind)
      << "the grown cone holds the object's echoes";

  std::vector<core::ReflectiveObject> objects{ haze, edge_on };
  runStage(sweep, objects);
  EXPECT_EQ(objects[0].type, core::ObjectType::mirror);
  EXPECT_TRUE(objects[0].intensity.typed);
}

// Shiny metal: off its peak lit like a wall (30 % of the reference over cos(incidence)), each echo with
// its reflection behind the plane; `backed` of the 30 beams have it.
void addShinyMetal(std::vector<std::pair<Echo, Echo>>& beams, int backed = 30)
{
  for (int i = 0; i < 30; ++i)
  {
    const Eigen::Vector3f p = offPeak(i);
    const float lit = 0.3f * cosIncidence(p) / p.squaredNorm();
    beams.push_back({ Echo{ p, lit }, i < backed ? Echo{ p * 1.4f, 0.25f * lit } : kNone });
  }
}

// An object the type analysis looked at, every point behind its inside with a surface echo in front.
core::ReflectiveObject analysed(core::ObjectType type = core::ObjectType::unknown)
{
  core::ReflectiveObject o = object(type);
  o.evidence.surface_backed_share = 1.0f;
  return o;
}

// An object the geometry typed glass: its points behind, as the type analysis counted them.
// An object of the given type with its points behind as the type analysis counted them.
core::ReflectiveObject counted(core::ObjectType type, std::size_t phantoms, std::size_t transmitted,
                               std::size_t undecided, std::size_t path_blocked = 0)
{
  core::ReflectiveObject o = analysed(type);
  o.evidence.phantom_points = phantoms;
  o.evidence.transmitted_points = transmitted;
  o.evidence.undecided_points = undecided;
  o.evidence.path_blocked_points = path_blocked;
  return o;
}

core::ReflectiveObject geometricGlass(std::size_t phantoms, std::size_t transmitted, std::size_t undecided)
{
  return counted(core::ObjectType::glass, phantoms, transmitted, undecided);
}

TEST(IntensityEvidence, ShinyMetalIsAMirrorWhereTheGeometrySaidGlassOrNothing)
{
  std::vector<std::pair<Echo, Echo>> beams;
  addWalls(beams, 200);
  addShinyMetal(beams);
  const core::Sweep sweep = sweepOf(beams);
  // Unknown; glass from occluded points (none seen through); glass with some seen through, fewer than
  // twice the rest; a mirror.
  std::vector<core::ReflectiveObject> objects{ analysed(), geometricGlass(0, 0, 220), geometricGlass(20, 130, 50),
                                               analysed(core::ObjectType::mirror) };
  runStage(sweep, objects);
  const core::IntensityFeatures& f = objects[0].intensity;
  EXPECT_EQ(f.off_peak, 30u);
  EXPECT_EQ(f.bright_off_peak, 30u);
  EXPECT_FLOAT_EQ(f.bright_backed_share, 1.0f);
  EXPECT_TRUE(core::diffuseReflector(f));
  EXPECT_LT(f.log_odds, 0.0f) << "to the mirror/glass features a bright surface off the peak looks like glass";
  for (std::size_t j = 0; j < 3; ++j)
  {
    EXPECT_EQ(objects[j].type, core::ObjectType::mirror) << j;
    EXPECT_TRUE(objects[j].intensity.diffuse_reflector) << j;
    EXPECT_FALSE(objects[j].intensity.typed) << j;
  }
  EXPECT_EQ(objects[3].type, core::ObjectType::mirror);
  EXPECT_FALSE(objects[3].intensity.diffuse_reflector) << "the geometry's mirror needs no rule";
}

TEST(IntensityEvidence, ShinyMetalWithFourFifthsOfItsEchoesBackedAndSomeMergedIsAMirror)
{
  // Stop 50: metal panels whose bright echoes have a reflection behind for 76-85 % of them, and
  // whose points behind have their surface echo in front for 76-89 % (merged echoes), were left
  // glass by the old thresholds (0.85 and 0.9).
  std::vector<std::pair<Echo, Echo>> beams;
  addWalls(beams, 200);
  addShinyMetal(beams, 24);
  const core::Sweep sweep = sweepOf(beams);
  core::ReflectiveObject panel = geometricGlass(0, 0, 220);
  panel.evidence.surface_backed_share = 0.8f;
  std::vector<core::ReflectiveObject> objects{ panel };
  runStage(sweep, objects);
  EXPECT_NEAR(objects[0].intensity.bright_backed_share, 0.8f, 1e-6f);
  EXPECT_EQ(objects[0].type, core::ObjectType::mirror);
  EXPECT_TRUE(objects[0].intensity.diffuse_reflector);
}

TEST(IntensityEvidence, GlassSeenThroughOrTypedByDimPhantomsStaysGlassAndABrightSurfaceNeedsReflectionsBehind)
{
  std::vector<std::pair<Echo, Echo>> beams;
  addWalls(beams, 200);
  addShinyMetal(beams);
  const core::Sweep sweep = sweepOf(beams);
  core::ReflectiveObject dim = geometricGlass(0, 0, 220);
  dim.evidence.typed_by_dim_phantoms = true;
  std::vector<core::ReflectiveObject> objects{ geometricGlass(20, 141, 50), dim };
  EXPECT_FALSE(core::diffuseReflectorMayOverrule(objects[0])) << "141 seen through > 2 x (20 + 50)";
  EXPECT_TRUE(core::diffuseReflectorMayOverrule(geometricGlass(20, 140, 50)));
  runStage(sweep, objects);
  for (const core::ReflectiveObject& o : objects)
  {
    EXPECT_TRUE(core::diffuseReflector(o.intensity));
    EXPECT_EQ(o.type, core::ObjectType::glass);
    EXPECT_FALSE(o.intensity.diffuse_reflector);
  }

  // A strip 0.2 m wide around the same echoes (mixed pixels along a depth edge): no rule.
  core::ReflectiveObject strip = geometricGlass(0, 0, 220);
  strip.centre.y() = offPeak(0).y();
  strip.width = 0.2f;
  objects = { strip };
  runStage(sweep, objects);
  EXPECT_TRUE(core::diffuseReflector(objects[0].intensity)) << "its echoes are a reflector's";
  EXPECT_FALSE(core::diffuseReflector(objects[0]));
  EXPECT_EQ(objects[0].type, core::ObjectType::glass);

  // Points seen through its inside without a surface echo in front (a pane, bright only at its frame): no rule.
  core::ReflectiveObject framed_pane = geometricGlass(0, 0, 220);
  framed_pane.evidence.surface_backed_share = 0.6f;
  objects = { framed_pane };
  runStage(sweep, objects);
  EXPECT_TRUE(core::diffuseReflector(objects[0].intensity));
  EXPECT_FALSE(core::diffuseReflector(objects[0]));
  EXPECT_EQ(objects[0].type, core::ObjectType::glass);

  // Under 75 % of the bright echoes with a reflection behind (a wall in the plane, a frame): no rule.
  std::vector<std::pair<Echo, Echo>> framed;
  addWalls(framed, 200);
  addShinyMetal(framed, 22);
  const core::Sweep framed_sweep = sweepOf(framed);
  objects = { analysed(), geometricGlass(0, 0, 220) };
  runStage(framed_sweep, objects);
  EXPECT_NEAR(objects[0].intensity.bright_backed_share, 22.0f / 30.0f, 1e-6f);
  EXPECT_FALSE(core::diffuseReflector(objects[0].intensity));
  EXPECT_NE(objects[0].type, core::ObjectType::mirror);
  EXPECT_EQ(objects[1].type, core::ObjectType::glass);
}

// Reflective glass as the geometry may take it for a mirror: off its peak only the frame and the
// wall around it, lit like a wall, with nothing behind; near the perpendicular a faint echo on the
// pane and, `ratio` times as bright, what is seen through it.
void addReflectivePane(std::vector<std::pair<Echo, Echo>>& beams, float ratio)
{
  addFrame(beams);
  for (int i = 0; i < 10; ++i)
  {
    const Eigen::Vector3f p(kPlaneX, 0.0f, -0.05f + 0.01f * i);
    const float seen_through = 1.0f / (9.0f * p.squaredNorm());
    beams.push_back({ Echo{ p, seen_through / ratio }, Echo{ p * 3.0f, seen_through } });
  }
}

TEST(IntensityEvidence, APaneTheGeometryTookForAMirrorIsGlassByItsEchoes)
{
  std::vector<std::pair<Echo, Echo>> beams;
  addWalls(beams, 200);
  addReflectivePane(beams, 50.0f);
  const core::Sweep sweep = sweepOf(beams);
  std::vector<core::ReflectiveObject> objects{ analysed(core::ObjectType::mirror) };
  runStage(sweep, objects);
  const core::IntensityFeatures& f = objects[0].intensity;
  EXPECT_EQ(f.off_peak, 20u);
  EXPECT_FLOAT_EQ(f.faint_share, 0.0f);
  EXPECT_NEAR(f.echo_ratio, 50.0f, 0.01f);
  EXPECT_TRUE(core::paneByItsEchoes(f));
  EXPECT_EQ(objects[0].type, core::ObjectType::glass);
  EXPECT_TRUE(objects[0].intensity.pane_by_echoes);
  EXPECT_FALSE(objects[0].intensity.typed) << "a rule on the geometry's mirror, not the log-odds";

  // Far echoes only ten times the near ones: the geometry's mirror stands.
  std::vector<std::pair<Echo, Echo>> dimmer;
  addWalls(dimmer, 200);
  addReflectivePane(dimmer, 10.0f);
  objects = { analysed(core::ObjectType::mirror) };
  runStage(sweepOf(dimmer), objects);
  EXPECT_FALSE(core::paneByItsEchoes(objects[0].intensity));
  EXPECT_EQ(objects[0].type, core::ObjectType::mirror);
  EXPECT_FALSE(objects[0].intensity.pane_by_echoes);
}

TEST(IntensityEvidence, AMirrorsHazeOrShinyMetalsLitFaceKeepsTheGeometrysMirror)
{
  // A mirror: a faint haze off its peak, its phantoms 30 times as bright as the haze.
  std::vector<std::pair<Echo, Echo>> mirror_beams;
  addWalls(mirror_beams, 200);
  addMirrorHaze(mirror_beams, false, 30.0f);
  std::vector<core::ReflectiveObject> objects{ analysed(core::ObjectType::mirror) };
  runStage(sweepOf(mirror_beams), objects);
  EXPECT_FLOAT_EQ(objects[0].intensity.faint_share, 1.0f);
  EXPECT_GE(objects[0].intensity.echo_ratio, core::kMinPaneEchoRatio);
  EXPECT_EQ(objects[0].type, core::ObjectType::mirror);
  EXPECT_FALSE(objects[0].intensity.pane_by_echoes);

  // Shiny metal: lit like a wall off its peak, its reflections dimmer than that.
  std::vector<std::pair<Echo, Echo>> metal_beams;
  addWalls(metal_beams, 200);
  addShinyMetal(metal_beams);
  objects = { analysed(core::ObjectType::mirror) };
  runStage(sweepOf(metal_beams), objects);
  EXPECT_FLOAT_EQ(objects[0].intensity.faint_share, 0.0f);
  EXPECT_LT(objects[0].intensity.echo_ratio, 1.0f);
  EXPECT_EQ(objects[0].type, core::ObjectType::mirror);
  EXPECT_FALSE(objects[0].intensity.pane_by_echoes);
}


// An object the geometry left unknown, with `seen_through` points behind it seen through (and
// `path_blocked` of its occluded ones real by their path) and `phantoms` landed as phantoms.
core::ReflectiveObject unknownSeenThrough(std::size_t seen_through, std::size_t phantoms, std::size_t path_blocked = 0)
{
  return counted(core::ObjectType::unknown, phantoms, seen_through, path_blocked, path_blocked);
}

TEST(IntensityEvidence, AnUnknownObjectSeenThroughWhoseIntensitiesLeanToGlassIsGlass)
{
  // Off the peak only a frame lit like a wall: intensities of glass. The typing threshold is set out
  // of reach, so that the log-odds lean to glass without typing anything by themselves.
  std::vector<std::pair<Echo, Echo>> beams;
  addWalls(beams, 200);
  addFrame(beams);
  const core::Sweep pane_sweep = sweepOf(beams);
  core::IntensityEvidenceConfig leaning = config();
  leaning.type_log_odds = 100.0f;
  ASSERT_EQ(leaning.min_seen_through, 30u) << "icp_min_points";
  auto run = [&leaning](const core::Sweep& sweep, std::vector<core::ReflectiveObject>& objects) {
    core::SweepLabels labels;
    core::IntensityEvidence(leaning).process(sweep, origin(), core::ReflectionEvidence(), labels, objects);
  };
  std::vector<core::ReflectiveObject> objects{ unknownSeenThrough(40, 0),      unknownSeenThrough(10, 0, 20),
                                               unknownSeenThrough(40, 21),     unknownSeenThrough(29, 0),
                                               analysed(core::ObjectType::mirror) };
  objects[4].evidence.transmitted_points = 100;
  run(pane_sweep, objects);
  ASSERT_LT(objects[0].intensity.log_odds, 0.0f);
  EXPECT_FALSE(core::diffuseReflector(objects[0].intensity)) << "nothing behind the frame";
  for (std::size_t j = 0; j < 2; ++j)
  {
    EXPECT_EQ(objects[j].type, core::ObjectType::glass) << j;
    EXPECT_TRUE(objects[j].intensity.seen_through_pane) << j;
    EXPECT_FALSE(objects[j].intensity.typed) << j;
  }
  // Seen through, but fewer than twice as many as landed; too few seen through; typed by the geometry.
  for (std::size_t j = 2; j < 4; ++j)
  {
    EXPECT_EQ(objects[j].type, core::ObjectType::unknown) << j;
    EXPECT_FALSE(objects[j].intensity.seen_through_pane) << j;
  }
  EXPECT_EQ(objects[4].type, core::ObjectType::mirror);
  EXPECT_FALSE(objects[4].intensity.seen_through_pane);

  // Intensities of a mirror (a faint haze over its face, phantoms behind): beside a mirror the sensor
  // sees as much, and the object stays unknown.
  std::vector<std::pair<Echo, Echo>> mirror_beams;
  addWalls(mirror_beams, 200);
  addMirrorHaze(mirror_beams, false);
  objects = { unknownSeenThrough(40, 0) };
  run(sweepOf(mirror_beams), objects);
  ASSERT_GT(objects[0].intensity.log_odds, 0.0f);
  EXPECT_EQ(objects[0].type, core::ObjectType::unknown);
  EXPECT_FALSE(objects[0].intensity.seen_through_pane);
}

}  // namespace
}  // namespace ohm_mirror_detector3d
