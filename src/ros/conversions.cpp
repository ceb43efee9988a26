#include "ohm_mirror_detector3d/ros/conversions.h"

#include "ohm_mirror_detector3d/core/output_records.h"
#include "ohm_mirror_detector3d/ros/point_fields.h"

#include <sensor_msgs/PointField.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <cstring>
#include <limits>

namespace ohm_mirror_detector3d
{
namespace ros_io
{
namespace
{
using sensor_msgs::PointField;

void appendField(sensor_msgs::PointCloud2& cloud, const std::string& name, std::uint32_t offset, std::uint8_t datatype)
{
  PointField field;
  field.name = name;
  field.offset = offset;
  field.datatype = datatype;
  field.count = 1;
  cloud.fields.push_back(field);
}

std::uint8_t datatypeOf(core::OutputFieldType type)
{
  switch (type)
  {
    case core::OutputFieldType::float32: return PointField::FLOAT32;
    case core::OutputFieldType::uint8: return PointField::UINT8;
    case core::OutputFieldType::uint32: return PointField::UINT32;
  }
  return 0;
}

// A cloud of `points` core::OutputRecords (fields, sizes; data sized, to be written).
void prepareOutputCloud(const std_msgs::Header& header, std::size_t points, sensor_msgs::PointCloud2& cloud)
{
  cloud.header = header;
  cloud.height = 1;
  cloud.width = static_cast<std::uint32_t>(points);
  cloud.is_bigendian = false;
  cloud.is_dense = false;
  cloud.point_step = sizeof(core::OutputRecord);
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.fields.clear();
  for (const core::OutputField& field : core::outputFields())
    appendField(cloud, field.name, field.offset, datatypeOf(field.type));
  cloud.data.resize(static_cast<std::size_t>(cloud.row_step));
}
}  // namespace

core::SweepContext toSweepContext(const std_msgs::Header& header)
{
  core::SweepContext context;
  context.stamp_ns = header.stamp.toNSec();
  context.frame_id = header.frame_id;
  return context;
}

std_msgs::Header toHeader(const core::SweepContext& context)
{
  std_msgs::Header header;
  header.stamp.fromNSec(context.stamp_ns);
  header.frame_id = context.frame_id;
  return header;
}

Eigen::Isometry3d toIsometry(const geometry_msgs::Transform& transform)
{
  const geometry_msgs::Quaternion& q = transform.rotation;
  const geometry_msgs::Vector3& t = transform.translation;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized().toRotationMatrix();
  pose.translation() = Eigen::Vector3d(t.x, t.y, t.z);
  return pose;
}

std::string readEchoCloud(const sensor_msgs::PointCloud2& cloud, core::EchoCloud& echo, bool& has_intensity)
{
  std::string layout = checkCloudLayout(cloud);
  if (!layout.empty())
    return layout;
  const std::size_t points = static_cast<std::size_t>(cloud.width) * cloud.height;
  const PointField* x = findField(cloud, "x");
  const PointField* y = findField(cloud, "y");
  const PointField* z = findField(cloud, "z");
  for (const auto& named : { std::make_pair(x, "x"), std::make_pair(y, "y"), std::make_pair(z, "z") })
  {
    const std::string problem = checkField(named.first, named.second, cloud.point_step, true);
    if (!problem.empty())
      return problem;
  }
  const PointField* intensity = findField(cloud, "intensity");
  if (intensity != nullptr && !checkField(intensity, "intensity", cloud.point_step, false).empty())
    return checkField(intensity, "intensity", cloud.point_step, false);
  has_intensity = intensity != nullptr;

  echo.points.resize(points);
  echo.ranges.resize(points);
  echo.intensities.resize(points);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::size_t i = 0;
  // An empty cloud may still claim up to 2^32 - 1 rows of width 0 (found by the fuzzer: an
  // unoptimised build then spins for minutes): no point, no loop.
  const std::uint32_t rows = points == 0 ? 0 : cloud.height;
  for (std::uint32_t row = 0; row < rows; ++row)
  {
    const std::uint8_t* point = cloud.data.data() + static_cast<std::size_t>(row) * cloud.row_step;
    for (std::uint32_t col = 0; col < cloud.width; ++col, ++i, point += cloud.point_step)
    {
      Eigen::Vector3f& p = echo.points[i];
      std::memcpy(&p.x(), point + x->offset, sizeof(float));
      std::memcpy(&p.y(), point + y->offset, sizeof(float));
      std::memcpy(&p.z(), point + z->offset, sizeof(float));
      echo.intensities[i] = intensity != nullptr ? readNumber(point + intensity->offset, intensity->datatype) : nan;
    }
  }
  return "";
}

std::string echoCloudsToSweep(const sensor_msgs::PointCloud2& echo1, const sensor_msgs::PointCloud2& echo2,
                              core::Sweep& sweep)
{
  const std::uint64_t size1 = static_cast<std::uint64_t>(echo1.width) * echo1.height;
  const std::uint64_t size2 = static_cast<std::uint64_t>(echo2.width) * echo2.height;
  if (size1 != size2)
    return "echo1 has " + std::to_string(size1) + " points but echo2 has " + std::to_string(size2) +
           "; the echoes must be index-aligned";
  bool intensity1 = false;
  bool intensity2 = false;
  std::string problem = readEchoCloud(echo1, sweep.echoes[0], intensity1);
  if (!problem.empty())
    return "echo1 " + problem;
  problem = readEchoCloud(echo2, sweep.echoes[1], intensity2);
  if (!problem.empty())
    return "echo2 " + problem;
  // An empty cloud is a 0 x 0 grid, whatever its height or width claims.
  sweep.rows = size1 == 0 ? 0 : echo1.height;
  sweep.cols = size1 == 0 ? 0 : echo1.width;
  sweep.has_intensity = intensity1 && intensity2;
  sweep.input_cells.clear();
  sweep.computeRanges(Eigen::Vector3f::Zero());
  return "";
}

std::string echoPairToSweep(const EchoPair& pair, core::Sweep& sweep)
{
  return echoCloudsToSweep(pair.echo1, pair.echo2, sweep);
}

void toLabelledCloud(const std_msgs::Header& header, const core::Sweep& sweep, const core::SweepLabels& labels,
                     sensor_msgs::PointCloud2& cloud)
{
  prepareOutputCloud(header, core::labelledRecordCount(sweep), cloud);
  core::writeLabelledRecords(sweep, labels, cloud.data.data());
}

void toCleanedCloud(const std_msgs::Header& header, const std::vector<core::OutputPoint>& points,
                    sensor_msgs::PointCloud2& cloud)
{
  prepareOutputCloud(header, points.size(), cloud);
  cloud.is_dense = true;
  core::writeCleanedRecords(points, cloud.data.data());
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d

namespace ohm_mirror_detector3d
{
namespace ros_io
{
geometry_msgs::Point toPoint(const Eigen::Vector3f& p)
{
  geometry_msgs::Point point;
  point.x = p.x();
  point.y = p.y();
  point.z = p.z();
  return point;
}

std_msgs::ColorRGBA objectColour(core::ObjectType type)
{
  std_msgs::ColorRGBA colour;
  colour.a = 1.0f;
  switch (type)
  {
    case core::ObjectType::mirror:  // blue
      colour.r = 0.2f, colour.g = 0.4f, colour.b = 1.0f;
      break;
    case core::ObjectType::glass:  // turquoise, the paper's surface colour
      colour.r = 0.25f, colour.g = 0.88f, colour.b = 0.82f;
      break;
    default:  // yellow: something reflects, type undecided
      colour.r = 1.0f, colour.g = 0.8f, colour.b = 0.0f;
  }
  return colour;
}

void toObjectArray(const std_msgs::Header& header, const std::vector<core::ReflectiveObject>& objects,
                   ReflectiveObjectArray& array)
{
  array.header = header;
  array.objects.resize(objects.size());
  for (std::size_t j = 0; j < objects.size(); ++j)
  {
    const core::ReflectiveObject& object = objects[j];
    ReflectiveObject& out = array.objects[j];
    out.id = object.id;
    out.type = static_cast<std::uint8_t>(object.type);
    const std::array<Eigen::Vector3f, 4> corners = object.corners();
    for (std::size_t c = 0; c < 4; ++c)
      out.corners[c] = toPoint(corners[c]);
    out.width = object.width;
    out.height = object.height;
    const std::array<Eigen::Vector3f, 4> patch = object.patchCorners();
    for (std::size_t c = 0; c < 4; ++c)
      out.patch_corners[c] = toPoint(patch[c]);
    out.patch_width = object.grown ? object.patch_width : object.width;
    out.patch_height = object.grown ? object.patch_height : object.height;
    out.growth_capped = object.growth_capped;
    for (int c = 0; c < 4; ++c)
      out.plane[static_cast<std::size_t>(c)] = object.plane[c];
    out.surface_points = static_cast<std::uint32_t>(object.surface_points);
    out.behind_points = static_cast<std::uint32_t>(object.behind_points);
    out.phantom_points = static_cast<std::uint32_t>(object.phantom_points);
    out.transmitted_points = static_cast<std::uint32_t>(object.transmitted_points);
    out.ambiguous_points = static_cast<std::uint32_t>(object.ambiguous_points);
    out.undecided_points = static_cast<std::uint32_t>(object.undecided_points);
    const core::TypeEvidence& evidence = object.evidence;
    out.mirrored_points = static_cast<std::uint32_t>(evidence.mirrored_points);
    out.tested_points = static_cast<std::uint32_t>(evidence.tested_points);
    out.inlier_fraction = evidence.inlier_fraction;
    out.real_fraction = evidence.real_fraction;
    out.landing_fitness = evidence.landing_fitness;
    out.plane_refined = evidence.plane_refined;
    out.plane_correction = evidence.plane_correction;
    out.mean_surface_intensity = object.mean_surface_intensity;
  }
}

void toMarkers(const std_msgs::Header& header, const std::vector<core::ReflectiveObject>& objects,
               visualization_msgs::MarkerArray& markers)
{
  markers.markers.clear();
  visualization_msgs::Marker clear;
  clear.header = header;
  clear.action = visualization_msgs::Marker::DELETEALL;
  markers.markers.push_back(clear);
  for (const core::ReflectiveObject& object : objects)
  {
    visualization_msgs::Marker outline;
    outline.header = header;
    outline.ns = "objects";
    outline.id = static_cast<std::int32_t>(object.id);
    outline.type = visualization_msgs::Marker::LINE_STRIP;
    outline.action = visualization_msgs::Marker::ADD;
    outline.pose.orientation.w = 1.0;
    outline.scale.x = 0.02;
    outline.color = objectColour(object.type);
    const std::array<Eigen::Vector3f, 4> corners = object.corners();
    for (const Eigen::Vector3f& corner : corners)
      outline.points.push_back(toPoint(corner));
    outline.points.push_back(toPoint(corners[0]));
    markers.markers.push_back(outline);
    if (object.grown)
    {
      // The surface-echo patch the rectangle grew from, thinner inside it.
      visualization_msgs::Marker patch = outline;
      patch.ns = "patches";
      patch.scale.x = 0.01;
      patch.points.clear();
      const std::array<Eigen::Vector3f, 4> patch_corners = object.patchCorners();
      for (const Eigen::Vector3f& corner : patch_corners)
        patch.points.push_back(toPoint(corner));
      patch.points.push_back(toPoint(patch_corners[0]));
      markers.markers.push_back(patch);
    }

    visualization_msgs::Marker text;
    text.header = header;
    text.ns = "labels";
    text.id = static_cast<std::int32_t>(object.id);
    text.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
    text.action = visualization_msgs::Marker::ADD;
    text.pose.position = toPoint(object.centre + (0.5f * object.height + 0.1f) * object.height_axis);
    text.pose.orientation.w = 1.0;
    text.scale.z = 0.1;
    text.color = objectColour(object.type);
    char description[96];
    std::snprintf(description, sizeof(description), "%s %u: %.1f x %.1f cm", core::objectTypeName(object.type),
                  object.id, 100.0 * object.width, 100.0 * object.height);
    text.text = description;
    markers.markers.push_back(text);
  }
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
