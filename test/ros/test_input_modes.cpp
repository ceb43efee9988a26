// The input-mode table and the input path of nodelet and prefilter_bag (SweepInput), without a
// master: messages go in serialized, as prefilter_bag feeds them; what comes out is recorded.
#include <gtest/gtest.h>

#include <ros/serialization.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2/buffer_core.h>

#include <boost/make_shared.hpp>
#include <cmath>
#include <string>
#include <vector>

#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/MultiEchoLaserScan.h>

#include "ohm_mirror_detector3d/EchoPair.h"
#include "ohm_mirror_detector3d/core/param_table.h"
#include "ohm_mirror_detector3d/ros/conversions.h"
#include "ohm_mirror_detector3d/ros/hokuyo3d_legacy.h"
#include "ohm_mirror_detector3d/ros/input_mode.h"
#include "ohm_mirror_detector3d/ros/legacy_output.h"
#include "ohm_mirror_detector3d/ros/message_pipeline.h"
#include "ohm_mirror_detector3d/ros/sensor_pose_queue.h"
#include "ohm_mirror_detector3d/ros/sweep_input.h"

namespace ohm_mirror_detector3d
{
namespace
{
using ros_io::InputProblem;
using ros_io::SensorPoseQueue;

// Keeps what an input hands on: the sweeps' sizes and contexts, the problems.
class Recorder : public ros_io::SweepReceiver
{
public:
  void sweepReady(core::Sweep& sweep, const core::SweepContext& context) override
  {
    beams.push_back(sweep.beamCount());
    contexts.push_back(context);
  }
  void inputProblem(const InputProblem& problem) override { problems.push_back(problem); }
  void inputTypeFound(const ros_io::FoundInputType& type) override { types.push_back(type); }

