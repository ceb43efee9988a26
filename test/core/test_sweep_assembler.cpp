#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <vector>

#include "ohm_mirror_detector3d/core/sweep_assembler.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::EchoChoice;
using core::ProjectedScan;
using core::SweepAssembler;
using core::SweepBoundary;

constexpr double kPi = 3.14159265358979323846;
const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

EchoChoice choose(const std::vector<float>& ranges)
{
  return core::chooseEchoes(ranges.data(), ranges.size(), 0.1f, 30.0f);
}

TEST(ChooseEchoes, NoEchoMeansNoReturn)
{
  EXPECT_FALSE(choose({}).hasReturn());
  EXPECT_EQ(choose({}).first, -1);
  EXPECT_EQ(choose({}).last, -1);
}

TEST(ChooseEchoes, OneEchoIsRepeatedAsEcho2)
{
  const EchoChoice c = choose({ 2.0f });
  EXPECT_EQ(c.first, 0);
  EXPECT_EQ(c.last, 0);
}

TEST(ChooseEchoes, TwoEchoesAreFirstAndLast)
{
  const EchoChoice c = choose({ 2.0f, 5.0f });
  EXPECT_EQ(c.first, 0);
  EXPECT_EQ(c.last, 1);
}

TEST(ChooseEchoes, ThreeEchoesKeepFirstAndLastAndDropTheMiddle)
{
  const EchoChoice c = choose({ 2.0f, 3.0f, 5.0f });
  EXPECT_EQ(c.first, 0);
  EXPECT_EQ(c.last, 2);
}

TEST(ChooseEchoes, UnusableEchoesAreSkipped)
{
  // Non-finite (REP-117) and out of [range_min, range_max].
  EXPECT_FALSE(choose({ kNaN, kInf, -kInf, 0.05f, 31.0f }).hasReturn());
  const EchoChoice c = choose({ kNaN, 2.0f, 40.0f });
  EXPECT_EQ(c.first, 1);
  EXPECT_EQ(c.last, 1);
  const EchoChoice d = choose({ 0.01f, 2.0f, kInf, 4.0f, kNaN });
  EXPECT_EQ(d.first, 1);
  EXPECT_EQ(d.last, 3);
}

TEST(TwistAngle, IsTheRotationAboutTheAxisWhateverTheMounting)
{
  // The simulator's mounting: the scan plane (x-y of the laser) vertical, laser x up.
  const Eigen::Quaterniond mount(0.5, -0.5, -0.5, -0.5);
  const double offset = core::twistAngle(mount, Eigen::Vector3d::UnitZ());
  for (double phi : { -3.0, -1.0, 0.0, 0.3, 1.5, 3.0 })
  {
    const Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitZ())) * mount;
    EXPECT_NEAR(core::unwrapAngle(core::twistAngle(q, Eigen::Vector3d::UnitZ()) - offset, 0.0), phi, 1e-9)
        << "phi " << phi;
  }
  // About another axis, given unnormalised.
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitX()));
  EXPECT_NEAR(core::twistAngle(q, Eigen::Vector3d(2.0, 0.0, 0.0)), 0.7, 1e-9);
  EXPECT_NEAR(core::twistAngle(q, Eigen::Vector3d::UnitZ()), 0.0, 1e-9);
}

TEST(UnwrapAngle, ShiftsByWholeTurnsToTheReference)
{
  EXPECT_NEAR(core::unwrapAngle(-3.1, 3.1), 2 * kPi - 3.1, 1e-12);
  EXPECT_NEAR(core::unwrapAngle(3.1, -3.1), 3.1 - 2 * kPi, 1e-12);
  EXPECT_NEAR(core::unwrapAngle(0.5, 4 * kPi), 0.5 + 4 * kPi, 1e-12);
}

// The phase of scan k of a unit turning `scans` steps per half rotation, starting at `start`,
// wrapped into (-pi, pi] as a rotation angle from tf would be.
double wrappedAngle(double start, int k, int scans, double direction = 1.0)
{
  return core::unwrapAngle(start + direction * k * kPi / scans, 0.0);
}

TEST(SweepBoundary, StartsASweepEveryHalfRotationAcrossTheWrap)
{
  SweepBoundary boundary(kPi, true);
  const int scans = 200;
  for (int k = 0; k < 5 * scans; ++k)
    ASSERT_EQ(boundary.update(wrappedAngle(2.9, k, scans)), k / scans) << "scan " << k;
}

TEST(SweepBoundary, WorksTurningTheOtherWay)
{
  SweepBoundary boundary(kPi, true);
  const int scans = 7;
  for (int k = 0; k < 4 * scans; ++k)
    ASSERT_EQ(boundary.update(wrappedAngle(-1.0, k, scans, -1.0)), k / scans) << "scan " << k;
}

