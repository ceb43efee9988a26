#include "ohm_mirror_detector3d/ros/legacy_outputs.h"

#include "ohm_mirror_detector3d/ros/conversions.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
namespace
{
using core::Label;

// Whether a point labelled `label` belongs to a point set measured as it is.
bool selects(LegacyContent content, Label label)
{
  switch (content)
  {
    case LegacyContent::object:
      return label == Label::errorSurface || label == Label::reflectiveSurface || label == Label::transparentSurface;
    case LegacyContent::transparent:
      return label == Label::transparentSurface;
    case LegacyContent::mirror:
      return label == Label::reflectiveSurface;
    case LegacyContent::affected:
      return label == Label::behindErrorS || label == Label::behindReflective || label == Label::behindTransparent;
    case LegacyContent::behind_transparent:
      return label == Label::behindTransparent;
    case LegacyContent::behind_mirror:
      return label == Label::behindReflective;
    default:
      return false;
  }
}
}  // namespace

const std::vector<LegacyOutput>& legacyOutputs()
{
  static const std::vector<LegacyOutput> outputs = {
    { "pub_scan", "legacy/scan", LegacyContent::scan },
    { "pub_object", "legacy/object", LegacyContent::object },
    { "pub_transp", "legacy/transp", LegacyContent::transparent },
    { "pub_mirror", "legacy/mirror", LegacyContent::mirror },
    { "pub_affected", "legacy/affected", LegacyContent::affected },
    { "pub_behTransp", "legacy/behTransp", LegacyContent::behind_transparent },
    { "pub_behMirror", "legacy/behMirror", LegacyContent::behind_mirror },
    { "pub_backprojMirror", "legacy/backprojMirror", LegacyContent::back_projected },
    { "pub_cleaned", "legacy/cleaned", LegacyContent::cleaned },
    { "pub_marker", "legacy/marker", LegacyContent::marker },
  };
  return outputs;
}

void collectLegacyPoints(LegacyContent content, const core::Sweep& sweep, const core::PipelineResult& result,
                         std::vector<core::OutputPoint>& points)
{
  points.clear();
  if (content == LegacyContent::cleaned || content == LegacyContent::back_projected)
  {
    for (const core::OutputPoint& point : result.cleaned)
      if (content == LegacyContent::cleaned || point.label == Label::behindReflective)
        points.push_back(point);
    return;
  }
  const std::size_t beams = sweep.beamCount();
  for (std::size_t i = 0; i < beams; ++i)
    for (std::size_t k = 0; k < 2; ++k)
    {
      const Label label = result.labels.echoes[k][i];
      if (!selects(content, label))
        continue;
      const Eigen::Vector3f& p = sweep.echoes[k].points[i];
      if (k == 1 && p == sweep.echoes[0].points[i] && selects(content, result.labels.echoes[0][i]))
        continue;
      points.push_back(core::OutputPoint{ p, sweep.echoes[k].intensities[i], label, static_cast<std::uint8_t>(k + 1),
                                          static_cast<std::uint32_t>(i) });
    }
}

void toLegacyMarker(const std_msgs::Header& header, const std::vector<core::ReflectiveObject>& objects,
                    visualization_msgs::Marker& marker)
{
  marker = visualization_msgs::Marker();
  marker.header = header;
  marker.ns = "objects";
  marker.id = 0;
  marker.pose.orientation.w = 1.0;
  if (objects.empty())
  {
    // rviz warns about a line list without points: take the last outlines away instead.
    marker.action = visualization_msgs::Marker::DELETE;
    return;
  }
  marker.type = visualization_msgs::Marker::LINE_LIST;
  marker.action = visualization_msgs::Marker::ADD;
  marker.scale.x = 0.02;
  marker.color = objectColour(core::ObjectType::unknown);
  for (const core::ReflectiveObject& object : objects)
  {
    const std::array<Eigen::Vector3f, 4> corners = object.corners();
    const std_msgs::ColorRGBA colour = objectColour(object.type);
    for (std::size_t c = 0; c < 4; ++c)
    {
      marker.points.push_back(toPoint(corners[c]));
      marker.points.push_back(toPoint(corners[(c + 1) % 4]));
      marker.colors.push_back(colour);
      marker.colors.push_back(colour);
    }
  }
}

