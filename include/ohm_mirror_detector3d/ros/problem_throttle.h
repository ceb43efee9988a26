// Throttling of the errors about bad input, per kind of problem. ROS's *_THROTTLE macros
// throttle per line of code: one malformed message would then hide every other problem for
// the whole period, however different. Here each kind of problem (its text with the numbers
// masked, so "data holds 12 bytes" and "data holds 40 bytes" are one kind) is reported at
// most once per period, and a broken driver still cannot flood the log.
#pragma once

#include <cstddef>
#include <map>
#include <string>

namespace ohm_mirror_detector3d
{
namespace ros_io
{
class ProblemThrottle
{
public:
  explicit ProblemThrottle(double period_seconds) : period_(period_seconds) {}

  // True when `problem` (on `topic`) should be reported now (`now`: seconds, monotonic); then
  // `suppressed` is how many reports of that kind were held back since the last one.
  bool shouldReport(const std::string& topic, const std::string& problem, double now, std::size_t& suppressed);

  // The kind of a problem: its text with every run of digits replaced by '#'.
  static std::string kindOf(const std::string& problem);

private:
  struct Entry
  {
    double last_report = 0.0;
    std::size_t suppressed = 0;
  };
  // Bounds the memory a stream of ever new problem kinds could take.
  static constexpr std::size_t kMaxKinds = 256;

  double period_;
  std::map<std::string, Entry> entries_;
};

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
