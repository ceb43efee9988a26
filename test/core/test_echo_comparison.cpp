#include <gtest/gtest.h>

#include "ohm_mirror_detector3d/core/echo_comparison.h"
#include "ohm_mirror_detector3d/core/range_gate.h"
#include "ohm_mirror_detector3d/core/stage_configs.h"
#include "sweep_fixtures.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::Label;
using test::ahead;
using test::filled;
using test::kNaN;

struct Compared
{
  core::SweepLabels labels;
  std::size_t affected;
};

Compared compare(const core::Sweep& sweep, const core::Params& params = core::Params())
{
  Compared out;
  out.labels.reset(sweep.beamCount());
  const core::StageConfigs configs = core::stageConfigs(params);
  core::RangeGate(configs.range_gate).apply(sweep, out.labels);
  out.affected = core::EchoComparison(configs.echo_comparison).apply(sweep, out.labels);
  return out;
}

TEST(EchoComparison, MarksNearEchoErrorSurfaceAndFarEchoErrorWhenEchoesDisagree)
{
  // A mirror at 2 m: echo 1 on its surface, echo 2 a phantom 1.5 m behind it.
  const Compared out = compare(test::makeSweep({ { ahead(2.0f), ahead(3.5f) } }));
  EXPECT_EQ(out.labels.echoes[0][0], Label::errorSurface);
  EXPECT_EQ(out.labels.echoes[1][0], Label::error);
  EXPECT_EQ(out.affected, 1u);
}

TEST(EchoComparison, HandlesEchoesInEitherOrder)
{
  const Compared out = compare(test::makeSweep({ { ahead(3.5f), ahead(2.0f) } }));
  EXPECT_EQ(out.labels.echoes[0][0], Label::error);
  EXPECT_EQ(out.labels.echoes[1][0], Label::errorSurface);
}

TEST(EchoComparison, LeavesAgreeingEchoesUnchecked)
{
  // Within d_thres = 0.05 m both echoes see the same surface (range noise).
  const Compared out = compare(test::makeSweep({ { ahead(2.0f), ahead(2.04f) }, { ahead(5.0f), ahead(5.0f) } }));
  EXPECT_EQ(out.labels.count(0, Label::unchecked), 2u);
  EXPECT_EQ(out.labels.count(1, Label::unchecked), 2u);
  EXPECT_EQ(out.affected, 0u);
}

TEST(EchoComparison, TheThresholdIsStrict)
{
  core::Params params;
  params.echo_threshold = 0.5;
  const Compared out = compare(test::makeSweep({ { ahead(2.0f), ahead(2.5f) }, { ahead(2.0f), ahead(2.51f) } }), params);
  EXPECT_EQ(out.labels.echoes[0][0], Label::unchecked);
  EXPECT_EQ(out.labels.echoes[0][1], Label::errorSurface);
}

TEST(EchoComparison, TreatsABeamWithOneReturnAsAValidSingleEchoBeam)
{
  // Missing second return as NaN, or missing first return; neither is a discontinuity.
  const Compared out = compare(test::makeSweep({ { ahead(2.0f), filled(kNaN) }, { filled(kNaN), ahead(7.0f) } }));
  EXPECT_EQ(out.labels.echoes[0][0], Label::unchecked);
  EXPECT_EQ(out.labels.echoes[1][0], Label::nanPoint);
  EXPECT_EQ(out.labels.echoes[0][1], Label::nanPoint);
  EXPECT_EQ(out.labels.echoes[1][1], Label::unchecked);
  EXPECT_EQ(out.affected, 0u);
}

TEST(EchoComparison, IgnoresAnEchoTheRangeGateRemoved)
{
  // Echo 2 beyond d_max: the beam has one usable return, so it cannot be compared.
  core::Params params;
  params.max_range = 10.0;
  const Compared out = compare(test::makeSweep({ { ahead(2.0f), ahead(12.0f) } }), params);
  EXPECT_EQ(out.labels.echoes[0][0], Label::unchecked);
  EXPECT_EQ(out.labels.echoes[1][0], Label::nanPoint);
}

TEST(EchoComparison, ComparesRangesNotPositions)
{
  // Same range, different directions: not a discontinuity of the range.
  const Compared out =
      compare(test::makeSweep({ { Eigen::Vector3f(3.0f, 0.0f, 0.0f), Eigen::Vector3f(0.0f, 3.0f, 0.0f) } }));
  EXPECT_EQ(out.labels.echoes[0][0], Label::unchecked);
}

}  // namespace
}  // namespace ohm_mirror_detector3d
