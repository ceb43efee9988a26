#include <gtest/gtest.h>

#include <cmath>

#include "ohm_mirror_detector3d/core/dual_return.h"
#include "ohm_mirror_detector3d/core/pipeline.h"
#include "sweep_fixtures.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::PointRef;
using test::kNaN;

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// A cloud built point by point: position from azimuth [deg], elevation [deg] and range.
struct CloudBuilder
{
  core::DualReturnInput input;

  CloudBuilder& add(double azimuth, double range, std::int64_t ring, std::int64_t ret, double elevation = 0.0)
  {
    const Eigen::Vector3f p(static_cast<float>(range * std::cos(elevation * kDeg) * std::cos(azimuth * kDeg)),
                            static_cast<float>(range * std::cos(elevation * kDeg) * std::sin(azimuth * kDeg)),
                            static_cast<float>(range * std::sin(elevation * kDeg)));
    return addPoint(p, ring, ret);
  }

  CloudBuilder& addPoint(const Eigen::Vector3f& p, std::int64_t ring, std::int64_t ret)
  {
    input.points.points.push_back(p);
    input.points.intensities.push_back(static_cast<float>(input.size()));
    input.rings.push_back(ring);
    input.returns.push_back(ret);
    input.has_intensity = true;
    return *this;
  }
};

// The sweep buffer, reused across calls like the nodelet's.
class DualReturn : public ::testing::Test
{
protected:
  core::Sweep sweep_;
};

TEST_F(DualReturn, AzimuthResolutionIsValidatedWithItsName)
{
  EXPECT_EQ(core::validateAzimuthResolution(0.2), "");
  EXPECT_EQ(core::validateAzimuthResolution(360.0 / 2048.0), "");
  // 0: not given, worked out from the cloud.
  EXPECT_EQ(core::validateAzimuthResolution(core::kAzimuthStepFromCloud), "");
  for (double bad : { -0.2, 0.001, 45.0, std::nan("") })
  {
    const std::string message = core::validateAzimuthResolution(bad);
    EXPECT_NE(message.find("azimuth_resolution_deg"), std::string::npos) << bad;
    EXPECT_NE(message.find("0.01 .. 10"), std::string::npos) << message;
  }
  EXPECT_EQ(core::azimuthBins(0.2), 1800u);
  EXPECT_EQ(core::azimuthBins(360.0 / 2048.0), 2048u);
  EXPECT_EQ(core::azimuthBins(0.1758), 2048u);  // rounded to whole bins
}

TEST_F(DualReturn, PairsReturnsOfABeamByRingAndAzimuthInAnyOrder)
{
  CloudBuilder cloud;
  // Driver order: per column, per ring; the second return (stored only when it differs)
  // may come first and may be the nearer one.
  cloud.add(10.0, 3.0, 0, 1).add(10.0, 5.0, 0, 2);   // beam (0, 50): two returns
  cloud.add(10.0, 2.0, 1, 2).add(10.0, 4.0, 1, 1);   // beam (1, 50): second first, nearer
  cloud.add(10.2, 6.0, 0, 1);                        // beam (0, 51): single return
  cloud.add(359.95, 7.0, 1, 1).add(0.02, 8.0, 1, 2); // beam (1, 0): across 0/360 deg
  const core::DualReturnStats stats = core::binDualReturns(cloud.input, 0.2, sweep_);
  EXPECT_EQ(stats.return_base, 1);
  EXPECT_EQ(stats.binned, 7u);
  EXPECT_EQ(stats.unbinned(), 0u);
  EXPECT_EQ(stats.paired_beams, 3u);
  EXPECT_EQ(stats.single_beams, 1u);
  ASSERT_EQ(sweep_.rows, 2u);
  ASSERT_EQ(sweep_.cols, 1800u);
  const std::uint32_t b050 = 50, b150 = 1800 + 50, b051 = 51, b100 = 1800;
  ASSERT_EQ(sweep_.input_cells.size(), 7u);
  const std::vector<std::pair<std::uint32_t, std::uint8_t>> expected = { { b050, 0 }, { b050, 1 }, { b150, 1 },
                                                                         { b150, 0 }, { b051, 0 }, { b100, 0 },
                                                                         { b100, 1 } };
  for (std::size_t i = 0; i < expected.size(); ++i)
  {
    EXPECT_EQ(sweep_.input_cells[i].beam, expected[i].first) << i;
    EXPECT_EQ(sweep_.input_cells[i].echo, expected[i].second) << i;
    // Every point lands in its cell unchanged.
    const PointRef ref = sweep_.input_cells[i];
    EXPECT_EQ(sweep_.echoes[ref.echo].points[ref.beam], cloud.input.points.points[i]) << i;
    EXPECT_EQ(sweep_.echoes[ref.echo].intensities[ref.beam], cloud.input.points.intensities[i]) << i;
  }
  EXPECT_NEAR(sweep_.echoes[0].ranges[b150], 4.0f, 1e-5f);
  EXPECT_NEAR(sweep_.echoes[1].ranges[b150], 2.0f, 1e-5f);
  // The single-return beam has no second echo; empty cells are NaN.
  EXPECT_FALSE(sweep_.echoes[1].points[b051].allFinite());
  EXPECT_TRUE(std::isnan(sweep_.echoes[1].ranges[b051]));
  EXPECT_FALSE(sweep_.echoes[0].points[7].allFinite());
}

