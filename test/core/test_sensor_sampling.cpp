// The stages that follow the sensor (issue 14 item 1) and the implausible-removal report
// (item 2), on organised sweeps of a sparse 64-ring lidar geometry built by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "ohm_mirror_detector3d/core/dual_return.h"
#include "ohm_mirror_detector3d/core/mixed_pixels.h"
#include "ohm_mirror_detector3d/core/outlier_filter.h"
#include "ohm_mirror_detector3d/core/pipeline.h"
#include "ohm_mirror_detector3d/core/removal_report.h"
#include "ohm_mirror_detector3d/core/stage_configs.h"
#include "ohm_mirror_detector3d/core/sweep_sampling.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::Label;

constexpr double kPi = 3.14159265358979323846;
constexpr double kRowStepDeg = 1.45;  // a 64-ring, 104 degree lidar
constexpr double kColStepDeg = 0.6;   // 600 columns

Eigen::Vector3f direction(double elevation_deg, double azimuth_deg)
{
  const double e = elevation_deg * kPi / 180.0, a = azimuth_deg * kPi / 180.0;
  return Eigen::Vector3f(static_cast<float>(std::cos(e) * std::cos(a)), static_cast<float>(std::cos(e) * std::sin(a)),
                         static_cast<float>(std::sin(e)));
}

// rows x cols beams around +x (row 0 lowest, col 0 rightmost), both echoes on a wall x = 4
// (single returns, echo 2 repeating echo 1).
core::Sweep wallSweep(std::size_t rows, std::size_t cols, float wall_x = 4.0f)
{
  core::Sweep sweep;
  sweep.resize(rows, cols);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c)
    {
      const double elevation = (static_cast<double>(r) - 0.5 * static_cast<double>(rows)) * kRowStepDeg;
      const double azimuth = (static_cast<double>(c) - 0.5 * static_cast<double>(cols)) * kColStepDeg;
      const Eigen::Vector3f d = direction(elevation, azimuth);
      const Eigen::Vector3f p = d * (wall_x / d.x());
      const std::size_t b = r * cols + c;
      sweep.echoes[0].points[b] = p;
      sweep.echoes[1].points[b] = p;
    }
  sweep.computeRanges(Eigen::Vector3f::Zero());
  return sweep;
}

void setSecondEcho(core::Sweep& sweep, std::size_t beam, float range)
{
  const Eigen::Vector3f p = sweep.echoes[0].points[beam];
  sweep.echoes[1].points[beam] = p.normalized() * range;
  sweep.computeRanges(Eigen::Vector3f::Zero());
}

core::SweepLabels unchecked(const core::Sweep& sweep)
{
  core::SweepLabels labels;
  labels.reset(sweep.beamCount());
  return labels;
}

TEST(SweepSampling, AnOrganisedSweepIsItsOwnGridWithItsAngularSteps)
{
  const core::Sweep sweep = wallSweep(16, 40);
  core::SamplingEstimator estimator;
  const core::SweepSampling& sampling = estimator.estimate(sweep, Eigen::Vector3f::Zero());
  ASSERT_TRUE(sampling.hasGrid());
  EXPECT_EQ(sampling.rows, 16u);
  EXPECT_EQ(sampling.cols, 40u);
  EXPECT_FALSE(sampling.folded);
  EXPECT_NEAR(sampling.row_step * 180.0 / kPi, kRowStepDeg, 0.05);
  EXPECT_NEAR(sampling.col_step * 180.0 / kPi, kColStepDeg, 0.05);
}

TEST(SweepSampling, AOneRowSweepIsFoldedAtItsScanPeriod)
{
  const core::Sweep organised = wallSweep(12, 30);
  core::Sweep flat;
  flat.resize(1, organised.beamCount());
  flat.echoes = organised.echoes;
  flat.computeRanges(Eigen::Vector3f::Zero());
  core::SamplingEstimator estimator;
  const core::SweepSampling& sampling = estimator.estimate(flat, Eigen::Vector3f::Zero());
  ASSERT_TRUE(sampling.hasGrid());
  EXPECT_TRUE(sampling.folded);
  EXPECT_EQ(sampling.cols, 30u);
  EXPECT_EQ(sampling.rows, 12u);
}

