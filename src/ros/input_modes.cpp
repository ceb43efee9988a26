// The input modes' adapters and their table (input_mode.h).
#include "ohm_mirror_detector3d/ros/input_mode.h"

#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <message_filters/time_synchronizer.h>
#include <ros/message_event.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/MultiEchoLaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <topic_tools/shape_shifter.h>

#include <cmath>
#include <cstdio>
#include <deque>
#include <map>
#include <mutex>
#include <set>

#include "ohm_mirror_detector3d/EchoPair.h"
#include "ohm_mirror_detector3d/ros/conversions.h"
#include "ohm_mirror_detector3d/ros/dual_return.h"
#include "ohm_mirror_detector3d/ros/hokuyo3d_legacy.h"
#include "ohm_mirror_detector3d/ros/point_fields.h"

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

// "" when the frames agree (an empty frame_id says nothing), else the problem, naming both:
// the echoes of a beam must be measured in one frame, or the comparison of their ranges and
// the back-projection mix two frames.
std::string frameMismatch(const std::string& what1, const std::string& frame1, const std::string& what2,
                          const std::string& frame2)
{
  if (frame1.empty() || frame2.empty() || frame1 == frame2)
    return "";
  return what1 + " is in frame '" + frame1 + "' but " + what2 + " in frame '" + frame2 +
         "'; both echoes must be in one frame";
}

// "12.5 s" with a precision that keeps stamps apart.
std::string seconds(double value)
{
  char text[48];
  std::snprintf(text, sizeof(text), "%.6g s", value);
  return text;
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
    std::string problem = frameMismatch("echo1", pair.echo1.header.frame_id, "echo2", pair.echo2.header.frame_id);
    for (const sensor_msgs::PointCloud2* echo : { &pair.echo1, &pair.echo2 })
      if (problem.empty())
        problem = frameMismatch(echo == &pair.echo1 ? "echo1" : "echo2", echo->header.frame_id, "the EchoPair",
                                pair.header.frame_id);
    if (problem.empty())
      problem = echoPairToSweep(pair, sweep_);
    if (!problem.empty())
      return reportDropped(sink, "sweep", topic_, problem);
    sink.receiver.sweepReady(sweep_, toSweepContext(pair.header));
  }

  std::string topic_;
  core::Sweep sweep_;
};

// two_topics: two PointCloud2 topics paired by their header stamps: equal stamps (message_filters'
// exact time synchroniser), or with approximate_sync > 0 stamps at most that far apart (its
// approximate time synchroniser). A sweep is made when the second cloud of a pair arrives. A
// cloud whose partner does not come (the synchroniser drops it when a later pair completes or
// its queue overflows, or the bag ends) is reported with the stamp difference to the nearest
// cloud of the other topic and the count so far.
class TwoTopicsAdapter : public InputAdapter
{
public:
  explicit TwoTopicsAdapter(const InputOptions& options)
    : names_{ options.echo1_topic, options.echo2_topic }, approximate_sync_(options.approximate_sync)
  {
    addTopic<sensor_msgs::PointCloud2>(
        names_[0], "--echo1-topic", kSweepQueueSize,
        [this](const sensor_msgs::PointCloud2::ConstPtr& cloud, const InputSink& sink) { add(0, cloud, sink); });
    addTopic<sensor_msgs::PointCloud2>(
        names_[1], "--echo2-topic", kSweepQueueSize,
        [this](const sensor_msgs::PointCloud2::ConstPtr& cloud, const InputSink& sink) { add(1, cloud, sink); });
    startSync();
  }

  std::string describe() const override
  {
    if (approximate_sync_ <= 0.0)
      return "";
    return "two_topics: pairing clouds whose stamps differ by at most " + seconds(approximate_sync_) +
           " (approximate_sync)";
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
      for (const ros::Time& stamp : pending_[side])
        reportUnpaired(sink, side, stamp);
    startSync();
  }

private:
  using Cloud = sensor_msgs::PointCloud2;
  using ExactSync = message_filters::TimeSynchronizer<Cloud, Cloud>;
  using ApproximatePolicy = message_filters::sync_policies::ApproximateTime<Cloud, Cloud>;
  using ApproximateSync = message_filters::Synchronizer<ApproximatePolicy>;
  // Stamps of recent clouds per side, for the nearest partner of an unpaired cloud.
  static constexpr std::size_t kRecentStamps = 16;

