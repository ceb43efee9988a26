// The writers of the original's output types (legacy_output.h): md5sums as ROS computes them,
// messages that the hokuyo3d_legacy decoder and the message walker read back, definitions of
// another layout followed, definitions that do not fit refused.
#include <gtest/gtest.h>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <ros/serialization.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/MultiEchoLaserScan.h>
#include <sensor_msgs/NavSatFix.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/String.h>
#include <visualization_msgs/MarkerArray.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/EchoPair.h"
#include "ohm_mirror_detector3d/ReflectiveObjectArray.h"
#include "ohm_mirror_detector3d/ros/hokuyo3d_legacy.h"
#include "ohm_mirror_detector3d/ros/legacy_output.h"
#include "ohm_mirror_detector3d/ros/legacy_outputs.h"
#include "ohm_mirror_detector3d/core/param_table.h"
#include "ohm_mirror_detector3d/ros/conversions.h"
#include "ohm_mirror_detector3d/ros/message_walker.h"

namespace ohm_mirror_detector3d
{
namespace
{
using ros_io::FieldLocation;

const float kNaN = std::numeric_limits<float>::quiet_NaN();

std::vector<std::uint8_t> bytesOf(const topic_tools::ShapeShifter& message)
{
  std::vector<std::uint8_t> bytes(message.size());
  ros::serialization::OStream stream(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
  message.write(stream);
  return bytes;
}

template <typename M>
void expectSameMd5AsRos()
{
  ros_io::MessageDefinition definition;
  const std::string datatype = ros::message_traits::datatype<M>();
  ASSERT_EQ(definition.parse(datatype, ros::message_traits::definition<M>()), "") << datatype;
  EXPECT_EQ(ros_io::md5sum(definition.root()), ros::message_traits::md5sum<M>()) << datatype;
  // The announced text of the type describes it again.
  ros_io::MessageDefinition again;
  ASSERT_EQ(again.parse(datatype, ros_io::fullDefinition(definition.root())), "") << datatype;
  EXPECT_EQ(ros_io::md5sum(again.root()), ros::message_traits::md5sum<M>()) << datatype;
}

template <typename T>
std::vector<T> arrayAt(const std::vector<std::uint8_t>& bytes, const FieldLocation& location)
{
  std::vector<T> values(location.count);
  if (location.count > 0)
    std::memcpy(values.data(), bytes.data() + location.offset, location.count * sizeof(T));
  return values;
}

TEST(LegacyOutput, Md5sumsAreThoseRosGeneratesForItsOwnTypes)
{
  // Constants (also "int8 X = -1" with blanks), fixed-size arrays, nested arrays of nested
  // types, strings, time and duration, types of this package.
  expectSameMd5AsRos<std_msgs::Header>();
  expectSameMd5AsRos<std_msgs::String>();
  expectSameMd5AsRos<sensor_msgs::PointCloud2>();
  expectSameMd5AsRos<sensor_msgs::MultiEchoLaserScan>();
  expectSameMd5AsRos<sensor_msgs::CameraInfo>();
  expectSameMd5AsRos<sensor_msgs::NavSatFix>();
  expectSameMd5AsRos<geometry_msgs::PoseWithCovarianceStamped>();
  expectSameMd5AsRos<visualization_msgs::MarkerArray>();
  expectSameMd5AsRos<diagnostic_msgs::DiagnosticArray>();
  expectSameMd5AsRos<EchoPair>();
  expectSameMd5AsRos<ReflectiveObjectArray>();
}

TEST(LegacyOutput, NestedTypesHaveTheirOwnMd5sum)
{
  ros_io::MessageDefinition definition;
  ASSERT_EQ(definition.parse("visualization_msgs/MarkerArray",
                             ros::message_traits::definition<visualization_msgs::MarkerArray>()),
            "");
  const ros_io::MessageSpec* marker = definition.find("visualization_msgs/Marker");
  ASSERT_NE(marker, nullptr);
  EXPECT_EQ(ros_io::md5sum(*marker), ros::message_traits::md5sum<visualization_msgs::Marker>());
  EXPECT_EQ(definition.find("visualization_msgs/Nothing"), nullptr);
}

TEST(LegacyOutput, BuiltinTypesAreTheReconstructedDriverTypes)
{
  const ros_io::LegacyScanWriter scan;
  const ros_io::LegacyPointSetWriter points;
  EXPECT_EQ(scan.type().datatype, "ohm_hokuyo3d/CoordDistMulti");
  EXPECT_EQ(points.type().datatype, "ohm_hokuyo3d/CoordDist");
  EXPECT_EQ(scan.type().md5sum.size(), 32u);
  EXPECT_NE(scan.type().md5sum, points.type().md5sum);
  // The point set's announced definition is CoordDist's with the nested types it uses.
  ros_io::MessageDefinition coord_dist;
  ASSERT_EQ(coord_dist.parse(points.type().datatype, points.type().definition), "");
  EXPECT_EQ(ros_io::md5sum(coord_dist.root()), points.type().md5sum);
  EXPECT_NE(coord_dist.find("ohm_hokuyo3d/Coord"), nullptr);
  EXPECT_NE(coord_dist.find("std_msgs/Header"), nullptr);
  EXPECT_EQ(coord_dist.find("ohm_hokuyo3d/CoordDistMulti"), nullptr);
}

core::Sweep threeBeamSweep()
{
  core::Sweep sweep;
  sweep.resize(1, 3);
  sweep.echoes[0].points = { { 1.0f, 2.0f, 3.0f }, { -1.0f, 0.5f, 0.25f }, { 4.0f, 0.0f, 0.0f } };
  sweep.echoes[1].points = { { 2.0f, 4.0f, 6.0f }, Eigen::Vector3f::Constant(kNaN), { 4.0f, 0.0f, 0.0f } };
  sweep.echoes[0].intensities = { 10.0f, 20.0f, 30.0f };
  sweep.echoes[1].intensities = { 11.0f, 21.0f, 31.0f };
  sweep.has_intensity = true;
  sweep.computeRanges(Eigen::Vector3f::Zero());
  return sweep;
}

std_msgs::Header header(const std::string& frame)
{
  std_msgs::Header header;
  header.seq = 9;
  header.stamp = ros::Time(1234, 5678);
  header.frame_id = frame;
  return header;
}

TEST(LegacyOutput, ScanRoundTripsThroughTheHokuyo3dLegacyDecoder)
{
  ros_io::LegacyScanWriter writer;
  const core::Sweep sweep = threeBeamSweep();
  const topic_tools::ShapeShifter::Ptr message = writer.write(header("laser"), sweep);
  EXPECT_EQ(message->getDataType(), writer.type().datatype);
  EXPECT_EQ(message->getMD5Sum(), writer.type().md5sum);
  EXPECT_EQ(message->getMessageDefinition(), writer.type().definition);

  const std::vector<std::uint8_t> bytes = bytesOf(*message);
  ros_io::Hokuyo3dLegacyDecoder decoder;
  core::Sweep decoded;
  std_msgs::Header decoded_header;
  ASSERT_EQ(decoder.decode(message->getDataType(), message->getMessageDefinition(), bytes.data(), bytes.size(),
                           decoded, decoded_header),
            "");
  EXPECT_EQ(decoded_header.frame_id, "laser");
  EXPECT_EQ(decoded_header.stamp, ros::Time(1234, 5678));
  EXPECT_EQ(decoded_header.seq, 9u);
  ASSERT_EQ(decoded.beamCount(), 3u);
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t i = 0; i < 3; ++i)
    {
      if (!sweep.echoes[k].points[i].allFinite())
      {
        EXPECT_FALSE(decoded.echoes[k].points[i].allFinite()) << k << " " << i;
        continue;
      }
      EXPECT_EQ(decoded.echoes[k].points[i], sweep.echoes[k].points[i]) << k << " " << i;
      EXPECT_EQ(decoded.echoes[k].intensities[i], sweep.echoes[k].intensities[i]) << k << " " << i;
    }

  // The fields the decoder does not read: ranges, the Dist's own mask and header.
  ros_io::MessageDefinition definition;
  ASSERT_EQ(definition.parse(message->getDataType(), message->getMessageDefinition()), "");
  std::map<std::string, FieldLocation> at;
  ASSERT_EQ(ros_io::walkMessage(definition, bytes.data(), bytes.size(), at), "");
  const std::vector<float> dists = arrayAt<float>(bytes, at.at("coorddist[1].dist.dists"));
  EXPECT_FLOAT_EQ(dists[0], std::sqrt(56.0f));
  EXPECT_EQ(dists[1], 0.0f);
  EXPECT_EQ(arrayAt<std::uint8_t>(bytes, at.at("coorddist[1].dist.mask")), (std::vector<std::uint8_t>{ 1, 0, 1 }));
  EXPECT_EQ(at.at("coorddist[1].dist.header.frame_id").count, 5u);
  EXPECT_EQ(at.at("coorddist[0].coord.normals").count, 0u);
  EXPECT_EQ(at.at("coorddist[0].coord.objectType").count, 0u);
  EXPECT_EQ(at.at("coorddist[0].dist.phi").count, 0u);
  EXPECT_EQ(arrayAt<std::uint32_t>(bytes, at.at("coorddist[0].coord.fragmentsize")),
            (std::vector<std::uint32_t>{ 1 }));
}

TEST(LegacyOutput, TheDecoderRefusesEchoesInDifferentFramesNamingBoth)
{
  ros_io::LegacyScanWriter writer;
  const topic_tools::ShapeShifter::Ptr message = writer.write(header("laser"), threeBeamSweep());
  std::vector<std::uint8_t> bytes = bytesOf(*message);
  ros_io::MessageDefinition definition;
  ASSERT_EQ(definition.parse(message->getDataType(), message->getMessageDefinition()), "");
  std::map<std::string, FieldLocation> at;
  ASSERT_EQ(ros_io::walkMessage(definition, bytes.data(), bytes.size(), at), "");
  const FieldLocation& second_frame = at.at("coorddist[1].coord.header.frame_id");
  ASSERT_EQ(second_frame.count, 5u);
  bytes[second_frame.offset + 4] = 'R';  // "laseR": another frame of the same length

  ros_io::Hokuyo3dLegacyDecoder decoder;
  core::Sweep decoded;
  std_msgs::Header decoded_header;
  EXPECT_EQ(decoder.decode(message->getDataType(), message->getMessageDefinition(), bytes.data(), bytes.size(),
                           decoded, decoded_header),
            "'coorddist[1].coord.header.frame_id' is 'laseR' but 'coorddist[0].coord.header.frame_id' is 'laser'; "
            "both echoes must be in one frame");
}

TEST(LegacyOutput, ScanMasksOutPointsLabelledNanPoint)
{
  ros_io::LegacyScanWriter writer;
  const core::Sweep sweep = threeBeamSweep();
  core::SweepLabels labels;
  labels.reset(3, core::Label::valid);
  labels.echoes[0][2] = core::Label::nanPoint;
  const std::vector<std::uint8_t> bytes = bytesOf(*writer.write(header("laser"), sweep, &labels));

  ros_io::MessageDefinition definition;
  ASSERT_EQ(definition.parse(writer.type().datatype, writer.type().definition), "");
  std::map<std::string, FieldLocation> at;
  ASSERT_EQ(ros_io::walkMessage(definition, bytes.data(), bytes.size(), at), "");
  EXPECT_EQ(arrayAt<std::uint8_t>(bytes, at.at("coorddist[0].coord.mask")), (std::vector<std::uint8_t>{ 1, 1, 0 }));
  EXPECT_EQ(arrayAt<std::uint8_t>(bytes, at.at("coorddist[1].coord.mask")), (std::vector<std::uint8_t>{ 1, 0, 1 }));
  const std::vector<float> coords = arrayAt<float>(bytes, at.at("coorddist[0].coord.coords"));
  EXPECT_EQ(coords, (std::vector<float>{ 1.0f, 2.0f, 3.0f, -1.0f, 0.5f, 0.25f, 0.0f, 0.0f, 0.0f }));

  core::SweepLabels wrong;
  wrong.reset(2);
  EXPECT_THROW(writer.write(header("laser"), sweep, &wrong), std::invalid_argument);
}

std::vector<core::OutputPoint> somePoints()
{
  std::vector<core::OutputPoint> points(3);
  points[0].position = { 3.0f, 4.0f, 0.0f };
  points[0].intensity = 7.0f;
  points[1].position = Eigen::Vector3f::Constant(kNaN);
  points[1].intensity = 8.0f;
  points[2].position = { 1.0f, 1.0f, 2.0f };
  points[2].intensity = kNaN;
  return points;
}

TEST(LegacyOutput, PointSetHoldsThePointsTheirIntensitiesAndRanges)
{
  ros_io::LegacyPointSetWriter writer;
  const std::vector<std::uint8_t> bytes =
      bytesOf(*writer.write(header("base"), somePoints(), Eigen::Vector3f(1.0f, 1.0f, 0.0f)));
  ros_io::MessageDefinition definition;
  ASSERT_EQ(definition.parse(writer.type().datatype, writer.type().definition), "");
  std::map<std::string, FieldLocation> at;
  ASSERT_EQ(ros_io::walkMessage(definition, bytes.data(), bytes.size(), at), "");
  EXPECT_EQ(arrayAt<float>(bytes, at.at("coord.coords")),
            (std::vector<float>{ 3.0f, 4.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 1.0f, 2.0f }));
  EXPECT_EQ(arrayAt<std::uint8_t>(bytes, at.at("coord.mask")), (std::vector<std::uint8_t>{ 1, 0, 1 }));
  EXPECT_EQ(arrayAt<std::uint8_t>(bytes, at.at("dist.mask")), (std::vector<std::uint8_t>{ 1, 0, 1 }));
  const std::vector<float> intensity = arrayAt<float>(bytes, at.at("coord.intensity"));
  EXPECT_EQ(intensity[0], 7.0f);
  EXPECT_EQ(intensity[1], 0.0f);
  EXPECT_TRUE(std::isnan(intensity[2]));
  const std::vector<float> dists = arrayAt<float>(bytes, at.at("dist.dists"));
  EXPECT_FLOAT_EQ(dists[0], std::sqrt(13.0f));
  EXPECT_EQ(dists[1], 0.0f);
  EXPECT_FLOAT_EQ(dists[2], 2.0f);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(bytes.data()) + at.at("dist.header.frame_id").offset,
                        at.at("dist.header.frame_id").count),
            "base");

