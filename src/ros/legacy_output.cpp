#include "ohm_mirror_detector3d/ros/legacy_output.h"

#include <ros/serialization.h>

#include <stdexcept>

namespace ohm_mirror_detector3d
{
namespace ros_io
{
namespace
{
const char* const kEchoArray = "coorddist";

// The layout the hokuyo3d_legacy input reads (src/ohm_mirror_detector3d/hokuyo3d_legacy.py
// writes the same; test/legacy_msgs/ohm_hokuyo3d holds it as .msg files).
const char* const kBuiltinScanDefinition =
    "CoordDist[] coorddist\n"
    "================================================================================\n"
    "MSG: ohm_hokuyo3d/CoordDist\n"
    "Coord coord\n"
    "Dist dist\n"
    "================================================================================\n"
    "MSG: ohm_hokuyo3d/Coord\n"
    "Header header\n"
    "uint32 fragmentid\n"
    "uint32 fragmentsize\n"
    "float32[] coords\n"
    "float32[] normals\n"
    "bool[] mask\n"
    "float32[] intensity\n"
    "int32[] objectType\n"
    "================================================================================\n"
    "MSG: std_msgs/Header\n"
    "uint32 seq\n"
    "time stamp\n"
    "string frame_id\n"
    "================================================================================\n"
    "MSG: ohm_hokuyo3d/Dist\n"
    "Header header\n"
    "float32[] dists\n"
    "float32[] phi\n"
    "bool[] mask\n";

const FieldSpec* fieldNamed(const MessageSpec& spec, const std::string& name)
{
  for (const FieldSpec& field : spec.fields)
    if (field.name == name)
      return &field;
  return nullptr;
}
}  // namespace

const std::string& builtinLegacyScanDefinition()
{
  static const std::string definition(kBuiltinScanDefinition);
  return definition;
}

ros::Publisher advertise(ros::NodeHandle& nh, const AnnouncedType& type, const std::string& topic,
                         std::uint32_t queue_size, const ros::SubscriberStatusCallback& connect,
                         const ros::SubscriberStatusCallback& disconnect)
{
  ros::AdvertiseOptions options(topic, queue_size, type.md5sum, type.datatype, type.definition, connect, disconnect);
  // roscpp would write a sequence number over the first bytes of a message "with a header";
  // these messages start with other fields.
  options.has_header = false;
  return nh.advertise(options);
}

void LegacyWriter::PointSetBuffers::resize(std::size_t points)
{
  coords.resize(3 * points);
  mask.resize(points);
  intensity.resize(points);
  dists.resize(points);
}

LegacyWriter::LegacyWriter(bool coord_dist_only) : coord_dist_only_(coord_dist_only)
{
  const std::string problem = useDefinition(kLegacyScanDatatype, builtinLegacyScanDefinition());
  if (!problem.empty())
    throw std::logic_error("the built-in definition of " + std::string(kLegacyScanDatatype) + " is unusable: " +
                           problem);
}

std::string LegacyWriter::specFor(const MessageDefinition& definition, const MessageSpec*& spec) const
{
  const MessageSpec& root = definition.root();
  const FieldSpec* echoes = fieldNamed(root, kEchoArray);
  if (echoes == nullptr || !echoes->is_array || echoes->nested == nullptr)
    return "message definition of " + root.name + " has no field '" + kEchoArray +
           "' that is an array of CoordDist messages";
  const FieldSpec* coord = fieldNamed(*echoes->nested, "coord");
  const FieldSpec* coords = coord != nullptr && coord->nested != nullptr ? fieldNamed(*coord->nested, "coords") : nullptr;
  if (coords == nullptr || coords->typeName() != "float32[]")
    return "message definition of " + root.name + ": " + echoes->nested->name +
           " has no field 'coord.coords' of type float32[]";
  spec = coord_dist_only_ ? echoes->nested : &root;
  return "";
}

std::string LegacyWriter::useDefinition(const std::string& datatype, const std::string& definition)
{
  MessageDefinition candidate;
  std::string problem = candidate.parse(datatype, definition);
  const MessageSpec* spec = nullptr;
  if (problem.empty())
    problem = specFor(candidate, spec);
  if (problem.empty())
  {
    // A one-point message with every value the writer fills finds any field of another type.
    PointSetBuffers point;
    point.resize(1);
    values_.clear();
    if (coord_dist_only_)
      setCoordDist("", point);
    else
    {
      values_.setCount(kEchoArray, 2);
      setCoordDist(std::string(kEchoArray) + "[0].", point);
      setCoordDist(std::string(kEchoArray) + "[1].", point);
    }
    problem = serializeMessage(*spec, values_, bytes_);
    values_.clear();
  }
  if (!problem.empty())
    return problem;
  const std::string name = spec->name;
  definition_ = std::move(candidate);
  spec_ = definition_.find(name);
  type_ = AnnouncedType{ spec_->name, md5sum(*spec_), fullDefinition(*spec_) };
  return "";
}

void LegacyWriter::setHeader(const std_msgs::Header& header)
{
  seq_ = header.seq;
  stamp_ = { header.stamp.sec, header.stamp.nsec };
  frame_id_ = header.frame_id;
}

void LegacyWriter::setCoordDist(const std::string& prefix, const PointSetBuffers& buffers)
{
  for (const char* part : { "coord.", "dist." })
  {
    const std::string header = prefix + part + "header.";
    values_.set(header + "seq", "uint32", &seq_, 1);
    values_.set(header + "stamp", "time", stamp_.data(), 1);
    values_.setString(header + "frame_id", frame_id_);
  }
  values_.set(prefix + "coord.fragmentid", "uint32", &fragment_id_, 1);
  values_.set(prefix + "coord.fragmentsize", "uint32", &fragment_size_, 1);
  values_.set(prefix + "coord.coords", "float32", buffers.coords.data(), buffers.coords.size());
  values_.set(prefix + "coord.mask", "bool", buffers.mask.data(), buffers.mask.size());
  values_.set(prefix + "coord.intensity", "float32", buffers.intensity.data(), buffers.intensity.size());
  values_.set(prefix + "dist.dists", "float32", buffers.dists.data(), buffers.dists.size());
  values_.set(prefix + "dist.mask", "bool", buffers.mask.data(), buffers.mask.size());
}

topic_tools::ShapeShifter::Ptr LegacyWriter::serialize() const
{
  const std::string problem = serializeMessage(*spec_, values_, bytes_);
  if (!problem.empty())  // useDefinition() wrote the same fields into this spec
    throw std::logic_error("cannot serialize " + type_.datatype + ": " + problem);
  topic_tools::ShapeShifter::Ptr message(new topic_tools::ShapeShifter);
  message->morph(type_.md5sum, type_.datatype, type_.definition, "0");
  ros::serialization::IStream stream(bytes_.data(), static_cast<std::uint32_t>(bytes_.size()));
  message->read(stream);
  return message;
}

LegacyScanWriter::LegacyScanWriter() : LegacyWriter(false)
{
}

topic_tools::ShapeShifter::Ptr LegacyScanWriter::write(const std_msgs::Header& header, const core::Sweep& sweep,
                                                       const core::SweepLabels* labels)
{
  const std::size_t beams = sweep.beamCount();
  if (labels != nullptr && (labels->echoes[0].size() != beams || labels->echoes[1].size() != beams))
    throw std::invalid_argument("LegacyScanWriter: labels for " + std::to_string(labels->echoes[0].size()) +
                                " beams, the sweep has " + std::to_string(beams));
  setHeader(header);
  values_.clear();
  values_.setCount(kEchoArray, 2);
  for (std::size_t k = 0; k < 2; ++k)
  {
    const core::EchoCloud& echo = sweep.echoes[k];
    PointSetBuffers& out = echoes_[k];
    out.resize(beams);
    for (std::size_t i = 0; i < beams; ++i)
    {
      const bool valid =
          echo.points[i].allFinite() && (labels == nullptr || labels->echoes[k][i] != core::Label::nanPoint);
      const Eigen::Vector3f point = valid ? echo.points[i] : Eigen::Vector3f::Zero();
      out.coords[3 * i] = point.x();
      out.coords[3 * i + 1] = point.y();
      out.coords[3 * i + 2] = point.z();
      out.mask[i] = valid ? 1 : 0;
      out.intensity[i] = valid ? echo.intensities[i] : 0.0f;
      out.dists[i] = valid ? echo.ranges[i] : 0.0f;
    }
    setCoordDist(std::string(kEchoArray) + "[" + std::to_string(k) + "].", out);
  }
  return serialize();
}

LegacyPointSetWriter::LegacyPointSetWriter() : LegacyWriter(true)
{
}

topic_tools::ShapeShifter::Ptr LegacyPointSetWriter::write(const std_msgs::Header& header,
                                                           const std::vector<core::OutputPoint>& points,
                                                           const Eigen::Vector3f& origin)
{
  setHeader(header);
  values_.clear();
  points_.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const bool valid = points[i].position.allFinite();
    const Eigen::Vector3f point = valid ? points[i].position : Eigen::Vector3f::Zero();
    points_.coords[3 * i] = point.x();
    points_.coords[3 * i + 1] = point.y();
    points_.coords[3 * i + 2] = point.z();
    points_.mask[i] = valid ? 1 : 0;
    points_.intensity[i] = valid ? points[i].intensity : 0.0f;
    points_.dists[i] = valid ? (point - origin).norm() : 0.0f;
  }
  setCoordDist("", points_);
  return serialize();
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
