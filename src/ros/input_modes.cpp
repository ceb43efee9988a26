// The input modes' adapters and their table (input_mode.h).
#include "ohm_mirror_detector3d/ros/input_mode.h"

#include <message_filters/time_synchronizer.h>
#include <ros/message_event.h>
#include <sensor_msgs/MultiEchoLaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <topic_tools/shape_shifter.h>

#include <cstdio>
#include <map>
#include <mutex>
#include <set>

#include "ohm_mirror_detector3d/EchoPair.h"
#include "ohm_mirror_detector3d/ros/conversions.h"
#include "ohm_mirror_detector3d/ros/dual_return.h"
#include "ohm_mirror_detector3d/ros/hokuyo3d_legacy.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
namespace
{
// A sweep is large and a late one is worth less than the next: keep few.
constexpr std::uint32_t kSweepQueueSize = 2;
// Scans are small and come at 40 Hz; keep 10 s of them while a sweep is processed.
constexpr std::uint32_t kScanQueueSize = 400;

const char* const kPairTopic = "/echo_pair";
const char* const kDualReturnTopic = "/points";
const char* const kLegacyTopic = "/coord_dist";
const char* const kScanTopic = "/scan_echoes";

std::string inputTopic(const InputOptions& options, const char* default_topic)
{
  return options.input_topic.empty() ? default_topic : options.input_topic;
}

void reportDropped(const InputSink& sink, const std::string& what, const std::string& topic, const std::string& text)
{
  sink.receiver.inputProblem(InputProblem{ true, what, topic, text });
}

// pair: one EchoPair per sweep.
class PairAdapter : public InputAdapter
{
public:
  explicit PairAdapter(const InputOptions& options) : topic_(inputTopic(options, kPairTopic))
  {
    addTopic<EchoPair>(topic_, "--input-topic", kSweepQueueSize,
                       [this](const EchoPair::ConstPtr& pair, const InputSink& sink) { onPair(*pair, sink); });
  }

private:
  void onPair(const EchoPair& pair, const InputSink& sink)
  {
    const std::string problem = echoPairToSweep(pair, sweep_);
    if (!problem.empty())
      return reportDropped(sink, "sweep", topic_, problem);
    sink.receiver.sweepReady(sweep_, toSweepContext(pair.header));
  }

  std::string topic_;
  core::Sweep sweep_;
};

// two_topics: two PointCloud2 topics paired by identical header stamp (message_filters' exact
// time synchroniser). A sweep is made when the second cloud of a pair arrives; a cloud whose
// partner does not come (the synchroniser drops it when a later pair completes or its queue
// overflows, or the bag ends) is reported.
class TwoTopicsAdapter : public InputAdapter
{
public:
  explicit TwoTopicsAdapter(const InputOptions& options) : names_{ options.echo1_topic, options.echo2_topic }
  {
    addTopic<sensor_msgs::PointCloud2>(
        names_[0], "--echo1-topic", kSweepQueueSize,
        [this](const sensor_msgs::PointCloud2::ConstPtr& cloud, const InputSink& sink) { add(0, cloud, sink); });
    addTopic<sensor_msgs::PointCloud2>(
        names_[1], "--echo2-topic", kSweepQueueSize,
        [this](const sensor_msgs::PointCloud2::ConstPtr& cloud, const InputSink& sink) { add(1, cloud, sink); });
    startSync();
  }

  void reset() override
  {
    std::lock_guard<std::mutex> lock(mutex_);
    startSync();
  }

  void finish(const InputSink& sink) override
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (int side = 0; side < 2; ++side)
      for (std::size_t i = 0; i < pending_[side].size(); ++i)
        reportDropped(sink, "sweep", topics(), unpaired(side));
    startSync();
  }

private:
  using Cloud = sensor_msgs::PointCloud2;
  using Sync = message_filters::TimeSynchronizer<Cloud, Cloud>;

  // A synchroniser without inputs: add() feeds it. Its queue holds the stamps of as many
  // sweeps as the two subscribers hold clouds.
  void startSync()
  {
    sync_.reset(new Sync(2 * kSweepQueueSize));
    sync_->registerCallback(&TwoTopicsAdapter::onPair, this);
    sync_->registerDropCallback(&TwoTopicsAdapter::onUnpaired, this);
    pending_[0].clear();
    pending_[1].clear();
  }

  void add(int side, const Cloud::ConstPtr& cloud, const InputSink& sink)
  {
    // The two subscribers' callbacks may run at once; the synchroniser calls back from add().
    std::lock_guard<std::mutex> lock(mutex_);
    sink_ = &sink;
    if (!pending_[side].insert(cloud->header.stamp).second)
      reportDropped(sink, "sweep", topics(),
                    "two clouds on " + names_[side] + " have the same stamp; the first is dropped");
    // The receipt time is not used: given, so that no ros::Time::now() is needed (prefilter_bag).
    const ros::MessageEvent<const Cloud> event(cloud, ros::Time());
    if (side == 0)
      sync_->add<0>(event);
    else
      sync_->add<1>(event);
    sink_ = nullptr;
  }