  // An empty set is a valid message of empty arrays.
  const std::vector<std::uint8_t> empty = bytesOf(*writer.write(header("base"), {}));
  ASSERT_EQ(ros_io::walkMessage(definition, empty.data(), empty.size(), at), "");
  EXPECT_EQ(at.at("coord.coords").count, 0u);
}

// A driver whose definition differs from the reconstruction: comments, constants, another
// field order, an extra field, no `phi`, another package name.
const char* const kOtherDriverDefinition =
    "# tuples of echoes\n"
    "CoordDist[] coorddist\n"
    "uint8 VERSION=2\n"
    "\n"
    "================================================================================\n"
    "MSG: other_driver/CoordDist\n"
    "Dist dist\n"
    "Coord coord\n"
    "\n"
    "================================================================================\n"
    "MSG: other_driver/Dist\n"
    "Header header\n"
    "bool[] mask\n"
    "float32[] dists\n"
    "\n"
    "================================================================================\n"
    "MSG: std_msgs/Header\n"
    "uint32 seq\n"
    "time stamp\n"
    "string frame_id\n"
    "\n"
    "================================================================================\n"
    "MSG: other_driver/Coord\n"
    "Header header\n"
    "float32[] coords   # x y z\n"
    "float32[] intensity\n"
    "float64 temperature\n"
    "bool[] mask\n";