TEST_F(DualReturn, ZeroBasedReturnIndicesAreRecognised)
{
  CloudBuilder cloud;
  cloud.add(0.0, 3.0, 0, 0).add(0.0, 5.0, 0, 1).add(1.0, 3.0, 2, 0);
  const core::DualReturnStats stats = core::binDualReturns(cloud.input, 1.0, sweep_);
  EXPECT_EQ(stats.return_base, 0);
  EXPECT_EQ(stats.paired_beams, 1u);
  EXPECT_EQ(sweep_.rows, 3u);  // max ring + 1, rings need not be contiguous
  EXPECT_EQ(sweep_.cols, 360u);
  EXPECT_EQ(sweep_.input_cells[1].echo, 1);
  EXPECT_EQ(sweep_.input_cells[2].beam, 2u * 360u + 1u);
}

TEST_F(DualReturn, SecondReturnPairsOnlyWithinHalfABin)
{
  CloudBuilder cloud;
  // Bins of 1 deg. The first return at 10.3 deg (bin 10) and the second at 10.7 (bin 11)
  // are 0.4 deg apart: partners, by azimuth, not by bin.
  cloud.add(10.3, 3.0, 0, 1).add(10.7, 5.0, 0, 2);
  // A first return at 20.4 (bin 20) and a second at 21.45 (bin 21): 1.05 deg apart, no
  // partner, so it becomes the single return of bin 21.
  cloud.add(20.4, 3.0, 0, 1).add(21.45, 5.0, 0, 2);
  // The first return at 30.45 (bin 30) and a second at 29.6 (bin 30, 0.85 deg away): no
  // partner, and bin 30 has its first return, so the second has no cell.
  cloud.add(30.45, 3.0, 0, 1).add(29.6, 5.0, 0, 2);
  const core::DualReturnStats stats = core::binDualReturns(cloud.input, 1.0, sweep_);
  EXPECT_EQ(sweep_.input_cells[1].beam, 10u);
  EXPECT_EQ(sweep_.input_cells[1].echo, 1);
  EXPECT_EQ(sweep_.input_cells[3].beam, 21u);
  EXPECT_EQ(sweep_.input_cells[3].echo, 0);
  EXPECT_EQ(sweep_.input_cells[5].echo, PointRef::kNoCell);
  EXPECT_EQ(stats.duplicates, 1u);
  EXPECT_EQ(stats.paired_beams, 1u);
  EXPECT_EQ(stats.single_beams, 3u);
}

