#include "ohm_mirror_detector3d/ros/problem_throttle.h"

#include <cctype>

namespace ohm_mirror_detector3d
{
namespace ros_io
{
std::string ProblemThrottle::kindOf(const std::string& problem)
{
  std::string kind;
  kind.reserve(problem.size());
  for (const char c : problem)
  {
    if (std::isdigit(static_cast<unsigned char>(c)))
    {
      if (kind.empty() || kind.back() != '#')
        kind.push_back('#');
    }
    else
      kind.push_back(c);
  }
  return kind;
}

bool ProblemThrottle::shouldReport(const std::string& topic, const std::string& problem, double now,
                                   std::size_t& suppressed)
{
  const std::string key = topic + '\n' + kindOf(problem);
  auto it = entries_.find(key);
  if (it == entries_.end())
  {
    if (entries_.size() >= kMaxKinds)
      entries_.clear();
    entries_[key].last_report = now;
    suppressed = 0;
    return true;
  }
  Entry& entry = it->second;
  if (now - entry.last_report < period_)
  {
    ++entry.suppressed;
    return false;
  }
  suppressed = entry.suppressed;
  entry.suppressed = 0;
  entry.last_report = now;
  return true;
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
