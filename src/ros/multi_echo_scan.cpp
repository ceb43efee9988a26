#include "ohm_mirror_detector3d/ros/multi_echo_scan.h"

#include <ros/console.h>
#include <tf2/exceptions.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <utility>

#include "ohm_mirror_detector3d/ros/conversions.h"
#include "ohm_mirror_detector3d/ros/tf_availability.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
namespace
{
constexpr double kThrottleSeconds = 5.0;
// A scan waiting this long for its transforms gets a (throttled) warning.
constexpr double kWaitWarningSeconds = 1.0;
// A scan whose frame tf has never heard of is dropped after this long: the queue is worked
// in order, so one scan with a wrong frame_id would otherwise hold back every later scan
// until the queue overflows (max_pending_scans). Frames that tf knows keep waiting.
constexpr double kUnknownFrameDropSeconds = 3.0;
// Longest a single scan may take from its first to its last beam (a Hokuyo: 25 ms).
constexpr double kMaxScanSeconds = 10.0;

std::string formatTime(const ros::Time& t)
{
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(3);
  out << t.toSec();
  return out.str();
}
}  // namespace

MultiEchoScanOptions readMultiEchoScanOptions(const ParamSource& source, std::vector<std::string>& errors)
{
  MultiEchoScanOptions options;
  if (!source.has("sweep_frame"))
    errors.push_back("parameter " + source.describe("sweep_frame") +
                     " is required in input_mode multi_echo_scan: the fixed frame to assemble sweeps in "
                     "(e.g. base_link)");
  else if (!source.get("sweep_frame", options.sweep_frame) || options.sweep_frame.empty())
    errors.push_back("parameter " + source.describe("sweep_frame") + " must be a non-empty frame name");
  else if (options.sweep_frame[0] == '/')
    options.sweep_frame.erase(0, 1);  // tf2 frame names have no leading slash

  if (source.has("sweep_period"))
  {
    if (!source.get("sweep_period", options.sweep_period))
      errors.push_back("parameter " + source.describe("sweep_period") + " has the wrong type: expected a number");
    else if (!std::isfinite(options.sweep_period) || options.sweep_period < 0.0)
      errors.push_back("parameter " + source.describe("sweep_period") + " = " +
                       std::to_string(options.sweep_period) +
                       " is out of range: allowed >= 0 [s] (0 = one sweep per half rotation)");
  }

  if (source.has("rotation_axis"))
  {
    std::vector<double> axis;
    if (!source.get("rotation_axis", axis) || axis.size() != 3)
      errors.push_back("parameter " + source.describe("rotation_axis") +
                       " must be a list of three numbers [x, y, z] (the axis in sweep_frame)");
    else
    {
      const Eigen::Vector3d v(axis[0], axis[1], axis[2]);
      if (!v.allFinite() || v.norm() < 1e-9)
        errors.push_back("parameter " + source.describe("rotation_axis") +
                         " must be a finite, non-zero vector [x, y, z]");
      else
        options.rotation_axis = v.normalized();
    }
  }
  return options;
}