  // A synchroniser without inputs: add() feeds it. Its queue holds the stamps of as many
  // sweeps as the two subscribers hold clouds.
  void startSync()
  {
    exact_.reset();
    approximate_.reset();
    if (approximate_sync_ > 0.0)
    {
      ApproximatePolicy policy(2 * kSweepQueueSize);
      policy.setMaxIntervalDuration(ros::Duration(approximate_sync_));
      approximate_.reset(new ApproximateSync(policy));
      approximate_->registerCallback(&TwoTopicsAdapter::onPair, this);
    }
    else
    {
      exact_.reset(new ExactSync(2 * kSweepQueueSize));
      exact_->registerCallback(&TwoTopicsAdapter::onPair, this);
      exact_->registerDropCallback(&TwoTopicsAdapter::onUnpaired, this);
    }
    for (int side = 0; side < 2; ++side)
    {
      pending_[side].clear();
      recent_[side].clear();
    }
  }

  void add(int side, const Cloud::ConstPtr& cloud, const InputSink& sink)
  {
    // The two subscribers' callbacks may run at once; the synchroniser calls back from add().
    std::lock_guard<std::mutex> lock(mutex_);
    sink_ = &sink;
    const ros::Time stamp = cloud->header.stamp;
    if (!pending_[side].insert(stamp).second)
      reportDropped(sink, "sweep", topics(),
                    "two clouds on " + names_[side] + " have the same stamp; the first is dropped");
    recent_[side].push_back(stamp);
    if (recent_[side].size() > kRecentStamps)
      recent_[side].pop_front();
    // The receipt time is not used: given, so that no ros::Time::now() is needed (prefilter_bag).
    const ros::MessageEvent<const Cloud> event(cloud, ros::Time());
    if (exact_)
      side == 0 ? exact_->add<0>(event) : exact_->add<1>(event);
    else
    {
      side == 0 ? approximate_->add<0>(event) : approximate_->add<1>(event);
      // The approximate synchroniser drops the oldest cloud of a full queue without a word.
      while (pending_[side].size() > 2 * kSweepQueueSize)
        dropPending(side, pending_[side].begin());
    }
    sink_ = nullptr;
  }

