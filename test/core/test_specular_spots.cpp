#include <gtest/gtest.h>

#include <cmath>

#include "ohm_mirror_detector3d/core/echo_comparison.h"
#include "ohm_mirror_detector3d/core/pipeline.h"
#include "ohm_mirror_detector3d/core/range_gate.h"
#include "ohm_mirror_detector3d/core/specular_spots.h"
#include "ohm_mirror_detector3d/core/stage_configs.h"
#include "ohm_mirror_detector3d/core/sweep_sampling.h"
#include "sweep_fixtures.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::Label;

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kDegree = static_cast<float>(M_PI) / 180.0f;

// A wall 4 m ahead (x = 4) with an opening of +-0.6 m (y, z). A pane in
// the opening returns an echo only within 1.5 degrees of perpendicular incidence, 30 times as bright
// as the wall (intensity x range^2); elsewhere the rays pass it and, with `open_behind`, return
// nothing (a window to the sky), else from a wall 0.02 m behind the pane (no opening at all: a
// bright patch on an opaque surface). The opening and its bright patch are centred at
// `bright_azimuth_deg`: away from 0 the patch is not where the beams meet the wall head-on.
core::Sweep windowSweep(bool open_behind, float bright_azimuth_deg = 0.0f)
{
  // 0.5 degree steps, elevation -20..20, azimuth -30..30.
  return test::gridSweep(81, 121, -20.0f, 0.5f, 0.0f, -30.0f, 0.5f, [&](const Eigen::Vector3f& d) {
    const float t = 4.0f / d.x();
    const Eigen::Vector3f on_wall = t * d;
    const bool in_opening = std::fabs(on_wall.y() - 4.0f * std::tan(bright_azimuth_deg * kDegree)) < 0.6f &&
                            std::fabs(on_wall.z()) < 0.6f;
    const float wall_intensity = 1.0f / (t * t);
    if (!in_opening)
      return std::make_pair(Eigen::Vector3f(on_wall), wall_intensity);
    const Eigen::Vector3f bright_axis(std::cos(bright_azimuth_deg * kDegree), std::sin(bright_azimuth_deg * kDegree),
                                      0.0f);
    if (std::acos(std::min(1.0f, d.dot(bright_axis))) < 1.5f * kDegree)
      return std::make_pair(Eigen::Vector3f(on_wall), 30.0f * wall_intensity);
    if (open_behind)
      return std::make_pair(Eigen::Vector3f(Eigen::Vector3f::Constant(kNaN)), kNaN);
    const Eigen::Vector3f behind = (4.02f / d.x()) * d;
    return std::make_pair(Eigen::Vector3f(behind), wall_intensity);
  });
}

// The returns the pane gave: in the opening, and not on the wall.
std::size_t paneReturns(const core::Sweep& sweep, float bright_azimuth_deg = 0.0f)
{
  std::size_t count = 0;
  for (const Eigen::Vector3f& p : sweep.echoes[0].points)
    count += p.allFinite() && std::fabs(p.y() - 4.0f * std::tan(bright_azimuth_deg * kDegree)) < 0.6f &&
                     std::fabs(p.z()) < 0.6f
                 ? 1
                 : 0;
  return count;
}

struct Spotted
{
  core::SweepLabels labels;
  std::size_t labelled = 0;
};

Spotted findSpots(core::Sweep sweep, const core::Params& params = core::Params())
{
  sweep.has_intensity = true;
  Spotted out;
  out.labels.reset(sweep.beamCount());
  const core::StageConfigs configs = core::stageConfigs(params);
  core::RangeGate(configs.range_gate).apply(sweep, out.labels);
  core::EchoComparison(configs.echo_comparison).apply(sweep, out.labels);
  core::SamplingEstimator estimator;
  const core::SweepSampling sampling = estimator.estimate(sweep, Eigen::Vector3f::Zero());
  core::SpecularSpots spots(configs.specular_spots);
  out.labelled = spots.apply(sweep, sampling, Eigen::Vector3f::Zero(), out.labels);
  return out;
}

