// Work shared among threads, the same result for any number of them: the stages split their
// work into tasks that write disjoint data (one object each, a range of beams each), and combine
// what the tasks counted in task order afterwards, so that one thread and eight give the same
// labels, objects and counts.
//
// The threads are a pool of our own (parallel.cpp), not OpenMP: libgomp's threads spin after every
// parallel region, and measured on the 64 x 600 lidar frame on two cores that took the process's
// CPU time from 34 to 45 ms per frame for the same 20 ms of latency (OMP_WAIT_POLICY=PASSIVE, which
// a library cannot set for its host process, gave 34 ms); the pool's idle threads sleep.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <vector>

namespace ohm_mirror_detector3d
{
namespace core
{
// The threads a pipeline uses when the `threads` parameter is left automatic: the machine's
// cores, at most kMaxAutomaticThreads (beyond four the stages that split their work gain little
// on sweeps of up to a million returns, and a robot runs more than this filter).
constexpr int kMaxAutomaticThreads = 4;
int automaticThreadCount();

// The workers runTasks uses for `tasks` tasks on up to `threads` threads (at least 1): a caller
// with scratch memory per worker makes this many.
inline std::size_t workersFor(std::size_t tasks, int threads)
{
  return std::max<std::size_t>(1, std::min<std::size_t>(tasks, static_cast<std::size_t>(std::max(threads, 1))));
}

// Runs job(worker) for worker 0 (on the calling thread) and 1 .. workers - 1 (on the pool's
// threads, started when first needed and kept asleep between jobs), and returns when all have
// returned. False, having run nothing, when the pool is busy with another job (a second pipeline in
// another thread, or a job started from inside a task) or was inherited through fork(): the caller
// then runs the work itself.
bool runOnPool(std::size_t workers, const std::function<void(std::size_t)>& job);

// Calls task(t, worker) for t in [0, tasks) on workersFor(tasks, threads) threads, each task once,
// in no particular order; `worker` (< workersFor(tasks, threads)) is the thread's own number, for
// its scratch memory. The tasks must not write the same data. An exception thrown by a task
// leaves runTasks (side by side: after the other tasks ran, the first in task order), never a
// worker thread, where it could only end the process.
template <typename Task>
void runTasks(std::size_t tasks, int threads, Task task)
{
  if (tasks == 0)
    return;
  const std::size_t workers = workersFor(tasks, threads);
  if (workers == 1)
  {
    for (std::size_t t = 0; t < tasks; ++t)
      task(t, std::size_t(0));
    return;
  }
  std::vector<std::exception_ptr> failures(tasks);
  // Each thread takes the next task when done with one: tasks differ in size (an object behind
  // which half the sweep lies, one with nothing behind it), and on a shared machine a thread may
  // be slowed by others.
  std::atomic<std::size_t> next_task{ 0 };
  const std::function<void(std::size_t)> job = [&](std::size_t worker) {
    for (std::size_t t = next_task++; t < tasks; t = next_task++)
    {
      try
      {
        task(t, worker);
      }
      catch (...)
      {
        failures[t] = std::current_exception();
      }
    }
  };
  if (!runOnPool(workers, job))
    job(0);
  for (const std::exception_ptr& failure : failures)
    if (failure)
      std::rethrow_exception(failure);
}

// How many ranges to cut `items` into for `threads` threads: one for one thread, else a few per
// thread (ranges differ in their work) but none below `min_items` items.
constexpr std::size_t kRangesPerThread = 4;
inline std::size_t partsFor(std::size_t items, int threads, std::size_t min_items)
{
  if (threads <= 1)
    return 1;
  const std::size_t most = kRangesPerThread * static_cast<std::size_t>(threads);
  return std::max<std::size_t>(1, std::min(most, items / std::max<std::size_t>(min_items, 1)));
}

// [begin, end) of range `part` when [0, size) is cut into `parts` nearly equal ranges: range
// `part` begins at partBegin(size, parts, part) and ends where range part + 1 begins.
inline std::size_t partBegin(std::size_t size, std::size_t parts, std::size_t part)
{
  return size / parts * part + std::min(part, size % parts);
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
