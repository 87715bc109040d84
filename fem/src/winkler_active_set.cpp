// Active-set (semismooth Newton) iteration of the Winkler solvers, and what
// both report.
//
// The line search needs no operator of the solver: every state u the
// iteration visits has B u - f = Σ_c α_c w_c (B = K - σM) with per-cell
// coefficients α, because a linear solve with the set A gives
// B u_N - f = Σ_{c∈A} k_n A d_c(u_N) w_c and a step mixes two such states
// linearly; and d(u) = δ_fit - W u is affine, so W s = d(u) - d(u_N) for
// s = u_N - u. Along u + t s then
//   Φ'(t) = Σ_c (α_c + t (α_N,c - α_c)) e_c - Σ_c k_n A max(d_c - t e_c, 0) e_c,
//   e_c = d_c - d_N,c,
// piecewise linear and non-decreasing in t (Φ is convex).
#include "winkler_active_set.h"

#include <algorithm>
#include <cmath>
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

  namespace
  {
    /// α of the linear solution for `active`: k_n A d_c on the set, 0 elsewhere.
    std::vector<double> coefficients(const std::vector<double> &penetration, const std::vector<unsigned char> &active,
                                     double cell_stiffness)
    {
      std::vector<double> alpha(penetration.size(), 0.0);
      for (std::size_t c = 0; c < penetration.size(); ++c)
        if (active[c])
          alpha[c] = cell_stiffness * penetration[c];
      return alpha;
    }

    /// The step from (d, α) towards (d_N, α_N): 1 if that lowers Φ, else the
    /// t ∈ (0, 1) that minimises Φ along the way.
    double exact_step(const std::vector<double> &d, const std::vector<double> &alpha, const std::vector<double> &d_new,
                      const std::vector<double> &alpha_new, double cell_stiffness)
    {
      const auto slope = [&](double t) {
        double s = 0.0;
        for (std::size_t c = 0; c < d.size(); ++c)
          {
            const double e = d[c] - d_new[c];
            s += (alpha[c] + t * (alpha_new[c] - alpha[c])) * e - cell_stiffness * std::max(d[c] - t * e, 0.0) * e;
          }
        return s;
      };
      // Φ(1) - Φ(0): the plain active-set step, taken whenever it lowers Φ
      // (the exact minimiser along the line would cost more steps).
      double change = 0.0;
      for (std::size_t c = 0; c < d.size(); ++c)
        {
          const double e = d[c] - d_new[c], before = std::max(d[c], 0.0), after = std::max(d_new[c], 0.0);
          change += alpha[c] * e + 0.5 * (alpha_new[c] - alpha[c]) * e + 0.5 * cell_stiffness * (after * after - before * before);
        }
      // Not a descent direction only through round-off at the solution: the
      // full step then changes nothing that matters.
      if (change < 0.0 || slope(1.0) <= 0.0 || slope(0.0) >= 0.0)
        return 1.0;
      // Bisection down to the linear piece holding the root, then that piece's root.
      double low = 0.0, high = 1.0;
      for (int k = 0; k < 60; ++k)
        {
          const double mid = 0.5 * (low + high);
          (slope(mid) < 0.0 ? low : high) = mid;
        }
      const double s_low = slope(low), s_high = slope(high);
      const double t     = s_high > s_low ? low - s_low * (high - low) / (s_high - s_low) : high;
      return std::clamp(t, low, high);
    }
  } // namespace

  void iterate_active_set(const std::size_t n_cells, const std::vector<unsigned char> &initial,
                          const unsigned int max_iterations, const double cell_stiffness, const std::string &solver,
                          const ActiveSetSolver &callbacks, WinklerGridSolution &result)
  {
    if (!initial.empty() && initial.size() != n_cells)
      throw std::invalid_argument(solver + ": the initial active set needs one entry per grid cell (" +
                                  std::to_string(n_cells) + "), got " + std::to_string(initial.size()));
    if (max_iterations == 0)
      throw std::invalid_argument(solver + ": at least one iteration is needed");
    std::vector<unsigned char> assumed(n_cells, 1);
    if (!initial.empty())
      std::transform(initial.begin(), initial.end(), assumed.begin(), [](unsigned char a) { return a ? 1 : 0; });

    std::vector<double> d = callbacks.solve(assumed);
    callbacks.accept(1.0);
    std::vector<double> alpha = coefficients(d, assumed, cell_stiffness);
    bool                full_step = true;
    for (unsigned int iteration = 1;; ++iteration)
      {
        std::vector<unsigned char> next(n_cells);
        std::size_t                changed = 0, count = 0;
        for (std::size_t c = 0; c < n_cells; ++c)
          {
            next[c] = d[c] > 0.0 ? 1 : 0;
            changed += next[c] != assumed[c];
            count += next[c];
          }
        if (full_step && changed == 0)
          {
            result.penetration  = std::move(d);
            result.active       = std::move(next);
            result.active_cells = count;
            result.iterations   = iteration;
            return;
          }
        if (iteration >= max_iterations)
          throw std::runtime_error(solver + ": the active set did not settle in " + std::to_string(max_iterations) +
                                   " solves (" + std::to_string(changed) + " of " + std::to_string(n_cells) +
                                   " cells still change)");
        assumed                               = std::move(next);
        const std::vector<double> d_new       = callbacks.solve(assumed);
        const std::vector<double> alpha_new   = coefficients(d_new, assumed, cell_stiffness);
        const double              t           = exact_step(d, alpha, d_new, alpha_new, cell_stiffness);
        full_step                             = t == 1.0;
        callbacks.accept(t);
        if (full_step)
          {
            d     = d_new;
            alpha = alpha_new;
          }
        else
          for (std::size_t c = 0; c < n_cells; ++c)
            {
              d[c] += t * (d_new[c] - d[c]);
              alpha[c] += t * (alpha_new[c] - alpha[c]);
            }
      }
  }

  double foundation_pressure(const double normal_stiffness, const double cell_stiffness, WinklerGridSolution &result)
  {
    const std::size_t cells = result.penetration.size();
    result.pressure.resize(cells);
    double energy = 0.0;
    for (std::size_t c = 0; c < cells; ++c)
      {
        const double d     = std::max(result.penetration[c], 0.0);
        result.pressure[c] = normal_stiffness * d;
        energy += 0.5 * cell_stiffness * d * d;
      }
    return energy;
  }
} // namespace fretsim::fem