std::string checkMultiEchoScan(const sensor_msgs::MultiEchoLaserScan& scan)
{
  std::ostringstream problem;
  const std::size_t n = scan.ranges.size();
  if (scan.header.frame_id.empty())
    problem << "empty header.frame_id";
  else if (scan.header.stamp.isZero())
    problem << "header.stamp is zero (tf needs the time of the scan)";
  else if (n == 0)
    problem << "no beams (ranges is empty)";
  else if (!std::isfinite(scan.angle_min) || !std::isfinite(scan.angle_max) || !std::isfinite(scan.angle_increment) ||
           scan.angle_increment == 0.0f)
    problem << "angle_min, angle_max and angle_increment must be finite and angle_increment non-zero (got "
            << scan.angle_min << ", " << scan.angle_max << ", " << scan.angle_increment << ")";
  else if (std::abs(scan.angle_min + static_cast<double>(n - 1) * scan.angle_increment - scan.angle_max) >
           std::abs(scan.angle_increment) * 1.01)
    problem << n << " beams from angle_min " << scan.angle_min << " in steps of angle_increment "
            << scan.angle_increment << " end at " << scan.angle_min + static_cast<double>(n - 1) * scan.angle_increment
            << ", not at angle_max " << scan.angle_max;
  else if (!std::isfinite(scan.time_increment) || scan.time_increment < 0.0f)
    problem << "time_increment " << scan.time_increment << " must be finite and >= 0";
  // Found by the fuzzer: ros::Duration / ros::Time throw (std::runtime_error, out of the
  // callback) when the scan's last beam time is beyond their 32-bit range.
  else if (static_cast<double>(scan.time_increment) * static_cast<double>(n - 1) > kMaxScanSeconds)
    problem << n << " beams " << scan.time_increment << " s apart (time_increment) take "
            << static_cast<double>(scan.time_increment) * static_cast<double>(n - 1) << " s: more than "
            << kMaxScanSeconds << " s for one scan";
  else if (scan.header.stamp.toSec() + static_cast<double>(scan.time_increment) * static_cast<double>(n - 1) >=
           static_cast<double>(std::numeric_limits<std::uint32_t>::max()))
    problem << "header.stamp " << scan.header.stamp.toSec() << " plus the scan's duration is beyond ros::Time's range";
  else if (std::isnan(scan.range_min) || std::isnan(scan.range_max) || scan.range_min > scan.range_max)
    problem << "range_min " << scan.range_min << " and range_max " << scan.range_max
            << " must be numbers with range_min <= range_max";
  else if (!scan.intensities.empty() && scan.intensities.size() != n)
    problem << "ranges has " << n << " beams but intensities has " << scan.intensities.size()
            << " (must be equal, or intensities empty)";
  else if (!scan.intensities.empty())
  {
    for (std::size_t i = 0; i < n; ++i)
    {
      if (scan.intensities[i].echoes.size() != scan.ranges[i].echoes.size())
      {
        problem << "beam " << i << " has " << scan.ranges[i].echoes.size() << " range echoes but "
                << scan.intensities[i].echoes.size() << " intensity echoes";
        break;
      }
    }
  }
  return problem.str();
}

MultiEchoScanInput::MultiEchoScanInput(const MultiEchoScanOptions& options, const std::string& name)
  : options_(options)
  , name_(name)
  , assembler_(options.sweep_period > 0.0 ? options.sweep_period : core::SweepAssembler::kHalfRotation,
               !(options.sweep_period > 0.0))
{
}

MultiEchoScanInput::~MultiEchoScanInput() = default;

std::string MultiEchoScanInput::frames(const sensor_msgs::MultiEchoLaserScan& scan) const
{
  return "from " + scan.header.frame_id + " to " + options_.sweep_frame;
}

std::string MultiEchoScanInput::addScan(const sensor_msgs::MultiEchoLaserScan::ConstPtr& scan)
{
  std::string problem = checkMultiEchoScan(*scan);
  if (!problem.empty())
    return problem;
  std::lock_guard<std::mutex> lock(pending_mutex_);
  if (!last_stamp_.isZero() && scan->header.stamp < last_stamp_)
  {
    ROS_WARN_STREAM(name_ << ": scan stamp " << formatTime(scan->header.stamp) << " is older than the previous one ("
                          << formatTime(last_stamp_) << "): time went backwards, starting a new sweep");
    pending_.clear();
    reset_requested_ = true;
  }
  last_stamp_ = scan->header.stamp;
  if (pending_.size() >= options_.max_pending_scans)
  {
    const sensor_msgs::MultiEchoLaserScan& oldest = *pending_.front().scan;
    ROS_WARN_STREAM_THROTTLE(kThrottleSeconds,
                             name_ << ": " << pending_.size() << " scans are waiting for the transform "
                                   << frames(oldest) << "; dropping the oldest (stamp " << formatTime(oldest.header.stamp)
                                   << "). Is tf published for these frames?");
    pending_.pop_front();
  }
  pending_.push_back(Pending{ scan, ros::WallTime::now() });
  return std::string();
}

