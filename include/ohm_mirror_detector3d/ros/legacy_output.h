// Outputs in the original node's message types, for downstream nodes compiled against the
// original driver's package ohm_hokuyo3d, which we do not have: ohm_hokuyo3d/CoordDistMulti
// (the prefiltered scan, both echoes) and ohm_hokuyo3d/CoordDist (a set of points). The
// messages are serialized field by field from a message definition -- the one the driver's
// connection carries (its CoordDistMulti and the CoordDist nested in it), else a
// reconstructed built-in one -- into a topic_tools::ShapeShifter that announces the type's
// datatype, md5sum (computed from the definition as genmsg does) and definition, so that a
// subscriber of the real type accepts the connection.
//
// Fields are found by name, as the hokuyo3d_legacy input finds them (hokuyo3d_legacy.h):
// per CoordDist, coord.header, coord.coords (x y z per point), coord.mask (true: a return),
// coord.intensity, dist.header, dist.dists (range from the scanner), dist.mask, and
// coord.fragmentid 0 / coord.fragmentsize 1 (every message is whole). Every other field
// (normals, objectType, phi, fields of another layout) is written empty: zeros, "" or an
// array of no elements, fixed-size arrays of empty elements.
//
// Wiring, e.g. for a point set:
//   LegacyPointSetWriter writer;                       // built-in definition
//   writer.useDefinition(driver->getDataType(), driver->getMessageDefinition());  // if known
//   ros::Publisher pub = advertise(nh, writer.type(), "/cleaned_scan", 1);
//   pub.publish(writer.write(header, points, context.sensorOrigin()));
// A publisher announces one type: after a useDefinition() that changed type().md5sum (a driver
// whose layout differs from the reconstruction), advertise again.
#pragma once

#include <Eigen/Core>
#include <ros/node_handle.h>
#include <std_msgs/Header.h>
#include <topic_tools/shape_shifter.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/core/cleaned_output.h"
#include "ohm_mirror_detector3d/core/sweep.h"
#include "ohm_mirror_detector3d/ros/hokuyo3d_legacy.h"
#include "ohm_mirror_detector3d/ros/message_walker.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
// A message type as its publisher announces it in the connection header.
struct AnnouncedType
{
  std::string datatype;
  std::string md5sum;
  std::string definition;
};

// The reconstructed definition of ohm_hokuyo3d/CoordDistMulti (kLegacyScanDatatype, full text,
// nested types included), used while no driver connection has given its own.
const std::string& builtinLegacyScanDefinition();

// Advertises `topic` of `nh` as `type`, for the ShapeShifters of a writer; the callbacks let a
// nodelet publish only while someone subscribes.
ros::Publisher advertise(ros::NodeHandle& nh, const AnnouncedType& type, const std::string& topic,
                         std::uint32_t queue_size,
                         const ros::SubscriberStatusCallback& connect = ros::SubscriberStatusCallback(),
                         const ros::SubscriberStatusCallback& disconnect = ros::SubscriberStatusCallback());

// What both writers share: the definition in use, its announced type, the reused buffers.
class LegacyWriter
{
public:
  // The type the messages of write() have; changes only with useDefinition().
  const AnnouncedType& type() const { return type_; }

  // Takes the definition of the driver's connection: `datatype` and full `definition` of its
  // CoordDistMulti (any type whose field `coorddist` is an array of CoordDist-like messages
  // with coord.coords float32[]). On a problem (a field of another type than the writer
  // fills, a missing one) the definition in use stays and the problem is returned, naming
  // the field; an empty string on success.
  std::string useDefinition(const std::string& datatype, const std::string& definition);

protected:
  // One CoordDist's worth of values, reused from message to message.
  struct PointSetBuffers
  {
    std::vector<float> coords;
    std::vector<std::uint8_t> mask;
    std::vector<float> intensity;
    std::vector<float> dists;

    void resize(std::size_t points);
  };

  // `coord_dist_only`: the point-set writer (type: the CoordDist nested in the definition);
  // otherwise the scan writer (type: the CoordDistMulti itself).
  explicit LegacyWriter(bool coord_dist_only);

  // Sets the values of one CoordDist under `prefix` ("" or "coorddist[k].").
  void setCoordDist(const std::string& prefix, const PointSetBuffers& buffers);
  void setHeader(const std_msgs::Header& header);
  // Serializes values_ as type() into a new ShapeShifter.
  topic_tools::ShapeShifter::Ptr serialize() const;

  FieldValues values_;

private:
  // The spec written for `definition`, or a problem naming what does not fit.
  std::string specFor(const MessageDefinition& definition, const MessageSpec*& spec) const;

  bool coord_dist_only_;
  MessageDefinition definition_;
  const MessageSpec* spec_ = nullptr;
  AnnouncedType type_;
  std::array<std::uint32_t, 2> stamp_{};
  std::uint32_t seq_ = 0;
  std::string frame_id_;
  const std::uint32_t fragment_id_ = 0;
  const std::uint32_t fragment_size_ = 1;
  mutable std::vector<std::uint8_t> bytes_;
};

// The prefiltered scan as ohm_hokuyo3d/CoordDistMulti: coorddist[0] is echo 1 and
// coorddist[1] echo 2 of every beam of the sweep (index-aligned, row-major), the driver's
// layout, intensities NaN when the input had none. A point without return, or labelled
// nanPoint (range gate, outlier filter) when labels are given, has mask false, coordinates
// and range 0.
class LegacyScanWriter : public LegacyWriter
{
public:
  LegacyScanWriter();

  topic_tools::ShapeShifter::Ptr write(const std_msgs::Header& header, const core::Sweep& sweep,
                                       const core::SweepLabels* labels = nullptr);

private:
  std::array<PointSetBuffers, 2> echoes_;
};

// A set of points as ohm_hokuyo3d/CoordDist: the points in order, mask true, their
// intensities (NaN when the input had none) and their distances from `origin` (the
// scanner's optical centre in the header's frame); a non-finite point is written as the
// driver writes a beam without return (mask false, zeros).
class LegacyPointSetWriter : public LegacyWriter
{
public:
  LegacyPointSetWriter();

  topic_tools::ShapeShifter::Ptr write(const std_msgs::Header& header, const std::vector<core::OutputPoint>& points,
                                       const Eigen::Vector3f& origin = Eigen::Vector3f::Zero());

private:
  PointSetBuffers points_;
};

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