  std::vector<std::size_t> beams;
  std::vector<core::SweepContext> contexts;
  std::vector<InputProblem> problems;
  std::vector<ros_io::FoundInputType> types;
};

sensor_msgs::PointCloud2 echoCloud(const std::string& frame, double stamp, std::size_t points, float range)
{
  sensor_msgs::PointCloud2 cloud;
  cloud.header.frame_id = frame;
  cloud.header.stamp.fromSec(stamp);
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  modifier.setPointCloud2FieldsByString(1, "xyz");
  modifier.resize(points);
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x");
  sensor_msgs::PointCloud2Iterator<float> y(cloud, "y");
  sensor_msgs::PointCloud2Iterator<float> z(cloud, "z");
  for (std::size_t i = 0; i < points; ++i, ++x, ++y, ++z)
  {
    *x = range * std::cos(0.1f * static_cast<float>(i));
    *y = range * std::sin(0.1f * static_cast<float>(i));
    *z = 0.0f;
  }
  return cloud;
}

EchoPair echoPair(const std::string& frame, double stamp, std::size_t points = 5)
{
  EchoPair pair;
  pair.echo1 = echoCloud(frame, stamp, points, 2.0f);
  pair.echo2 = echoCloud(frame, stamp, points, 3.0f);
  pair.header = pair.echo1.header;
  return pair;
}

template <typename M>
std::vector<std::uint8_t> serialized(const M& message)
{
  std::vector<std::uint8_t> bytes(ros::serialization::serializationLength(message));
  ros::serialization::OStream stream(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
  ros::serialization::serialize(stream, message);
  return bytes;
}

// What rosbag records beside a message of type M.
boost::shared_ptr<ros::M_string> connectionHeader(const std::string& type, const std::string& md5sum,
                                                  const std::string& definition)
{
  auto header = boost::make_shared<ros::M_string>();
  (*header)["type"] = type;
  (*header)["md5sum"] = md5sum;
  (*header)["message_definition"] = definition;
  return header;
}

template <typename M>
boost::shared_ptr<ros::M_string> connectionHeader()
{
  return connectionHeader(ros::message_traits::datatype<M>(), ros::message_traits::md5sum<M>(),
                          ros::message_traits::definition<M>());
}

geometry_msgs::TransformStamped transform(const std::string& parent, const std::string& child, double stamp,
                                          const Eigen::Isometry3d& pose)
{
  geometry_msgs::TransformStamped t;
  t.header.frame_id = parent;
  t.header.stamp.fromSec(stamp);
  t.child_frame_id = child;
  const Eigen::Quaterniond q(pose.linear());
  t.transform.rotation.x = q.x();
  t.transform.rotation.y = q.y();
  t.transform.rotation.z = q.z();
  t.transform.rotation.w = q.w();
  t.transform.translation.x = pose.translation().x();
  t.transform.translation.y = pose.translation().y();
  t.transform.translation.z = pose.translation().z();
  return t;
}

Eigen::Isometry3d mountPose()
{
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
                  Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(0.3, -0.2, 0.5);
  return pose;
}

core::SweepContext contextAt(const std::string& frame, double stamp)
{
  std_msgs::Header header;
  header.frame_id = frame;
  header.stamp.fromSec(stamp);
  return ros_io::toSweepContext(header);
}

core::Sweep sweepOfBeams(std::size_t beams)
{
  core::Sweep sweep;
  sweep.resize(1, beams);
  return sweep;
}

TEST(InputModes, OneTableNamesEveryModeWithTheTopicsAndTypesItReads)
{
  std::vector<std::string> names;
  for (const ros_io::InputMode& mode : ros_io::inputModes())
    names.push_back(mode.name);
  EXPECT_EQ(names, (std::vector<std::string>{ "pair", "two_topics", "dual_return", "hokuyo3d_legacy",
                                              "multi_echo_scan" }));
  EXPECT_EQ(ros_io::findInputMode("nope"), nullptr);
  EXPECT_EQ(ros_io::unknownInputModeMessage("nope"),
            "input_mode 'nope' is unknown: allowed values are 'pair', 'two_topics', 'dual_return', "
            "'hokuyo3d_legacy', 'multi_echo_scan'");

  ros_io::InputOptions options;
  options.input_topic = "/in";
  options.echo1_topic = "/a";
  options.echo2_topic = "/b";
  const auto topicsOf = [&](const char* name) {
    std::vector<std::string> topics;
    const std::unique_ptr<ros_io::InputAdapter> adapter = ros_io::findInputMode(name)->make(options);
    for (const std::unique_ptr<ros_io::InputTopic>& topic : adapter->topics())
      topics.push_back(topic->name + " " + topic->datatype + " " + topic->option);
    return topics;
  };
  EXPECT_EQ(topicsOf("pair"), (std::vector<std::string>{ "/in ohm_mirror_detector3d/EchoPair --input-topic" }));
  EXPECT_EQ(topicsOf("two_topics"), (std::vector<std::string>{ "/a sensor_msgs/PointCloud2 --echo1-topic",
                                                               "/b sensor_msgs/PointCloud2 --echo2-topic" }));
  EXPECT_EQ(topicsOf("dual_return"), (std::vector<std::string>{ "/in sensor_msgs/PointCloud2 --input-topic" }));
  EXPECT_EQ(topicsOf("hokuyo3d_legacy"),
            (std::vector<std::string>{ "/in ohm_hokuyo3d/CoordDistMulti --input-topic" }));
  EXPECT_EQ(topicsOf("multi_echo_scan"),
            (std::vector<std::string>{ "/in sensor_msgs/MultiEchoLaserScan --input-topic" }));
  EXPECT_EQ(ros_io::findInputMode("hokuyo3d_legacy")->make(options)->topics()[0]->md5sum, "*");
  EXPECT_TRUE(ros_io::findInputMode("multi_echo_scan")->make(options)->readsTf());
  EXPECT_FALSE(ros_io::findInputMode("pair")->make(options)->readsTf());
}

// The input_mode row of the parameter table (which the README's table is made from) names the
// modes in words: they must be the input-mode table's, and its default the table's first mode.
TEST(InputModes, TheInputModeParameterNamesTheTablesModesAndWhatItsAbsenceChoosesFrom)
{
  std::string names;
  for (const ros_io::InputMode& mode : ros_io::inputModes())
    names += std::string(names.empty() ? "" : ", ") + "`" + mode.name + "`";
  const core::ParamInfo* row = core::findParameter("input_mode");
  ASSERT_NE(row, nullptr);
  EXPECT_EQ(std::string(row->allowed), names);
  // Not set, the type on the topic chooses among runTimeChoices(): the row's default says which.
  EXPECT_STREQ(row->default_value.text, "");
  const std::string when_unset = row->default_value.when_unset;
  for (const ros_io::InputMode* mode : ros_io::runTimeChoices())
    EXPECT_NE(when_unset.find(std::string("`") + mode->name + "`"), std::string::npos) << mode->name;
}

TEST(InputModes, ARecordedEchoPairBecomesASweepWithTheStampAndFrameOfItsHeader)
{
  tf2::BufferCore tf;
  Recorder recorder;
  ros_io::InputOptions options;
  ros_io::SweepInput input(*ros_io::findInputMode("pair"), options, tf, recorder, []() { return 0.0; });
  EXPECT_FALSE(input.readsTf());
  ASSERT_EQ(input.topics().size(), 1u);
  EXPECT_EQ(input.topics()[0]->name, "/echo_pair");  // prefilter_bag's default

  input.addSerialized(*input.topics()[0], serialized(echoPair("laser", 12.5)), connectionHeader<EchoPair>());
  ASSERT_EQ(recorder.contexts.size(), 1u);
  EXPECT_EQ(recorder.beams[0], 5u);
  EXPECT_EQ(recorder.contexts[0].frame_id, "laser");
  EXPECT_EQ(recorder.contexts[0].stamp_ns, 12500000000ull);
  EXPECT_TRUE(recorder.contexts[0].sensor_pose.isApprox(Eigen::Isometry3d::Identity()));

  // Bytes that are not an EchoPair: reported, nothing handed on.
  const std::vector<std::uint8_t> garbage = { 1, 2, 3 };
  input.addSerialized(*input.topics()[0], garbage, connectionHeader<EchoPair>());
  ASSERT_EQ(recorder.problems.size(), 1u);
  EXPECT_TRUE(recorder.problems[0].dropped);
  EXPECT_EQ(recorder.problems[0].topic, "/echo_pair");
  EXPECT_NE(recorder.problems[0].text.find("cannot be read"), std::string::npos);
  EXPECT_EQ(recorder.contexts.size(), 1u);
}

TEST(InputModes, TwoTopicsPairsCloudsOfTheSameStampAndReportsThoseWithoutPartner)
{
  tf2::BufferCore tf;
  Recorder recorder;
  ros_io::InputOptions options;
  options.echo1_topic = "/a";
  options.echo2_topic = "/b";
  ros_io::SweepInput input(*ros_io::findInputMode("two_topics"), options, tf, recorder, []() { return 0.0; });
  const ros_io::InputTopic& echo1 = *input.topics()[0];
  const ros_io::InputTopic& echo2 = *input.topics()[1];
  const auto header = connectionHeader<sensor_msgs::PointCloud2>();
  const auto add = [&](const ros_io::InputTopic& topic, double stamp, float range) {
    input.addSerialized(topic, serialized(echoCloud("laser", stamp, 4, range)), header);
  };

  add(echo1, 1.0, 2.0f);
  EXPECT_TRUE(recorder.contexts.empty());  // waits for its partner
  add(echo2, 1.0, 3.0f);
  ASSERT_EQ(recorder.contexts.size(), 1u);
  EXPECT_EQ(recorder.contexts[0].stamp_ns, 1000000000ull);

  add(echo1, 2.0, 2.0f);  // never gets a partner: dropped once a later pair is complete
  add(echo2, 3.0, 3.0f);
  add(echo1, 3.0, 2.0f);
  ASSERT_EQ(recorder.contexts.size(), 2u);
  ASSERT_EQ(recorder.problems.size(), 1u);
  EXPECT_EQ(recorder.problems[0].describe(), "sweep on /a + /b: cloud on /a has no cloud on /b with the same stamp");

  add(echo2, 4.0, 3.0f);
  add(echo2, 4.0, 3.0f);  // the same stamp again: the first is replaced
  ASSERT_EQ(recorder.problems.size(), 2u);
  EXPECT_EQ(recorder.problems[1].text, "two clouds on /b have the same stamp; the first is dropped");
  input.finish();  // the end of the bag: what still waits for a partner is reported
  ASSERT_EQ(recorder.problems.size(), 3u);
  EXPECT_EQ(recorder.problems[2].text, "cloud on /b has no cloud on /a with the same stamp");
  EXPECT_EQ(recorder.contexts.size(), 2u);
}

TEST(InputModes, TwoTopicsSaysHowFarApartTheCloudsThatDoNotPairAre)
{
  tf2::BufferCore tf;
  Recorder recorder;
  ros_io::InputOptions options;
  options.echo1_topic = "/a";
  options.echo2_topic = "/b";
  ros_io::SweepInput input(*ros_io::findInputMode("two_topics"), options, tf, recorder, []() { return 0.0; });
  const auto header = connectionHeader<sensor_msgs::PointCloud2>();
  const auto add = [&](int side, double stamp) {
    input.addSerialized(*input.topics()[side], serialized(echoCloud("laser", stamp, 4, 2.0f + side)), header);
  };
  // A driver whose two returns are stamped 12 ms apart never pairs with equal stamps.
  for (int k = 0; k < 4; ++k)
  {
    add(0, 1.0 + k);
    add(1, 1.012 + k);
  }
  EXPECT_TRUE(recorder.contexts.empty());
  ASSERT_GE(recorder.problems.size(), 2u);
  const InputProblem& first = recorder.problems[0];
  EXPECT_EQ(first.text, "cloud on /a has no cloud on /b with the same stamp");
  EXPECT_EQ(first.detail, "its stamp 1 s; the nearest there is 0.012 s later: approximate_sync pairs clouds that far "
                          "apart; 1 unpaired so far");
  EXPECT_NE(recorder.problems.back().detail.find(std::to_string(recorder.problems.size()) + " unpaired so far"),
            std::string::npos);

  // approximate_sync pairs them.
  Recorder paired;
  options.approximate_sync = 0.02;
  ros_io::SweepInput approximate(*ros_io::findInputMode("two_topics"), options, tf, paired, []() { return 0.0; });
  EXPECT_NE(approximate.describe().find("at most 0.02 s"), std::string::npos);
  for (int k = 0; k < 4; ++k)
  {
    approximate.addSerialized(*approximate.topics()[0], serialized(echoCloud("laser", 1.0 + k, 4, 2.0f)), header);
    approximate.addSerialized(*approximate.topics()[1], serialized(echoCloud("laser", 1.012 + k, 4, 3.0f)), header);
  }
  // The approximate synchroniser publishes a pair once a later cloud shows it is the best.
  EXPECT_GE(paired.contexts.size(), 3u);
  EXPECT_TRUE(paired.problems.empty());
  // A cloud farther away than that has no partner: reported when a later pair is complete.
  approximate.addSerialized(*approximate.topics()[0], serialized(echoCloud("laser", 10.0, 4, 2.0f)), header);
  approximate.addSerialized(*approximate.topics()[0], serialized(echoCloud("laser", 11.0, 4, 2.0f)), header);
  approximate.addSerialized(*approximate.topics()[1], serialized(echoCloud("laser", 10.5, 4, 3.0f)), header);
  approximate.addSerialized(*approximate.topics()[1], serialized(echoCloud("laser", 11.005, 4, 3.0f)), header);
  approximate.addSerialized(*approximate.topics()[0], serialized(echoCloud("laser", 12.0, 4, 2.0f)), header);
  approximate.addSerialized(*approximate.topics()[1], serialized(echoCloud("laser", 12.0, 4, 3.0f)), header);
  ASSERT_FALSE(paired.problems.empty());
  EXPECT_EQ(paired.problems[0].text, "cloud on /a has no cloud on /b within approximate_sync 0.02 s");

  // Its value is read and checked as the mode's start-up parameter.
  class Negative : public ros_io::ParamSource
  {
  public:
    bool has(const std::string& name) const override { return name == "approximate_sync"; }
    bool get(const std::string& name, double& value) const override { return has(name) && (value = -1.0, true); }
    bool get(const std::string&, int&) const override { return false; }
    bool get(const std::string&, std::string&) const override { return false; }
    bool get(const std::string&, std::vector<double>&) const override { return false; }
    std::string describe(const std::string& name) const override { return "~" + name; }
  } negative;
  std::vector<std::string> errors;
  ros_io::readInputOptions(negative, *ros_io::findInputMode("two_topics"), options, errors);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("approximate_sync = -1"), std::string::npos);
}

TEST(InputModes, EchoesInDifferentFramesAreRefusedNamingBoth)
{
  tf2::BufferCore tf;
  Recorder recorder;
  ros_io::InputOptions options;
  ros_io::SweepInput input(*ros_io::findInputMode("pair"), options, tf, recorder, []() { return 0.0; });
  EchoPair pair = echoPair("laser", 3.0);
  pair.echo2.header.frame_id = "laser_2";
  input.addSerialized(*input.topics()[0], serialized(pair), connectionHeader<EchoPair>());
  ASSERT_EQ(recorder.problems.size(), 1u);
  EXPECT_EQ(recorder.problems[0].text,
            "echo1 is in frame 'laser' but echo2 in frame 'laser_2'; both echoes must be in one frame");
  pair = echoPair("laser", 4.0);
  pair.header.frame_id = "base_link";
  input.addSerialized(*input.topics()[0], serialized(pair), connectionHeader<EchoPair>());
  ASSERT_EQ(recorder.problems.size(), 2u);
  EXPECT_EQ(recorder.problems[1].text,
            "echo1 is in frame 'laser' but the EchoPair in frame 'base_link'; both echoes must be in one frame");
  // Clouds without a frame take the pair's.
  pair = echoPair("", 5.0);
  pair.header.frame_id = "laser";
  input.addSerialized(*input.topics()[0], serialized(pair), connectionHeader<EchoPair>());
  EXPECT_EQ(recorder.problems.size(), 2u);
  ASSERT_EQ(recorder.contexts.size(), 1u);
  EXPECT_EQ(recorder.contexts[0].frame_id, "laser");

  Recorder two;
  options.echo1_topic = "/a";
  options.echo2_topic = "/b";
  ros_io::SweepInput clouds(*ros_io::findInputMode("two_topics"), options, tf, two, []() { return 0.0; });
  const auto header = connectionHeader<sensor_msgs::PointCloud2>();
  clouds.addSerialized(*clouds.topics()[0], serialized(echoCloud("laser", 1.0, 4, 2.0f)), header);
  clouds.addSerialized(*clouds.topics()[1], serialized(echoCloud("laser_2", 1.0, 4, 3.0f)), header);
  ASSERT_EQ(two.problems.size(), 1u);
  EXPECT_EQ(two.problems[0].text, "/a is in frame 'laser' but /b in frame 'laser_2'; both echoes must be in one frame");
  EXPECT_TRUE(two.contexts.empty());
}

// A message of the original driver's type, as its connection gives it: bytes and header.
struct LegacyMessage
{
  std::vector<std::uint8_t> bytes;
  boost::shared_ptr<ros::M_string> header;
};

LegacyMessage legacyMessage(std::size_t beams, double stamp)
{
  core::Sweep sweep = sweepOfBeams(beams);
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t i = 0; i < beams; ++i)
    {
      sweep.echoes[k].points[i] = Eigen::Vector3f(2.0f + k, 0.1f * i, 0.0f);
      sweep.echoes[k].intensities[i] = 1.0f;
    }
  sweep.computeRanges(Eigen::Vector3f::Zero());
  ros_io::LegacyScanWriter writer;
  std_msgs::Header header;
  header.frame_id = "laser";
  header.stamp.fromSec(stamp);
  const topic_tools::ShapeShifter::Ptr message = writer.write(header, sweep);
  LegacyMessage legacy;
  legacy.bytes.resize(message->size());
  ros::serialization::OStream stream(legacy.bytes.data(), static_cast<std::uint32_t>(legacy.bytes.size()));
  message->write(stream);
  legacy.header = connectionHeader(writer.type().datatype, writer.type().md5sum, writer.type().definition);
  return legacy;
}

TEST(InputModes, WithoutInputModeTheTypeOfTheMessagesChoosesTheMode)
{
  tf2::BufferCore tf;
  Recorder recorder;
  ros_io::InputOptions options;
  options.input_topic = "/dist_coord_multi";
  ros_io::SweepInput input(ros_io::runTimeInputMode(), options, tf, recorder, []() { return 0.0; });
  ASSERT_EQ(input.topics().size(), 1u);
  const ros_io::InputTopic& topic = *input.topics()[0];
  EXPECT_EQ(topic.name, "/dist_coord_multi");
  EXPECT_EQ(topic.md5sum, "*");

  // An EchoPair is read as in input_mode pair.
  input.addSerialized(topic, serialized(echoPair("laser", 1.0, 5)), connectionHeader<EchoPair>());
  ASSERT_EQ(recorder.contexts.size(), 1u);
  EXPECT_EQ(recorder.beams[0], 5u);
  ASSERT_EQ(recorder.types.size(), 1u);
  EXPECT_EQ(recorder.types[0].mode, "pair");
  EXPECT_EQ(recorder.types[0].datatype, "ohm_mirror_detector3d/EchoPair");

  // The original driver's CoordDistMulti as in hokuyo3d_legacy; its definition goes on.
  const LegacyMessage legacy = legacyMessage(7, 2.0);
  input.addSerialized(topic, legacy.bytes, legacy.header);
  ASSERT_EQ(recorder.contexts.size(), 2u);
  EXPECT_EQ(recorder.beams[1], 7u);
  EXPECT_EQ(recorder.contexts[1].stamp_ns, 2000000000ull);
  ASSERT_GE(recorder.types.size(), 2u);
  EXPECT_EQ(recorder.types.back().mode, "hokuyo3d_legacy");
  EXPECT_EQ(recorder.types.back().definition, (*legacy.header)["message_definition"]);
  EXPECT_TRUE(recorder.problems.empty());

  // Any other type: dropped, naming it and the mode that reads it.
  sensor_msgs::MultiEchoLaserScan scan;
  input.addSerialized(topic, serialized(scan), connectionHeader<sensor_msgs::MultiEchoLaserScan>());
  ASSERT_EQ(recorder.problems.size(), 1u);
  EXPECT_TRUE(recorder.problems[0].dropped);
  EXPECT_EQ(recorder.problems[0].topic, "/dist_coord_multi");
  EXPECT_EQ(recorder.problems[0].text,
            "its type sensor_msgs/MultiEchoLaserScan is not read without input_mode (that reads "
            "ohm_mirror_detector3d/EchoPair as pair and ohm_hokuyo3d/CoordDistMulti as hokuyo3d_legacy); input_mode "
            "multi_echo_scan reads it, with sweep_frame (the fixed frame the rotating unit turns in, e.g. base_link)");
  EXPECT_EQ(recorder.contexts.size(), 2u);
}

TEST(InputModes, AMismatchNamesTheModeThatReadsTheType)
{
  sensor_msgs::PointCloud2 lidar = echoCloud("lidar", 1.0, 3, 2.0f);
  sensor_msgs::PointCloud2Modifier(lidar).setPointCloud2Fields(
      5, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32, "z", 1,
      sensor_msgs::PointField::FLOAT32, "return", 1, sensor_msgs::PointField::UINT8, "ring", 1,
      sensor_msgs::PointField::UINT16);
  const auto shapeShifterOf = [](const sensor_msgs::PointCloud2& cloud) {
    topic_tools::ShapeShifter shifter;
    shifter.morph(ros::message_traits::md5sum<sensor_msgs::PointCloud2>(),
                  ros::message_traits::datatype<sensor_msgs::PointCloud2>(),
                  ros::message_traits::definition<sensor_msgs::PointCloud2>(), "0");
    std::vector<std::uint8_t> bytes = serialized(cloud);
    ros::serialization::IStream stream(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
    shifter.read(stream);
    return shifter;
  };
  const std::string cloud_type = "sensor_msgs/PointCloud2";
  const topic_tools::ShapeShifter with_rings = shapeShifterOf(lidar);
  EXPECT_EQ(ros_io::modeThatReads(cloud_type, "", &with_rings).find("it has a return and a ring field: input_mode "
                                                                     "dual_return reads one cloud"),
            0u);
  const topic_tools::ShapeShifter plain = shapeShifterOf(echoCloud("lidar", 1.0, 3, 2.0f));
  EXPECT_EQ(ros_io::modeThatReads(cloud_type, "", &plain),
            "it has no return and ring fields: input_mode two_topics reads two clouds, the first echo on ~echo1 and "
            "the second on ~echo2");
  // Without a message (a publisher's type from the master): both.
  EXPECT_NE(ros_io::modeThatReads(cloud_type).find("dual_return"), std::string::npos);
  EXPECT_NE(ros_io::modeThatReads(cloud_type).find("two_topics"), std::string::npos);
  EXPECT_EQ(ros_io::modeThatReads("ohm_mirror_detector3d/EchoPair"), "input_mode pair reads it");
  EXPECT_EQ(ros_io::modeThatReads(ros_io::kLegacyScanDatatype, ros_io::builtinLegacyScanDefinition()),
            "input_mode hokuyo3d_legacy reads it");
  EXPECT_NE(ros_io::modeThatReads("sensor_msgs/LaserScan").find("holds one echo per beam"), std::string::npos);
  EXPECT_NE(ros_io::modeThatReads("std_msgs/String").find("no input mode reads it"), std::string::npos);

  // An EchoPair of another definition is named as such.
  const ros_io::InputTypeMatch other =
      ros_io::matchInputType("ohm_mirror_detector3d/EchoPair", "0123456789abcdef0123456789abcdef", "");
  EXPECT_EQ(other.mode, nullptr);
  EXPECT_NE(other.problem.find("another version of the message"), std::string::npos);
  // A type of the driver's name but not its layout.
  const ros_io::InputTypeMatch broken = ros_io::matchInputType(ros_io::kLegacyScanDatatype, "*", "int32 x\n");
  EXPECT_EQ(broken.mode, nullptr);
  EXPECT_NE(broken.problem.find("has no field 'coorddist'"), std::string::npos);
  // Any type of the driver's layout is read as hokuyo3d_legacy, whatever its name.
  EXPECT_EQ(ros_io::matchInputType("ohm_hokuyo3d/Tuple", "*", ros_io::builtinLegacyScanDefinition()).mode,
            ros_io::findInputMode("hokuyo3d_legacy"));
}

TEST(InputModes, SensorFrameGoesThroughTheWaitForTheScannersPose)
{
  tf2::BufferCore tf;
  Recorder recorder;
  ros_io::InputOptions options;
  options.sensor_frame = "laser";
  ros_io::SweepInput input(*ros_io::findInputMode("pair"), options, tf, recorder, []() { return 0.0; });
  EXPECT_TRUE(input.readsTf());
  input.addSerialized(*input.topics()[0], serialized(echoPair("base_link", 7.0)), connectionHeader<EchoPair>());
  EXPECT_TRUE(recorder.contexts.empty());
  tf.setTransform(transform("base_link", "laser", 0.0, mountPose()), "test", true);
  input.poll();
  ASSERT_EQ(recorder.contexts.size(), 1u);
  EXPECT_EQ(recorder.beams[0], 5u);
  EXPECT_TRUE(recorder.contexts[0].sensor_pose.isApprox(mountPose(), 1e-9));
}

// The queue with a clock the test sets.
struct PoseQueueFixture : public ::testing::Test
{
  tf2::BufferCore tf;
  Recorder recorder;
  double now = 100.0;
  SensorPoseQueue queue{ "laser", "", "/in", tf, recorder, [this]() { return now; } };

  void send(const std::string& frame, double stamp, std::size_t beams = 3)
  {
    core::Sweep sweep = sweepOfBeams(beams);
    queue.sweepReady(sweep, contextAt(frame, stamp));
  }
};

TEST_F(PoseQueueFixture, ASweepWaitsForItsTransformAndGetsItsFullPose)
{
  send("base_link", 10.0);
  EXPECT_TRUE(recorder.contexts.empty());
  EXPECT_EQ(queue.waitingSweeps(), 1u);
  queue.poll();
  EXPECT_TRUE(recorder.contexts.empty());  // still no transform

  // A moving mount: transforms before and after the stamp, interpolated.
  Eigen::Isometry3d before = mountPose();
  Eigen::Isometry3d after = mountPose();
  after.translation().x() += 0.2;
  tf.setTransform(transform("base_link", "laser", 9.0, before), "test");
  queue.poll();
  EXPECT_TRUE(recorder.contexts.empty());  // tf has nothing after the stamp yet
  tf.setTransform(transform("base_link", "laser", 11.0, after), "test");
  queue.poll();
  ASSERT_EQ(recorder.contexts.size(), 1u);
  Eigen::Isometry3d expected = mountPose();
  expected.translation().x() += 0.1;
  EXPECT_TRUE(recorder.contexts[0].sensor_pose.isApprox(expected, 1e-9));
  EXPECT_EQ(recorder.contexts[0].frame_id, "base_link");
  EXPECT_EQ(recorder.beams[0], 3u);  // the sweep itself, not an empty one
  EXPECT_TRUE(recorder.problems.empty());
  EXPECT_EQ(queue.waitingSweeps(), 0u);

  // Clouds in the scanner's own frame need no transform.
  send("laser", 10.5);
  ASSERT_EQ(recorder.contexts.size(), 2u);
  EXPECT_TRUE(recorder.contexts[1].sensor_pose.isApprox(Eigen::Isometry3d::Identity()));
}

TEST_F(PoseQueueFixture, SweepsGoOnInTheOrderTheyCame)
{
  send("base_link", 10.0, 1);
  tf.setTransform(transform("base_link", "laser", 0.0, mountPose()), "test", true);
  send("base_link", 11.0, 2);  // its transform is there, but an older sweep waits
  ASSERT_EQ(recorder.beams, (std::vector<std::size_t>{ 1, 2 }));
}

TEST_F(PoseQueueFixture, ATransformThatWillNotComeDropsTheSweepNamingBothFrames)
{
  tf.setTransform(transform("base_link", "laser", 20.0, mountPose()), "test");
  tf.setTransform(transform("base_link", "laser", 21.0, mountPose()), "test");
  send("base_link", 10.0);  // tf already holds later transforms, but none for its stamp
  EXPECT_TRUE(recorder.contexts.empty());
  ASSERT_EQ(recorder.problems.size(), 1u);
  EXPECT_TRUE(recorder.problems[0].dropped);
  EXPECT_EQ(recorder.problems[0].topic, "/in");
  EXPECT_EQ(recorder.problems[0].text.find("no transform from sensor_frame 'laser' to the cloud's frame 'base_link' "
                                           "will come for its stamp 10.000"),
            0u)
      << recorder.problems[0].text;
  EXPECT_EQ(queue.waitingSweeps(), 0u);

  send("", 10.0);  // tf cannot use an empty frame at all
  ASSERT_EQ(recorder.problems.size(), 2u);
  EXPECT_NE(recorder.problems[1].text.find("cannot use the cloud's frame_id ''"), std::string::npos);
}

TEST_F(PoseQueueFixture, ASweepWaitsAtMostItsTimeAndAtMostTwoWait)
{
  send("odom", 10.0, 1);
  now += SensorPoseQueue::kMaxWaitSeconds - 0.5;
  queue.poll();
  EXPECT_TRUE(recorder.problems.empty());
  now += 1.0;
  queue.poll();
  ASSERT_EQ(recorder.problems.size(), 1u);
  EXPECT_EQ(recorder.problems[0].text.find("no transform from sensor_frame 'laser' to the cloud's frame 'odom' after "
                                           "waiting 5.500 s for its stamp 10.000"),
            0u)
      << recorder.problems[0].text;

  send("odom", 11.0, 1);
  send("odom", 12.0, 2);
  send("odom", 13.0, 3);  // a third: the oldest goes
  ASSERT_EQ(recorder.problems.size(), 2u);
  EXPECT_NE(recorder.problems[1].text.find("for the stamp 11.000, and 2 newer sweeps wait"), std::string::npos)
      << recorder.problems[1].text;
  EXPECT_EQ(queue.waitingSweeps(), 2u);
  queue.finish();
  ASSERT_EQ(recorder.problems.size(), 4u);
  EXPECT_NE(recorder.problems[3].text.find("for the stamp 13.000 by the end of the bag"), std::string::npos);
  EXPECT_TRUE(recorder.contexts.empty());

  send("odom", 14.0);
  queue.reset();  // subscribing again: forgotten, not reported
  EXPECT_EQ(queue.waitingSweeps(), 0u);
  EXPECT_EQ(recorder.problems.size(), 4u);
}

// The post-filter's wait: clouds in base_link, the fixed frame odom (no sensor_frame).
struct FixedPoseFixture : public ::testing::Test
{
  tf2::BufferCore tf;
  Recorder recorder;
  double now = 100.0;
  SensorPoseQueue queue{ "", "odom", "/in", tf, recorder, [this]() { return now; } };

  void send(double stamp)
  {
    core::Sweep sweep = sweepOfBeams(3);
    queue.sweepReady(sweep, contextAt("base_link", stamp));
  }
};

TEST_F(FixedPoseFixture, ASweepWaitsForItsFixedPoseAndGetsIt)
{
  send(10.0);
  EXPECT_TRUE(recorder.contexts.empty());
  Eigen::Isometry3d odom_from_base = mountPose();
  tf.setTransform(transform("odom", "base_link", 9.0, odom_from_base), "test");
  tf.setTransform(transform("odom", "base_link", 11.0, odom_from_base), "test");
  queue.poll();
  ASSERT_EQ(recorder.contexts.size(), 1u);
  EXPECT_TRUE(recorder.contexts[0].has_fixed_pose);
  EXPECT_EQ(recorder.contexts[0].fixed_frame_id, "odom");
  EXPECT_TRUE(recorder.contexts[0].fixed_from_sweep.isApprox(odom_from_base, 1e-9));
  EXPECT_TRUE(recorder.contexts[0].sensor_pose.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_TRUE(recorder.problems.empty());
}

TEST_F(FixedPoseFixture, AMissingFixedPoseIsAnErrorButTheSweepIsProcessedSingleSweep)
{
  tf.setTransform(transform("odom", "base_link", 20.0, mountPose()), "test");
  tf.setTransform(transform("odom", "base_link", 21.0, mountPose()), "test");
  send(10.0);  // before tf's cache: it will not come
  ASSERT_EQ(recorder.contexts.size(), 1u);
  EXPECT_FALSE(recorder.contexts[0].has_fixed_pose);
  ASSERT_EQ(recorder.problems.size(), 1u);
  EXPECT_FALSE(recorder.problems[0].dropped);
  EXPECT_TRUE(recorder.problems[0].error);
  EXPECT_NE(recorder.problems[0].text.find("to fixed_frame 'odom': processed single-sweep"), std::string::npos)
      << recorder.problems[0].text;
  EXPECT_NE(recorder.problems[0].detail.find("none will come for its stamp 10.000"), std::string::npos)
      << recorder.problems[0].detail;

  // No transform at all for longer than a sweep may wait: the same, once it has waited.
  tf.clear();
  send(30.0);
  EXPECT_EQ(recorder.contexts.size(), 1u);
  now += SensorPoseQueue::kMaxWaitSeconds + 0.5;
  queue.poll();
  ASSERT_EQ(recorder.contexts.size(), 2u);
  EXPECT_FALSE(recorder.contexts[1].has_fixed_pose);
  ASSERT_EQ(recorder.problems.size(), 2u);
  EXPECT_NE(recorder.problems[1].detail.find("waited 5.500 s for its stamp 30.000"), std::string::npos)
      << recorder.problems[1].detail;
}

TEST(MessagePipeline, TheContextGivesTheSensorOriginAndTheOutputsStampAndFrame)
{
  core::Params params;
  params.outlier_min_neighbors = 1;
  params.outlier_radius = 100.0;
  ros_io::MessagePipeline pipeline(params);
  ASSERT_TRUE(ros_io::echoPairToSweep(echoPair("laser", 3.0), pipeline.sweep()).empty());
  const float range_from_laser = pipeline.sweep().echoes[0].ranges[0];
  core::SweepContext context = contextAt("base_link", 4.25);
  context.sensor_pose = mountPose();
  ros_io::OutputMessages outputs;
  pipeline.process(context, ros_io::OutputRequest(), outputs);
  const Eigen::Vector3f point = pipeline.sweep().echoes[0].points[0];
  EXPECT_TRUE(context.sensorOrigin().isApprox(mountPose().translation().cast<float>()));
  EXPECT_FLOAT_EQ(pipeline.sweep().echoes[0].ranges[0], (point - context.sensorOrigin()).norm());
  EXPECT_NE(pipeline.sweep().echoes[0].ranges[0], range_from_laser);
  EXPECT_EQ(outputs.labelled->header.frame_id, "base_link");
  EXPECT_EQ(outputs.labelled->header.stamp, ros::Time(4, 250000000));
  EXPECT_EQ(outputs.objects->header.stamp, ros::Time(4, 250000000));
}

}  // namespace
}  // namespace ohm_mirror_detector3d