std::size_t MultiEchoScanInput::pendingScans()
{
  std::lock_guard<std::mutex> lock(pending_mutex_);
  return pending_.size();
}

void MultiEchoScanInput::reset()
{
  std::lock_guard<std::mutex> lock(pending_mutex_);
  pending_.clear();
  last_stamp_ = ros::Time();
  reset_requested_ = true;
}

void MultiEchoScanInput::drain(const tf2::BufferCore& tf, const SweepSink& sink)
{
  std::unique_lock<std::mutex> drain_lock(drain_mutex_, std::try_to_lock);
  if (!drain_lock.owns_lock())
    return;
  for (;;)
  {
    Pending next;
    {
      std::lock_guard<std::mutex> lock(pending_mutex_);
      if (reset_requested_)
      {
        assembler_.reset();
        reset_requested_ = false;
      }
      if (pending_.empty())
        return;
      next = pending_.front();
    }
    const sensor_msgs::MultiEchoLaserScan& scan = *next.scan;
    std::string reason;
    const Projection projection = project(tf, scan, reason);
    const double waited = (ros::WallTime::now() - next.received).toSec();
    if (projection == Projection::wait && waited > kUnknownFrameDropSeconds &&
        !tf._frameExists(scan.header.frame_id))
    {
      {
        std::lock_guard<std::mutex> lock(pending_mutex_);
        if (!reset_requested_ && !pending_.empty() && pending_.front().scan == next.scan)
          pending_.pop_front();
      }
      ROS_ERROR_STREAM_THROTTLE(kThrottleSeconds, name_ << ": dropping scan (stamp " << formatTime(scan.header.stamp)
                                                        << "): its frame_id '" << scan.header.frame_id
                                                        << "' is unknown to tf (no transform to "
                                                        << options_.sweep_frame << " after " << waited << " s)");
      continue;
    }
    if (projection == Projection::wait)
    {
      if (waited > kWaitWarningSeconds)
        ROS_WARN_STREAM_THROTTLE(kThrottleSeconds, name_ << ": waiting for the transform " << frames(scan) << " at "
                                                         << formatTime(scan.header.stamp) << ": " << reason);
      return;
    }
    {
      std::lock_guard<std::mutex> lock(pending_mutex_);
      // reset() or an overflow may have removed it meanwhile.
      if (reset_requested_ || pending_.empty() || pending_.front().scan != next.scan)
        continue;
      pending_.pop_front();
    }
    if (projection == Projection::never)
    {
      ROS_ERROR_STREAM_THROTTLE(kThrottleSeconds, name_ << ": dropping scan (stamp " << formatTime(scan.header.stamp)
                                                        << "): no transform " << frames(scan)
                                                        << " will come for its time: " << reason);
      continue;
    }

    switch (assembler_.add(projected_))
    {
      case core::SweepAssembler::AddResult::width_changed:
        ROS_WARN_STREAM(name_ << ": scans now have " << projected_.size()
                              << " beams, other than the sweep being assembled: discarding it and starting anew");
        break;
      case core::SweepAssembler::AddResult::overflow:
        ROS_ERROR_STREAM_THROTTLE(kThrottleSeconds,
                                  name_ << ": no sweep boundary after " << assembler_.rows()
                                        << " scans: discarding them. Does the unit rotate about rotation_axis in "
                                        << options_.sweep_frame << "? (Or set sweep_period.)");
        break;
      case core::SweepAssembler::AddResult::sweep_complete:
      {
        // The scanner turns through the sweep: its mean optical centre, sweep_frame's axes
        // (SweepAssembler::takeSweep).
        core::SweepContext context;
        assembler_.takeSweep(sweep_, context);
        context.frame_id = options_.sweep_frame;
        sink(sweep_, context);
        break;
      }
      case core::SweepAssembler::AddResult::added:
        break;
    }
  }
}

