#pragma once
// A one-line progress display for long runs: steps (or points) done,
// simulated time where there is one, ETA.
// Silent when standard error is not a terminal (CI logs, pipes).
#include <chrono>
#include <string>

namespace fretsim::app
{
  class Progress
  {
  public:
    /// `unit` names what is counted ("step", "point").
    Progress(const std::string &label, long total_steps, bool enabled = true, const std::string &unit = "step");
    ~Progress(); // ends the line if one was drawn

    /// A NaN simulated_time is not shown.
    void update(long steps_done, double simulated_time);
    void finish();

  private:
    std::string                           label, unit;
    long                                  total_steps;
    bool                                  active;
    bool                                  drawn = false;
    std::chrono::steady_clock::time_point start;
    std::chrono::steady_clock::time_point last_draw;
  };
} // namespace fretsim::app
