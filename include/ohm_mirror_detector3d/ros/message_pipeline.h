// The pre-filter on ROS messages: the receiver of the input path (sweep_input.h) swaps each
// sweep an input adapter made into sweep(), process() runs the core pipeline and builds the
// output messages. The nodelet and prefilter_bag both use it, so they run exactly the same code.
#pragma once

#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>
#include <visualization_msgs/MarkerArray.h>

#include "ohm_mirror_detector3d/ObjectMapEvidence.h"
#include "ohm_mirror_detector3d/ReflectiveObjectArray.h"
#include "ohm_mirror_detector3d/core/pipeline.h"
#include "ohm_mirror_detector3d/core/sweep_context.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
// Which outputs to build (a nodelet builds only those somebody listens to).
struct OutputRequest
{
  bool labelled = true;
  bool cleaned = true;
  bool objects = true;
  bool markers = true;
  // The post-filter's map, in the fixed frame (built only for a sweep with a fixed pose).
  bool map_objects = false;
  bool map_markers = false;
  bool map_evidence = false;
};

// Output messages of one sweep; those not requested stay null.
struct OutputMessages
{
  sensor_msgs::PointCloud2Ptr labelled;
  sensor_msgs::PointCloud2Ptr cleaned;
  ReflectiveObjectArrayPtr objects;
  visualization_msgs::MarkerArrayPtr markers;
  ReflectiveObjectArrayPtr map_objects;
  visualization_msgs::MarkerArrayPtr map_markers;
  ObjectMapEvidencePtr map_evidence;
};

class MessagePipeline
{
public:
  // Throws std::invalid_argument naming every bad value (core::Pipeline).
  explicit MessagePipeline(const core::Params& params = core::Params());

  // Same check; on failure the previous parameters stay in force.
  void setParams(const core::Params& params) { pipeline_.setParams(params); }
  const core::Params& params() const { return pipeline_.params(); }

  // The sweep process() runs on: the front end swaps each converted sweep into it (or fills it);
  // reused from message to message.
  core::Sweep& sweep() { return sweep_; }
  // The post-filter's object map (core::Pipeline::objectMap).
  core::ObjectMap& objectMap() { return pipeline_.objectMap(); }

  // Runs the pipeline on sweep() with what `context` says about it (the vision cones start at
  // the scanner's position) and builds the requested outputs, stamped and framed as the context
  // says. The result is valid until the next call.
  const core::PipelineResult& process(const core::SweepContext& context, const OutputRequest& request,
                                      OutputMessages& outputs);

private:
  core::Pipeline pipeline_;
  core::Sweep sweep_;
};

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