TEST(SweepBoundary, ToleratesRoundingAtTheBoundary)
{
  SweepBoundary boundary(kPi, true);
  const int scans = 4;
  const double eps = 1e-9;
  EXPECT_EQ(boundary.update(0.0), 0);
  EXPECT_EQ(boundary.update(kPi / 4 + eps), 0);
  EXPECT_EQ(boundary.update(kPi / 2 - eps), 0);
  EXPECT_EQ(boundary.update(3 * kPi / 4), 0);
  EXPECT_EQ(boundary.update(kPi - eps), 1);  // just short of the boundary: the new sweep all the same
  EXPECT_EQ(boundary.update(-3 * kPi / 4 + eps), 1);
  (void)scans;
}

TEST(SweepBoundary, SplitsTimeByThePeriod)
{
  SweepBoundary boundary(0.5, false);
  EXPECT_EQ(boundary.update(100.0), 0);
  EXPECT_EQ(boundary.update(100.25), 0);
  EXPECT_EQ(boundary.update(100.5), 1);
  EXPECT_EQ(boundary.update(100.75), 1);
  EXPECT_EQ(boundary.update(101.0), 2);
  boundary.reset();
  EXPECT_EQ(boundary.update(200.1), 0);  // a new anchor
  EXPECT_EQ(boundary.update(200.35), 0);
  EXPECT_EQ(boundary.update(200.6), 1);
}

// A scan of `beams` beams; beam i of scan `row` lies at (row, i, echo) so that tests can see
// where every point went.
ProjectedScan makeScan(int row, std::size_t beams, double phase, std::uint64_t stamp_ns)
{
  ProjectedScan scan;
  scan.reset(beams);
  scan.has_intensity = true;
  for (std::size_t i = 0; i < beams; ++i)
  {
    scan.echo1[i] = Eigen::Vector3f(static_cast<float>(row), static_cast<float>(i), 1.0f);
    scan.echo2[i] = Eigen::Vector3f(static_cast<float>(row), static_cast<float>(i), 2.0f);
    scan.intensity1[i] = 10.0f * row + i;
    scan.intensity2[i] = -(10.0f * row + i);
  }
  scan.origin = Eigen::Vector3d(0.0, 0.0, row);
  scan.phase = phase;
  scan.stamp_ns = stamp_ns;
  return scan;
}

TEST(SweepAssembler, EmitsASweepWhenTheNextHalfRotationBegins)
{
  const int scans = 4;
  const std::size_t beams = 3;
  SweepAssembler assembler;
  core::Sweep sweep;
  core::SweepContext context;
  for (int k = 0; k < scans; ++k)
  {
    EXPECT_EQ(assembler.add(makeScan(k, beams, wrappedAngle(1.0, k, scans), 1000 + k)), SweepAssembler::AddResult::added);
    EXPECT_FALSE(assembler.hasCompleteSweep());
    EXPECT_EQ(assembler.takeSweep(sweep, context), 0u);
  }
  // Scan 4 is half a turn after scan 0: it completes scans 0..3 and starts the next sweep.
  EXPECT_EQ(assembler.add(makeScan(scans, beams, wrappedAngle(1.0, scans, scans), 1000 + scans)),
            SweepAssembler::AddResult::sweep_complete);
  ASSERT_TRUE(assembler.hasCompleteSweep());
  ASSERT_EQ(assembler.takeSweep(sweep, context), static_cast<std::size_t>(scans));
  EXPECT_EQ(context.stamp_ns, 1003u);  // the stamp of its last scan
  EXPECT_EQ(sweep.rows, static_cast<std::size_t>(scans));
  EXPECT_EQ(sweep.cols, beams);
  EXPECT_TRUE(sweep.has_intensity);
  EXPECT_TRUE(sweep.input_cells.empty());
  EXPECT_EQ(assembler.rows(), 1u);

  // Row-major, echoes index-aligned: beam index = scan * beams + i.
  for (int row = 0; row < scans; ++row)
  {
    for (std::size_t i = 0; i < beams; ++i)
    {
      const std::size_t b = static_cast<std::size_t>(row) * beams + i;
      EXPECT_EQ(sweep.echoes[0].points[b], Eigen::Vector3f(row, i, 1.0f));
      EXPECT_EQ(sweep.echoes[1].points[b], Eigen::Vector3f(row, i, 2.0f));
      EXPECT_EQ(sweep.echoes[0].intensities[b], 10.0f * row + i);
      EXPECT_EQ(sweep.echoes[1].intensities[b], -(10.0f * row + i));
    }
  }
  // The origin is the mean scanner position, and ranges are measured from it.
  EXPECT_TRUE(context.sensorOrigin().isApprox(Eigen::Vector3f(0.0f, 0.0f, 1.5f)));
  EXPECT_NEAR(sweep.echoes[1].ranges[5], (Eigen::Vector3f(1.0f, 2.0f, 2.0f) - context.sensorOrigin()).norm(), 1e-6);

  // The next sweep: scans 4..7, completed by scan 8.
  for (int k = scans + 1; k < 2 * scans; ++k)
    EXPECT_EQ(assembler.add(makeScan(k, beams, wrappedAngle(1.0, k, scans), 1000 + k)), SweepAssembler::AddResult::added);
  EXPECT_EQ(assembler.add(makeScan(2 * scans, beams, wrappedAngle(1.0, 2 * scans, scans), 2000)),
            SweepAssembler::AddResult::sweep_complete);
  ASSERT_EQ(assembler.takeSweep(sweep, context), static_cast<std::size_t>(scans));
  EXPECT_EQ(context.stamp_ns, 1007u);
  EXPECT_EQ(sweep.echoes[0].points[0], Eigen::Vector3f(4.0f, 0.0f, 1.0f));
}

