#include "fuzz_entry.h"

#include <ros/serialization.h>
#include <sensor_msgs/MultiEchoLaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2/buffer_core.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>

#include "ohm_mirror_detector3d/EchoPair.h"
#include "ohm_mirror_detector3d/core/labels.h"
#include "ohm_mirror_detector3d/ros/conversions.h"
#include "ohm_mirror_detector3d/ros/dual_return.h"
#include "ohm_mirror_detector3d/ros/hokuyo3d_legacy.h"
#include "ohm_mirror_detector3d/ros/message_pipeline.h"
#include "ohm_mirror_detector3d/ros/message_walker.h"
#include "ohm_mirror_detector3d/ros/multi_echo_scan.h"

namespace ohm_mirror_detector3d
{
namespace fuzz
{
namespace
{
using ros_io::FieldLocation;
using ros_io::MessageDefinition;
using ros_io::walkMessage;

// Reports a broken invariant and aborts, which libFuzzer turns into a crash reproducer.
[[noreturn]] void fail(const std::string& what)
{
  std::fprintf(stderr, "fuzz invariant broken: %s\n", what.c_str());
  std::abort();
}

// Parameter sets: the defaults (most fuzz clouds are then all outliers) and small ones with
// which a cloud of a few dozen points reaches object extraction, the ICP type test and the
// cone labelling.
core::Params paramSet(std::uint8_t selector)
{
  core::Params params;
  switch (selector % 3)
  {
    case 1:
      params.outlier_min_neighbors = 1;
      params.outlier_radius = 100.0;
      params.min_object_points = 3;
      params.icp_min_points = 3;
      break;
    case 2:
      params.outlier_min_neighbors = 2;
      params.outlier_radius = 0.5;
      params.min_object_points = 4;
      params.icp_min_points = 4;
      params.echo_threshold = 0.01;
      params.vision_cone_margin = 0.0;
      break;
    default:
      break;
  }
  return params;
}

// roscpp's deserializer sizes a vector from its length prefix before it checks that the
// bytes are there, so a short message with a huge prefix would make it allocate gigabytes:
// the bytes are first walked with the message's own definition, which checks every length
// against what is left (a real subscriber gets whole messages from its publisher).
template <typename Message>
bool deserialize(const std::uint8_t* data, std::size_t size, Message& message)
{
  static MessageDefinition definition;
  static const std::string parse_problem = definition.parse(ros::message_traits::datatype<Message>(),
                                                            ros::message_traits::definition<Message>());
  if (!parse_problem.empty())
    fail("cannot parse the definition of " + std::string(ros::message_traits::datatype<Message>()) + ": " +
         parse_problem);
  std::map<std::string, FieldLocation> locations;
  if (!walkMessage(definition, data, size, locations).empty())
    return false;
  try
  {
    ros::serialization::IStream stream(const_cast<std::uint8_t*>(data), static_cast<std::uint32_t>(size));
    ros::serialization::deserialize(stream, message);
  }
  catch (const ros::serialization::StreamOverrunException&)
  {
    fail("walkMessage accepted bytes that roscpp cannot deserialize");
  }
  return true;
}

// Checks the outputs of one sweep against the input it came from.
void checkOutputs(const core::Sweep& sweep, std::size_t input_points, const ros_io::OutputMessages& outputs,
                  const core::PipelineResult& result)
{
  const sensor_msgs::PointCloud2& labelled = *outputs.labelled;
  const std::size_t labelled_points = static_cast<std::size_t>(labelled.width) * labelled.height;
  if (labelled_points != input_points)
    fail("labelled holds " + std::to_string(labelled_points) + " points for " + std::to_string(input_points) +
         " input points");
  if (labelled.data.size() != static_cast<std::size_t>(labelled.row_step) * labelled.height)
    fail("labelled data size does not match row_step * height");
  for (std::size_t i = 0; i < labelled_points; ++i)
  {
    const std::uint8_t label = labelled.data[i * labelled.point_step + 16];
    if (label < static_cast<std::uint8_t>(core::Label::valid) || label > static_cast<std::uint8_t>(core::Label::error))
      fail("labelled point " + std::to_string(i) + " has label " + std::to_string(label));
  }
  const sensor_msgs::PointCloud2& cleaned = *outputs.cleaned;
  if (static_cast<std::size_t>(cleaned.width) * cleaned.height > 2 * sweep.beamCount())
    fail("cleaned holds more points than the sweep");
  if (outputs.objects->objects.size() != result.objects.size())
    fail("objects message and result disagree");
}

std::size_t inputPoints(const core::Sweep& sweep)
{
  return sweep.input_cells.empty() ? 2 * sweep.beamCount() : sweep.input_cells.size();
}

void runPipeline(ros_io::MessagePipeline& pipeline, const core::SweepContext& context, FuzzOutcome& outcome)
{
  const std::size_t input_points = inputPoints(pipeline.sweep());
  ros_io::OutputMessages outputs;
  const core::PipelineResult& result = pipeline.process(context, ros_io::OutputRequest(), outputs);
  checkOutputs(pipeline.sweep(), input_points, outputs, result);
  ++outcome.sweeps;
}

void runMultiEchoScans(const std::uint8_t* data, std::size_t size, ros_io::MessagePipeline& pipeline,
                       FuzzOutcome& outcome)
{
  tf2::BufferCore buffer;
  geometry_msgs::TransformStamped laser;
  laser.header.frame_id = "map";
  laser.child_frame_id = "laser";
  laser.transform.rotation.w = 1.0;
  laser.transform.translation.z = 0.5;
  buffer.setTransform(laser, "fuzz", true);
  ros_io::MultiEchoScanOptions options;
  options.sweep_frame = "map";
  options.sweep_period = 0.05;
  options.max_pending_scans = 8;
  ros_io::MultiEchoScanInput input(options, "fuzz");
  const ros_io::MultiEchoScanInput::SweepSink sink = [&](core::Sweep& sweep, const core::SweepContext& context) {
    std::swap(pipeline.sweep(), sweep);
    runPipeline(pipeline, context, outcome);
  };
  std::size_t offset = 0;
  while (offset + 4 <= size)
  {
    std::uint32_t length;
    std::memcpy(&length, data + offset, 4);
    offset += 4;
    if (length > size - offset)
      break;
    sensor_msgs::MultiEchoLaserScan::Ptr scan(new sensor_msgs::MultiEchoLaserScan);
    const bool ok = deserialize(data + offset, length, *scan);
    offset += length;
    if (!ok)
      continue;
    outcome.deserialized = true;
    const std::string problem = input.addScan(scan);
    if (problem.empty())
      outcome.converted = true;
    else
      outcome.problem = problem;
    input.drain(buffer, sink);
  }
}
}  // namespace

const std::string& legacyDefinition()
{
  static const std::string line(80, '=');
  static const std::string definition =
      "CoordDist[] coorddist\n" + line + "\nMSG: ohm_hokuyo3d/CoordDist\nCoord coord\nDist dist\n" + line +
      "\nMSG: ohm_hokuyo3d/Coord\nHeader header\nuint32 fragmentid\nuint32 fragmentsize\nfloat32[] coords\n"
      "float32[] normals\nbool[] mask\nfloat32[] intensity\nint32[] objectType\n" +
      line + "\nMSG: std_msgs/Header\nuint32 seq\ntime stamp\nstring frame_id\n" + line +
      "\nMSG: ohm_hokuyo3d/Dist\nHeader header\nfloat32[] dists\nfloat32[] phi\nbool[] mask\n";
  return definition;
}

FuzzOutcome runFuzzInput(const std::uint8_t* data, std::size_t size)
{
  FuzzOutcome outcome;
  if (size < 2)
    return outcome;
  const FuzzMode mode = static_cast<FuzzMode>(data[0] % kFuzzModes);
  ros_io::MessagePipeline pipeline(paramSet(data[1]));
  data += 2;
  size -= 2;
  std::string problem;
  std_msgs::Header header;
  switch (mode)
  {
    case FuzzMode::pair:
    case FuzzMode::two_topics:
    {
      EchoPair pair;
      if (!deserialize(data, size, pair))
        return outcome;
      outcome.deserialized = true;
      header = pair.header;
      problem = mode == FuzzMode::pair ? ros_io::echoPairToSweep(pair, pipeline.sweep()) :
                                         ros_io::echoCloudsToSweep(pair.echo1, pair.echo2, pipeline.sweep());
      break;
    }
    case FuzzMode::dual_return:
    {
      sensor_msgs::PointCloud2 cloud;
      if (!deserialize(data, size, cloud))
        return outcome;
      outcome.deserialized = true;
      header = cloud.header;
      core::DualReturnInput input;
      core::DualReturnBinner binner;
      core::DualReturnStats stats;
      problem = ros_io::dualReturnCloudToSweep(cloud, core::kAzimuthStepFromCloud, input, binner, pipeline.sweep(),
                                               stats);
      if (problem.empty())
        core::describeUnbinned(stats);
      break;
    }
    case FuzzMode::hokuyo3d_legacy:
    {
      ros_io::Hokuyo3dLegacyDecoder decoder;
      outcome.deserialized = true;
      problem = decoder.decode("ohm_hokuyo3d/CoordDistMulti", legacyDefinition(), data, size, pipeline.sweep(),
                               header);
      break;
    }
    case FuzzMode::multi_echo_scan:
      runMultiEchoScans(data, size, pipeline, outcome);
      return outcome;
  }
  outcome.problem = problem;
  if (!problem.empty())
    return outcome;
  outcome.converted = true;
  runPipeline(pipeline, ros_io::toSweepContext(header), outcome);
  return outcome;
}

}  // namespace fuzz
}  // namespace ohm_mirror_detector3d