TEST(SensorOutlierFilter, KeepsASparseWallTheMetricDefaultsWouldDelete)
{
  core::Sweep sweep = wallSweep(16, 40);
  // A lone return far in front of the wall: an outlier on any sensor.
  const std::size_t lone = 8 * 40 + 20;
  sweep.echoes[0].points[lone] = sweep.echoes[0].points[lone] * 0.4f;
  sweep.echoes[1].points[lone] = sweep.echoes[0].points[lone];
  sweep.computeRanges(Eigen::Vector3f::Zero());
  core::SamplingEstimator estimator;
  const core::SweepSampling& sampling = estimator.estimate(sweep, Eigen::Vector3f::Zero());

  core::OutlierFilter automatic(core::stageConfigs(core::Params()).outlier_filter);
  core::SweepLabels labels = unchecked(sweep);
  EXPECT_EQ(automatic.apply(sweep, sampling, Label::unchecked, labels), 2u);  // the lone point, both echoes
  EXPECT_EQ(labels.echoes[0][lone], Label::nanPoint);
  EXPECT_EQ(labels.count(0, Label::nanPoint), 1u);

  // The original's 0.1 m / 50 neighbours, set explicitly, are honoured: on this sampling
  // (points ~4-10 cm apart) they delete every point.
  core::Params metric;
  metric.outlier_radius = 0.1;
  metric.outlier_min_neighbors = 50;
  core::OutlierFilter fixed(core::stageConfigs(metric).outlier_filter);
  core::SweepLabels fixed_labels = unchecked(sweep);
  fixed.apply(sweep, sampling, Label::unchecked, fixed_labels);
  EXPECT_EQ(fixed_labels.count(0, Label::nanPoint), sweep.beamCount());
}

TEST(MixedPixels, ADoubleEchoLineAlongADepthEdgeIsGivenBackToTheScene)
{
  // A box edge in front of a wall: beams of column 20 straddle it, first echo on the edge at
  // 4 m (continuing the wall of columns < 20 at 4 m), second on the wall behind at 6 m (as
  // the columns > 20 see it).
  core::Sweep sweep = wallSweep(16, 40);
  for (std::size_t r = 0; r < 16; ++r)
    for (std::size_t c = 21; c < 40; ++c)
    {
      const std::size_t b = r * 40 + c;
      sweep.echoes[0].points[b] = sweep.echoes[0].points[b] * 1.5f;
      sweep.echoes[1].points[b] = sweep.echoes[0].points[b];
    }
  sweep.computeRanges(Eigen::Vector3f::Zero());
  for (std::size_t r = 0; r < 16; ++r)
    setSecondEcho(sweep, r * 40 + 20, sweep.echoes[0].ranges[r * 40 + 20] * 1.5f);

  core::Pipeline pipeline{ core::Params() };
  const core::PipelineResult& result = pipeline.process(sweep, core::SweepContext());
  EXPECT_EQ(result.error_surface_points, 16u);
  EXPECT_TRUE(result.objects.empty());
  EXPECT_EQ(result.mixed_pixel_beams, 16u);
  for (std::size_t r = 0; r < 16; ++r)
    for (int k = 0; k < 2; ++k)
      EXPECT_NE(result.labels.echoes[k][r * 40 + 20], Label::error) << r;
}

TEST(SensorDefaults, AGlassPaneOnASparseLidarIsAnObject)
{
  // 10 x 12 beams of glass at 4 m with the room's wall 3 m behind: 120 surface echoes, as a
  // 64-ring lidar sees a pane of about 1 m x 0.5 m. The original's n_object = 100 at 0.1 m
  // would need them within 10 cm of each other.
  core::Sweep sweep = wallSweep(24, 50, 7.0f);
  for (std::size_t r = 6; r < 16; ++r)
    for (std::size_t c = 20; c < 32; ++c)
    {
      const std::size_t b = r * 50 + c;
      const Eigen::Vector3f behind = sweep.echoes[0].points[b];
      sweep.echoes[0].points[b] = behind * (4.0f / 7.0f);
      sweep.echoes[1].points[b] = behind;
    }
  sweep.computeRanges(Eigen::Vector3f::Zero());
  core::Pipeline pipeline{ core::Params() };
  const core::PipelineResult& result = pipeline.process(sweep, core::SweepContext());
  EXPECT_EQ(result.error_surface_points, 120u);
  ASSERT_EQ(result.objects.size(), 1u);
  EXPECT_GE(result.objects[0].surface_inliers.size(), 100u);
  EXPECT_TRUE(core::implausibleRemovals(result.removals).empty());
}