void LegacyPublishers::advertise(ros::NodeHandle& nh, const ParamSource& source, bool every_output,
                                 const ros::SubscriberStatusCallback& on_connection)
{
  nh_ = nh;
  on_connection_ = on_connection;
  std::vector<Active> active;
  for (const LegacyOutput& output : legacyOutputs())
  {
    std::string topic;
    if (source.has(output.parameter))
      source.get(output.parameter, topic);
    if (topic.empty() && every_output)
      topic = output.default_topic;
    if (topic.empty())
      continue;
    Active entry{ &output, topic, ros::Publisher() };
    entry.publisher = advertiseOne(entry);
    active.push_back(entry);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  active_ = std::move(active);
}

ros::Publisher LegacyPublishers::advertiseOne(const Active& active)
{
  switch (active.output->content)
  {
    case LegacyContent::scan:
      return ros_io::advertise(nh_, scan_writer_.type(), active.topic, 1, on_connection_, on_connection_);
    case LegacyContent::marker:
      return nh_.advertise<visualization_msgs::Marker>(active.topic, 1, on_connection_, on_connection_);
    default:
      return ros_io::advertise(nh_, point_writer_.type(), active.topic, 1, on_connection_, on_connection_);
  }
}

bool LegacyPublishers::anySubscribed() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  for (const Active& active : active_)
    if (active.publisher.getNumSubscribers() > 0)
      return true;
  return false;
}

std::string LegacyPublishers::describe() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  std::string text;
  for (const Active& active : active_)
    text += (text.empty() ? "" : ", ") + std::string(active.output->parameter) + " " + active.publisher.getTopic();
  return text;
}

std::string LegacyPublishers::useDefinition(const std::string& datatype, const std::string& definition)
{
  const std::string scan_md5 = scan_writer_.type().md5sum;
  const std::string point_md5 = point_writer_.type().md5sum;
  std::string problem = scan_writer_.useDefinition(datatype, definition);
  if (problem.empty())
    problem = point_writer_.useDefinition(datatype, definition);
  if (scan_writer_.type().md5sum != scan_md5)
    readvertise(true);
  if (point_writer_.type().md5sum != point_md5)
    readvertise(false);
  return problem;
}

void LegacyPublishers::readvertise(bool scan)
{
  std::vector<Active*> changed;
  std::vector<ros::Publisher> old;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (Active& active : active_)
      if ((active.output->content == LegacyContent::scan) == scan && active.output->content != LegacyContent::marker)
      {
        changed.push_back(&active);
        old.push_back(active.publisher);
        active.publisher = ros::Publisher();
      }
  }
  // Outside the lock: a topic is advertised with one type at a time, so the old publisher goes first.
  for (ros::Publisher& publisher : old)
    publisher.shutdown();
  for (Active* active : changed)
  {
    ros::Publisher publisher = advertiseOne(*active);
    std::lock_guard<std::mutex> lock(mutex_);
    active->publisher = publisher;
  }
}

void LegacyPublishers::publish(const std_msgs::Header& header, const core::Sweep& sweep,
                               const core::PipelineResult& result, const Eigen::Vector3f& origin)
{
  std::lock_guard<std::mutex> lock(mutex_);
  for (Active& active : active_)
  {
    if (active.publisher.getNumSubscribers() == 0)
      continue;
    const LegacyContent content = active.output->content;
    if (content == LegacyContent::scan)
      active.publisher.publish(scan_writer_.write(header, sweep, &result.labels));
    else if (content == LegacyContent::marker)
    {
      visualization_msgs::MarkerPtr marker(new visualization_msgs::Marker);
      toLegacyMarker(header, result.objects, *marker);
      active.publisher.publish(marker);
    }
    else
    {
      collectLegacyPoints(content, sweep, result, points_);
      active.publisher.publish(point_writer_.write(header, points_, origin));
    }
  }
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