  void onPair(const Cloud::ConstPtr& echo1, const Cloud::ConstPtr& echo2)
  {
    const ros::Time stamps[2] = { echo1->header.stamp, echo2->header.stamp };
    for (int side = 0; side < 2; ++side)
    {
      pending_[side].erase(stamps[side]);
      // It pairs in the order of time: an older cloud still waiting has lost its chance.
      while (!pending_[side].empty() && *pending_[side].begin() < stamps[side])
        dropPending(side, pending_[side].begin());
    }
    std::string problem = frameMismatch(names_[0], echo1->header.frame_id, names_[1], echo2->header.frame_id);
    if (problem.empty())
      problem = echoCloudsToSweep(*echo1, *echo2, sweep_);
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
      const auto pending = pending_[side].find(clouds[side]->header.stamp);
      if (pending != pending_[side].end())
        dropPending(side, pending);
    }
  }

  void dropPending(int side, std::set<ros::Time>::iterator pending)
  {
    const ros::Time stamp = *pending;
    pending_[side].erase(pending);
    reportUnpaired(*sink_, side, stamp);
  }

  std::string topics() const { return names_[0] + " + " + names_[1]; }

  // The cloud of `side` with `stamp` found no partner: with the nearest stamp on the other topic
  // and how many clouds went unpaired so far.
  void reportUnpaired(const InputSink& sink, int side, const ros::Time& stamp)
  {
    ++unpaired_count_;
    const std::string& other = names_[1 - side];
    InputProblem problem{ true, "sweep", topics(),
                          "cloud on " + names_[side] + " has no cloud on " + other +
                              (approximate_sync_ > 0.0 ? " within approximate_sync " + seconds(approximate_sync_) :
                                                         std::string(" with the same stamp")),
                          "its stamp " + seconds(stamp.toSec()) };
    const std::deque<ros::Time>& others = recent_[1 - side];
    if (others.empty())
      problem.detail += "; no cloud has come on " + other;
    else
    {
      double nearest = (others.front() - stamp).toSec();
      for (const ros::Time& candidate : others)
        if (std::fabs((candidate - stamp).toSec()) < std::fabs(nearest))
          nearest = (candidate - stamp).toSec();
      problem.detail +=
          "; the nearest there is " + seconds(std::fabs(nearest)) + (nearest < 0.0 ? " earlier" : " later");
      if (approximate_sync_ <= 0.0 && nearest != 0.0)
        problem.detail += ": approximate_sync pairs clouds that far apart";
    }
    problem.detail += "; " + std::to_string(unpaired_count_) + " unpaired so far";
    sink.receiver.inputProblem(problem);
  }

  std::string names_[2];
  double approximate_sync_;
  std::mutex mutex_;  // guards everything below
  std::unique_ptr<ExactSync> exact_;              // approximate_sync 0
  std::unique_ptr<ApproximateSync> approximate_;  // approximate_sync > 0
  // The stamps of the clouds in the synchroniser, per side (to report those still there at the
  // end of the bag, and a second cloud with the same stamp, which it would silently replace).
  std::set<ros::Time> pending_[2];
  std::deque<ros::Time> recent_[2];
  std::size_t unpaired_count_ = 0;
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
    const std::string unbinned = core::describeUnbinned(stats);
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
        kLegacyScanDatatype);
  }

private:
  void onMessage(const topic_tools::ShapeShifter& message, const InputSink& sink)
  {
    const std::string& datatype = message.getDataType();
    const std::string& definition = message.getMessageDefinition();
    if (datatype != datatype_ || definition != definition_)
    {
      datatype_ = datatype;
      definition_ = definition;
      if (legacyLayoutProblem(datatype, definition).empty())
        sink.receiver.inputTypeFound(FoundInputType{ topic_, "hokuyo3d_legacy", datatype, message.getMD5Sum(),
                                                     definition });
    }
    bytes_.resize(message.size());
    ros::serialization::OStream stream(bytes_.data(), static_cast<std::uint32_t>(bytes_.size()));
    message.write(stream);
    std_msgs::Header header;
    std::string problem = decoder_.decode(datatype, definition, bytes_.data(), bytes_.size(), sweep_, header);
    if (!problem.empty() && !legacyLayoutProblem(datatype, definition).empty())
      problem += " (" + modeThatReads(datatype, definition, &message) + ")";
    if (!problem.empty())
      return reportDropped(sink, "sweep", topic_ + " (" + datatype + ")", problem);
    sink.receiver.sweepReady(sweep_, toSweepContext(header));
  }

  std::string topic_;
  std::string datatype_;    // of the last message
  std::string definition_;  // of the last message
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

// input_mode not set: one topic of any type; each message goes to the mode that reads its type
// (runTimeChoices(), matchInputType()), as a ShapeShifter (hokuyo3d_legacy) or deserialized
// into its type (pair). The decision is made again whenever the type changes.
class RunTimeTypeAdapter : public InputAdapter
{
public:
  explicit RunTimeTypeAdapter(const InputOptions& options) : topic_(inputTopic(options, kPairTopic))
  {
    InputOptions chosen = options;
    chosen.input_topic = topic_;
    for (const InputMode* mode : runTimeChoices())
      choices_.push_back(mode->make(chosen));
    addTopic<topic_tools::ShapeShifter>(
        topic_, "--input-topic", kSweepQueueSize,
        [this](const topic_tools::ShapeShifter::ConstPtr& message, const InputSink& sink) {
          onMessage(message, sink);
        },
        "ohm_mirror_detector3d/EchoPair or ohm_hokuyo3d/CoordDistMulti");
  }

