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
  return result;
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
