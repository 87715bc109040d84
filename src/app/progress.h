#pragma once
// A one-line progress display for long runs: steps done, simulated time, ETA.
// Silent when standard error is not a terminal (CI logs, pipes).
#include <chrono>
#include <string>

namespace fretsim::app
{
  class Progress
  {
  public:
    Progress(const std::string &label, long total_steps, bool enabled = true);
    ~Progress(); // ends the line if one was drawn

    void update(long steps_done, double simulated_time);
    void finish();

  private:
    std::string                           label;
    long                                  total_steps;
    bool                                  active;
    bool                                  drawn = false;
    std::chrono::steady_clock::time_point start;
    std::chrono::steady_clock::time_point last_draw;
  };
} // namespace fretsim::app
