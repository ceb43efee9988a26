#include "ohm_mirror_detector3d/ros/processing_stats.h"

#include <diagnostic_msgs/DiagnosticStatus.h>

#include <algorithm>

namespace ohm_mirror_detector3d
{
namespace ros_io
{
void ProcessingStats::recordProcessed(double seconds, std::size_t objects, std::size_t points)
{
  std::lock_guard<std::mutex> lock(mutex_);
  ++processed_total_;
  ++processed_;
  seconds_sum_ += seconds;
  seconds_max_ = std::max(seconds_max_, seconds);
  last_seconds_ = seconds;
  last_objects_ = objects;
  last_points_ = points;
}

void ProcessingStats::recordImplausibleRemoval(const std::string& description)
{
  std::lock_guard<std::mutex> lock(mutex_);
  ++implausible_;
  last_implausible_removal_ = description;
}

void ProcessingStats::recordDropped(const std::string& problem)
{
  std::lock_guard<std::mutex> lock(mutex_);
  ++dropped_total_;
  ++dropped_;
  last_problem_ = problem;
}

void ProcessingStats::recordPublisherProblem(const std::string& problem)
{
  std::lock_guard<std::mutex> lock(mutex_);
  publisher_problem_ = problem;
}

void ProcessingStats::report(diagnostic_updater::DiagnosticStatusWrapper& status, bool subscribed)
{
  std::lock_guard<std::mutex> lock(mutex_);
  const Clock::time_point now = Clock::now();
  const double interval = std::chrono::duration<double>(now - interval_start_).count();
  const std::uint64_t received = processed_ + dropped_;
  const double input_rate = interval > 0.0 ? static_cast<double>(received) / interval : 0.0;

  using diagnostic_msgs::DiagnosticStatus;
  if (processed_ == 0 && dropped_ > 0)
    status.summaryf(DiagnosticStatus::ERROR, "every input dropped: %s", last_problem_.c_str());
  else if (dropped_ > 0)
    status.summaryf(DiagnosticStatus::WARN, "%lu of %lu inputs dropped: %s", static_cast<unsigned long>(dropped_),
                    static_cast<unsigned long>(received), last_problem_.c_str());
  else if (implausible_ > 0)
    status.summaryf(DiagnosticStatus::WARN, "in %lu of %lu sweeps %s", static_cast<unsigned long>(implausible_),
                    static_cast<unsigned long>(processed_), last_implausible_removal_.c_str());
  else if (received > 0)
    status.summary(DiagnosticStatus::OK, "processing sweeps");
  else if (subscribed && !publisher_problem_.empty())
    status.summaryf(DiagnosticStatus::ERROR, "no input can arrive: %s", publisher_problem_.c_str());
  else if (subscribed)
    status.summary(DiagnosticStatus::OK, "waiting for input");
  else
    status.summary(DiagnosticStatus::OK, "idle: no subscriber to any output, input not subscribed");

  status.add("input subscribed", subscribed);
  status.addf("input rate (sweeps/s)", "%.3f", input_rate);
  status.addf("sweeps processed", "%lu", static_cast<unsigned long>(processed_total_));
  status.addf("inputs dropped", "%lu", static_cast<unsigned long>(dropped_total_));
  status.addf("mean processing time (ms)", "%.2f",
              processed_ > 0 ? 1e3 * seconds_sum_ / static_cast<double>(processed_) : 0.0);
  status.addf("max processing time (ms)", "%.2f", 1e3 * seconds_max_);
  status.addf("last processing time (ms)", "%.2f", 1e3 * last_seconds_);
  status.addf("objects in last sweep", "%zu", last_objects_);
  status.addf("points in last sweep", "%zu", last_points_);
  status.add("last drop reason", last_problem_.empty() ? std::string("none") : last_problem_);
  status.add("last implausible removal",
             last_implausible_removal_.empty() ? std::string("none") : last_implausible_removal_);

  interval_start_ = now;
  processed_ = 0;
  dropped_ = 0;
  implausible_ = 0;
  seconds_sum_ = 0.0;
  seconds_max_ = 0.0;
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