TEST(LegacyOutput, FollowsTheDefinitionOfTheDriversConnection)
{
  ros_io::MessageDefinition driver;
  ASSERT_EQ(driver.parse("other_driver/CoordDistMulti", kOtherDriverDefinition), "");

  ros_io::LegacyScanWriter scan;
  ASSERT_EQ(scan.useDefinition("other_driver/CoordDistMulti", kOtherDriverDefinition), "");
  EXPECT_EQ(scan.type().datatype, "other_driver/CoordDistMulti");
  EXPECT_EQ(scan.type().md5sum, ros_io::md5sum(driver.root()));
  const core::Sweep sweep = threeBeamSweep();
  const std::vector<std::uint8_t> bytes = bytesOf(*scan.write(header("laser"), sweep));
  ros_io::Hokuyo3dLegacyDecoder decoder;
  core::Sweep decoded;
  std_msgs::Header decoded_header;
  ASSERT_EQ(decoder.decode(scan.type().datatype, kOtherDriverDefinition, bytes.data(), bytes.size(), decoded,
                           decoded_header),
            "");
  EXPECT_EQ(decoded.echoes[0].points[1], sweep.echoes[0].points[1]);
  EXPECT_FALSE(decoded.echoes[1].points[1].allFinite());

  ros_io::LegacyPointSetWriter points;
  ASSERT_EQ(points.useDefinition("other_driver/CoordDistMulti", kOtherDriverDefinition), "");
  EXPECT_EQ(points.type().datatype, "other_driver/CoordDist");
  EXPECT_EQ(points.type().md5sum, ros_io::md5sum(*driver.find("other_driver/CoordDist")));
  const std::vector<std::uint8_t> set = bytesOf(*points.write(header("laser"), somePoints()));
  const ros_io::MessageSpec& coord_dist = *driver.find("other_driver/CoordDist");
  ros_io::MessageDefinition announced;
  ASSERT_EQ(announced.parse(points.type().datatype, points.type().definition), "");
  std::map<std::string, FieldLocation> at;
  ASSERT_EQ(ros_io::walkMessage(announced, set.data(), set.size(), at), "");
  EXPECT_EQ(arrayAt<float>(set, at.at("coord.coords"))[0], 3.0f);
  EXPECT_EQ(arrayAt<double>(set, at.at("coord.temperature")), (std::vector<double>{ 0.0 }));
  EXPECT_EQ(ros_io::md5sum(announced.root()), ros_io::md5sum(coord_dist));
}

