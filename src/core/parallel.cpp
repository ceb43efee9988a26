#include "ohm_mirror_detector3d/core/parallel.h"

#include <unistd.h>

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// The process's pool: threads that wait (asleep, on a condition variable) for a job, take a worker
// number each, run the job and report back. One job at a time; a second caller meanwhile runs its
// work itself, so that pipelines in several threads never wait for each other.
class ThreadPool
{
public:
  ThreadPool() : owner_(getpid()) {}
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  ~ThreadPool()
  {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& thread : threads_)
      if (thread.joinable())
        thread.join();
  }

  bool run(std::size_t workers, const std::function<void(std::size_t)>& job)
  {
    const std::size_t helpers = workers - 1;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      // A child of fork() has none of the parent's threads: the pool is of no use there.
      if (busy_ || stop_ || getpid() != owner_)
        return false;
      busy_ = true;
      while (threads_.size() < helpers)
        threads_.emplace_back([this]() { serve(); });
      job_ = &job;
      wanted_ = helpers;
      started_ = finished_ = 0;
      ++generation_;
    }
    wake_.notify_all();
    std::exception_ptr failure;
    try
    {
      job(0);
    }
    catch (...)
    {
      failure = std::current_exception();
    }
    {
      // The helpers read the job: it must outlive them, whatever worker 0 did.
      std::unique_lock<std::mutex> lock(mutex_);
      done_.wait(lock, [this]() { return finished_ == wanted_; });
      job_ = nullptr;
      busy_ = false;
    }
    if (failure)
      std::rethrow_exception(failure);
    return true;
  }

private:
  void serve()
  {
    std::uint64_t seen = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;)
    {
      wake_.wait(lock, [&]() { return stop_ || (generation_ != seen && started_ < wanted_); });
      if (stop_)
        return;
      seen = generation_;
      const std::size_t worker = ++started_;
      const std::function<void(std::size_t)>* job = job_;
      lock.unlock();
      (*job)(worker);  // runTasks's job catches what its tasks throw
      lock.lock();
      if (++finished_ == wanted_)
        done_.notify_one();
    }
  }

  const pid_t owner_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::vector<std::thread> threads_;
  const std::function<void(std::size_t)>* job_ = nullptr;
  std::size_t wanted_ = 0, started_ = 0, finished_ = 0;
  std::uint64_t generation_ = 0;
  bool busy_ = false, stop_ = false;
};
}  // namespace

int automaticThreadCount()
{
  // hardware_concurrency() is 0 where the machine does not tell.
  const unsigned cores = std::thread::hardware_concurrency();
  return std::max(1, std::min(kMaxAutomaticThreads, static_cast<int>(cores)));
}

bool runOnPool(std::size_t workers, const std::function<void(std::size_t)>& job)
{
  if (workers <= 1)
    return false;
  static ThreadPool pool;
  return pool.run(workers, job);
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