TEST(SpecularSpots, APaneMetHeadOnWithNothingInRangeBehindItGivesSurfaceEchoes)
{
  const Spotted out = findSpots(windowSweep(true));
  // The head-on spot (the beams within 1.5 degrees) and its rim on the pane's plane (the pane
  // returned nothing there: none); nothing else in the sweep.
  EXPECT_GE(out.labelled, 25u);
  EXPECT_EQ(out.labelled, paneReturns(windowSweep(true)));
  EXPECT_EQ(out.labels.count(0, Label::errorSurface), out.labelled);
  const std::size_t centre = 40 * 121 + 60;
  EXPECT_EQ(out.labels.echoes[0][centre], Label::errorSurface);
  EXPECT_EQ(out.labels.echoes[0][0], Label::unchecked);
  // Off, it finds nothing.
  core::Params off;
  off.specular_spot_ratio = 0.0;
  EXPECT_EQ(findSpots(windowSweep(true), off).labelled, 0u);
}

TEST(SpecularSpots, ABrightPatchOnAnOpaqueSurfaceIsNoSpot)
{
  // The same bright returns, but the rays around them come back from just behind their plane.
  EXPECT_EQ(findSpots(windowSweep(false)).labelled, 0u);
}

TEST(SpecularSpots, ABrightPatchMetObliquelyIsNoSpot)
{
  // The bright patch 20 degrees off the wall's normal: a specular spot comes back only where the
  // beam meets the surface perpendicularly, which this patch's plane (the wall's) is not.
  EXPECT_EQ(findSpots(windowSweep(true, 20.0f)).labelled, 0u);
  // 5 degrees off is within the 10 degrees a spot's fitted plane may be off.
  EXPECT_EQ(findSpots(windowSweep(true, 5.0f)).labelled, paneReturns(windowSweep(true, 5.0f), 5.0f));
}

TEST(SpecularSpots, ASpotNextToTheEchoComparisonsSurfaceEchoesIsLeftToThem)
{
  // A beam beside the spot returned two echoes that differ: the surface it lies on is the
  // double echoes' to find (or a reflection behind a pane, which a spot must not join).
  core::Sweep sweep = windowSweep(true);
  const std::size_t beside = 40 * 121 + 63;  // 1.5 degrees right of the centre: next to the spot
  sweep.echoes[0].points[beside] = Eigen::Vector3f(4.0f, 4.0f * std::tan(1.5f * kDegree), 0.0f);
  sweep.echoes[1].points[beside] = Eigen::Vector3f(6.0f, 6.0f * std::tan(1.5f * kDegree), 0.0f);
  sweep.computeRanges(Eigen::Vector3f::Zero());
  const Spotted out = findSpots(sweep);
  EXPECT_EQ(out.labelled, 0u);
  EXPECT_EQ(out.labels.echoes[0][beside], Label::errorSurface);
}

TEST(SpecularSpots, ThePipelineTypesAnOpenSpotGlass)
{
  core::Sweep sweep = windowSweep(true);
  sweep.has_intensity = true;
  core::Pipeline pipeline{ core::Params() };
  const core::PipelineResult& result = pipeline.process(sweep, core::SweepContext());
  ASSERT_EQ(result.objects.size(), 1u);
  const core::ReflectiveObject& pane = result.objects[0];
  EXPECT_EQ(pane.type, core::ObjectType::glass);
  EXPECT_TRUE(pane.evidence.typed_as_open_spot);
  EXPECT_NEAR(std::fabs(pane.plane[0]), 1.0f, 0.02f);
  EXPECT_NEAR(std::fabs(pane.plane[3]), 4.0f, 0.05f);
  EXPECT_GT(result.specular_spot_points, 0u);

  core::Params off;
  off.specular_spot_ratio = 0.0;
  core::Pipeline without{ off };
  EXPECT_TRUE(without.process(sweep, core::SweepContext()).objects.empty());
}

}  // namespace
}  // namespace ohm_mirror_detector3d
