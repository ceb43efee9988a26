#include "ohm_mirror_detector3d/core/post_filter.h"

#include <algorithm>
#include <iterator>

namespace ohm_mirror_detector3d
{
namespace core
{
void PostFilter::process(const Sweep& /*sweep*/, const SweepContext& context, const ReflectionEvidence& /*evidence*/,
                         SweepLabels& /*labels*/, std::vector<ReflectiveObject>& objects)
{
  if (!context.has_fixed_pose)
    return;
  map_.observe(objects, context.fixed_from_sweep, merged_ids_);
  const Eigen::Isometry3d sweep_from_fixed = context.fixed_from_sweep.inverse();
  const Eigen::Vector3f sensor_origin = context.sensorOrigin();
  const Eigen::Vector3d sensor_in_fixed = context.fixed_from_sweep * sensor_origin.cast<double>();
  const std::vector<MapObject>& map_objects = map_.objects();
  std::vector<bool> placed(map_objects.size(), false);
  const auto indexOf = [&map_objects](std::uint32_t id) {
    return static_cast<std::size_t>(
        std::find_if(map_objects.begin(), map_objects.end(), [id](const MapObject& o) { return o.id == id; }) -
        map_objects.begin());
  };

  labelling_.clear();
  // The sweep's objects, each replaced by the map object it is part of; the first sweep object
  // of a map object brings its evidence, all of them their surface echoes.
  std::vector<std::size_t> labelling_of(map_objects.size(), 0);
  for (std::size_t k = 0; k < objects.size(); ++k)
  {
    const std::size_t m = indexOf(merged_ids_[k]);
    if (m == map_objects.size())
      continue;  // not merged (a non-finite plane): it cannot label either
    // This sweep's phantom planes of the object and the surfaces seen through it (phantom_planes.h, in
    // the sweep's frame) go with it.
    if (placed[m])
    {
      ReflectiveObject& target = labelling_[labelling_of[m]];
      target.surface_inliers.insert(target.surface_inliers.end(), objects[k].surface_inliers.begin(),
                                    objects[k].surface_inliers.end());
      std::move(objects[k].phantom_planes.begin(), objects[k].phantom_planes.end(),
                std::back_inserter(target.phantom_planes));
      std::move(objects[k].seen_through_surfaces.begin(), objects[k].seen_through_surfaces.end(),
                std::back_inserter(target.seen_through_surfaces));
      continue;
    }
    placed[m] = true;
    labelling_of[m] = labelling_.size();
    labelling_.push_back(map_.toReflectiveObject(map_objects[m], sweep_from_fixed, sensor_origin));
    ReflectiveObject& replaced = labelling_.back();
    replaced.evidence = objects[k].evidence;
    replaced.surface_inliers = std::move(objects[k].surface_inliers);
    replaced.phantom_planes = std::move(objects[k].phantom_planes);
    replaced.seen_through_surfaces = std::move(objects[k].seen_through_surfaces);
  }
  // The map objects this sweep did not see.
  for (std::size_t m = 0; m < map_objects.size(); ++m)
    if (!placed[m] && map_.labelsFrom(map_objects[m], sensor_in_fixed))
      labelling_.push_back(map_.toReflectiveObject(map_objects[m], sweep_from_fixed, sensor_origin));
  for (std::size_t k = 0; k < labelling_.size(); ++k)
    labelling_[k].id = static_cast<std::uint32_t>(k);
  objects.swap(labelling_);
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
