#include "ohm_mirror_detector3d/core/stage_configs.h"

namespace ohm_mirror_detector3d
{
namespace core
{
StageConfigs stageConfigs(const Params& params)
{
  StageConfigs configs;
  configs.range_gate = RangeGateConfig{ params.min_range, params.max_range };
  configs.outlier_filter = OutlierFilterConfig{ params.outlier_radius, params.outlier_min_neighbors };
  configs.echo_comparison = EchoComparisonConfig{ params.echo_threshold };
  // Surface echoes of one object are as dense as the points the outlier filter keeps: its
  // radius also decides which of them are connected.
  configs.object_extraction =
      ObjectExtractionConfig{ params.plane_threshold, params.min_object_points, params.outlier_radius };
  configs.object_type =
      ObjectTypeConfig{ params.plane_threshold,       params.vision_cone_margin, params.icp_max_distance,
                        params.icp_fitness_threshold, params.icp_min_points,     params.icp_min_inlier_fraction };
  configs.cone_labelling = ConeLabellingConfig{ params.plane_threshold, params.vision_cone_margin };
  return configs;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
