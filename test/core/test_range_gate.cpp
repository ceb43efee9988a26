#include <gtest/gtest.h>

#include "ohm_mirror_detector3d/core/range_gate.h"
#include "ohm_mirror_detector3d/core/stage_configs.h"
#include "sweep_fixtures.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::Label;
using test::ahead;
using test::Beam;
using test::filled;
using test::kInf;
using test::kNaN;

core::SweepLabels gate(const core::Sweep& sweep, const core::Params& params = core::Params())
{
  core::SweepLabels labels;
  labels.reset(sweep.beamCount());
  core::RangeGate(core::stageConfigs(params).range_gate).apply(sweep, labels);
  return labels;
}

TEST(RangeGate, KeepsReturnsInsideTheRangeUnchecked)
{
  const core::Sweep sweep = test::makeSweep({ { ahead(1.0f), ahead(2.0f) }, { ahead(0.023f), ahead(60.0f) } });
  const core::SweepLabels labels = gate(sweep);
  for (int k = 0; k < 2; ++k)
    EXPECT_EQ(labels.count(k, Label::unchecked), 2u) << "echo " << k + 1;
}

TEST(RangeGate, LabelsReturnsNearerThanMinRangeOrFartherThanMaxRangeNanPoint)
{
  const core::Sweep sweep = test::makeSweep({ { ahead(0.01f), ahead(61.0f) }, { ahead(5.0f), ahead(5.0f) } });
  const core::SweepLabels labels = gate(sweep);
  EXPECT_EQ(labels.echoes[0][0], Label::nanPoint);
  EXPECT_EQ(labels.echoes[1][0], Label::nanPoint);
  EXPECT_EQ(labels.echoes[0][1], Label::unchecked);
  EXPECT_EQ(labels.echoes[1][1], Label::unchecked);
}

TEST(RangeGate, LabelsEveryNonFiniteReturnNanPoint)
{
  // REP-117: NaN means no return, +Inf out of range far, -Inf too near; any coordinate counts.
  const core::Sweep sweep = test::makeSweep({ { filled(kNaN), filled(kInf) },
                                              { filled(-kInf), Eigen::Vector3f(1.0f, kNaN, 0.0f) },
                                              { Eigen::Vector3f(kInf, 0.0f, 0.0f), ahead(3.0f) } });
  const core::SweepLabels labels = gate(sweep);
  EXPECT_EQ(labels.count(0, Label::nanPoint), 3u);
  EXPECT_EQ(labels.count(1, Label::nanPoint), 2u);
  EXPECT_EQ(labels.echoes[1][2], Label::unchecked);
}

TEST(RangeGate, LabelsAPointAtTheOriginNanPoint)
{
  // Some drivers write (0, 0, 0) for a missing return.
  const core::Sweep sweep = test::makeSweep({ { Eigen::Vector3f::Zero(), ahead(2.0f) } });
  const core::SweepLabels labels = gate(sweep);
  EXPECT_EQ(labels.echoes[0][0], Label::nanPoint);
  EXPECT_EQ(labels.echoes[1][0], Label::unchecked);
}

TEST(RangeGate, UsesTheConfiguredLimits)
{
  core::Params params;
  params.min_range = 1.5;
  params.max_range = 4.0;
  const core::Sweep sweep = test::makeSweep({ { ahead(1.0f), ahead(2.0f) }, { ahead(4.5f), ahead(3.9f) } });
  const core::SweepLabels labels = gate(sweep, params);
  EXPECT_EQ(labels.echoes[0][0], Label::nanPoint);
  EXPECT_EQ(labels.echoes[1][0], Label::unchecked);
  EXPECT_EQ(labels.echoes[0][1], Label::nanPoint);
  EXPECT_EQ(labels.echoes[1][1], Label::unchecked);
}

TEST(RangeGate, MeasuresRangeFromTheSensorOrigin)
{
  core::Sweep sweep = test::makeSweep({ { ahead(10.0f), ahead(10.0f) } });
  sweep.computeRanges(ahead(9.99f));
  const core::SweepLabels labels = gate(sweep);
  EXPECT_EQ(labels.count(0, Label::nanPoint), 1u);
}

TEST(RangeGate, ReturnsHowManyPointsItLabelled)
{
  const core::Sweep sweep = test::makeSweep({ { filled(kNaN), filled(kNaN) }, { ahead(1.0f), ahead(100.0f) } });
  core::SweepLabels labels;
  labels.reset(sweep.beamCount());
  EXPECT_EQ(core::RangeGate(core::stageConfigs(core::Params()).range_gate).apply(sweep, labels), 3u);
}

}  // namespace
}  // namespace ohm_mirror_detector3d
