#include "ohm_mirror_detector3d/ros/bag_input.h"

#include <ros/message_traits.h>
#include <sensor_msgs/PointCloud2.h>

#include <exception>
#include <map>

#include "ohm_mirror_detector3d/EchoPair.h"
#include "ohm_mirror_detector3d/ros/conversions.h"

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

// pair: one EchoPair per sweep (the nodelet's onEchoPair).
class PairInput : public BagInput
{
public:
  explicit PairInput(const BagInputOptions& options) : topic_(options.input_topic) {}

  std::vector<BagInputTopic> topics() const override { return { topicOf<EchoPair>(topic_, "--input-topic") }; }

  void add(const rosbag::MessageInstance& message, core::Sweep& sweep, SweepSink& sink) override
  {
    std::string problem;
    const EchoPair::ConstPtr pair = instantiate<EchoPair>(message, problem);
    if (pair)
      problem = echoPairToSweep(*pair, sweep);
    if (problem.empty())
      sink.sweepReady(pair->header, message.getTime());
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
      sink.sweepReady(echo1->header, message.getTime());
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

template <typename Input>
std::unique_ptr<BagInput> make(const BagInputOptions& options)
{
  return std::unique_ptr<BagInput>(new Input(options));
}
}  // namespace

const std::vector<BagInputMode>& bagInputModes()
{
  static const std::vector<BagInputMode> modes = {
    { "pair", "one ohm_mirror_detector3d/EchoPair per sweep on --input-topic", &make<PairInput> },
    { "two_topics", "two sensor_msgs/PointCloud2 per sweep, on --echo1-topic and --echo2-topic, same stamp",
      &make<TwoTopicsInput> },
    // dual_return, hokuyo3d_legacy, multi_echo_scan: a BagInput above and a row here. A mode
    // that needs tf (multi_echo_scan) lists /tf and /tf_static among its topics().
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
