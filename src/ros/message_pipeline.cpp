#include "ohm_mirror_detector3d/ros/message_pipeline.h"

#include "ohm_mirror_detector3d/ros/conversions.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
MessagePipeline::MessagePipeline(const core::Params& params) : pipeline_(params)
{
}

const core::PipelineResult& MessagePipeline::process(const core::SweepContext& context, const OutputRequest& request,
                                                     OutputMessages& outputs)
{
  // The adapters measure ranges from the origin of the points' frame; a context that puts the
  // scanner elsewhere (sensor_frame, the mean position of a rotating scanner) is where they are
  // measured from.
  const Eigen::Vector3f sensor_origin = context.sensorOrigin();
  if (sensor_origin != Eigen::Vector3f::Zero())
    sweep_.computeRanges(sensor_origin);
  const core::PipelineResult& result = pipeline_.process(sweep_, context);
  const std_msgs::Header header = toHeader(context);
  outputs = OutputMessages();
  if (request.labelled)
  {
    outputs.labelled.reset(new sensor_msgs::PointCloud2);
    toLabelledCloud(header, sweep_, result.labels, *outputs.labelled);
  }
  if (request.cleaned)
  {
    outputs.cleaned.reset(new sensor_msgs::PointCloud2);
    toCleanedCloud(header, result.cleaned, *outputs.cleaned);
  }
  if (request.objects)
  {
    outputs.objects.reset(new ReflectiveObjectArray);
    toObjectArray(header, result.objects, *outputs.objects);
  }
  if (request.markers)
  {
    outputs.markers.reset(new visualization_msgs::MarkerArray);
    toMarkers(header, result.objects, *outputs.markers);
  }
  if (context.has_fixed_pose && (request.map_objects || request.map_markers || request.map_evidence))
  {
    std_msgs::Header fixed_header = header;
    fixed_header.frame_id = context.fixed_frame_id;
    const Eigen::Vector3f sensor_in_fixed = (context.fixed_from_sweep * context.sensor_pose.translation()).cast<float>();
    std::vector<core::ReflectiveObject> map_objects;
    const core::ObjectMap& map = pipeline_.objectMap();
    for (const core::MapObject& object : map.objects())
      map_objects.push_back(map.toReflectiveObject(object, Eigen::Isometry3d::Identity(), sensor_in_fixed));
    if (request.map_objects)
    {
      outputs.map_objects.reset(new ReflectiveObjectArray);
      toObjectArray(fixed_header, map_objects, *outputs.map_objects);
    }
    if (request.map_markers)
    {
      outputs.map_markers.reset(new visualization_msgs::MarkerArray);
      toMarkers(fixed_header, map_objects, *outputs.map_markers);
    }
    if (request.map_evidence)
    {
      outputs.map_evidence.reset(new ObjectMapEvidence);
      outputs.map_evidence->header = fixed_header;
      for (const core::MapObject& object : map.objects())
      {
        outputs.map_evidence->ids.push_back(object.id);
        outputs.map_evidence->sweeps_seen.push_back(object.sweeps_seen);
        outputs.map_evidence->mirror_log_odds.push_back(static_cast<float>(object.mirror_log_odds));
      }
    }
  }
  return result;
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
