#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ohm_mirror_detector3d/core/params.h"

namespace ohm_mirror_detector3d
{
namespace
{
bool mentions(const std::vector<std::string>& errors, const std::string& text)
{
  for (const std::string& error : errors)
    if (error.find(text) != std::string::npos)
      return true;
  return false;
}

TEST(Params, DefaultsAreTheOriginalLaunchFileValuesExceptWhereTheyFollowTheSensor)
{
  const core::Params params;
  EXPECT_DOUBLE_EQ(params.min_range, 0.023);
  EXPECT_DOUBLE_EQ(params.max_range, 60.0);
  // The original's 0.1 m / 50 neighbours / 100 points fit one scanner at one speed: unset,
  // they follow each sweep's sampling (stage_configs.h).
  EXPECT_EQ(params.outlier_radius, core::kAutomatic);
  EXPECT_EQ(params.outlier_min_neighbors, core::kAutomatic);
  EXPECT_EQ(params.min_object_points, core::kAutomatic);
  EXPECT_DOUBLE_EQ(params.echo_threshold, 0.05);
  EXPECT_DOUBLE_EQ(params.plane_threshold, 0.05);
  EXPECT_DOUBLE_EQ(params.vision_cone_margin, 0.05);
  EXPECT_TRUE(params.validate().empty());
}

TEST(Params, NamesEveryBadValueWithItsRosAndPaperName)
{
  core::Params params;
  params.outlier_radius = -0.1;
  params.outlier_min_neighbors = -1;  // 0 would be automatic
  params.echo_threshold = std::numeric_limits<double>::quiet_NaN();
  params.plane_threshold = 0.0;
  params.min_object_points = 2;
  params.vision_cone_margin = -1.0;
  params.icp_max_distance = std::numeric_limits<double>::infinity();
  params.icp_fitness_threshold = 0.0;
  const std::vector<std::string> errors = params.validate();
  EXPECT_EQ(errors.size(), 8u);
  EXPECT_TRUE(mentions(errors, "outlierFilter_searchRadius (r) = -0.1"));
  EXPECT_TRUE(mentions(errors, "outlierFilter_minNeighbors (n_inlier)"));
  EXPECT_TRUE(mentions(errors, "substract_threshold_distance (d_thres) = nan"));
  EXPECT_TRUE(mentions(errors, "planeDetection_threshold_distance (d_thres_plane)"));
  EXPECT_TRUE(mentions(errors, "planeDetection_minAmountPoints (n_object)"));
  EXPECT_TRUE(mentions(errors, "visionCone_threshold (d_thres_visionCone)"));
  EXPECT_TRUE(mentions(errors, "max_Dist_ICP"));
  EXPECT_TRUE(mentions(errors, "fitness_Fct_ICP"));
}

TEST(Params, RefusesMinRangeNotBelowMaxRange)
{
  core::Params params;
  params.min_range = 5.0;
  params.max_range = 5.0;
  const std::vector<std::string> errors = params.validate();
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_TRUE(mentions(errors, "min_measure_distance (d_min) = 5"));
  EXPECT_TRUE(mentions(errors, "max_measure_distance (d_max)"));
}

TEST(Params, SaysTheAllowedRange)
{
  core::Params params;
  params.min_range = -1.0;
  const std::vector<std::string> errors = params.validate();
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_TRUE(mentions(errors, ">= 0"));
}

}  // namespace
}  // namespace ohm_mirror_detector3d