  std::string describe() const override
  {
    std::string modes;
    for (const InputMode* mode : runTimeChoices())
      modes += std::string(modes.empty() ? "" : ", ") + mode->name;
    return "input_mode not set: the type of the messages on " + topic_ + " chooses the mode (" + modes + ")";
  }

  void reset() override
  {
    for (const std::unique_ptr<InputAdapter>& choice : choices_)
      choice->reset();
  }

  void finish(const InputSink& sink) override
  {
    for (const std::unique_ptr<InputAdapter>& choice : choices_)
      choice->finish(sink);
  }

private:
  void onMessage(const topic_tools::ShapeShifter::ConstPtr& message, const InputSink& sink)
  {
    if (message->getDataType() != datatype_ || message->getMD5Sum() != md5sum_ ||
        message->getMessageDefinition() != definition_)
    {
      datatype_ = message->getDataType();
      md5sum_ = message->getMD5Sum();
      definition_ = message->getMessageDefinition();
      match_ = matchInputType(datatype_, md5sum_, definition_, message.get());
      chosen_ = nullptr;
      for (std::size_t k = 0; k < runTimeChoices().size(); ++k)
        if (runTimeChoices()[k] == match_.mode)
          chosen_ = choices_[k].get();
      if (chosen_ != nullptr)
        sink.receiver.inputTypeFound(FoundInputType{ topic_, match_.mode->name, datatype_, md5sum_, definition_ });
    }
    if (chosen_ == nullptr)
      return reportDropped(sink, "message", topic_, match_.problem);
    try
    {
      chosen_->topics().front()->addShapeShifter(message, sink);
    }
    catch (const std::exception& e)  // bytes that do not match the announced type
    {
      reportDropped(sink, "message", topic_, std::string("cannot be read as ") + datatype_ + ": " + e.what());
    }
  }

  std::string topic_;
  std::vector<std::unique_ptr<InputAdapter>> choices_;  // one per runTimeChoices() entry
  // The type of the last message and what reads it.
  std::string datatype_;
  std::string md5sum_;
  std::string definition_;
  InputTypeMatch match_;
  InputAdapter* chosen_ = nullptr;
};

void readTwoTopicsOptions(const ParamSource& source, InputOptions& options, std::vector<std::string>& errors)
{
  options.approximate_sync = 0.0;
  if (source.has("approximate_sync") && !source.get("approximate_sync", options.approximate_sync))
    errors.push_back("parameter " + source.describe("approximate_sync") +
                     " has the wrong type: expected a number (seconds)");
  else if (!std::isfinite(options.approximate_sync) || options.approximate_sync < 0.0)
    errors.push_back("approximate_sync = " + std::to_string(options.approximate_sync) +
                     " is out of range: must be finite and >= 0 s (0: equal stamps)");
}

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
    { "two_topics",
      "two sensor_msgs/PointCloud2 per sweep, on --echo1-topic and --echo2-topic, same stamp (or within "
      "approximate_sync)",
      nullptr, &readTwoTopicsOptions, &make<TwoTopicsAdapter> },
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

const InputMode& runTimeInputMode()
{
  static const InputMode mode = { "",
                                  "ohm_mirror_detector3d/EchoPair is read as pair, ohm_hokuyo3d/CoordDistMulti (or "
                                  "any type of its layout) as hokuyo3d_legacy",
                                  kPairTopic, nullptr, &make<RunTimeTypeAdapter> };
  return mode;
}

const std::vector<const InputMode*>& runTimeChoices()
{
  static const std::vector<const InputMode*> choices = { findInputMode("pair"), findInputMode("hokuyo3d_legacy") };
  return choices;
}

