// Active-set iteration of the Winkler solvers, and what both report.
#include "winkler_active_set.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

namespace fretsim::fem
{
  double WinklerGridSolution::contact_fraction() const
  {
    return active.empty() ? 0.0 : static_cast<double>(active_cells) / static_cast<double>(active.size());
  }

  double WinklerGridSolution::peak_pressure() const
  {
    return pressure.empty() ? 0.0 : *std::max_element(pressure.begin(), pressure.end());
  }

  void check_layer(const WinklerLayer &layer, const std::string &solver)
  {
    if (!(layer.normal_stiffness > 0.0) || !std::isfinite(layer.normal_stiffness))
      throw std::invalid_argument(solver + ": the normal stiffness k_n must be finite and > 0 Pa/m");
    if (!std::isfinite(layer.radial_interference))
      throw std::invalid_argument(solver + ": the radial interference must be finite");
  }

  void iterate_active_set(const std::size_t n_cells, const std::vector<unsigned char> &initial,
                          const unsigned int max_iterations, const std::string &solver,
                          const SolveWithActiveSet &solve, WinklerGridSolution &result)
  {
    if (!initial.empty() && initial.size() != n_cells)
      throw std::invalid_argument(solver + ": the initial active set needs one entry per grid cell (" +
                                  std::to_string(n_cells) + "), got " + std::to_string(initial.size()));
    if (max_iterations == 0)
      throw std::invalid_argument(solver + ": at least one iteration is needed");
    std::vector<unsigned char> active(n_cells, 1);
    if (!initial.empty())
      std::transform(initial.begin(), initial.end(), active.begin(), [](unsigned char a) { return a ? 1 : 0; });
    // Every set tried: the iteration is deterministic, so a set that comes
    // back (other than as the fixed point) would come back forever.
    std::set<std::vector<unsigned char>> tried;
    for (unsigned int iteration = 1;; ++iteration)
      {
        tried.insert(active);
        std::vector<double>        penetration = solve(active);
        std::vector<unsigned char> next(n_cells);
        std::size_t                changed = 0, count = 0;
        for (std::size_t c = 0; c < n_cells; ++c)
          {
            next[c] = penetration[c] > 0.0 ? 1 : 0;
            changed += next[c] != active[c];
            count += next[c];
          }
        if (changed == 0)
          {
            result.penetration  = std::move(penetration);
            result.active       = std::move(next);
            result.active_cells = count;
            result.iterations   = iteration;
            return;
          }
        if (tried.count(next) != 0)
          throw std::runtime_error(solver + ": the active set cycles (after " + std::to_string(iteration) +
                                   " solves a set tried before comes back; " + std::to_string(changed) +
                                   " cells change): the contact problem is not resolved");
        if (iteration >= max_iterations)
          throw std::runtime_error(solver + ": the active set did not settle in " + std::to_string(max_iterations) +
                                   " solves (" + std::to_string(changed) + " of " + std::to_string(n_cells) +
                                   " cells still change)");
        active = std::move(next);
      }
  }
} // namespace fretsim::fem
