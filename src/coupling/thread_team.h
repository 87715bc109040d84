#pragma once
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <type_traits>
#include <utility>

namespace fretsim::coupling
{
  class ThreadTeam;

  /// A team thread's share of a task: `part` of `parts`, and the barrier
  /// across them.
  struct TeamPart
  {
    int         part  = 0;
    int         parts = 1;
    ThreadTeam *team  = nullptr;
    /// Returns when every part has called it (nothing with one part).
    void wait() const;
    /// This part's share [begin, end) of `count` items, the parts in order.
    std::pair<std::size_t, std::size_t> share(std::size_t count) const
    {
      return {count * part / parts, count * (part + 1) / parts};
    }
  };

  /// The caller and one worker thread sharing the interface's loops: a few
  /// tens of microseconds of work each, thousands per step, too short for an
  /// OpenMP region when its threads sleep between regions (a passive wait
  /// policy: 0.05-0.1 ms to wake one on a 2-core virtual machine, more than
  /// the loop). The worker spins for the next task for spin_seconds, then
  /// sleeps. One task at a time: a task run while another runs (another
  /// thread's, or from within a task) runs on its caller alone, as does one
  /// whose caller's OpenMP may use one thread only or runs in an OpenMP
  /// parallel region.
  class ThreadTeam
  {
  public:
    /// The process's team: threads_for(OMP_WAIT_POLICY, OpenMP's threads,
    /// at most the cores the process may run on).
    static ThreadTeam &shared();
    /// Two threads where OpenMP may use two (its OMP_NUM_THREADS), else
    /// one; one also under OMP_WAIT_POLICY=active, whose threads never
    /// leave their cores: the worker would wait for one at every task (a
    /// flexible-housing pass took 30 times as long).
    static int threads_for(const char *wait_policy, int openmp_threads);
    explicit ThreadTeam(int threads);
    ~ThreadTeam();
    ThreadTeam(const ThreadTeam &)            = delete;
    ThreadTeam &operator=(const ThreadTeam &) = delete;

    /// task(const TeamPart &) on every thread of the team, part 0 on the
    /// caller's; returns when every part has, rethrowing the first
    /// exception. A part that throws must do so before its first wait, as
    /// the others do (same arguments, same checks).
    template <typename Task>
    void run(Task &&task)
    {
      using Callable = std::remove_reference_t<Task>;
      run_erased([](void *callable, const TeamPart &part) { (*static_cast<Callable *>(callable))(part); },
                 const_cast<void *>(static_cast<const void *>(&task)));
    }

    int size() const { return worker.joinable() ? 2 : 1; }

    /// How long the worker waits for the next task before it sleeps [s].
    static constexpr double spin_seconds = 2e-4;

  private:
    friend struct TeamPart;
    using Call = void (*)(void *, const TeamPart &);
    void run_erased(Call call, void *callable);
    void barrier();
    void work();

    std::thread              worker;
    std::mutex               busy; ///< held by the running task's caller
    Call                     call     = nullptr;
    void                    *callable = nullptr;
    std::exception_ptr       worker_error;
    std::atomic<unsigned>    posted{0}, finished{0}; ///< tasks posted to and finished by the worker
    std::atomic<bool>        stopping{false}, sleeping{false};
    std::mutex               sleep_mutex;
    std::condition_variable  wake;
    std::atomic<unsigned>    arrived{0}, generation{0}; ///< the barrier's
  };
} // namespace fretsim::coupling