InputTypeMatch matchInputType(const std::string& datatype, const std::string& md5sum, const std::string& definition,
                              const topic_tools::ShapeShifter* message)
{
  InputTypeMatch match;
  const std::string pair_type = ros::message_traits::DataType<EchoPair>::value();
  const std::string pair_md5 = ros::message_traits::MD5Sum<EchoPair>::value();
  if (datatype == pair_type && (md5sum == pair_md5 || md5sum == "*"))
    match.mode = findInputMode("pair");
  else if (datatype == pair_type)
    match.problem = "its type " + datatype + " has the md5sum " + md5sum + ", this build's " + pair_md5 +
                    ": another version of the message; build the publisher and the pre-filter from the same one";
  else if (legacyLayoutProblem(datatype, definition).empty())
    match.mode = findInputMode("hokuyo3d_legacy");
  else if (datatype == kLegacyScanDatatype)
    match.problem = "its type " + datatype + " has not the layout of the original driver's: " +
                    legacyLayoutProblem(datatype, definition);
  else
    match.problem = "its type " + datatype + " is not read without input_mode (that reads " + pair_type +
                    " as pair and " + kLegacyScanDatatype + " as hokuyo3d_legacy); " +
                    modeThatReads(datatype, definition, message);
  return match;
}

std::string modeThatReads(const std::string& datatype, const std::string& definition,
                          const topic_tools::ShapeShifter* message)
{
  if (datatype == ros::message_traits::DataType<EchoPair>::value())
    return "input_mode pair reads it";
  if (legacyLayoutProblem(datatype, definition).empty())
    return "input_mode hokuyo3d_legacy reads it";
  if (datatype == ros::message_traits::DataType<sensor_msgs::PointCloud2>::value())
  {
    sensor_msgs::PointCloud2::ConstPtr cloud;
    if (message != nullptr && message->getMD5Sum() == ros::message_traits::MD5Sum<sensor_msgs::PointCloud2>::value())
      cloud = message->instantiate<sensor_msgs::PointCloud2>();
    const auto hasOneOf = [&cloud](const char* const* begin, const char* const* end) {
      for (const char* const* name = begin; name != end; ++name)
        if (findField(*cloud, *name) != nullptr)
          return true;
      return false;
    };
    const std::string dual_return = "input_mode dual_return reads one cloud with both returns (a return and a ring "
                                    "field; azimuth_resolution_deg the lidar's azimuth step)";
    const std::string two_topics = "input_mode two_topics reads two clouds, the first echo on ~echo1 and the "
                                   "second on ~echo2";
    if (!cloud)
      return dual_return + "; " + two_topics;
    if (hasOneOf(std::begin(kReturnFieldNames), std::end(kReturnFieldNames)) &&
        hasOneOf(std::begin(kRingFieldNames), std::end(kRingFieldNames)))
      return "it has a return and a ring field: " + dual_return;
    return "it has no return and ring fields: " + two_topics;
  }
  if (datatype == ros::message_traits::DataType<sensor_msgs::MultiEchoLaserScan>::value())
    return "input_mode multi_echo_scan reads it, with sweep_frame (the fixed frame the rotating unit turns in, "
           "e.g. base_link)";
  if (datatype == ros::message_traits::DataType<sensor_msgs::LaserScan>::value())
    return "no input mode reads it: a LaserScan holds one echo per beam and the pre-filter compares two "
           "(urg_node publishes both as sensor_msgs/MultiEchoLaserScan on `echoes`: input_mode multi_echo_scan)";
  return "no input mode reads it (they read ohm_mirror_detector3d/EchoPair, sensor_msgs/PointCloud2, "
         "sensor_msgs/MultiEchoLaserScan and ohm_hokuyo3d/CoordDistMulti)";
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
  options.fixed_frame.clear();
  if (source.has("fixed_frame") && !source.get("fixed_frame", options.fixed_frame))
    errors.push_back("parameter " + source.describe("fixed_frame") +
                     " has the wrong type: expected a string (the post-filter's fixed tf frame)");
  if (!options.fixed_frame.empty() && options.fixed_frame[0] == '/')
    options.fixed_frame.erase(0, 1);
  if (mode.read_options != nullptr)
    mode.read_options(source, options, errors);
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
