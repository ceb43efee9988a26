#include "ohm_mirror_detector3d/core/parallel.h"

#include <thread>

namespace ohm_mirror_detector3d
{
namespace core
{
int automaticThreadCount()
{
  // hardware_concurrency() is 0 where the machine does not tell.
  const unsigned cores = std::thread::hardware_concurrency();
  return std::max(1, std::min(kMaxAutomaticThreads, static_cast<int>(cores)));
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
