#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "ohm_mirror_detector3d/core/pipeline.h"
#include "object_fixtures.h"
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
  const core::PipelineResult& result = pipeline.process(sweep, core::SweepContext());
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
  const std::vector<core::OutputPoint>& cleaned = pipeline.process(sweep, core::SweepContext()).cleaned;
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
                                     { ahead(2.0f), ahead(3.5f) } }), core::SweepContext());
  const core::PipelineResult& result =
      pipeline.process(test::makeSweep({ { ahead(4.0f), ahead(4.0f) }, { ahead(5.0f), ahead(5.0f) } }),
                       core::SweepContext());
  EXPECT_EQ(result.labels.echoes[0].size(), 2u);
  EXPECT_EQ(result.labels.echoes[0][0], Label::valid);
  EXPECT_EQ(result.cleaned.size(), 2u);
}

TEST(Pipeline, ReportsNonNegativeStageTimesThatAddUpToTheTotal)
{
  core::Pipeline pipeline(permissiveOutliers());
  const core::PipelineResult& result =
      pipeline.process(test::makeSweep({ { ahead(2.0f), ahead(3.5f) }, { ahead(4.0f), ahead(4.0f) } }),
                       core::SweepContext());
  const core::StageTimes& t = result.times;
  for (double stage : { t.range_gate, t.outlier_filter, t.echo_comparison, t.object_extraction, t.type_analysis,
                        t.object_stages, t.cone_labelling, t.cleaned_output })
    EXPECT_GE(stage, 0.0);
  EXPECT_GT(t.total, 0.0);
  EXPECT_NEAR(t.sumOfStages(), t.total, 1e-9 + 1e-6 * t.total);
}

// An object stage that writes down what it saw and then adds a 1 x 1 m wall object at x = 2
// (facing the origin) of the given type, or, with no type, turns the first object into a mirror.
class WallStage : public core::ObjectStage
{
public:
  WallStage(std::string name, std::vector<std::string>& log, bool adds, core::ObjectType type)
    : name_(std::move(name)), log_(log), adds_(adds), type_(type)
  {
  }
  const char* name() const override { return name_.c_str(); }
  void process(const core::Sweep& sweep, const core::SweepContext& context, const core::ReflectionEvidence&,
               core::SweepLabels& labels, std::vector<core::ReflectiveObject>& objects) override
  {
    log_.push_back(name_ + " saw " + std::to_string(objects.size()) + " object(s), " +
                   std::to_string(labels.echoes[0].size()) + " of " + std::to_string(sweep.beamCount()) +
                   " beams labelled, frame '" + context.frame_id + "'");
    if (adds_)
      objects.push_back(test::wallObject(2.0f, 1.0f, 1.0f, type_, static_cast<std::uint32_t>(objects.size())));
    else if (!objects.empty())
      objects.front().type = type_;
  }

private:
  std::string name_;
  std::vector<std::string>& log_;
  bool adds_;
  core::ObjectType type_;
};

// A point on the wall and one behind it (single returns).
core::Sweep wallSweep()
{
  return test::makeSweep({ { Eigen::Vector3f(2.0f, 0.1f, 0.1f), Eigen::Vector3f(2.0f, 0.1f, 0.1f) },
                           { Eigen::Vector3f(3.0f, 0.1f, 0.1f), Eigen::Vector3f(3.0f, 0.1f, 0.1f) } });
}

TEST(Pipeline, ObjectStagesRunBetweenDetectAndLabelInTheOrderAdded)
{
  std::vector<std::string> log;
  core::Pipeline pipeline(permissiveOutliers());
  pipeline.addObjectStage(std::make_unique<WallStage>("grow", log, true, core::ObjectType::glass));
  pipeline.addObjectStage(std::make_unique<WallStage>("decide", log, false, core::ObjectType::mirror));
  core::SweepContext context;
  context.frame_id = "laser";
  const core::PipelineResult& result = pipeline.process(wallSweep(), context);
  ASSERT_EQ(log.size(), 2u);
  EXPECT_EQ(log[0], "grow saw 0 object(s), 2 of 2 beams labelled, frame 'laser'");
  EXPECT_EQ(log[1], "decide saw 1 object(s), 2 of 2 beams labelled, frame 'laser'");
  // The cone labelling labels by what the stages left: one mirror.
  ASSERT_EQ(result.objects.size(), 1u);
  EXPECT_EQ(result.objects[0].type, core::ObjectType::mirror);
  EXPECT_EQ(result.labels.echoes[0][0], Label::reflectiveSurface);
  EXPECT_EQ(result.labels.echoes[0][1], Label::behindReflective);
  // Its phantom is back-projected across it: x = 3 behind the plane x = 2 is really at x = 1.
  ASSERT_EQ(result.cleaned.size(), 2u);
  EXPECT_TRUE(result.cleaned[1].position.isApprox(Eigen::Vector3f(1.0f, 0.1f, 0.1f)));
  EXPECT_GE(result.times.object_stages, 0.0);
}

TEST(Pipeline, KeepsItsObjectStagesWhenTheParametersChange)
{
  std::vector<std::string> log;
  core::Pipeline pipeline(permissiveOutliers());
  pipeline.addObjectStage(std::make_unique<WallStage>("grow", log, true, core::ObjectType::glass));
  core::Params params = permissiveOutliers();
  params.plane_threshold = 0.02;
  pipeline.setParams(params);
  const core::PipelineResult& result = pipeline.process(wallSweep(), core::SweepContext());
  EXPECT_EQ(log.size(), 1u);
  EXPECT_EQ(result.labels.echoes[0][1], Label::behindTransparent);
}

TEST(Pipeline, TheVisionConesStartAtTheContextsSensorOrigin)
{
  std::vector<std::string> log;
  core::Pipeline pipeline(permissiveOutliers());
  pipeline.addObjectStage(std::make_unique<WallStage>("grow", log, true, core::ObjectType::glass));
  // From x = 4 the sensor sees the wall's back: nothing is on or behind the surface it faces.
  core::SweepContext context;
  context.sensor_pose.translation() = Eigen::Vector3d(4.0, 0.0, 0.0);
  core::Sweep sweep = wallSweep();
  sweep.computeRanges(context.sensorOrigin());
  const core::PipelineResult& result = pipeline.process(sweep, context);
  EXPECT_EQ(result.labels.echoes[0][0], Label::valid);
  EXPECT_EQ(result.labels.echoes[0][1], Label::valid);
  // From the origin it is seen from the front.
  const core::PipelineResult& front = pipeline.process(wallSweep(), core::SweepContext());
  EXPECT_EQ(front.labels.echoes[0][1], Label::behindTransparent);
}

TEST(Pipeline, ProcessesAnEmptySweep)
{
  core::Pipeline pipeline;
  const core::PipelineResult& result = pipeline.process(test::makeSweep({}), core::SweepContext());
  EXPECT_TRUE(result.labels.echoes[0].empty());
  EXPECT_TRUE(result.cleaned.empty());
}

}  // namespace
}  // namespace ohm_mirror_detector3d
