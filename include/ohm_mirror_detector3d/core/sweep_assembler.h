// Sweeps of a rotating 2D multi-echo scanner, assembled from single scans (ROS-free).
//
// The ROS layer (ros/multi_echo_scan.h) projects every beam of a scan into the fixed sweep
// frame with tf; this file holds what does not need ROS: which echoes of a beam become echo 1
// and echo 2, the rotation angle of the scanner about the rotation axis, the detection of
// sweep boundaries (every half rotation or every sweep_period seconds) and the assembly of
// projected scans into a core::Sweep (rows = scans, cols = beams per scan).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/core/sweep.h"
#include "ohm_mirror_detector3d/core/sweep_context.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// The echoes of one beam that become echo 1 and echo 2: the first and the last usable echo
// (finite, within [range_min, range_max]) in the order the scanner reports them (time of
// flight: first = nearest). A beam with one usable echo has first == last (echo 2 repeats
// echo 1, as the Hokuyo3D driver does); a third echo in between is not used; -1 = no return.
struct EchoChoice
{
  int first = -1;
  int last = -1;

  bool hasReturn() const { return first >= 0; }
};

EchoChoice chooseEchoes(const float* ranges, std::size_t count, float range_min, float range_max);

// The rotation angle [rad] of `rotation` about the unit `axis` (the twist of its swing-twist
// decomposition): 2 atan2(q.vec() . axis, q.w()), in (-pi, pi]. For a scanner whose pose in
// the sweep frame is R_axis(phi) * R0 (a unit turning about an axis fixed in the sweep frame)
// it is phi + const, whatever the fixed mounting R0 (undefined only when R0 turns the axis
// by exactly 180 deg).
double twistAngle(const Eigen::Quaterniond& rotation, const Eigen::Vector3d& axis);

// `angle` shifted by a multiple of 2 pi to lie within pi of `reference` (unwrapping of a
// continuously measured angle; assumes less than half a turn between two measurements).
double unwrapAngle(double angle, double reference);

// Splits a monotonic sequence of phases (the rotation angle of each scan, or its time stamp)
// into sweeps of `period` (pi for half rotations, or sweep_period seconds). Angular phases
// are unwrapped first (each to within pi of the previous one). The first phase after
// construction or reset() anchors the boundaries: sweep k holds the scans with
// anchor + k period <= phase < anchor + (k + 1) period (for a falling phase mirrored), with
// half the last phase step as tolerance, so that a scan that lands on a boundary up to
// rounding starts the new sweep. A period <= 0 never splits.
class SweepBoundary
{
public:
  explicit SweepBoundary(double period = 0.0, bool angular = false) : period_(period), angular_(angular) {}

  void configure(double period, bool angular)
  {
    period_ = period;
    angular_ = angular;
    reset();
  }
  double period() const { return period_; }
  bool angular() const { return angular_; }
  void reset() { started_ = false; }

  // Index of the sweep that `phase` belongs to (0 for the anchor).
  long update(double phase);
  // The last phase, unwrapped.
  double lastPhase() const { return last_; }

private:
  double period_;
  bool angular_;
  bool started_ = false;
  double anchor_ = 0.0;
  double last_ = 0.0;
  double step_ = 0.0;
};

// One scan projected into the sweep frame, echo 1 and echo 2 index-aligned per beam.
struct ProjectedScan
{
  std::vector<Eigen::Vector3f> echo1;  // non-finite: no return
  std::vector<Eigen::Vector3f> echo2;  // == echo1 for a beam with one return
  std::vector<float> intensity1;       // NaN when unknown
  std::vector<float> intensity2;
  bool has_intensity = false;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // the scanner's optical centre during the scan
  double phase = 0.0;         // what SweepBoundary splits on: rotation angle [rad] or stamp [s]
  std::uint64_t stamp_ns = 0;  // the scan's stamp, passed through to the sweep

  std::size_t size() const { return echo1.size(); }
  // Sizes all arrays for `beams` beams, every beam without return.
  void reset(std::size_t beams);
};

// Collects projected scans into sweeps. add() says when the scan starts a new sweep
// (AddResult::sweep_complete); the completed one then waits for takeSweep(). Scans are rows in
// arrival order.
class SweepAssembler
{
public:
  // period, angular: see SweepBoundary (pi and true for half rotations). max_rows: a sweep
  // that grows beyond this many scans without a boundary (a unit that does not rotate) is
  // discarded.
  explicit SweepAssembler(double period = kHalfRotation, bool angular = true, std::size_t max_rows = 10000);

  static constexpr double kHalfRotation = 3.14159265358979323846;

  void configure(double period, bool angular);

  // Discards every scan collected so far (the next scan anchors the sweep boundaries anew).
  void reset();

  enum class AddResult
  {
    added,          // the scan belongs to the sweep being assembled
    sweep_complete, // the scan starts a new sweep; the previous one waits for takeSweep()
    width_changed,  // the scan has another beam count: the partial sweep was discarded, the scan starts anew
    overflow        // the sweep had max_rows scans without a boundary: discarded, the scan starts anew
  };
  AddResult add(const ProjectedScan& scan);

  // True from an add() that returned sweep_complete until takeSweep() (a later completion
  // replaces a sweep that was not taken).
  bool hasCompleteSweep() const { return complete_.rows > 0; }
  // Moves the completed sweep into `sweep` (rows = scans, cols = beams, ranges from the mean
  // scanner position over its scans, input_cells empty) and sets context.stamp_ns (the stamp
  // of its last scan) and context.sensor_pose (translation: that mean position; rotation:
  // identity, since the scanner turns during the sweep); the frame is the caller's. Returns its
  // number of rows, 0 when none was complete (sweep and context then stay as they are).
  std::size_t takeSweep(Sweep& sweep, SweepContext& context);

  std::size_t rows() const { return building_.rows; }
  std::size_t cols() const { return building_.cols; }

private:
  struct Buffer
  {
    std::size_t rows = 0;
    std::size_t cols = 0;
    std::vector<Eigen::Vector3f> points[2];
    std::vector<float> intensities[2];
    bool has_intensity = true;
    Eigen::Vector3d origin_sum = Eigen::Vector3d::Zero();
    std::uint64_t last_stamp_ns = 0;
    long index = 0;  // SweepBoundary index

    void clear();
    void append(const ProjectedScan& scan);
  };

  SweepBoundary boundary_;
  std::size_t max_rows_;
  Buffer building_;
  Buffer complete_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
