#pragma once
// The active-set iteration shared by the full and the reduced Winkler solvers
// (winkler_foundation.h); plain C++.
#include <fretsim/fem/winkler_foundation.h>

#include <functional>
#include <string>
#include <vector>

namespace fretsim::fem
{
  /// Solves with the cells of a set in contact and returns every cell's
  /// penetration d_c [m] (the same on every rank).
  using SolveWithActiveSet = std::function<std::vector<double>(const std::vector<unsigned char> &active)>;

  /// Iterates from `initial` (empty: every cell) until the set of cells with
  /// d_c > 0 repeats; fills penetration, active, active_cells and iterations
  /// of `result`. Throws std::runtime_error, naming `solver`, if an earlier set
  /// comes back or `max_iterations` solves do not settle it.
  void iterate_active_set(std::size_t n_cells, const std::vector<unsigned char> &initial, unsigned int max_iterations,
                          const std::string &solver, const SolveWithActiveSet &solve, WinklerGridSolution &result);

  /// Throws std::invalid_argument (naming `solver`) unless k_n > 0 is finite
  /// and δ_fit is finite.
  void check_layer(const WinklerLayer &layer, const std::string &solver);
} // namespace fretsim::fem