TEST(LegacyOutput, RefusesDefinitionsThatDoNotFitAndKeepsTheOneInUse)
{
  ros_io::LegacyPointSetWriter writer;
  const ros_io::AnnouncedType builtin = writer.type();
  std::string wrong_coords = ros_io::builtinLegacyScanDefinition();
  wrong_coords.replace(wrong_coords.find("float32[] coords"), 16, "float64[] coords");
  EXPECT_NE(writer.useDefinition("ohm_hokuyo3d/CoordDistMulti", wrong_coords).find("coord.coords"),
            std::string::npos);

  std::string wrong_mask = ros_io::builtinLegacyScanDefinition();
  wrong_mask.replace(wrong_mask.find("bool[] mask"), 11, "int32[] mask");
  const std::string problem = writer.useDefinition("ohm_hokuyo3d/CoordDistMulti", wrong_mask);
  EXPECT_NE(problem.find("'coord.mask' is int32[] but was given bool values"), std::string::npos) << problem;

  EXPECT_NE(writer.useDefinition("pkg/Other", "float32[] coords\n").find("'coorddist'"), std::string::npos);
  EXPECT_NE(writer.useDefinition("pkg/Broken", "CoordDist[] coorddist\n").find("no 'MSG: pkg/CoordDist'"),
            std::string::npos);

  EXPECT_EQ(writer.type().md5sum, builtin.md5sum);
  EXPECT_EQ(writer.type().definition, builtin.definition);
  EXPECT_EQ(writer.write(header("laser"), somePoints())->getMD5Sum(), builtin.md5sum);
}