  void onPair(const Cloud::ConstPtr& echo1, const Cloud::ConstPtr& echo2)
  {
    pending_[0].erase(echo1->header.stamp);
    pending_[1].erase(echo2->header.stamp);
    const std::string problem = echoCloudsToSweep(*echo1, *echo2, sweep_);
    if (!problem.empty())
      return reportDropped(*sink_, "sweep", topics(), problem);
    sink_->receiver.sweepReady(sweep_, toSweepContext(echo1->header));
  }

  void onUnpaired(const Cloud::ConstPtr& echo1, const Cloud::ConstPtr& echo2)
  {
    const Cloud::ConstPtr clouds[2] = { echo1, echo2 };
    for (int side = 0; side < 2; ++side)
    {
      if (!clouds[side])
        continue;
      pending_[side].erase(clouds[side]->header.stamp);
      reportDropped(*sink_, "sweep", topics(), unpaired(side));
    }
  }

  std::string topics() const { return names_[0] + " + " + names_[1]; }

  std::string unpaired(int side) const
  {
    return "cloud on " + names_[side] + " has no cloud on " + names_[1 - side] + " with the same stamp";
  }

  std::string names_[2];
  std::mutex mutex_;  // guards everything below
  std::unique_ptr<Sync> sync_;
  // The stamps of the clouds in the synchroniser, per side (to report those still there at the
  // end of the bag, and a second cloud with the same stamp, which it would silently replace).
  std::set<ros::Time> pending_[2];
  const InputSink* sink_ = nullptr;  // the sink of the add() that is running
  core::Sweep sweep_;
};

// dual_return: one PointCloud2 with both returns of every beam per sweep.
class DualReturnAdapter : public InputAdapter
{
public:
  explicit DualReturnAdapter(const InputOptions& options)
    : topic_(inputTopic(options, kDualReturnTopic)), azimuth_resolution_deg_(options.azimuth_resolution_deg)
  {
    addTopic<sensor_msgs::PointCloud2>(
        topic_, "--input-topic", kSweepQueueSize,
        [this](const sensor_msgs::PointCloud2::ConstPtr& cloud, const InputSink& sink) { onCloud(*cloud, sink); });
  }

  std::string describe() const override
  {
    if (azimuth_resolution_deg_ == core::kAzimuthStepFromCloud)
      return "dual_return: the azimuth bins follow each cloud's azimuth step (azimuth_resolution_deg not given)";
    const std::size_t bins = core::azimuthBins(azimuth_resolution_deg_);
    char line[96];
    std::snprintf(line, sizeof(line), "dual_return: %zu azimuth bins of %.8g deg", bins,
                  360.0 / static_cast<double>(bins));
    return line;
  }

private:
  void onCloud(const sensor_msgs::PointCloud2& cloud, const InputSink& sink)
  {
    core::DualReturnStats stats;
    const std::string problem =
        dualReturnCloudToSweep(cloud, azimuth_resolution_deg_, buffer_, binner_, sweep_, stats);
    if (!problem.empty())
      return reportDropped(sink, "sweep", topic_, problem);
    const std::string unbinned = describeUnbinned(stats);
    if (!unbinned.empty())
      sink.receiver.inputProblem(InputProblem{ false, "sweep", topic_, unbinned });
    sink.receiver.sweepReady(sweep_, toSweepContext(cloud.header));
  }

  std::string topic_;
  double azimuth_resolution_deg_;
  core::DualReturnInput buffer_;
  core::DualReturnBinner binner_;
  core::Sweep sweep_;
};

// hokuyo3d_legacy: ohm_hokuyo3d/CoordDistMulti of the original driver, a package we do not
// have: taken as a ShapeShifter and decoded from the definition its publisher (or the bag)
// gives. Any type is taken: the decoder names the field a message lacks.
class Hokuyo3dLegacyAdapter : public InputAdapter
{
public:
  explicit Hokuyo3dLegacyAdapter(const InputOptions& options) : topic_(inputTopic(options, kLegacyTopic))
  {
    addTopic<topic_tools::ShapeShifter>(
        topic_, "--input-topic", kSweepQueueSize,
        [this](const topic_tools::ShapeShifter::ConstPtr& message, const InputSink& sink) {
          onMessage(*message, sink);
        },
        "ohm_hokuyo3d/CoordDistMulti");
  }

private:
  void onMessage(const topic_tools::ShapeShifter& message, const InputSink& sink)
  {
    bytes_.resize(message.size());
    ros::serialization::OStream stream(bytes_.data(), static_cast<std::uint32_t>(bytes_.size()));
    message.write(stream);
    std_msgs::Header header;
    const std::string problem = decoder_.decode(message.getDataType(), message.getMessageDefinition(), bytes_.data(),
                                                bytes_.size(), sweep_, header);
    if (!problem.empty())
      return reportDropped(sink, "sweep", topic_ + " (" + message.getDataType() + ")", problem);
    sink.receiver.sweepReady(sweep_, toSweepContext(header));
  }

