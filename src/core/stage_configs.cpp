#include "ohm_mirror_detector3d/core/stage_configs.h"

#include <algorithm>
#include <cmath>

#include "ohm_mirror_detector3d/core/param_table.h"
#include "ohm_mirror_detector3d/core/parallel.h"

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
bool isAutomatic(const Params& params, const char* name)
{
  return findParameter(name)->isAutomatic(params);
}

// Rings of beams around a point that hold at least `neighbours` beams: (2 w + 1)^2 - 1 >= n,
// at most kMaxHalfWidth (beyond it a neighbour is no longer near; more neighbours than that
// window holds leave every point an outlier, as the user asked).
constexpr int kMaxHalfWidth = 8;
int halfWidthHolding(int neighbours)
{
  int w = 1;
  while (w < kMaxHalfWidth && (2 * w + 1) * (2 * w + 1) - 1 < neighbours)
    ++w;
  return w;
}
}  // namespace

StageConfigs stageConfigs(const Params& params)
{
  const bool radius_automatic = isAutomatic(params, "outlierFilter_searchRadius");
  const bool neighbours_automatic = isAutomatic(params, "outlierFilter_minNeighbors");
  const int min_neighbors = neighbours_automatic ? kAutomaticMinNeighbors : params.outlier_min_neighbors;
  BeamNeighbourhoodConfig around;
  around.half_width = 1;
  around.step_factor = kNeighbourStepFactor;
  // Two returns closer than d_thres are one surface, whatever the sampling.
  around.noise_floor = params.echo_threshold;

  StageConfigs configs;
  configs.range_gate = RangeGateConfig{ params.min_range, params.max_range };
  configs.outlier_filter.radius = params.outlier_radius;
  configs.outlier_filter.min_neighbors = min_neighbors;
  configs.outlier_filter.follows_sampling = radius_automatic;
  configs.outlier_filter.neighbourhood = around;
  configs.outlier_filter.neighbourhood.half_width = halfWidthHolding(min_neighbors);
  configs.echo_comparison = EchoComparisonConfig{ params.echo_threshold };
  configs.specular_spots.enabled = params.specular_spot_ratio > 0.0;
  configs.specular_spots.min_brightness_ratio = params.specular_spot_ratio;
  // Surface echoes of one object are as dense as the points the outlier filter keeps: its
  // neighbourhood also decides which of them are connected.
  configs.object_extraction.plane_threshold = params.plane_threshold;
  configs.object_extraction.min_object_points =
      isAutomatic(params, "planeDetection_minAmountPoints") ? kAutomaticMinObjectPoints : params.min_object_points;
  configs.object_extraction.connection_distance = params.outlier_radius;
  configs.specular_spots.min_points = static_cast<std::size_t>(std::max(configs.object_extraction.min_object_points, 3));
  configs.object_extraction.follows_sampling = radius_automatic;
  configs.object_extraction.neighbourhood = around;
  // The original's metric r, set, is honoured as the original used it: no test in beams.
  configs.object_extraction.min_beams_across = radius_automatic ? kMinBeamsAcross : 0;
  configs.object_extraction.footprint_steps = kFootprintSteps;
  configs.mixed_pixels = MixedPixelConfig{ around };
  configs.object_type =
      ObjectTypeConfig{ params.plane_threshold,       params.vision_cone_margin, params.icp_max_distance,
                        params.icp_fitness_threshold, params.icp_min_points,     params.icp_min_inlier_fraction };
  configs.cone_labelling = ConeLabellingConfig{ params.plane_threshold, params.vision_cone_margin };
  configs.phantom_planes.enabled = params.phantom_plane_share > 0.0;
  configs.phantom_planes.min_share = static_cast<float>(params.phantom_plane_share);
  configs.shared_normals.enabled = params.shared_normal_angle > 0.0;
  configs.shared_normals.min_cosine = static_cast<float>(std::cos(params.shared_normal_angle * M_PI / 180.0));
  configs.growth.panes = params.grow_objects >= 1;
  configs.growth.mirrors = params.grow_objects == 1;
  configs.growth.plane_threshold = static_cast<float>(params.plane_threshold);
  configs.growth.max_growth = static_cast<float>(params.growth_max_extent);
  configs.reflection_chains.max_reflections = params.max_reflections;
  configs.reflection_chains.plane_threshold = static_cast<float>(params.plane_threshold);
  configs.reflection_chains.cone_margin = static_cast<float>(params.vision_cone_margin);
  configs.object_map.enabled = params.post_filter != 0;
  configs.object_map.merge_distance = params.map_merge_distance;
  configs.object_map.merge_angle = params.map_merge_angle * M_PI / 180.0;
  configs.object_map.merge_gap = params.map_merge_gap;
  configs.object_map.cell_size = params.map_cell_size;
  configs.object_map.forgetting = params.map_forgetting;
  configs.object_map.type_log_odds = params.map_type_log_odds;
  configs.object_map.intensity_type_log_odds = params.intensity_type_log_odds;
  configs.object_map.plane_threshold = params.plane_threshold;
  configs.object_map.max_range = params.max_range;
  configs.intensity.enabled = params.intensity_evidence != 0;
  configs.intensity.plane_threshold = static_cast<float>(params.plane_threshold);
  configs.intensity.echo_threshold = static_cast<float>(params.echo_threshold);
  configs.intensity.type_log_odds = static_cast<float>(params.intensity_type_log_odds);
  configs.intensity.reach = static_cast<float>(params.growth_max_extent);
  configs.intensity.min_seen_through = static_cast<std::size_t>(std::max(params.icp_min_points, 0));
  auto feature = [](double mirror, double glass, double sigma) {
    return FeatureModel{ static_cast<float>(mirror), static_cast<float>(glass), static_cast<float>(sigma) };
  };
  configs.intensity.model.haze =
      feature(params.intensity_haze_mirror, params.intensity_haze_glass, params.intensity_haze_sigma);
  configs.intensity.model.faint_share = feature(params.intensity_faint_share_mirror,
                                                params.intensity_faint_share_glass, params.intensity_faint_share_sigma);
  configs.intensity.model.echo_ratio = feature(params.intensity_echo_ratio_mirror, params.intensity_echo_ratio_glass,
                                               params.intensity_echo_ratio_sigma);
  configs.threads = isAutomatic(params, "threads") ? automaticThreadCount() : params.threads;
  configs.outlier_filter.threads = configs.threads;
  configs.object_type.threads = configs.threads;
  configs.cone_labelling.threads = configs.threads;
  return configs;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