// A sweep of six beams with one echo each labelled as the original's point sets select them,
// and what the pipeline would have made of it.
struct LabelledSweep
{
  core::Sweep sweep;
  core::PipelineResult result;
};

LabelledSweep labelledSweep()
{
  using core::Label;
  LabelledSweep labelled;
  core::Sweep& sweep = labelled.sweep;
  sweep.resize(1, 6);
  const Label echo1[6] = { Label::valid, Label::reflectiveSurface, Label::transparentSurface, Label::errorSurface,
                           Label::valid, Label::nanPoint };
  const Label echo2[6] = { Label::valid, Label::behindReflective, Label::behindTransparent, Label::behindErrorS,
                           Label::error, Label::nanPoint };
  labelled.result.labels.reset(6);
  for (std::size_t i = 0; i < 6; ++i)
  {
    sweep.echoes[0].points[i] = Eigen::Vector3f(1.0f + i, 0.0f, 0.0f);
    sweep.echoes[1].points[i] = Eigen::Vector3f(1.0f + i, 1.0f, 0.0f);
    sweep.echoes[0].intensities[i] = 10.0f + i;
    sweep.echoes[1].intensities[i] = 20.0f + i;
    labelled.result.labels.echoes[0][i] = echo1[i];
    labelled.result.labels.echoes[1][i] = echo2[i];
  }
  // A single return repeated in echo 2 (beam 0): once in a point set.
  sweep.echoes[1].points[0] = sweep.echoes[0].points[0];
  sweep.computeRanges(Eigen::Vector3f::Zero());
  labelled.result.cleaned = { core::OutputPoint{ Eigen::Vector3f(1, 0, 0), 10.0f, Label::valid, 1, 0 },
                              core::OutputPoint{ Eigen::Vector3f(-2, 1, 0), 21.0f, Label::behindReflective, 2, 1 } };
  return labelled;
}

