#include <fretsim/contact/fretting_loop.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fretsim::contact
{
  double HarmonicSliding::displacement(double time) const
  {
    return amplitude * std::sin(2.0 * M_PI * time / period);
  }

  FrettingLoop::FrettingLoop(int steps_per_cycle)
    : steps_per_cycle(steps_per_cycle)
  {
    if (steps_per_cycle < 4)
      throw std::invalid_argument("a fretting cycle needs at least 4 steps");
  }

  void FrettingLoop::add(double displacement, double force)
  {
    displacements.push_back(displacement);
    forces.push_back(force);
  }

  int FrettingLoop::complete_cycles() const
  {
    return displacements.empty() ? 0 : static_cast<int>((displacements.size() - 1) / steps_per_cycle);
  }

  double FrettingLoop::reference_force(const MindlinLoop &reference, double amplitude,
                                       double displacement, double previous_displacement,
                                       bool reversed_before)
  {
    if (!reversed_before)
      return reference.virgin_force(displacement);
    const bool unloading = displacement < previous_displacement;
    return reference.loop_force(displacement, amplitude, unloading);
  }

  LoopMetrics FrettingLoop::last_cycle(double mu_P, const MindlinLoop &reference, double amplitude) const
  {
    const int cycles = complete_cycles();
    if (cycles < 1)
      throw std::logic_error("no complete fretting cycle recorded");
    const std::size_t end   = static_cast<std::size_t>(cycles) * steps_per_cycle; // last sample index
    const std::size_t begin = end - steps_per_cycle;

    LoopMetrics metrics;
    double      force_max = forces[begin];
    double      force_min = forces[begin];
    double      work      = 0.0;
    for (std::size_t i = begin + 1; i <= end; ++i)
      {
        force_max = std::max(force_max, forces[i]);
        force_min = std::min(force_min, forces[i]);
        // Trapezoidal rule on the recorded path: exact for piecewise-linear Q(delta).
        work += 0.5 * (forces[i] + forces[i - 1]) * (displacements[i] - displacements[i - 1]);
        const double expected =
          reference_force(reference, amplitude, displacements[i], displacements[i - 1], true);
        metrics.error_vs_reference =
          std::max(metrics.error_vs_reference, std::abs(forces[i] - expected) / mu_P);
        if (cycles > 1)
          metrics.change_from_previous_cycle =
            std::max(metrics.change_from_previous_cycle,
                     std::abs(forces[i] - forces[i - steps_per_cycle]) / mu_P);
      }
    metrics.force_amplitude   = 0.5 * (force_max - force_min);
    metrics.dissipated_energy = std::abs(work);
    if (cycles == 1)
      metrics.change_from_previous_cycle = std::nan("");
    return metrics;
  }
} // namespace fretsim::contact
