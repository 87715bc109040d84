#include <fretsim/support/progress.h>

#include <cmath>
#include <cstdio>
#include <unistd.h>

namespace fretsim::app
{
  Progress::Progress(const std::string &label, long total_steps, bool enabled, const std::string &unit)
    : label(label)
    , unit(unit)
    , total_steps(total_steps)
    , active(enabled && isatty(fileno(stderr)))
    , start(std::chrono::steady_clock::now())
    , last_draw(start)
  {}

  Progress::~Progress() { finish(); }

  void Progress::update(long steps_done, double simulated_time)
  {
    if (!active)
      return;
    const auto now = std::chrono::steady_clock::now();
    // Redraw at most ten times a second: a terminal is slower than the solver.
    if (steps_done < total_steps && now - last_draw < std::chrono::milliseconds(100))
      return;
    last_draw            = now;
    const double elapsed = std::chrono::duration<double>(now - start).count();
    const double eta     = steps_done > 0 ? elapsed * (total_steps - steps_done) / steps_done : 0.0;
    std::fprintf(stderr, "\r%s: %s %ld/%ld (%3.0f %%), ", label.c_str(), unit.c_str(), steps_done, total_steps,
                 100.0 * steps_done / total_steps);
    if (!std::isnan(simulated_time))
      std::fprintf(stderr, "t = %.4g s, ", simulated_time);
    std::fprintf(stderr, "elapsed %.1f s, ETA %.1f s   ", elapsed, eta);
    std::fflush(stderr);
    drawn = true;
  }

  void Progress::finish()
  {
    if (drawn)
      std::fputc('\n', stderr);
    drawn = false;
  }
} // namespace fretsim::app