  std::string topic_;
  std::vector<std::uint8_t> bytes_;
  Hokuyo3dLegacyDecoder decoder_;  // caches the parsed definition
  core::Sweep sweep_;
};

// multi_echo_scan: MultiEchoLaserScan projected with tf and assembled per half rotation
// (MultiEchoScanInput, which also gives the context). Each scan and each poll() hands on the
// sweeps whose scans tf could project by then.
class MultiEchoScanAdapter : public InputAdapter
{
public:
  explicit MultiEchoScanAdapter(const InputOptions& options)
    : topic_(inputTopic(options, kScanTopic)), scans_(options.scan_options, options.log_name)
  {
    addTopic<sensor_msgs::MultiEchoLaserScan>(
        topic_, "--input-topic", kScanQueueSize,
        [this](const sensor_msgs::MultiEchoLaserScan::ConstPtr& scan, const InputSink& sink) { onScan(scan, sink); });
  }

  bool readsTf() const override { return true; }

  void poll(const InputSink& sink) override
  {
    scans_.drain(sink.tf, [&sink](core::Sweep& sweep, const core::SweepContext& context) {
      sink.receiver.sweepReady(sweep, context);
    });
  }

  void reset() override { scans_.reset(); }

  void finish(const InputSink& sink) override
  {
    const std::size_t waiting = scans_.pendingScans();
    for (std::size_t i = 0; i < waiting; ++i)
      reportDropped(sink, "scan", topic_,
                    "still waits for its transform to " + scans_.options().sweep_frame + " at the end of the bag");
    scans_.reset();
  }

private:
  void onScan(const sensor_msgs::MultiEchoLaserScan::ConstPtr& scan, const InputSink& sink)
  {
    const std::string problem = scans_.addScan(scan);
    if (!problem.empty())
      reportDropped(sink, "scan", topic_, problem);
    poll(sink);
  }

  std::string topic_;
  MultiEchoScanInput scans_;
};

void readScanModeOptions(const ParamSource& source, InputOptions& options, std::vector<std::string>& errors)
{
  options.scan_options = readMultiEchoScanOptions(source, errors);
  if (!options.sensor_frame.empty())
    errors.push_back("sensor_frame is not used in input_mode multi_echo_scan (the origin comes from the scans' "
                     "frame in sweep_frame); remove it");
}

template <typename Adapter>
std::unique_ptr<InputAdapter> make(const InputOptions& options)
{
  return std::unique_ptr<InputAdapter>(new Adapter(options));
}
}  // namespace

const std::vector<InputMode>& inputModes()
{
  static const std::vector<InputMode> modes = {
    { "pair", "one ohm_mirror_detector3d/EchoPair per sweep on --input-topic", kPairTopic, nullptr,
      &make<PairAdapter> },
    { "two_topics", "two sensor_msgs/PointCloud2 per sweep, on --echo1-topic and --echo2-topic, same stamp",
      nullptr, nullptr, &make<TwoTopicsAdapter> },
    { "dual_return", "one sensor_msgs/PointCloud2 per sweep with both returns (fields return, ring) on --input-topic",
      kDualReturnTopic, nullptr, &make<DualReturnAdapter> },
    { "hokuyo3d_legacy", "one ohm_hokuyo3d/CoordDistMulti per sweep on --input-topic, decoded from its definition",
      kLegacyTopic, nullptr, &make<Hokuyo3dLegacyAdapter> },
    { "multi_echo_scan",
      "sensor_msgs/MultiEchoLaserScan on --input-topic with /tf (and /tf_static), assembled per half rotation",
      kScanTopic, &readScanModeOptions, &make<MultiEchoScanAdapter> },
  };
  return modes;
}

const InputMode* findInputMode(const std::string& name)
{
  for (const InputMode& mode : inputModes())
    if (name == mode.name)
      return &mode;
  return nullptr;
}

std::string unknownInputModeMessage(const std::string& name)
{
  std::string allowed;
  for (const InputMode& mode : inputModes())
    allowed += std::string(allowed.empty() ? "'" : ", '") + mode.name + "'";
  return "input_mode '" + name + "' is unknown: allowed values are " + allowed;
}

void readInputOptions(const ParamSource& source, const InputMode& mode, InputOptions& options,
                      std::vector<std::string>& errors)
{
  options.azimuth_resolution_deg = readAzimuthResolution(source, errors);
  options.sensor_frame.clear();
  if (source.has("sensor_frame") && !source.get("sensor_frame", options.sensor_frame))
    errors.push_back("parameter " + source.describe("sensor_frame") +
                     " has the wrong type: expected a string (the scanner's tf frame)");
  if (!options.sensor_frame.empty() && options.sensor_frame[0] == '/')
    options.sensor_frame.erase(0, 1);  // tf2 frame names have no leading slash
  if (mode.read_options != nullptr)
    mode.read_options(source, options, errors);
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
