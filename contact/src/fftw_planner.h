#pragma once
#include <mutex>

namespace fretsim::contact::detail
{
  /// FFTW's planner and fftw_destroy_plan share global state and are not
  /// thread safe (executing existing plans is): every plan made or destroyed
  /// in this library holds this one lock, so that runs in parallel threads
  /// are safe.
  std::mutex &fftw_planner_mutex();
  /// Called under that lock before plans made without timing (FFTW_ESTIMATE):
  /// they then start from no accumulated wisdom, so what other threads
  /// planned before cannot change the algorithm chosen, nor the result's
  /// last digits.
  void forget_planner_history();
} // namespace fretsim::contact::detail