std::vector<std::uint32_t> beamsOf(const std::vector<core::OutputPoint>& points, std::vector<int>* echoes = nullptr)
{
  std::vector<std::uint32_t> beams;
  for (const core::OutputPoint& point : points)
  {
    beams.push_back(point.beam);
    if (echoes != nullptr)
      echoes->push_back(point.echo);
  }
  return beams;
}

TEST(LegacyOutputs, ThePointSetsHoldThePointsTheOriginalsCommentsGiveThem)
{
  const LabelledSweep labelled = labelledSweep();
  std::vector<core::OutputPoint> points;
  const auto beams = [&](ros_io::LegacyContent content, std::vector<int>* echoes = nullptr) {
    ros_io::collectLegacyPoints(content, labelled.sweep, labelled.result, points);
    return beamsOf(points, echoes);
  };
  using Beams = std::vector<std::uint32_t>;
  EXPECT_EQ(beams(ros_io::LegacyContent::object), (Beams{ 1, 2, 3 }));  // mirror, glass and unknown surfaces
  EXPECT_EQ(beams(ros_io::LegacyContent::mirror), (Beams{ 1 }));
  EXPECT_EQ(beams(ros_io::LegacyContent::transparent), (Beams{ 2 }));
  std::vector<int> echoes;
  EXPECT_EQ(beams(ros_io::LegacyContent::affected, &echoes), (Beams{ 1, 2, 3 }));  // behind any of them
  EXPECT_EQ(echoes, (std::vector<int>{ 2, 2, 2 }));
  EXPECT_EQ(beams(ros_io::LegacyContent::behind_mirror), (Beams{ 1 }));
  // Measured positions, not back-projected.
  EXPECT_EQ(points[0].position, labelled.sweep.echoes[1].points[1]);
  EXPECT_EQ(points[0].intensity, 21.0f);
  EXPECT_EQ(beams(ros_io::LegacyContent::behind_transparent), (Beams{ 2 }));
  // The back-projected phantoms and the cleaned points are those of the cleaned output.
  EXPECT_EQ(beams(ros_io::LegacyContent::back_projected), (Beams{ 1 }));
  EXPECT_EQ(points[0].position, Eigen::Vector3f(-2, 1, 0));
  EXPECT_EQ(beams(ros_io::LegacyContent::cleaned), (Beams{ 0, 1 }));
}

