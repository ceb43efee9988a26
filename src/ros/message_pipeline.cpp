#include "ohm_mirror_detector3d/ros/message_pipeline.h"

#include "ohm_mirror_detector3d/ros/conversions.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
core::SweepContext sensorFrameContext(const std_msgs::Header& header)
{
  core::SweepContext context;
  context.stamp_ns = header.stamp.toNSec();
  context.frame_id = header.frame_id;
  return context;
}

MessagePipeline::MessagePipeline(const core::Params& params) : pipeline_(params)
{
}

const core::PipelineResult& MessagePipeline::process(const std_msgs::Header& header, const core::SweepContext& context,
                                                     const OutputRequest& request, OutputMessages& outputs)
{
  const core::PipelineResult& result = pipeline_.process(sweep_, context);
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
