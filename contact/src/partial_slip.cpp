#include <fretsim/contact/partial_slip.h>

#include "tangential_operator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace fretsim::contact
{
  namespace
  {
    detail::TangentialKernel make_kernel(const SurfaceGrid &grid, const MaterialPair &materials)
    {
      if (grid.nx <= 0 || grid.ny <= 0 || !(grid.hx > 0.0) || !(grid.hy > 0.0))
        throw std::invalid_argument("partial slip: the grid is empty or has non-positive spacing");
      for (const ElasticMaterial *m : {&materials.lower, &materials.upper})
        if (!(m->youngs_modulus > 0.0) || !std::isfinite(m->youngs_modulus) || !(m->poisson_ratio > -1.0) ||
            !(m->poisson_ratio <= 0.5))
          throw std::invalid_argument("partial slip: Young's modulus must be positive and finite, Poisson's "
                                      "ratio in (-1, 0.5]");
      detail::TangentialKernel kernel;
      kernel.hx        = grid.hx;
      kernel.hy        = grid.hy;
      kernel.materials = materials;
      return kernel;
    }

    void check_field(const SurfaceGrid &grid, const Field &field, const char *what)
    {
      if (field.size() != grid.size())
        throw std::invalid_argument(std::string("partial slip: ") + what + " does not match the grid");
      for (const double value : field)
        if (!std::isfinite(value))
          throw std::invalid_argument(std::string("partial slip: ") + what + " must be finite");
    }
  } // namespace

  // ------------------------------------------------------------------ TangentialCompliance

  struct TangentialCompliance::Impl
  {
    SurfaceGrid                               grid;
    detail::TangentialKernel                  kernel;
    std::unique_ptr<detail::BlockConvolution> convolution;
  };

  TangentialCompliance::TangentialCompliance(const SurfaceGrid &grid, const MaterialPair &materials,
                                             bool measure_fft_plans)
    : impl(std::make_unique<Impl>())
  {
    impl->grid        = grid;
    impl->kernel      = make_kernel(grid, materials);
    impl->convolution = std::make_unique<detail::BlockConvolution>(grid.nx, grid.ny, impl->kernel, measure_fft_plans);
  }

  TangentialCompliance::~TangentialCompliance()                                       = default;
  TangentialCompliance::TangentialCompliance(TangentialCompliance &&) noexcept            = default;
  TangentialCompliance &TangentialCompliance::operator=(TangentialCompliance &&) noexcept = default;

  double TangentialCompliance::kernel_xx(int di, int dj) const { return impl->kernel.xx(di, dj); }
  double TangentialCompliance::kernel_xy(int di, int dj) const { return impl->kernel.xy(di, dj); }
  double TangentialCompliance::kernel_yy(int di, int dj) const { return impl->kernel.yy(di, dj); }

  void TangentialCompliance::apply(const Field &tau_x, const Field &tau_y, Field &u_x, Field &u_y) const
  {
    const SurfaceGrid &grid = impl->grid;
    check_field(grid, tau_x, "tau_x");
    check_field(grid, tau_y, "tau_y");
    auto &op = *impl->convolution;
    op.clear();
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        {
          op.input_x()[op.padded_index(i, j)] = tau_x[grid.index(i, j)];
          op.input_y()[op.padded_index(i, j)] = tau_y[grid.index(i, j)];
        }
    op.execute();
    u_x.resize(grid.size());
    u_y.resize(grid.size());
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        {
          u_x[grid.index(i, j)] = op.output_x()[op.padded_index(i, j)];
          u_y[grid.index(i, j)] = op.output_y()[op.padded_index(i, j)];
        }
  }

  void TangentialCompliance::apply_direct(const Field &tau_x, const Field &tau_y, Field &u_x, Field &u_y) const
  {
    const SurfaceGrid &grid = impl->grid;
    check_field(grid, tau_x, "tau_x");
    check_field(grid, tau_y, "tau_y");
    const int nx = grid.nx, ny = grid.ny, tx = 2 * nx - 1;
    std::vector<double> kxx(static_cast<std::size_t>(tx) * (2 * ny - 1)), kxy(kxx.size()), kyy(kxx.size());
    for (int dj = -(ny - 1); dj < ny; ++dj)
      for (int di = -(nx - 1); di < nx; ++di)
        {
          const std::size_t n = static_cast<std::size_t>(dj + ny - 1) * tx + (di + nx - 1);
          kxx[n]              = impl->kernel.xx(di, dj);
          kxy[n]              = impl->kernel.xy(di, dj);
          kyy[n]              = impl->kernel.yy(di, dj);
        }
    u_x.assign(grid.size(), 0.0);
    u_y.assign(grid.size(), 0.0);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        {
          double sx = 0.0, sy = 0.0;
          for (int jj = 0; jj < ny; ++jj)
            for (int ii = 0; ii < nx; ++ii)
              {
                const std::size_t n = static_cast<std::size_t>(j - jj + ny - 1) * tx + (i - ii + nx - 1);
                const double      a = tau_x[grid.index(ii, jj)], b = tau_y[grid.index(ii, jj)];
                sx += kxx[n] * a + kxy[n] * b;
                sy += kxy[n] * a + kyy[n] * b;
              }
          u_x[grid.index(i, j)] = sx;
          u_y[grid.index(i, j)] = sy;
        }
  }

  // ------------------------------------------------------------------ PartialSlipSolver

  struct PartialSlipSolver::Impl
  {
    SurfaceGrid              grid;
    PartialSlipSettings      settings;
    detail::TangentialKernel kernel;
    double                   self_compliance = 0.0; ///< C_xx(0, 0) [m/Pa]

    // DC-FFT operator on a window of the grid, rebuilt only when the loaded
    // cells outgrow it.
    std::unique_ptr<detail::BlockConvolution> convolution;
    int                                       window_i0 = 0, window_j0 = 0;

    // State: tractions of the last completed step on the whole grid, the
    // loaded cells of that step and the displacement w = C tau on them.
    Field                      tau_x, tau_y, slip_x, slip_y;
    std::vector<unsigned char> slip_mask;
    std::vector<std::size_t>   previous_cells;
    std::vector<double>        previous_wx, previous_wy;
    double                     total_shift_x = 0.0, total_shift_y = 0.0;
    std::size_t                loaded_cells = 0;
    PartialSlipStep            step;
    /// Secant stiffness of the last force-controlled step [N/m] (0: unknown).
    double                     force_stiffness = 0.0;
    /// The tractions before the last step and its uniform shift increment,
    /// for the extrapolated start (PartialSlipSettings::extrapolated_start).
    Field                      older_x, older_y;
    double                     last_shift_x = 0.0, last_shift_y = 0.0;
    bool                       have_older   = false;

    // The current step's problem on the list of loaded cells.
    struct Problem
    {
      std::vector<std::size_t>   cells;   ///< grid indices
      std::vector<std::size_t>   padded;  ///< index into the operator's padded arrays
      std::vector<double>        bound;   ///< g = mu p [Pa]
      std::vector<double>        base_x, base_y; ///< w^{n-1} = (C tau^{n-1}) on the cells [m]
      double                     bound_max = 0.0;
    } problem;

    /// The iterate of a displacement-controlled solve.
    struct Iterate
    {
      std::vector<double>        tx, ty; ///< traction [Pa]
      std::vector<double>        wx, wy; ///< C tau [m], exact for tx, ty
      std::vector<unsigned char> slipping;
      int                        iterations = 0, convolutions = 0;
      double                     residual = 0.0;
    };

    Impl(const SurfaceGrid &grid, const MaterialPair &materials, PartialSlipSettings settings)
      : grid(grid)
      , settings(settings)
      , kernel(make_kernel(grid, materials))
      , self_compliance(kernel.xx(0, 0))
    {
      if (!(settings.tolerance > 0.0) || settings.max_iterations <= 0 || !(settings.force_tolerance > 0.0) ||
          settings.max_force_iterations <= 0)
        throw std::invalid_argument("PartialSlipSolver: tolerances and iteration limits must be positive");
      reset();
    }

    void reset()
    {
      tau_x     = grid.zeros();
      tau_y     = grid.zeros();
      slip_x    = grid.zeros();
      slip_y    = grid.zeros();
      slip_mask.assign(grid.size(), 0);
      previous_cells.clear();
      previous_wx.clear();
      previous_wy.clear();
      total_shift_x = total_shift_y = 0.0;
      loaded_cells                  = 0;
      step                          = PartialSlipStep{};
      force_stiffness               = 0.0;
      have_older                    = false;
    }

    // ---- the operator on the loaded cells

    /// w = C tau for tau given on the cells of `problem` (others zero).
    void apply(const std::vector<double> &tx, const std::vector<double> &ty, std::vector<double> &wx,
               std::vector<double> &wy)
    {
      auto       &op = *convolution;
      const auto &pi = problem.padded;
      op.clear();
      double *in_x = op.input_x(), *in_y = op.input_y();
      for (std::size_t c = 0; c < pi.size(); ++c)
        {
          in_x[pi[c]] = tx[c];
          in_y[pi[c]] = ty[c];
        }
      op.execute();
      const double *out_x = op.output_x(), *out_y = op.output_y();
      wx.resize(pi.size());
      wy.resize(pi.size());
      for (std::size_t c = 0; c < pi.size(); ++c)
        {
          wx[c] = out_x[pi[c]];
          wy[c] = out_y[pi[c]];
        }
    }

    std::size_t padded_index(std::size_t cell) const
    {
      const int i = static_cast<int>(cell % grid.nx), j = static_cast<int>(cell / grid.nx);
      return convolution->padded_index(i - window_i0, j - window_j0);
    }

    /// Loaded cells, the window, and w^{n-1} on the loaded cells.
    void set_up_problem(const Field &pressure, double friction_coefficient)
    {
      check_field(grid, pressure, "pressure");
      if (!(friction_coefficient >= 0.0) || !std::isfinite(friction_coefficient))
        throw std::invalid_argument("partial slip: the friction coefficient must be non-negative and finite");
      Problem next;
      int     i_lo = grid.nx, i_hi = -1, j_lo = grid.ny, j_hi = -1;
      auto    extend = [&](std::size_t cell) {
        const int i = static_cast<int>(cell % grid.nx), j = static_cast<int>(cell / grid.nx);
        i_lo = std::min(i_lo, i), i_hi = std::max(i_hi, i);
        j_lo = std::min(j_lo, j), j_hi = std::max(j_hi, j);
      };
      for (std::size_t cell = 0; cell < grid.size(); ++cell)
        {
          const double g = friction_coefficient * pressure[cell];
          if (g > 0.0)
            {
              next.cells.push_back(cell);
              next.bound.push_back(g);
              next.bound_max = std::max(next.bound_max, g);
              extend(cell);
            }
        }
      // The window must also hold last step's tractions: their displacement
      // is part of w^{n-1} at the new cells.
      for (const std::size_t cell : previous_cells)
        extend(cell);
      const bool same_cells = next.cells == previous_cells;
      problem               = std::move(next);
      if (problem.cells.empty())
        return;

      const int wx = i_hi - i_lo + 1, wy = j_hi - j_lo + 1;
      if (!convolution || convolution->window_x() < wx || convolution->window_y() < wy)
        {
          const int mx = detail::fft_friendly_size(std::max(wx, convolution ? convolution->window_x() : 0));
          const int my = detail::fft_friendly_size(std::max(wy, convolution ? convolution->window_y() : 0));
          convolution  = std::make_unique<detail::BlockConvolution>(mx, my, kernel, settings.measure_fft_plans);
        }
      window_i0 = i_lo;
      window_j0 = j_lo;
      problem.padded.resize(problem.cells.size());
      for (std::size_t c = 0; c < problem.cells.size(); ++c)
        problem.padded[c] = padded_index(problem.cells[c]);

      if (same_cells)
        {
          problem.base_x = previous_wx;
          problem.base_y = previous_wy;
        }
      else
        {
          // w^{n-1} = C tau^{n-1} at the new cells, from last step's
          // tractions wherever they were (one product).
          auto       &op = *convolution;
          op.clear();
          for (const std::size_t cell : previous_cells)
            {
              op.input_x()[padded_index(cell)] = tau_x[cell];
              op.input_y()[padded_index(cell)] = tau_y[cell];
            }
          op.execute();
          problem.base_x.resize(problem.cells.size());
          problem.base_y.resize(problem.cells.size());
          for (std::size_t c = 0; c < problem.cells.size(); ++c)
            {
              problem.base_x[c] = op.output_x()[problem.padded[c]];
              problem.base_y[c] = op.output_y()[problem.padded[c]];
            }
        }
    }

    /// Initial iterate: last step's tractions (plus `ahead` times their change
    /// over the step before), projected onto the new discs.
    Iterate initial_iterate(double ahead = 0.0)
    {
      Iterate     it;
      const auto &cells = problem.cells;
      const std::size_t n = cells.size();
      it.tx.resize(n);
      it.ty.resize(n);
      it.slipping.assign(n, 0);
      bool unchanged = cells == previous_cells && ahead == 0.0;
      for (std::size_t c = 0; c < n; ++c)
        {
          double tx = tau_x[cells[c]], ty = tau_y[cells[c]];
          if (ahead != 0.0)
            {
              tx += ahead * (tau_x[cells[c]] - older_x[cells[c]]);
              ty += ahead * (tau_y[cells[c]] - older_y[cells[c]]);
            }
          const double g = problem.bound[c], magnitude = std::hypot(tx, ty);
          if (magnitude >= g * (1.0 - 1e-12))
            {
              if (magnitude > g)
                unchanged = false;
              tx = g * tx / magnitude;
              ty = g * ty / magnitude;
              it.slipping[c] = 1;
            }
          it.tx[c] = tx;
          it.ty[c] = ty;
        }
      if (unchanged)
        {
          it.wx = problem.base_x;
          it.wy = problem.base_y;
        }
      else
        {
          apply(it.tx, it.ty, it.wx, it.wy);
          ++it.convolutions;
        }
      return it;
    }

    /// Displacement control on the loaded cells: the right-hand side is
    /// b = d + w^{n-1}; iterate from `it` to convergence (the algorithm of
    /// partial_slip.h).
    void solve(const std::vector<double> &bx, const std::vector<double> &by, Iterate &it)
    {
      const std::size_t n = problem.cells.size();
      const auto       &g = problem.bound;
      std::vector<double> sx(n), sy(n), rx(n), ry(n), dx(n, 0.0), dy(n, 0.0), vx, vy, lambda(n, 0.0);
      std::vector<double> rx_old(n, 0.0), ry_old(n, 0.0);
      bool   restart  = true;
      double rr_old   = 0.0;
      // Skipping C of the retraction correction while it is below 1 % of the
      // step (measured: a third fewer products, no change in the result).
      const double inexact_ratio     = 1e-2;
      const int    max_inexact_steps = 20;
      int          inexact_steps     = 0;  ///< updates of C tau that skipped a correction
      bool         updated           = false; ///< C tau updated by recurrence since the last product
      for (int iteration = 0;; ++iteration)
        {
          // Micro-slip s = b - C tau, release slip cells whose slip points
          // into the disc, projected residual r.
          double rr = 0.0, error = 0.0;
          for (std::size_t c = 0; c < n; ++c)
            {
              sx[c] = bx[c] - it.wx[c];
              sy[c] = by[c] - it.wy[c];
              if (it.slipping[c])
                {
                  const double nx = it.tx[c] / g[c], ny = it.ty[c] / g[c];
                  lambda[c]       = sx[c] * nx + sy[c] * ny;
                  if (lambda[c] < 0.0)
                    {
                      it.slipping[c] = 0;
                      restart        = true;
                    }
                }
              if (it.slipping[c])
                {
                  const double tx = -it.ty[c] / g[c], ty = it.tx[c] / g[c]; // unit tangent
                  const double st = sx[c] * tx + sy[c] * ty;
                  rx[c]           = st * tx;
                  ry[c]           = st * ty;
                  // Traction error of a slip cell: the elastic estimate
                  // |s_t| / C_self, or the misalignment g |s_t| / |s| of tau
                  // with the slip, whichever is smaller (the second one
                  // matters for large slip increments).
                  const double misalignment = std::abs(st) / self_compliance;
                  const double e = std::min(misalignment, g[c] * std::abs(st) / std::max(lambda[c], std::abs(st)));
                  error += e * e;
                }
              else
                {
                  rx[c]     = sx[c];
                  ry[c]     = sy[c];
                  lambda[c] = 0.0;
                  error += (sx[c] * sx[c] + sy[c] * sy[c]) / (self_compliance * self_compliance);
                }
              rr += rx[c] * rx[c] + ry[c] * ry[c];
            }
          // Relative to the RMS traction of the iterate, so that small
          // shifts are solved to the same relative accuracy as large ones.
          double traction_squares = 0.0;
          for (std::size_t c = 0; c < n; ++c)
            traction_squares += it.tx[c] * it.tx[c] + it.ty[c] * it.ty[c];
          it.residual = error == 0.0 ? 0.0 : std::sqrt(error / traction_squares);
          if (it.residual <= settings.tolerance)
            {
              if (!updated)
                {
                  it.iterations += iteration;
                  return;
                }
              // Converged on an updated C tau: verify with the exact one
              // (which is also what the next step starts from).
              apply(it.tx, it.ty, it.wx, it.wy);
              ++it.convolutions;
              inexact_steps = 0;
              updated       = false;
              --iteration;
              continue;
            }
          if (iteration >= settings.max_iterations)
            {
              std::ostringstream message;
              message << "PartialSlipSolver: no convergence after " << iteration << " iterations (residual "
                      << it.residual << ", tolerance " << settings.tolerance << ")";
              throw std::runtime_error(message.str());
            }

          // Search direction: Polak–Ribière+ on the tangent space of the
          // current active set; steepest descent after an active-set change.
          double beta = 0.0;
          if (!restart && rr_old > 0.0)
            {
              double numerator = 0.0;
              for (std::size_t c = 0; c < n; ++c)
                numerator += rx[c] * (rx[c] - rx_old[c]) + ry[c] * (ry[c] - ry_old[c]);
              beta = std::max(0.0, numerator / rr_old);
            }
          restart = false;
          for (std::size_t c = 0; c < n; ++c)
            {
              double px = beta * dx[c], py = beta * dy[c];
              if (it.slipping[c])
                {
                  const double tx = -it.ty[c] / g[c], ty = it.tx[c] / g[c];
                  const double pt = px * tx + py * ty;
                  px              = pt * tx;
                  py              = pt * ty;
                }
              dx[c] = rx[c] + px;
              dy[c] = ry[c] + py;
            }
          rr_old = rr;
          rx_old = rx;
          ry_old = ry;
          double numerator = 0.0;
          for (std::size_t c = 0; c < n; ++c)
            numerator += rx[c] * dx[c] + ry[c] * dy[c];
          if (!(numerator > 0.0))
            {
              // Not a descent direction (the nonlinearity of the circles):
              // restart along the residual.
              dx        = rx;
              dy        = ry;
              numerator = rr;
            }

          // Exact line search on the quadratic model: the energy decreases by
          // alpha r.d - alpha^2/2 (d.Cd + sum_slip lambda/g |d|^2).
          apply(dx, dy, vx, vy);
          ++it.convolutions;
          double denominator = 0.0;
          for (std::size_t c = 0; c < n; ++c)
            {
              denominator += dx[c] * vx[c] + dy[c] * vy[c];
              if (it.slipping[c])
                denominator += lambda[c] / g[c] * (dx[c] * dx[c] + dy[c] * dy[c]);
            }
          const double alpha = numerator / denominator;
          if (!(alpha > 0.0) || !std::isfinite(alpha))
            throw std::runtime_error("PartialSlipSolver: the conjugate-gradient step is not positive and finite");

          // Step, retraction of slip cells onto their circle, projection of
          // stick cells that left their disc (they become slip cells).
          // The product C tau of the new iterate follows from C d by
          // linearity, up to C of the retraction correction, which is
          // second order in the step along the circle. It is skipped while
          // small (w is then inexact by that much, and is recomputed before
          // convergence is accepted and every few iterations); a projection
          // of a stick cell (first order) always recomputes it.
          bool   projected = false;
          double correction = 0.0, step_norm = 0.0;
          for (std::size_t c = 0; c < n; ++c)
            {
              const double step_x = alpha * dx[c], step_y = alpha * dy[c];
              double       tx = it.tx[c] + step_x, ty = it.ty[c] + step_y;
              const double magnitude = std::hypot(tx, ty);
              step_norm += step_x * step_x + step_y * step_y;
              if (it.slipping[c] || magnitude >= g[c])
                {
                  if (!it.slipping[c])
                    {
                      it.slipping[c] = 1;
                      restart        = true;
                      projected      = true;
                    }
                  const double shrink = g[c] / magnitude;
                  correction += (1.0 - shrink) * (1.0 - shrink) * magnitude * magnitude;
                  tx *= shrink;
                  ty *= shrink;
                }
              it.tx[c] = tx;
              it.ty[c] = ty;
            }
          if (!projected && correction <= inexact_ratio * inexact_ratio * step_norm &&
              inexact_steps < max_inexact_steps)
            {
              for (std::size_t c = 0; c < n; ++c)
                {
                  it.wx[c] += alpha * vx[c];
                  it.wy[c] += alpha * vy[c];
                }
              if (correction > 0.0)
                ++inexact_steps;
              updated = true;
            }
          else
            {
              apply(it.tx, it.ty, it.wx, it.wy);
              ++it.convolutions;
              inexact_steps = 0;
              updated       = false;
            }
        }
    }

    /// Store a converged iterate as the state of step n.
    void commit(const Iterate &it, const std::vector<double> &bx, const std::vector<double> &by)
    {
      const auto &cells = problem.cells;
      std::fill(slip_x.begin(), slip_x.end(), 0.0);
      std::fill(slip_y.begin(), slip_y.end(), 0.0);
      std::fill(tau_x.begin(), tau_x.end(), 0.0);
      std::fill(tau_y.begin(), tau_y.end(), 0.0);
      std::fill(slip_mask.begin(), slip_mask.end(), 0);
      double force_x = 0.0, force_y = 0.0, dissipation = 0.0;
      std::size_t slipping = 0;
      for (std::size_t c = 0; c < cells.size(); ++c)
        {
          const std::size_t cell = cells[c];
          tau_x[cell]            = it.tx[c];
          tau_y[cell]            = it.ty[c];
          const double sx = bx[c] - it.wx[c], sy = by[c] - it.wy[c];
          if (it.slipping[c])
            {
              slip_x[cell] = sx;
              slip_y[cell] = sy;
              dissipation += it.tx[c] * sx + it.ty[c] * sy;
              ++slipping;
            }
          slip_mask[cell] = it.slipping[c];
          force_x += it.tx[c];
          force_y += it.ty[c];
        }
      const double area = grid.cell_area();
      step.force_x      = force_x * area;
      step.force_y      = force_y * area;
      step.dissipation  = dissipation * area;
      step.slip_cells   = slipping;
      step.stick_cells  = cells.size() - slipping;
      step.residual     = it.residual;
      loaded_cells      = cells.size();
      previous_cells    = cells;
      previous_wx       = it.wx;
      previous_wy       = it.wy;
    }

    /// Tractions vanish: no load or no friction.
    void commit_unloaded()
    {
      have_older = false;
      std::fill(tau_x.begin(), tau_x.end(), 0.0);
      std::fill(tau_y.begin(), tau_y.end(), 0.0);
      std::fill(slip_x.begin(), slip_x.end(), 0.0);
      std::fill(slip_y.begin(), slip_y.end(), 0.0);
      std::fill(slip_mask.begin(), slip_mask.end(), 0);
      previous_cells.clear();
      previous_wx.clear();
      previous_wy.clear();
      loaded_cells = 0;
      step.force_x = step.force_y = step.dissipation = step.residual = 0.0;
      step.stick_cells = step.slip_cells = 0;
    }

    void right_hand_side(double shift_x, double shift_y, const Field *field_x, const Field *field_y,
                         std::vector<double> &bx, std::vector<double> &by) const
    {
      const std::size_t n = problem.cells.size();
      bx.resize(n);
      by.resize(n);
      for (std::size_t c = 0; c < n; ++c)
        {
          bx[c] = problem.base_x[c] + (field_x ? (*field_x)[problem.cells[c]] : shift_x);
          by[c] = problem.base_y[c] + (field_y ? (*field_y)[problem.cells[c]] : shift_y);
        }
    }

    void displacement_step(const Field &pressure, double mu, double shift_x, double shift_y, const Field *field_x,
                           const Field *field_y)
    {
      if (!std::isfinite(shift_x) || !std::isfinite(shift_y))
        throw std::invalid_argument("PartialSlipSolver::advance: the shift increment must be finite");
      if (field_x)
        {
          check_field(grid, *field_x, "shift_x");
          check_field(grid, *field_y, "shift_y");
        }
      set_up_problem(pressure, mu);
      step                   = PartialSlipStep{};
      step.shift_x_increment = shift_x;
      step.shift_y_increment = shift_y;
      step.force_iterations  = 1;
      if (problem.cells.empty())
        commit_unloaded();
      else
        {
          std::vector<double> bx, by;
          right_hand_side(shift_x, shift_y, field_x, field_y, bx, by);
          // A uniform shift continuing along the last one on the same cells:
          // the tractions change nearly as over the last step, so the start
          // goes that change ahead, scaled to the increment.
          double     ahead = 0.0;
          const bool extrapolate =
            settings.extrapolated_start && !field_x && have_older && problem.cells == previous_cells;
          if (extrapolate)
            {
              const double last  = last_shift_x * last_shift_x + last_shift_y * last_shift_y;
              const double along = shift_x * last_shift_x + shift_y * last_shift_y;
              const double cross = shift_x * last_shift_y - shift_y * last_shift_x;
              if (last > 0.0 && along > 0.0 && std::abs(cross) <= 1e-9 * along)
                ahead = along / last;
            }
          Iterate it = initial_iterate(ahead);
          solve(bx, by, it);
          step.iterations   = it.iterations;
          step.convolutions = it.convolutions;
          if (settings.extrapolated_start)
            {
              older_x = tau_x;
              older_y = tau_y;
            }
          commit(it, bx, by);
          have_older   = settings.extrapolated_start && !field_x;
          last_shift_x = shift_x;
          last_shift_y = shift_y;
        }
      // Only a completed step moves the shift (a throw leaves the state).
      total_shift_x += shift_x;
      total_shift_y += shift_y;
    }

    void force_step(const Field &pressure, double mu, double target_x, double target_y)
    {
      have_older = false;
      if (!std::isfinite(target_x) || !std::isfinite(target_y))
        throw std::invalid_argument("PartialSlipSolver::advance_to_force: the force must be finite");
      set_up_problem(pressure, mu);
      double friction_limit = 0.0;
      for (const double g : problem.bound)
        friction_limit += g;
      friction_limit *= grid.cell_area();
      const double target = std::hypot(target_x, target_y);
      if (target == 0.0 && problem.cells.empty())
        {
          step                  = PartialSlipStep{};
          step.force_iterations = 0;
          commit_unloaded();
          return;
        }
      if (!(target < friction_limit))
        {
          std::ostringstream message;
          message << "PartialSlipSolver::advance_to_force: |Q| = " << target << " N is not below the friction limit "
                  << "mu sum(p A) = " << friction_limit << " N; the shift is undetermined in gross slip";
          throw std::invalid_argument(message.str());
        }

      step = PartialSlipStep{};
      const double area = grid.cell_area();
      // Initial tangent stiffness: last secant, else the compliance of a
      // uniform traction over the loaded cells (a lower bound on the
      // full-stick stiffness, so the first trial undershoots).
      Iterate start = initial_iterate();
      step.convolutions += start.convolutions;
      start.convolutions = 0;
      double  k0    = force_stiffness;
      if (!(k0 > 0.0))
        {
          std::vector<double> ones(problem.cells.size(), 1.0), zeros(problem.cells.size(), 0.0), ux, uy;
          apply(ones, zeros, ux, uy);
          ++step.convolutions;
          double mean = 0.0;
          for (const double u : ux)
            mean += u;
          mean /= static_cast<double>(ux.size());
          k0 = static_cast<double>(ux.size()) * area / mean;
        }
      // Broyden's method on F(d) = Q(d) - Q_target, d the uniform shift
      // increment; J ~ dQ/dd starts as k0 I.
      double J[2][2] = {{k0, 0.0}, {0.0, k0}};
      double d[2] = {0.0, 0.0}, F[2], F_previous[2], d_previous[2];
      double force_previous[2] = {0.0, 0.0};
      for (const std::size_t cell : previous_cells)
        force_previous[0] += tau_x[cell] * area, force_previous[1] += tau_y[cell] * area;
      F[0] = force_previous[0] - target_x;
      F[1] = force_previous[1] - target_y;
      // The previous force is Q(0) only if the pressure did not change; the
      // first trial uses it only for its direction and size.
      Iterate             it = std::move(start);
      std::vector<double> bx, by;
      const double        tolerance = settings.force_tolerance * friction_limit;
      bool                have_previous = false;
      for (int trial = 1;; ++trial)
        {
          const double det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
          double       step_x = -(J[1][1] * F[0] - J[0][1] * F[1]) / det;
          double       step_y = -(-J[1][0] * F[0] + J[0][0] * F[1]) / det;
          if (!std::isfinite(step_x) || !std::isfinite(step_y))
            throw std::runtime_error("PartialSlipSolver::advance_to_force: singular force-displacement Jacobian");
          d_previous[0] = d[0], d_previous[1] = d[1];
          F_previous[0] = F[0], F_previous[1] = F[1];
          double new_F[2] = {0.0, 0.0};
          for (int halving = 0;; ++halving)
            {
              d[0] = d_previous[0] + step_x;
              d[1] = d_previous[1] + step_y;
              right_hand_side(d[0], d[1], nullptr, nullptr, bx, by);
              Iterate candidate      = it;
              candidate.iterations   = 0;
              candidate.convolutions = 0;
              solve(bx, by, candidate);
              step.iterations += candidate.iterations;
              step.convolutions += candidate.convolutions;
              double qx = 0.0, qy = 0.0;
              for (std::size_t c = 0; c < candidate.tx.size(); ++c)
                qx += candidate.tx[c], qy += candidate.ty[c];
              new_F[0] = qx * area - target_x;
              new_F[1] = qy * area - target_y;
              // Backtrack if a trial overshot far into the flat gross-slip
              // part of Q(d), where the secant information is useless.
              if (!have_previous || std::hypot(new_F[0], new_F[1]) < std::hypot(F_previous[0], F_previous[1]) ||
                  halving >= 20)
                {
                  it = std::move(candidate);
                  break;
                }
              step_x *= 0.5;
              step_y *= 0.5;
            }
          F[0] = new_F[0], F[1] = new_F[1];
          step.force_iterations = trial;
          if (std::hypot(F[0], F[1]) <= tolerance)
            break;
          if (trial >= settings.max_force_iterations)
            {
              std::ostringstream message;
              message << "PartialSlipSolver::advance_to_force: no convergence after " << trial
                      << " solves (force error " << std::hypot(F[0], F[1]) << " N)";
              throw std::runtime_error(message.str());
            }
          if (have_previous)
            {
              // Broyden update J += (dF - J dd) dd^T / |dd|^2 (the first
              // trial has no exact F(0) to difference against).
              const double dd[2] = {d[0] - d_previous[0], d[1] - d_previous[1]};
              const double dF[2] = {F[0] - F_previous[0], F[1] - F_previous[1]};
              const double norm  = dd[0] * dd[0] + dd[1] * dd[1];
              if (norm > 0.0)
                for (int a = 0; a < 2; ++a)
                  {
                    const double mismatch = dF[a] - (J[a][0] * dd[0] + J[a][1] * dd[1]);
                    for (int b = 0; b < 2; ++b)
                      J[a][b] += mismatch * dd[b] / norm;
                  }
            }
          have_previous = true;
        }
      step.residual          = it.residual;
      step.shift_x_increment = d[0];
      step.shift_y_increment = d[1];
      total_shift_x += d[0];
      total_shift_y += d[1];
      const double shift = std::hypot(d[0], d[1]);
      if (shift > 0.0)
        {
          const double change = std::hypot(F[0] + target_x - force_previous[0], F[1] + target_y - force_previous[1]);
          if (change > 0.0)
            force_stiffness = change / shift;
        }
      commit(it, bx, by);
    }
  };

  PartialSlipSolver::PartialSlipSolver(const SurfaceGrid &grid, const MaterialPair &materials,
                                       PartialSlipSettings settings)
    : impl(std::make_unique<Impl>(grid, materials, settings))
  {
  }

  PartialSlipSolver::~PartialSlipSolver()                                    = default;
  PartialSlipSolver::PartialSlipSolver(PartialSlipSolver &&) noexcept            = default;
  PartialSlipSolver &PartialSlipSolver::operator=(PartialSlipSolver &&) noexcept = default;

  const PartialSlipStep &PartialSlipSolver::advance(const Field &pressure, double friction_coefficient,
                                                    double shift_x, double shift_y)
  {
    impl->displacement_step(pressure, friction_coefficient, shift_x, shift_y, nullptr, nullptr);
    return impl->step;
  }

  const PartialSlipStep &PartialSlipSolver::advance(const Field &pressure, double friction_coefficient,
                                                    const Field &shift_x, const Field &shift_y)
  {
    impl->displacement_step(pressure, friction_coefficient, 0.0, 0.0, &shift_x, &shift_y);
    return impl->step;
  }

  const PartialSlipStep &PartialSlipSolver::advance_to_force(const Field &pressure, double friction_coefficient,
                                                             double force_x, double force_y)
  {
    impl->force_step(pressure, friction_coefficient, force_x, force_y);
    return impl->step;
  }

  void PartialSlipSolver::reset() { impl->reset(); }

  const Field &PartialSlipSolver::traction_x() const { return impl->tau_x; }
  const Field &PartialSlipSolver::traction_y() const { return impl->tau_y; }
  const Field &PartialSlipSolver::slip_increment_x() const { return impl->slip_x; }
  const Field &PartialSlipSolver::slip_increment_y() const { return impl->slip_y; }
  const std::vector<unsigned char> &PartialSlipSolver::slip_mask() const { return impl->slip_mask; }
  double PartialSlipSolver::shift_x() const { return impl->total_shift_x; }
  double PartialSlipSolver::shift_y() const { return impl->total_shift_y; }
  const PartialSlipStep &PartialSlipSolver::last_step() const { return impl->step; }
  const SurfaceGrid     &PartialSlipSolver::grid() const { return impl->grid; }

  Field PartialSlipSolver::effective_friction() const
  {
    Field       ratio = impl->grid.zeros();
    const auto &cells = impl->previous_cells;
    for (std::size_t c = 0; c < cells.size(); ++c)
      {
        const std::size_t cell = cells[c];
        ratio[cell] = impl->slip_mask[cell]
                        ? 1.0
                        : std::min(1.0, std::hypot(impl->tau_x[cell], impl->tau_y[cell]) / impl->problem.bound[c]);
      }
    return ratio;
  }

  double PartialSlipSolver::slip_area_fraction() const
  {
    if (impl->loaded_cells == 0)
      return 0.0;
    return static_cast<double>(impl->step.slip_cells) / static_cast<double>(impl->loaded_cells);
  }
} // namespace fretsim::contact
