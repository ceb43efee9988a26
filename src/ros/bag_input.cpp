#include "ohm_mirror_detector3d/ros/bag_input.h"

#include <ros/message_traits.h>
#include <ros/serialization.h>
#include <sensor_msgs/MultiEchoLaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2/buffer_core.h>
#include <tf2_msgs/TFMessage.h>

#include <cstdint>
#include <exception>
#include <map>
#include <utility>

#include "ohm_mirror_detector3d/EchoPair.h"
#include "ohm_mirror_detector3d/ros/conversions.h"
#include "ohm_mirror_detector3d/ros/dual_return.h"
#include "ohm_mirror_detector3d/ros/hokuyo3d_legacy.h"
#include "ohm_mirror_detector3d/ros/message_pipeline.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
namespace
{
template <typename M>
BagInputTopic topicOf(const std::string& topic, const std::string& option)
{
  return { topic, ros::message_traits::DataType<M>::value(), ros::message_traits::MD5Sum<M>::value(), option };
}

// The message as M, or null with `problem` set (a corrupt record).
template <typename M>
boost::shared_ptr<M> instantiate(const rosbag::MessageInstance& message, std::string& problem)
{
  try
  {
    boost::shared_ptr<M> msg = message.instantiate<M>();
    if (!msg)
      problem = "message on " + message.getTopic() + " is not a " + ros::message_traits::DataType<M>::value();
    return msg;
  }
  catch (const std::exception& e)
  {
    problem = "message on " + message.getTopic() + " cannot be read: " + e.what();
    return nullptr;
  }
}

const char* const kPairTopic = "/echo_pair";
const char* const kDualReturnTopic = "/points";
const char* const kLegacyTopic = "/coord_dist";
const char* const kScanTopic = "/scan_echoes";

std::string inputTopic(const BagInputOptions& options, const char* default_topic)
{
  return options.input_topic.empty() ? default_topic : options.input_topic;
}

// pair: one EchoPair per sweep (the nodelet's onEchoPair).
class PairInput : public BagInput
{
public:
  explicit PairInput(const BagInputOptions& options) : topic_(inputTopic(options, kPairTopic)) {}

  std::vector<BagInputTopic> topics() const override { return { topicOf<EchoPair>(topic_, "--input-topic") }; }

  void add(const rosbag::MessageInstance& message, core::Sweep& sweep, SweepSink& sink) override
  {
    std::string problem;
    const EchoPair::ConstPtr pair = instantiate<EchoPair>(message, problem);
    if (pair)
      problem = echoPairToSweep(*pair, sweep);
    if (problem.empty())
      sink.sweepReady(pair->header, sensorFrameContext(pair->header), message.getTime());
    else
      sink.sweepDropped(problem, message.getTime());
  }

private:
  std::string topic_;
};

// two_topics: two PointCloud2 topics paired by identical header stamp, as the nodelet's
// exact-time synchroniser does. A sweep is made when its second cloud arrives.
class TwoTopicsInput : public BagInput
{
public:
  explicit TwoTopicsInput(const BagInputOptions& options) : topics_{ options.echo1_topic, options.echo2_topic } {}

  std::vector<BagInputTopic> topics() const override
  {
    return { topicOf<sensor_msgs::PointCloud2>(topics_[0], "--echo1-topic"),
             topicOf<sensor_msgs::PointCloud2>(topics_[1], "--echo2-topic") };
  }

  void add(const rosbag::MessageInstance& message, core::Sweep& sweep, SweepSink& sink) override
  {
    std::string problem;
    const sensor_msgs::PointCloud2::ConstPtr cloud = instantiate<sensor_msgs::PointCloud2>(message, problem);
    if (!cloud)
    {
      sink.sweepDropped(problem, message.getTime());
      return;
    }
    const int side = message.getTopic() == topics_[0] ? 0 : 1;
    const int other = 1 - side;
    const auto partner = pending_[other].find(cloud->header.stamp);
    if (partner == pending_[other].end())
    {
      const auto inserted = pending_[side].emplace(cloud->header.stamp, cloud);
      if (!inserted.second)
      {
        sink.sweepDropped("two clouds on " + topics_[side] + " have the same stamp; the first is dropped",
                          message.getTime());
        inserted.first->second = cloud;
      }
      trim(side, sink, message.getTime());
      return;
    }
    const sensor_msgs::PointCloud2::ConstPtr echo1 = side == 0 ? cloud : partner->second;
    const sensor_msgs::PointCloud2::ConstPtr echo2 = side == 0 ? partner->second : cloud;
    pending_[other].erase(partner);
    problem = echoCloudsToSweep(*echo1, *echo2, sweep);
    if (problem.empty())
      sink.sweepReady(echo1->header, sensorFrameContext(echo1->header), message.getTime());
    else
      sink.sweepDropped(problem, message.getTime());
  }

