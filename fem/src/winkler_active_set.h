#pragma once
// The active-set iteration shared by the full and the reduced Winkler solvers
// (winkler_foundation.h); plain C++.
#include <fretsim/fem/winkler_foundation.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace fretsim::fem
{
  /// The solver's side of the iteration. `solve` solves the linear problem
  /// with the cells of a set in contact, keeps that solution u_N as its
  /// candidate and returns every cell's penetration d_c(u_N) [m] (the same on
  /// every rank); `accept(t)` moves the current state to u + t (u_N - u) (the
  /// first call, with t = 1, makes u_N the current state).
  struct ActiveSetSolver
  {
    std::function<std::vector<double>(const std::vector<unsigned char> &active)> solve;
    std::function<void(double t)>                                                accept;
  };

  /// Semismooth Newton on Φ: from the solution for `initial` (empty: every
  /// cell), each step solves with the cells that penetrate at the current
  /// state and moves to that solution (the plain active-set iteration) if
  /// that lowers Φ, else by the step t ∈ (0, 1) that minimises Φ along the
  /// way (exactly: Φ is piecewise quadratic there); overshooting full steps
  /// are what lets the plain iteration cycle. Φ falls at every step, so no
  /// state comes back. Converged when a full
  /// step's solution penetrates exactly where it was assumed to (the linear
  /// solution is then the solution). `cell_stiffness` = k_n A [N/m]. Fills
  /// penetration, active, active_cells and iterations (linear solves) of
  /// `result`. Throws std::runtime_error, naming `solver`, after
  /// `max_iterations` solves without convergence.
  void iterate_active_set(std::size_t n_cells, const std::vector<unsigned char> &initial, unsigned int max_iterations,
                          double cell_stiffness, const std::string &solver, const ActiveSetSolver &callbacks,
                          WinklerGridSolution &result);

  /// Fills result.pressure = k_n max(d, 0) from its penetration and returns
  /// the foundation's energy ½ Σ k_n A max(d, 0)² [J] (`cell_stiffness` = k_n A).
  double foundation_pressure(double normal_stiffness, double cell_stiffness, WinklerGridSolution &result);

  /// What a Winkler transient (WinklerNewmark, WinklerPairNewmark) keeps of
  /// its steps: the foundation at time t and the counts over the steps.
  struct WinklerStepRecord
  {
    double              dt = 0.0, t = 0.0;
    WinklerGridSolution state; ///< the foundation at time t
    double              seconds = 0.0, factorisation_seconds = 0.0;
    unsigned int        steps = 0, factorisations = 0, solves = 0;

    /// Adds the step that produced `next` (its wall time: since `seconds_taken`
    /// was measured by the caller) and moves time on by dt.
    const WinklerGridSolution &add_step(WinklerGridSolution next, double seconds_taken)
    {
      factorisations += next.factorisations;
      factorisation_seconds += next.factorisation_seconds;
      solves += next.iterations;
      next.seconds = seconds_taken;
      seconds += seconds_taken;
      state = std::move(next);
      t += dt;
      ++steps;
      return state;
    }
  };

  /// Throws std::invalid_argument (naming `solver`) unless k_n > 0 is finite
  /// and δ_fit is finite.
  void check_layer(const WinklerLayer &layer, const std::string &solver);
} // namespace fretsim::fem