TEST(LegacyOutputs, OneParameterPerOutputOfTheOriginalInTheParameterTable)
{
  std::vector<std::string> names;
  for (const ros_io::LegacyOutput& output : ros_io::legacyOutputs())
  {
    names.push_back(output.parameter);
    const core::ParamInfo* row = core::findParameter(output.parameter);
    ASSERT_NE(row, nullptr) << output.parameter;
    EXPECT_EQ(row->scope, core::ParamScope::node);
    EXPECT_EQ(std::string(row->default_value.when_unset).find(std::string("`~") + output.default_topic + "`"),
              std::string("not published; ").size())
        << output.parameter;
  }
  EXPECT_EQ(names, (std::vector<std::string>{ "pub_scan", "pub_object", "pub_transp", "pub_mirror", "pub_affected",
                                              "pub_behTransp", "pub_behMirror", "pub_backprojMirror", "pub_cleaned",
                                              "pub_marker" }));
}

TEST(LegacyOutputs, TheMarkerOutlinesEveryObjectInItsColourAndIsDeletedWithoutObjects)
{
  std_msgs::Header header;
  header.frame_id = "laser";
  visualization_msgs::Marker marker;
  ros_io::toLegacyMarker(header, {}, marker);
  EXPECT_EQ(marker.action, visualization_msgs::Marker::DELETE);
  EXPECT_TRUE(marker.points.empty());

  std::vector<core::ReflectiveObject> objects(2);
  objects[0].type = core::ObjectType::mirror;
  objects[0].centre = Eigen::Vector3f(2, 0, 0);
  objects[0].width_axis = Eigen::Vector3f::UnitY();
  objects[0].height_axis = Eigen::Vector3f::UnitZ();
  objects[0].width = 0.6f;
  objects[0].height = 0.4f;
  objects[1] = objects[0];
  objects[1].type = core::ObjectType::glass;
  objects[1].centre = Eigen::Vector3f(4, 0, 0);
  ros_io::toLegacyMarker(header, objects, marker);
  EXPECT_EQ(marker.action, visualization_msgs::Marker::ADD);
  EXPECT_EQ(marker.type, visualization_msgs::Marker::LINE_LIST);
  EXPECT_EQ(marker.header.frame_id, "laser");
  ASSERT_EQ(marker.points.size(), 16u);  // four sides of two rectangles
  ASSERT_EQ(marker.colors.size(), 16u);
  const std::array<Eigen::Vector3f, 4> corners = objects[0].corners();
  for (std::size_t c = 0; c < 4; ++c)
  {
    EXPECT_FLOAT_EQ(marker.points[2 * c].y, corners[c].y());
    EXPECT_FLOAT_EQ(marker.points[2 * c + 1].z, corners[(c + 1) % 4].z());
  }
  EXPECT_EQ(marker.colors[0], ros_io::objectColour(core::ObjectType::mirror));
  EXPECT_EQ(marker.colors[8], ros_io::objectColour(core::ObjectType::glass));
}

}  // namespace
}  // namespace ohm_mirror_detector3d