  void finish(SweepSink& sink) override
  {
    for (int side = 0; side < 2; ++side)
    {
      for (const auto& entry : pending_[side])
        sink.sweepDropped(unpaired(side), entry.first);
      pending_[side].clear();
    }
  }

private:
  // Clouds wait for their partner at most this many stamps (the bag is in time order, so a
  // partner comes soon or never); the oldest go first.
  static constexpr std::size_t kMaxPending = 16;

  std::string unpaired(int side) const
  {
    return "cloud on " + topics_[side] + " has no cloud on " + topics_[1 - side] + " with the same stamp";
  }

  void trim(int side, SweepSink& sink, const ros::Time& bag_time)
  {
    while (pending_[side].size() > kMaxPending)
    {
      pending_[side].erase(pending_[side].begin());
      sink.sweepDropped(unpaired(side), bag_time);
    }
  }

  std::string topics_[2];
  std::map<ros::Time, sensor_msgs::PointCloud2::ConstPtr> pending_[2];
};

// dual_return: one PointCloud2 with both returns per sweep (the nodelet's onDualReturnCloud).
class DualReturnInput : public BagInput
{
public:
  explicit DualReturnInput(const BagInputOptions& options)
    : topic_(inputTopic(options, kDualReturnTopic)), azimuth_resolution_deg_(options.azimuth_resolution_deg)
  {
  }

  std::vector<BagInputTopic> topics() const override
  {
    return { topicOf<sensor_msgs::PointCloud2>(topic_, "--input-topic") };
  }

  void add(const rosbag::MessageInstance& message, core::Sweep& sweep, SweepSink& sink) override
  {
    std::string problem;
    const sensor_msgs::PointCloud2::ConstPtr cloud = instantiate<sensor_msgs::PointCloud2>(message, problem);
    core::DualReturnStats stats;
    if (cloud)
      problem = dualReturnCloudToSweep(*cloud, azimuth_resolution_deg_, buffer_, sweep, stats);
    if (!problem.empty())
    {
      sink.sweepDropped(problem, message.getTime());
      return;
    }
    // Points binning could not place are the nodelet's warning; here they are only counted
    // when the whole cloud is unusable (above).
    sink.sweepReady(cloud->header, sensorFrameContext(cloud->header), message.getTime());
  }

private:
  std::string topic_;
  double azimuth_resolution_deg_;
  core::DualReturnInput buffer_;
};

// hokuyo3d_legacy: ohm_hokuyo3d/CoordDistMulti of the original driver, decoded from the
// definition recorded in the bag (the nodelet's onLegacyMessage). Any type is read: the
// decoder names the field a message lacks.
class Hokuyo3dLegacyInput : public BagInput
{
public:
  explicit Hokuyo3dLegacyInput(const BagInputOptions& options) : topic_(inputTopic(options, kLegacyTopic)) {}

  std::vector<BagInputTopic> topics() const override
  {
    return { { topic_, "ohm_hokuyo3d/CoordDistMulti", "*", "--input-topic" } };
  }

  void add(const rosbag::MessageInstance& message, core::Sweep& sweep, SweepSink& sink) override
  {
    std::string problem;
    std_msgs::Header header;
    try
    {
      bytes_.resize(message.size());
      ros::serialization::OStream stream(bytes_.data(), static_cast<std::uint32_t>(bytes_.size()));
      message.write(stream);
      problem = decoder_.decode(message.getDataType(), message.getMessageDefinition(), bytes_.data(), bytes_.size(),
                                sweep, header);
    }
    catch (const std::exception& e)
    {
      problem = "message on " + message.getTopic() + " cannot be read: " + e.what();
    }
    if (problem.empty())
      sink.sweepReady(header, sensorFrameContext(header), message.getTime());
    else
      sink.sweepDropped(message.getDataType() + ": " + problem, message.getTime());
  }

private:
  std::string topic_;
  std::vector<std::uint8_t> bytes_;
  Hokuyo3dLegacyDecoder decoder_;
};

// multi_echo_scan: MultiEchoLaserScan projected with tf and assembled per half rotation (the
// nodelet's MultiEchoScanInput, the same code). Its tf buffer is filled from the bag's /tf and
// /tf_static in bag order; after every message the scans whose transforms are there are
// projected, so a sweep is made at the bag time of the message that completed it.
class MultiEchoScanBagInput : public BagInput
{
public:
  explicit MultiEchoScanBagInput(const BagInputOptions& options)
    : topic_(inputTopic(options, kScanTopic)), scans_(options.scan_options, tf_, "prefilter_bag")
  {
  }