MultiEchoScanInput::Projection MultiEchoScanInput::project(const tf2::BufferCore& tf,
                                                           const sensor_msgs::MultiEchoLaserScan& scan,
                                                           std::string& reason)
{
  const std::string& target = options_.sweep_frame;
  const std::string& source = scan.header.frame_id;
  const std::size_t n = scan.ranges.size();
  const ros::Time start = scan.header.stamp;
  const ros::Time end = start + ros::Duration(static_cast<double>(scan.time_increment) * static_cast<double>(n - 1));

  const auto covered = [&]() {
    return tf.canTransform(target, source, start, &reason) &&
           tf.canTransform(target, source, end, &reason);
  };
  if (!covered())
  {
    // Will they still come? Only while tf has nothing newer than the end of the scan.
    if (transformMayStillCome(tf, target, source, end, reason))
      return Projection::wait;
    // The listener fills the buffer on its own thread: the transforms for the end of the scan may have
    // arrived between the check above and the lookup of the newest one. Only a second miss, with the
    // newest transform already past the scan, means they never will (the scan fell into a gap).
    if (!covered())
      return Projection::never;
  }

  // Beam directions in the scan frame, recomputed only when the geometry changes.
  if (directions_.size() != n || directions_min_ != scan.angle_min || directions_increment_ != scan.angle_increment)
  {
    directions_.resize(n);
    for (std::size_t i = 0; i < n; ++i)
    {
      const double angle = scan.angle_min + static_cast<double>(i) * scan.angle_increment;
      directions_[i] = Eigen::Vector3f(static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle)), 0.0f);
    }
    directions_min_ = scan.angle_min;
    directions_increment_ = scan.angle_increment;
  }

  projected_.reset(n);
  projected_.has_intensity = !scan.intensities.empty();
  projected_.stamp_ns = start.toNSec();
  Eigen::Vector3d origin_sum = Eigen::Vector3d::Zero();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Eigen::Matrix3f rotation = Eigen::Matrix3f::Identity();
  Eigen::Vector3f translation = Eigen::Vector3f::Zero();
  ros::Time pose_time;
  try
  {
    for (std::size_t i = 0; i < n; ++i)
    {
      const ros::Time t = start + ros::Duration(static_cast<double>(scan.time_increment) * static_cast<double>(i));
      if (i == 0 || t != pose_time)
      {
        pose = toIsometry(tf.lookupTransform(target, source, t).transform);
        rotation = pose.linear().cast<float>();
        translation = pose.translation().cast<float>();
        pose_time = t;
      }
      if (i == 0)
      {
        // The rotation angle about the axis at the start of the scan.
        projected_.phase = options_.sweep_period > 0.0 ?
                               start.toSec() :
                               core::twistAngle(Eigen::Quaterniond(pose.linear()), options_.rotation_axis);
      }
      origin_sum += pose.translation();

      const std::vector<float>& ranges = scan.ranges[i].echoes;
      const core::EchoChoice choice = core::chooseEchoes(ranges.data(), ranges.size(), scan.range_min, scan.range_max);
      if (!choice.hasReturn())
        continue;
      projected_.echo1[i] = rotation * (directions_[i] * ranges[static_cast<std::size_t>(choice.first)]) + translation;
      projected_.echo2[i] = choice.last == choice.first ?
                                projected_.echo1[i] :
                                Eigen::Vector3f(rotation * (directions_[i] * ranges[static_cast<std::size_t>(choice.last)]) +
                                                translation);
      if (projected_.has_intensity)
      {
        const std::vector<float>& intensities = scan.intensities[i].echoes;
        projected_.intensity1[i] = intensities[static_cast<std::size_t>(choice.first)];
        projected_.intensity2[i] = intensities[static_cast<std::size_t>(choice.last)];
      }
    }
  }
  catch (const tf2::TransformException& e)
  {
    // Both ends were available, so a beam in between fell into a gap of the tf data.
    reason = e.what();
    return Projection::never;
  }
  projected_.origin = origin_sum / static_cast<double>(n);
  return Projection::done;
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
