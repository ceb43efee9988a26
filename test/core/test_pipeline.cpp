#include <gtest/gtest.h>

#include <stdexcept>

#include "ohm_mirror_detector3d/core/pipeline.h"
#include "sweep_fixtures.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::Label;
using test::ahead;
using test::filled;
using test::kNaN;

// The fixtures have a handful of beams metres apart: every point must count as a neighbour.
core::Params permissiveOutliers()
{
  core::Params params;
  params.outlier_min_neighbors = 1;
  params.outlier_radius = 100.0;
  return params;
}

TEST(Pipeline, RefusesInvalidParametersAndKeepsThePreviousOnes)
{
  core::Params bad;
  bad.echo_threshold = -1.0;
  EXPECT_THROW(core::Pipeline{ bad }, std::invalid_argument);
  core::Pipeline pipeline;
  EXPECT_THROW(pipeline.setParams(bad), std::invalid_argument);
  EXPECT_DOUBLE_EQ(pipeline.params().echo_threshold, 0.05);
}

TEST(Pipeline, LabelsEveryPointOfBothEchoesAndNothingStaysUnchecked)
{
  core::Pipeline pipeline(permissiveOutliers());
  const core::Sweep sweep = test::makeSweep(
      { { ahead(2.0f), ahead(3.5f) }, { ahead(4.0f), ahead(4.0f) }, { filled(kNaN), filled(kNaN) } });
  const core::PipelineResult& result = pipeline.process(sweep);
  // A discontinuity on no object: the near echo is a real surface, the far one is dropped.
  EXPECT_EQ(result.labels.echoes[0][0], Label::valid);
  EXPECT_EQ(result.labels.echoes[1][0], Label::error);
  EXPECT_EQ(result.labels.echoes[0][1], Label::valid);
  EXPECT_EQ(result.labels.echoes[1][1], Label::valid);
  EXPECT_EQ(result.labels.echoes[0][2], Label::nanPoint);
  EXPECT_EQ(result.labels.count(0, Label::unchecked) + result.labels.count(1, Label::unchecked), 0u);
  EXPECT_EQ(result.error_surface_points, 1u);
  EXPECT_EQ(result.range_gated_points, 2u);
}

TEST(Pipeline, CleanedDropsErrorAndNanPointsAndKeepsARepeatedSingleReturnOnce)
{
  core::Pipeline pipeline(permissiveOutliers());
  const core::Sweep sweep =
      test::makeSweep({ { ahead(2.0f), ahead(3.5f) }, { ahead(4.0f), ahead(4.0f) }, { ahead(5.0f), ahead(5.02f) },
                        { filled(kNaN), ahead(6.0f) } });
  const std::vector<core::OutputPoint>& cleaned = pipeline.process(sweep).cleaned;
  ASSERT_EQ(cleaned.size(), 5u);
  // Beam 0: near echo kept, far echo (error) dropped.
  EXPECT_EQ(cleaned[0].beam, 0u);
  EXPECT_EQ(cleaned[0].echo, 1);
  EXPECT_EQ(cleaned[0].label, Label::valid);
  // Beam 1: the single return repeated in echo 2 appears once.
  EXPECT_EQ(cleaned[1].beam, 1u);
  EXPECT_EQ(cleaned[2].beam, 2u);
  // Beam 2: two distinct returns within d_thres are both real measurements.
  EXPECT_EQ(cleaned[3].beam, 2u);
  EXPECT_EQ(cleaned[3].echo, 2);
  // Beam 3: the only return came in echo 2.
  EXPECT_EQ(cleaned[4].beam, 3u);
  EXPECT_EQ(cleaned[4].echo, 2);
  EXPECT_FLOAT_EQ(cleaned[4].intensity, 3.0f);
}

TEST(Pipeline, ReusesItsBuffersForSweepsOfDifferentSizes)
{
  core::Pipeline pipeline(permissiveOutliers());
  pipeline.process(test::makeSweep({ { ahead(2.0f), ahead(3.5f) }, { ahead(2.0f), ahead(3.5f) },
                                     { ahead(2.0f), ahead(3.5f) } }));
  const core::PipelineResult& result =
      pipeline.process(test::makeSweep({ { ahead(4.0f), ahead(4.0f) }, { ahead(5.0f), ahead(5.0f) } }));
  EXPECT_EQ(result.labels.echoes[0].size(), 2u);
  EXPECT_EQ(result.labels.echoes[0][0], Label::valid);
  EXPECT_EQ(result.cleaned.size(), 2u);
}

TEST(Pipeline, ReportsNonNegativeStageTimesThatAddUpToTheTotal)
{
  core::Pipeline pipeline(permissiveOutliers());
  const core::PipelineResult& result =
      pipeline.process(test::makeSweep({ { ahead(2.0f), ahead(3.5f) }, { ahead(4.0f), ahead(4.0f) } }));
  const core::StageTimes& t = result.times;
  for (double stage : { t.range_gate, t.outlier_filter, t.echo_comparison, t.object_extraction, t.type_analysis,
                        t.cone_labelling, t.cleaned_output })
    EXPECT_GE(stage, 0.0);
  EXPECT_GT(t.total, 0.0);
  EXPECT_NEAR(t.sumOfStages(), t.total, 1e-9 + 1e-6 * t.total);
}

TEST(Pipeline, ProcessesAnEmptySweep)
{
  core::Pipeline pipeline;
  const core::PipelineResult& result = pipeline.process(test::makeSweep({}));
  EXPECT_TRUE(result.labels.echoes[0].empty());
  EXPECT_TRUE(result.cleaned.empty());
}

}  // namespace
}  // namespace ohm_mirror_detector3d
