// What the pre-filter reports on /diagnostics: sweeps processed and dropped, processing time,
// input rate, objects per sweep, and a WARN while a stage removes an implausible share of the
// sweeps (core/removal_report.h). The input callbacks record, diagnostic_updater's timer
// reports; both may run on different threads, hence the mutex.
#pragma once

#include <diagnostic_updater/DiagnosticStatusWrapper.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>

namespace ohm_mirror_detector3d
{
namespace ros_io
{
class ProcessingStats
{
public:
  using Clock = std::chrono::steady_clock;

  // A sweep went through the pipeline in `seconds` (conversion to outputs included).
  void recordProcessed(double seconds, std::size_t objects, std::size_t points);
  // A stage of the last sweep processed removed an implausible share of it: `description`
  // (core::describeRemoval) says which, naming the parameter.
  void recordImplausibleRemoval(const std::string& description);
  // A sweep (or a scan of one) was refused: `problem` is what the throttled error said.
  void recordDropped(const std::string& problem);
  // Nothing can arrive from a publisher on an input topic (another message type): reported as
  // an error while no input comes, until the next check finds none ("").
  void recordPublisherProblem(const std::string& problem);

  // Summarises the interval since the previous call into `status` and starts a new one.
  // `subscribed`: whether the lazy input subscription is active (no input is then normal).
  void report(diagnostic_updater::DiagnosticStatusWrapper& status, bool subscribed);

private:
  std::mutex mutex_;
  Clock::time_point interval_start_ = Clock::now();
  // Totals since start.
  std::uint64_t processed_total_ = 0;
  std::uint64_t dropped_total_ = 0;
  // This interval.
  std::uint64_t processed_ = 0;
  std::uint64_t dropped_ = 0;
  std::uint64_t implausible_ = 0;  // sweeps with an implausible removal
  double seconds_sum_ = 0.0;
  double seconds_max_ = 0.0;
  // The last sweep processed.
  double last_seconds_ = 0.0;
  std::size_t last_objects_ = 0;
  std::size_t last_points_ = 0;
  std::string last_problem_;
  std::string last_implausible_removal_;
  std::string publisher_problem_;
};

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