  std::vector<BagInputTopic> topics() const override
  {
    std::vector<BagInputTopic> topics = { topicOf<sensor_msgs::MultiEchoLaserScan>(topic_, "--input-topic"),
                                          topicOf<tf2_msgs::TFMessage>("/tf", ""),
                                          topicOf<tf2_msgs::TFMessage>("/tf_static", "") };
    topics.back().required = false;
    return topics;
  }

  void add(const rosbag::MessageInstance& message, core::Sweep& sweep, SweepSink& sink) override
  {
    std::string problem;
    if (message.getTopic() == topic_)
    {
      const sensor_msgs::MultiEchoLaserScan::ConstPtr scan =
          instantiate<sensor_msgs::MultiEchoLaserScan>(message, problem);
      if (scan)
        problem = scans_.addScan(scan);
      if (!problem.empty())
        sink.sweepDropped("scan on " + topic_ + ": " + problem, message.getTime());
    }
    else
    {
      const tf2_msgs::TFMessage::ConstPtr transforms = instantiate<tf2_msgs::TFMessage>(message, problem);
      if (!transforms)
        sink.sweepDropped(problem, message.getTime());
      else
      {
        const bool is_static = message.getTopic() == "/tf_static";
        for (const geometry_msgs::TransformStamped& transform : transforms->transforms)
        {
          try
          {
            tf_.setTransform(transform, "bag", is_static);  // logs and ignores a bad transform
          }
          catch (const std::exception& e)
          {
            sink.sweepDropped("transform on " + message.getTopic() + ": " + e.what(), message.getTime());
          }
        }
      }
    }
    const ros::Time bag_time = message.getTime();
    scans_.drain([&](core::Sweep& assembled, const std_msgs::Header& header, const core::SweepContext& context) {
      std::swap(sweep, assembled);
      sink.sweepReady(header, context, bag_time);
    });
  }

  void finish(SweepSink& sink) override
  {
    const std::size_t waiting = scans_.pendingScans();
    for (std::size_t i = 0; i < waiting; ++i)
      sink.sweepDropped("scan on " + topic_ + " still waits for its transform to " +
                            scans_.options().sweep_frame + " at the end of the bag",
                        ros::Time());
    scans_.reset();
  }

private:
  std::string topic_;
  tf2::BufferCore tf_;  // default cache time, as the nodelet's tf2_ros::Buffer
  MultiEchoScanInput scans_;
};

template <typename Input>
std::unique_ptr<BagInput> make(const BagInputOptions& options)
{
  return std::unique_ptr<BagInput>(new Input(options));
}
}  // namespace

const std::vector<BagInputMode>& bagInputModes()
{
  static const std::vector<BagInputMode> modes = {
    { "pair", "one ohm_mirror_detector3d/EchoPair per sweep on --input-topic", kPairTopic, &make<PairInput> },
    { "two_topics", "two sensor_msgs/PointCloud2 per sweep, on --echo1-topic and --echo2-topic, same stamp",
      nullptr, &make<TwoTopicsInput> },
    { "dual_return", "one sensor_msgs/PointCloud2 per sweep with both returns (fields return, ring) on --input-topic",
      kDualReturnTopic, &make<DualReturnInput> },
    { "hokuyo3d_legacy", "one ohm_hokuyo3d/CoordDistMulti per sweep on --input-topic, decoded from its definition",
      kLegacyTopic, &make<Hokuyo3dLegacyInput> },
    { "multi_echo_scan",
      "sensor_msgs/MultiEchoLaserScan on --input-topic with /tf (and /tf_static), assembled per half rotation",
      kScanTopic, &make<MultiEchoScanBagInput> },
  };
  return modes;
}

const BagInputMode* findBagInputMode(const std::string& name)
{
  for (const BagInputMode& mode : bagInputModes())
    if (name == mode.name)
      return &mode;
  return nullptr;
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
