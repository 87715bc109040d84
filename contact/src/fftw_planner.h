#pragma once
#include <mutex>

namespace fretsim::contact::detail
{
  /// FFTW's planner and fftw_destroy_plan share global state and are not
  /// thread safe (executing existing plans is): every plan made or destroyed
  /// in this library holds this one lock, so that runs in parallel threads
  /// are safe.
  std::mutex &fftw_planner_mutex();
} // namespace fretsim::contact::detail
