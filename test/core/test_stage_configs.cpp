#include <gtest/gtest.h>

#include "ohm_mirror_detector3d/core/param_table.h"
#include "ohm_mirror_detector3d/core/parallel.h"
#include "ohm_mirror_detector3d/core/stage_configs.h"

namespace ohm_mirror_detector3d
{
namespace
{
// Every pipeline parameter set to a value of its own (its position in the table), so that a
// config field fed from the wrong parameter shows.
core::Params distinctParams()
{
  core::Params params;
  int k = 1;
  for (const core::ParamInfo& param : core::parameterTable())
  {
    if (param.real_field != nullptr)
      params.*param.real_field = 0.5 + k;
    else if (param.integer_field != nullptr)
      params.*param.integer_field = 1000 + k;
    ++k;
  }
  return params;
}

TEST(StageConfigs, EachStageGetsItsOwnValuesFromTheParameters)
{
  const core::Params p = distinctParams();
  const core::StageConfigs c = core::stageConfigs(p);
  EXPECT_EQ(c.range_gate.min_range, p.min_range);
  EXPECT_EQ(c.range_gate.max_range, p.max_range);
  EXPECT_EQ(c.outlier_filter.radius, p.outlier_radius);
  EXPECT_EQ(c.outlier_filter.min_neighbors, p.outlier_min_neighbors);
  EXPECT_EQ(c.echo_comparison.threshold, p.echo_threshold);
  EXPECT_EQ(c.specular_spots.min_brightness_ratio, p.specular_spot_ratio);
  EXPECT_EQ(c.specular_spots.enabled, p.specular_spot_ratio > 0.0);
  EXPECT_EQ(c.specular_spots.min_points, static_cast<std::size_t>(p.min_object_points));
  EXPECT_EQ(c.object_extraction.plane_threshold, p.plane_threshold);
  EXPECT_EQ(c.object_extraction.min_object_points, p.min_object_points);
  EXPECT_EQ(c.object_extraction.connection_distance, p.outlier_radius);
  EXPECT_EQ(c.object_type.plane_threshold, p.plane_threshold);
  EXPECT_EQ(c.object_type.cone_margin, p.vision_cone_margin);
  EXPECT_EQ(c.object_type.icp_max_distance, p.icp_max_distance);
  EXPECT_EQ(c.object_type.icp_fitness_threshold, p.icp_fitness_threshold);
  EXPECT_EQ(c.object_type.icp_min_points, p.icp_min_points);
  EXPECT_EQ(c.object_type.icp_min_inlier_fraction, p.icp_min_inlier_fraction);
  EXPECT_EQ(c.cone_labelling.plane_threshold, p.plane_threshold);
  EXPECT_EQ(c.cone_labelling.cone_margin, p.vision_cone_margin);
  EXPECT_EQ(c.threads, p.threads);
  EXPECT_EQ(c.outlier_filter.threads, p.threads);
  EXPECT_EQ(c.object_type.threads, p.threads);
  EXPECT_EQ(c.cone_labelling.threads, p.threads);
  EXPECT_TRUE(c.growth.panes);
  EXPECT_EQ(c.growth.mirrors, p.grow_objects == 1);
  EXPECT_FLOAT_EQ(c.growth.plane_threshold, static_cast<float>(p.plane_threshold));
  EXPECT_FLOAT_EQ(c.growth.max_growth, static_cast<float>(p.growth_max_extent));
  // The defaults grow panes only; 0 grows nothing (the paper's method).
  EXPECT_TRUE(core::stageConfigs(core::Params()).growth.panes);
  EXPECT_FALSE(core::stageConfigs(core::Params()).growth.mirrors);
  core::Params paper;
  paper.grow_objects = 0;
  EXPECT_FALSE(core::stageConfigs(paper).growth.panes);
  EXPECT_FALSE(core::stageConfigs(paper).growth.mirrors);
}

bool differsIn(const core::FeatureModel& a, const core::FeatureModel& b)
{
  return a.mirror != b.mirror || a.glass != b.glass || a.sigma != b.sigma;
}

bool differsIn(const core::IntensityModel& a, const core::IntensityModel& b)
{
  return differsIn(a.haze, b.haze) || differsIn(a.faint_share, b.faint_share) || differsIn(a.echo_ratio, b.echo_ratio);
}

TEST(StageConfigs, AutomaticThreadsAreTheMachinesCoresUpToFour)
{
  const core::StageConfigs c = core::stageConfigs(core::Params());
  EXPECT_EQ(c.threads, core::automaticThreadCount());
  EXPECT_GE(c.threads, 1);
  EXPECT_LE(c.threads, core::kMaxAutomaticThreads);
  EXPECT_EQ(c.cone_labelling.threads, c.threads);
}

TEST(StageConfigs, EveryPipelineParameterReachesSomeStage)
{
  // A parameter that no stage config changes with is a parameter nothing reads.
  const core::Params base = distinctParams();
  const core::StageConfigs before = core::stageConfigs(base);
  for (const core::ParamInfo& param : core::parameterTable())
  {
    if (param.scope != core::ParamScope::pipeline)
      continue;
    core::Params changed = base;
    if (param.real_field != nullptr)
      changed.*param.real_field += 0.25;
    else if (param.upper.present && changed.*param.integer_field >= param.upper.value)
      changed.*param.integer_field = static_cast<int>(param.lower.value);  // a switch: turned off
    else
      changed.*param.integer_field += 1;
    const core::StageConfigs after = core::stageConfigs(changed);
    const bool differs =
        after.range_gate.min_range != before.range_gate.min_range ||
        after.range_gate.max_range != before.range_gate.max_range ||
        after.outlier_filter.radius != before.outlier_filter.radius ||
        after.outlier_filter.min_neighbors != before.outlier_filter.min_neighbors ||
        after.echo_comparison.threshold != before.echo_comparison.threshold ||
        after.specular_spots.enabled != before.specular_spots.enabled ||
        after.specular_spots.min_brightness_ratio != before.specular_spots.min_brightness_ratio ||
        after.object_extraction.plane_threshold != before.object_extraction.plane_threshold ||
        after.object_extraction.min_object_points != before.object_extraction.min_object_points ||
        after.object_extraction.connection_distance != before.object_extraction.connection_distance ||
        after.object_type.icp_max_distance != before.object_type.icp_max_distance ||
        after.object_type.icp_fitness_threshold != before.object_type.icp_fitness_threshold ||
        after.object_type.icp_min_points != before.object_type.icp_min_points ||
        after.object_type.icp_min_inlier_fraction != before.object_type.icp_min_inlier_fraction ||
        after.cone_labelling.plane_threshold != before.cone_labelling.plane_threshold ||
        after.cone_labelling.cone_margin != before.cone_labelling.cone_margin ||
        after.phantom_planes.enabled != before.phantom_planes.enabled ||
        after.phantom_planes.min_share != before.phantom_planes.min_share ||
        after.shared_normals.enabled != before.shared_normals.enabled ||
        after.shared_normals.min_cosine != before.shared_normals.min_cosine ||
        after.growth.panes != before.growth.panes ||
        after.growth.mirrors != before.growth.mirrors || after.growth.max_growth != before.growth.max_growth ||
        after.reflection_chains.max_reflections != before.reflection_chains.max_reflections ||
        after.object_map.enabled != before.object_map.enabled ||
        after.object_map.merge_distance != before.object_map.merge_distance ||
        after.object_map.merge_angle != before.object_map.merge_angle ||
        after.object_map.merge_gap != before.object_map.merge_gap ||
        after.object_map.cell_size != before.object_map.cell_size ||
        after.object_map.forgetting != before.object_map.forgetting ||
        after.object_map.type_log_odds != before.object_map.type_log_odds ||
        after.intensity.enabled != before.intensity.enabled ||
        after.intensity.type_log_odds != before.intensity.type_log_odds || differsIn(after.intensity.model, before.intensity.model) ||
        after.outlier_filter.threads != before.outlier_filter.threads ||
        after.object_type.threads != before.object_type.threads ||
        after.cone_labelling.threads != before.cone_labelling.threads;
    EXPECT_TRUE(differs) << param.name << " reaches no stage";
  }
}

}  // namespace
}  // namespace ohm_mirror_detector3d