TEST(SweepAssembler, KeepsBeamsWithoutReturnAndRepeatedSingleEchoes)
{
  SweepAssembler assembler(0.1, false);  // one sweep per 0.1 s
  ProjectedScan scan = makeScan(0, 3, 0.0, 1);
  scan.echo1[1] = scan.echo2[1] = Eigen::Vector3f::Constant(kNaN);  // no return
  scan.echo2[2] = scan.echo1[2];                                     // one return
  scan.has_intensity = false;
  assembler.add(scan);
  assembler.add(makeScan(1, 3, 0.05, 2));
  EXPECT_EQ(assembler.add(makeScan(2, 3, 0.1, 3)), SweepAssembler::AddResult::sweep_complete);
  core::Sweep sweep;
  core::SweepContext context;
  ASSERT_EQ(assembler.takeSweep(sweep, context), 2u);
  EXPECT_FALSE(sweep.has_intensity);  // one scan without intensities: none for the sweep
  EXPECT_FALSE(sweep.echoes[0].points[1].allFinite());
  EXPECT_TRUE(std::isnan(sweep.echoes[0].ranges[1]));
  EXPECT_TRUE(std::isnan(sweep.echoes[1].ranges[1]));
  EXPECT_EQ(sweep.echoes[0].points[2], sweep.echoes[1].points[2]);
}

TEST(SweepAssembler, AnotherBeamCountDiscardsThePartialSweep)
{
  SweepAssembler assembler;
  EXPECT_EQ(assembler.add(makeScan(0, 3, 0.0, 1)), SweepAssembler::AddResult::added);
  EXPECT_EQ(assembler.add(makeScan(1, 3, 0.1, 2)), SweepAssembler::AddResult::added);
  EXPECT_EQ(assembler.add(makeScan(2, 4, 0.2, 3)), SweepAssembler::AddResult::width_changed);
  EXPECT_EQ(assembler.rows(), 1u);
  EXPECT_EQ(assembler.cols(), 4u);
  EXPECT_FALSE(assembler.hasCompleteSweep());
  // The new scan anchors the boundaries: half a turn after it completes the sweep.
  EXPECT_EQ(assembler.add(makeScan(3, 4, 0.2 + kPi / 2, 4)), SweepAssembler::AddResult::added);
  EXPECT_EQ(assembler.add(makeScan(4, 4, 0.2 + kPi, 5)), SweepAssembler::AddResult::sweep_complete);
}

TEST(SweepAssembler, AUnitThatDoesNotTurnOverflows)
{
  SweepAssembler assembler(kPi, true, 5);
  for (int k = 0; k < 5; ++k)
    EXPECT_EQ(assembler.add(makeScan(k, 2, 0.3, k)), SweepAssembler::AddResult::added);
  EXPECT_EQ(assembler.add(makeScan(5, 2, 0.3, 5)), SweepAssembler::AddResult::overflow);
  EXPECT_EQ(assembler.rows(), 1u);
}

TEST(SweepAssembler, ResetForgetsThePartialSweepAndTheAnchor)
{
  SweepAssembler assembler;
  assembler.add(makeScan(0, 2, 0.0, 1));
  assembler.add(makeScan(1, 2, 1.0, 2));
  assembler.reset();
  EXPECT_EQ(assembler.rows(), 0u);
  // Anchored anew at 2.0: 2.0 + pi (wrapped) completes.
  EXPECT_EQ(assembler.add(makeScan(2, 2, 2.0, 3)), SweepAssembler::AddResult::added);
  EXPECT_EQ(assembler.add(makeScan(3, 2, 2.0 + kPi / 2, 4)), SweepAssembler::AddResult::added);
  EXPECT_EQ(assembler.add(makeScan(4, 2, core::unwrapAngle(2.0 + kPi, 0.0), 5)),
            SweepAssembler::AddResult::sweep_complete);
  core::Sweep sweep;
  core::SweepContext context;
  EXPECT_EQ(assembler.takeSweep(sweep, context), 2u);
}

}  // namespace
}  // namespace ohm_mirror_detector3d
