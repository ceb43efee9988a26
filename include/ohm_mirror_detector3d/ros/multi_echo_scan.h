// Input mode multi_echo_scan: sensor_msgs/MultiEchoLaserScan of a rotating 2D scanner
// (urg_node's `echoes`), every beam projected with tf at its own time into the fixed
// sweep_frame and assembled into sweeps (core/sweep_assembler.h) for the pipeline.
#pragma once

#include <ros/time.h>
#include <sensor_msgs/MultiEchoLaserScan.h>
#include <tf2/buffer_core.h>

#include <Eigen/Core>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/core/sweep_assembler.h"
#include "ohm_mirror_detector3d/core/sweep_context.h"
#include "ohm_mirror_detector3d/ros/parameters.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
struct MultiEchoScanOptions
{
  std::string sweep_frame;  // fixed frame of the sweeps (required)
  double sweep_period = 0.0;  // [s]; 0 = a sweep every half rotation
  Eigen::Vector3d rotation_axis = Eigen::Vector3d::UnitZ();  // in sweep_frame, unit length
  std::size_t max_pending_scans = 400;  // scans waiting for their transforms (10 s at 40 Hz)
};

// Reads `sweep_frame`, `sweep_period` and `rotation_axis` (readInputOptions: the nodelet's
// private parameters, prefilter_bag's --params file); appends a message naming the parameter
// and its allowed values for every bad one.
MultiEchoScanOptions readMultiEchoScanOptions(const ParamSource& source, std::vector<std::string>& errors);

// What is wrong with a scan ("" when it can be used): no beams, ranges and intensities of
// different lengths (per scan or per beam), angles or times that are not finite, beams that
// do not fit angle_min/angle_max/angle_increment, an empty frame_id or a zero stamp.
std::string checkMultiEchoScan(const sensor_msgs::MultiEchoLaserScan& scan);

// Queues scans until tf can project them, projects them in arrival order and assembles the
// sweeps. Thread-safe: addScan() and drain() may be called from any thread; one drain()
// works at a time (a concurrent call returns at once, the running one picks up new scans).
class MultiEchoScanInput
{
public:
  // Receives each completed sweep and its context: framed sweep_frame, stamped with its last
  // scan's stamp, the sensor pose the mean optical centre over its scans (the sweep's origin)
  // with sweep_frame's axes (the scanner turns through the sweep). The sink may swap the
  // sweep's buffers with its own (std::swap), which saves a copy.
  using SweepSink = std::function<void(core::Sweep& sweep, const core::SweepContext& context)>;

  // `name` prefixes the log messages.
  MultiEchoScanInput(const MultiEchoScanOptions& options, const std::string& name);
  ~MultiEchoScanInput();

  // Checks a scan and queues it; returns the problem ("" when queued). A full queue drops
  // its oldest scan with a throttled warning.
  std::string addScan(const sensor_msgs::MultiEchoLaserScan::ConstPtr& scan);

  // Projects every queued scan whose transforms are in `tf`, in order, and calls `sink` for
  // each completed sweep. Scans whose transforms will never come (older than the tf buffer, or
  // a gap in tf) are dropped with a throttled error. The caller fills `tf`: the nodelet's tf
  // listener, or prefilter_bag from the bag's /tf and /tf_static in bag order (calling drain()
  // after each message).
  void drain(const tf2::BufferCore& tf, const SweepSink& sink);

  // Forgets the queued scans and the partial sweep (on (re)subscription).
  void reset();

  const MultiEchoScanOptions& options() const { return options_; }
  // Scans queued and not yet projected (waiting for their transforms).
  std::size_t pendingScans();

private:
  enum class Projection
  {
    done,   // projected_ holds the scan
    wait,   // transforms not available yet
    never   // transforms will not come: drop the scan
  };
  struct Pending
  {
    sensor_msgs::MultiEchoLaserScan::ConstPtr scan;
    ros::WallTime received;
  };

  Projection project(const tf2::BufferCore& tf, const sensor_msgs::MultiEchoLaserScan& scan, std::string& reason);
  std::string frames(const sensor_msgs::MultiEchoLaserScan& scan) const;

  MultiEchoScanOptions options_;
  std::string name_;

  std::mutex pending_mutex_;  // guards pending_, last_stamp_, reset_requested_
  std::deque<Pending> pending_;
  ros::Time last_stamp_;
  bool reset_requested_ = false;

  std::mutex drain_mutex_;  // guards everything below
  core::SweepAssembler assembler_;
  core::ProjectedScan projected_;
  core::Sweep sweep_;
  std::vector<Eigen::Vector3f> directions_;  // unit beam directions of the last scan geometry
  double directions_min_ = 0.0, directions_increment_ = 0.0;
};

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
