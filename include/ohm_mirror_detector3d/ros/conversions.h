// Conversions between ROS messages and the core's plain types.
#pragma once

#include <geometry_msgs/Point.h>
#include <geometry_msgs/Transform.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/ColorRGBA.h>
#include <std_msgs/Header.h>

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include <visualization_msgs/MarkerArray.h>

#include "ohm_mirror_detector3d/EchoPair.h"
#include "ohm_mirror_detector3d/ReflectiveObjectArray.h"
#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/cleaned_output.h"
#include "ohm_mirror_detector3d/core/sweep.h"
#include "ohm_mirror_detector3d/core/sweep_context.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
// The context of a sweep taken at `header`'s stamp in its frame, the scanner at the frame's
// origin (no rotation); an input with another scanner pose sets sensor_pose afterwards.
core::SweepContext toSweepContext(const std_msgs::Header& header);
// The header of the outputs of a sweep: its stamp and frame.
std_msgs::Header toHeader(const core::SweepContext& context);

// A tf transform as an isometry (the rotation normalised).
Eigen::Isometry3d toIsometry(const geometry_msgs::Transform& transform);

// Reads the x, y, z (float32) and optional numeric `intensity` fields of every point of
// `cloud` into `echo`, in row-major order. Returns an empty string on success, otherwise
// what is wrong with the cloud (missing or mistyped field, inconsistent sizes, ...);
// `echo` is then unspecified. Sets `has_intensity` to whether the cloud had intensities.
std::string readEchoCloud(const sensor_msgs::PointCloud2& cloud, core::EchoCloud& echo, bool& has_intensity);

// Fills `sweep` (rows = height, cols = width of echo1) from an EchoPair whose clouds
// are in the scanner frame. Returns an empty string on success, otherwise the problem.
std::string echoPairToSweep(const EchoPair& pair, core::Sweep& sweep);

// Same from two index-aligned clouds (input mode two_topics).
std::string echoCloudsToSweep(const sensor_msgs::PointCloud2& echo1, const sensor_msgs::PointCloud2& echo2,
                              core::Sweep& sweep);

// Every point of both echoes (echo 1 first, then echo 2, each in beam order; or, when the
// sweep has input_cells, the input's points in the input's order, those in no grid cell as
// nanPoint with echo 0 and beam 0xFFFFFFFF), fields x y z intensity label echo beam,
// positions as measured.
void toLabelledCloud(const std_msgs::Header& header, const core::Sweep& sweep, const core::SweepLabels& labels,
                     sensor_msgs::PointCloud2& cloud);

// The points for mapping, same fields as the labelled cloud.
void toCleanedCloud(const std_msgs::Header& header, const std::vector<core::OutputPoint>& points,
                    sensor_msgs::PointCloud2& cloud);

void toObjectArray(const std_msgs::Header& header, const std::vector<core::ReflectiveObject>& objects,
                   ReflectiveObjectArray& array);

// A corner or centre as a message point (the markers and the objects' corners).
geometry_msgs::Point toPoint(const Eigen::Vector3f& p);

// The colour of an object of `type` in rviz: mirror blue, glass turquoise, unknown yellow.
std_msgs::ColorRGBA objectColour(core::ObjectType type);

// A rectangle (line strip) per object coloured by type and a text with type and size (for an
// object that grew, its surface-echo patch too, namespace "patches", thinner), preceded by a DELETEALL so that markers of objects that went away disappear.
void toMarkers(const std_msgs::Header& header, const std::vector<core::ReflectiveObject>& objects,
               visualization_msgs::MarkerArray& markers);

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