TEST(RemovalReport, AnOutlierFilterThatDeletesMostOfASweepIsNamedWithItsShare)
{
  core::Sweep sweep = wallSweep(16, 40);
  for (std::size_t b = 0; b < sweep.beamCount(); b += 3)
    setSecondEcho(sweep, b, sweep.echoes[0].ranges[b] + 2.0f);
  core::Params metric;
  metric.outlier_radius = 0.1;
  metric.outlier_min_neighbors = 50;
  core::Pipeline pipeline{ metric };
  const core::PipelineResult& result = pipeline.process(sweep, core::SweepContext());
  const std::vector<core::ImplausibleRemoval> removals = core::implausibleRemovals(result.removals);
  ASSERT_EQ(removals.size(), 2u);
  EXPECT_EQ(removals[0].what, core::RemovedPoints::in_range_points);
  EXPECT_DOUBLE_EQ(removals[0].share(), 1.0);
  EXPECT_EQ(removals[1].what, core::RemovedPoints::second_returns);
  const std::string text = core::describeRemoval(removals[0], metric);
  EXPECT_NE(text.find("100.0 %"), std::string::npos) << text;
  EXPECT_NE(text.find("outlierFilter_searchRadius = 0.1 m"), std::string::npos) << text;
  EXPECT_NE(text.find("outlierFilter_minNeighbors = 50"), std::string::npos) << text;

  // With the defaults the same sweep loses nothing worth a word.
  core::Pipeline automatic{ core::Params() };
  EXPECT_TRUE(core::removalWarnings(automatic.process(sweep, core::SweepContext()).removals, core::Params()).empty());
}

TEST(RemovalReport, SmallSharesAndTinySweepsAreNotJudged)
{
  core::RemovalCounts counts;
  counts.in_range_points = 1000;
  counts.outlier_removed = 100;  // exactly 10 %: not above
  counts.second_returns = 10;
  counts.second_returns_removed = 10;  // all, but too few to judge
  EXPECT_TRUE(core::implausibleRemovals(counts).empty());
  counts.outlier_removed = 101;
  EXPECT_EQ(core::implausibleRemovals(counts).size(), 1u);
}

// A first return of `ring` at `azimuth_deg`, `range` metres away (10 cm higher a ring).
void addFirstReturn(core::DualReturnInput& input, int ring, double azimuth_deg, double range)
{
  const double azimuth = azimuth_deg * kPi / 180.0;
  input.points.points.emplace_back(static_cast<float>(range * std::cos(azimuth)),
                                   static_cast<float>(range * std::sin(azimuth)), static_cast<float>(ring) * 0.1f);
  input.points.intensities.push_back(0.0f);
  input.returns.push_back(1);
  input.rings.push_back(ring);
}

TEST(DualReturnAzimuth, TheStepIsWorkedOutFromARing)
{
  core::DualReturnInput input;
  for (int ring = 0; ring < 4; ++ring)
    for (int column = 0; column < 600; ++column)
    {
      if (column % 7 != 3)  // firings without a return leave wider gaps
        addFirstReturn(input, ring, column * 0.6, 5.0);
    }
  EXPECT_NEAR(core::estimateAzimuthStepDeg(input), 0.6, 1e-9);
  core::Sweep sweep;
  const core::DualReturnStats stats = core::binDualReturns(input, core::kAzimuthStepFromCloud, sweep);
  EXPECT_TRUE(stats.azimuth_from_cloud);
  EXPECT_EQ(sweep.cols, 600u);
  EXPECT_EQ(stats.duplicates, 0u);
}

TEST(DualReturnAzimuth, ARingThatReturnsFromAThirdOfTheRotationKeepsItsStep)
{
  // 2048 firings a rotation (0.17578125 deg), returns from only 700 of them in each ring (a lidar
  // with a 120 degree field of view, or one hemmed in by people next to it): the step is still
  // the firings', and every point gets a cell of its own.
  core::DualReturnInput input;
  const double step = 360.0 / 2048.0;
  for (int ring = 0; ring < 8; ++ring)
    for (int column = 100; column < 800; ++column)
      addFirstReturn(input, ring, column * step, 3.0);
  EXPECT_NEAR(core::estimateAzimuthStepDeg(input), step, 1e-9);
  core::Sweep sweep;
  const core::DualReturnStats stats = core::binDualReturns(input, core::kAzimuthStepFromCloud, sweep);
  EXPECT_EQ(sweep.cols, 2048u);
  EXPECT_EQ(stats.unbinned(), 0u);
}

TEST(DualReturnAzimuth, ReturnsBunchedIntoASmallArcMakeNoHugeGrid)
{
  // A corrupt cloud: 1000 returns a ring within one degree. The grid gets at most eight columns a
  // return, not the 36000 of the finest resolution allowed.
  core::DualReturnInput input;
  for (int ring = 0; ring < 4; ++ring)
    for (int k = 0; k < 1000; ++k)
      addFirstReturn(input, ring, k * 0.001, 3.0);
  core::Sweep sweep;
  core::binDualReturns(input, core::kAzimuthStepFromCloud, sweep);
  EXPECT_LE(sweep.cols, 8000u);
  EXPECT_GE(sweep.cols, 1000u);
}

}  // namespace
}  // namespace ohm_mirror_detector3d