TEST_F(DualReturn, TwoPointsForOneCellKeepTheOneNearestTheBinCentreAndAccountForTheOther)
{
  CloudBuilder cloud;
  cloud.add(10.3, 3.0, 0, 1).add(9.9, 3.1, 0, 1).add(9.9, 5.0, 0, 2).add(10.35, 5.5, 0, 2);
  const core::DualReturnStats stats = core::binDualReturns(cloud.input, 1.0, sweep_);
  EXPECT_EQ(stats.duplicates, 2u);
  EXPECT_EQ(stats.binned, 2u);
  EXPECT_EQ(sweep_.input_cells[0].echo, PointRef::kNoCell);
  EXPECT_EQ(sweep_.input_cells[1].beam, 10u);
  EXPECT_EQ(sweep_.input_cells[2].echo, 1);  // the second return at the partner's azimuth wins
  EXPECT_EQ(sweep_.input_cells[3].echo, PointRef::kNoCell);
  ASSERT_EQ(sweep_.unbinned.points.size(), 2u);
  EXPECT_EQ(sweep_.input_cells[0].beam, 0u);
  EXPECT_EQ(sweep_.input_cells[3].beam, 1u);
  EXPECT_EQ(sweep_.unbinned.points[0], cloud.input.points.points[0]);
  EXPECT_EQ(sweep_.unbinned.points[1], cloud.input.points.points[3]);
  EXPECT_EQ(sweep_.unbinned.intensities[1], cloud.input.points.intensities[3]);
}

TEST_F(DualReturn, PointsThatFitNoCellAreKeptAsUnbinnedInInputOrder)
{
  CloudBuilder cloud;
  cloud.add(0.0, 3.0, 0, 1);
  cloud.addPoint(Eigen::Vector3f::Constant(kNaN), 0, 1);      // no return (REP-117)
  cloud.addPoint(Eigen::Vector3f::Zero(), 1, 2);              // no return (zeros)
  cloud.add(5.0, 3.0, -1, 1).add(6.0, 3.0, core::kMaxRings, 1);  // ring out of range
  cloud.add(7.0, 3.0, 0, 3).add(8.0, 3.0, 0, -1);             // a third return, garbage
  const core::DualReturnStats stats = core::binDualReturns(cloud.input, 1.0, sweep_);
  EXPECT_EQ(stats.binned, 1u);
  EXPECT_EQ(stats.no_return, 2u);
  EXPECT_EQ(stats.ring_out_of_range, 2u);
  EXPECT_EQ(stats.return_out_of_range, 2u);
  EXPECT_EQ(stats.unbinned() + stats.binned, stats.points);
  EXPECT_EQ(sweep_.rows, 1u);  // rings of unbinned points do not size the grid
  for (std::size_t i = 1; i < cloud.input.size(); ++i)
  {
    EXPECT_EQ(sweep_.input_cells[i].echo, PointRef::kNoCell);
    EXPECT_EQ(sweep_.input_cells[i].beam, i - 1);
  }
}

TEST_F(DualReturn, ReusedSweepIsRefilledCompletely)
{
  CloudBuilder big;
  for (int ring = 0; ring < 4; ++ring)
    big.add(1.0, 3.0, ring, 1).add(1.0, 4.0, ring, 2);
  core::binDualReturns(big.input, 1.0, sweep_);
  CloudBuilder small;
  small.add(2.0, 3.0, 0, 1);
  small.addPoint(Eigen::Vector3f::Constant(kNaN), 0, 1);
  core::binDualReturns(small.input, 1.0, sweep_);
  EXPECT_EQ(sweep_.rows, 1u);
  EXPECT_EQ(sweep_.input_cells.size(), 2u);
  EXPECT_EQ(sweep_.unbinned.points.size(), 1u);
  EXPECT_FALSE(sweep_.echoes[0].points[1].allFinite());
  EXPECT_FALSE(sweep_.echoes[1].points[1].allFinite());
}

TEST_F(DualReturn, EmptyCloudGivesAnEmptySweepThePipelineAccepts)
{
  core::DualReturnInput empty;
  const core::DualReturnStats stats = core::binDualReturns(empty, 1.0, sweep_);
  EXPECT_EQ(stats.points, 0u);
  EXPECT_EQ(sweep_.beamCount(), 0u);
  core::Pipeline pipeline;
  const core::PipelineResult& result = pipeline.process(sweep_, core::SweepContext());
  EXPECT_TRUE(result.objects.empty());
  EXPECT_TRUE(result.cleaned.empty());
}

}  // namespace
}  // namespace ohm_mirror_detector3d
