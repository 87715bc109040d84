#include "thread_team.h"

#include <omp.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <string>

namespace fretsim::coupling
{
  namespace
  {
    /// One step of a busy wait: a pause, and after a few a yield: the
    /// partner may have lost its core to another process (two flexible
    /// passes at once on 2 cores took 2.8 times as long as with OpenMP's
    /// sleeping threads when the yield came after 4 096 pauses, 1.07 times
    /// after 8; alone the same).
    inline void spin(unsigned &count)
    {
      if (++count < 8)
        {
#if defined(__x86_64__) || defined(__i386__)
          __builtin_ia32_pause();
#endif
        }
      else
        std::this_thread::yield();
    }

    /// Set on a team's threads while they run a task.
    thread_local bool in_task = false;
  } // namespace

  void TeamPart::wait() const
  {
    if (parts > 1)
      team->barrier();
  }

  int ThreadTeam::threads_for(const char *wait_policy, int openmp_threads)
  {
    std::string policy = wait_policy ? wait_policy : "";
    std::transform(policy.begin(), policy.end(), policy.begin(), [](unsigned char c) { return std::tolower(c); });
    return policy == "active" ? 1 : std::clamp(openmp_threads, 1, 2);
  }

  ThreadTeam &ThreadTeam::shared()
  {
    // (omp_get_num_procs: the cores the process may run on, one under an
    // MPI launcher's binding to a core.)
    static ThreadTeam team(
      threads_for(std::getenv("OMP_WAIT_POLICY"), std::min(omp_get_max_threads(), omp_get_num_procs())));
    return team;
  }

  ThreadTeam::ThreadTeam(int threads)
  {
    if (threads >= 2 && std::thread::hardware_concurrency() != 1)
      worker = std::thread([this] { work(); });
  }

  ThreadTeam::~ThreadTeam()
  {
    if (!worker.joinable())
      return;
    stopping.store(true);
    posted.fetch_add(1);
    {
      std::lock_guard<std::mutex> lock(sleep_mutex);
    }
    wake.notify_one();
    worker.join();
  }

  void ThreadTeam::run_erased(Call task, void *task_callable)
  {
    std::unique_lock<std::mutex> lock(busy, std::defer_lock);
    // Alone also where the caller's OpenMP allows one thread (`fretsim
    // map` gives each point one core, and its result must not depend on
    // whether the team was free) or runs within an OpenMP region.
    if (!worker.joinable() || in_task || omp_get_max_threads() < 2 || omp_in_parallel() || !lock.try_lock())
      {
        task(task_callable, TeamPart{0, 1, this});
        return;
      }
    call         = task;
    callable     = task_callable;
    worker_error = nullptr;
    // Posting and the worker's going to sleep are both sequentially
    // consistent: either it sees the task, or this sees it asleep.
    const unsigned ticket = posted.fetch_add(1) + 1;
    if (sleeping.load())
      {
        std::lock_guard<std::mutex> sleeper(sleep_mutex);
        wake.notify_one();
      }
    std::exception_ptr error;
    in_task = true;
    try
      {
        task(task_callable, TeamPart{0, 2, this});
      }
    catch (...)
      {
        error = std::current_exception();
      }
    in_task = false;
    for (unsigned count = 0; finished.load(std::memory_order_acquire) != ticket;)
      spin(count);
    if (!error)
      error = worker_error;
    if (error)
      std::rethrow_exception(error);
  }

  void ThreadTeam::work()
  {
    using Clock   = std::chrono::steady_clock;
    unsigned seen = 0;
    in_task       = true;
    for (;;)
      {
        auto     since = Clock::now();
        unsigned count = 0;
        while (posted.load(std::memory_order_acquire) == seen)
          {
            spin(count);
            if (count % 64 != 0 || std::chrono::duration<double>(Clock::now() - since).count() < spin_seconds)
              continue;
            std::unique_lock<std::mutex> lock(sleep_mutex);
            sleeping.store(true);
            wake.wait(lock, [&] { return posted.load() != seen; });
            sleeping.store(false);
            since = Clock::now();
            count = 0;
          }
        seen = posted.load(std::memory_order_acquire);
        if (stopping.load())
          return;
        try
          {
            call(callable, TeamPart{1, 2, this});
          }
        catch (...)
          {
            worker_error = std::current_exception();
          }
        finished.store(seen, std::memory_order_release);
      }
  }

  void ThreadTeam::barrier()
  {
    const unsigned now = generation.load(std::memory_order_acquire);
    if (arrived.fetch_add(1, std::memory_order_acq_rel) == 1)
      { // the second to arrive lets both go
        arrived.store(0, std::memory_order_relaxed);
        generation.fetch_add(1, std::memory_order_release);
        return;
      }
    for (unsigned count = 0; generation.load(std::memory_order_acquire) == now;)
      spin(count);
  }
} // namespace fretsim::coupling
