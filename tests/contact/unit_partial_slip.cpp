// The exact partial-slip solver (partial_slip.h) on small grids: the block
// DC-FFT operator against direct summation, the solution of each load step
// against an independent dense solver (accelerated projected gradient on the
// same quadratic program with the compliance matrix written out), the
// complementarity conditions checked directly, and extreme inputs.
#include <fretsim/contact/material.h>
#include <fretsim/contact/mindlin.h>
#include <fretsim/contact/partial_slip.h>
#include <fretsim/contact/rectangle_kernels.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

using namespace fretsim::contact;

namespace
{
  const double       mu = 0.53, load = 1250.0, radius = 0.05;
  const MaterialPair steel{{200e9, 0.3}, {200e9, 0.3}};
  const MaterialPair steel_on_aluminium{{200e9, 0.3}, {70e9, 0.33}};

  struct Contact
  {
    SurfaceGrid grid;
    double      a = 0.0, p0 = 0.0, delta_t = 0.0;

    /// Hertz pressure at cell centres with the centre at (xc, 0).
    Field pressure(double xc = 0.0) const
    {
      Field p = grid.zeros();
      for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i)
          {
            const double r2 = (std::pow(grid.x(i) - xc, 2) + std::pow(grid.y(j), 2)) / (a * a);
            p[grid.index(i, j)] = p0 * std::sqrt(std::max(0.0, 1.0 - r2));
          }
      return p;
    }
  };

  Contact hertz_contact(int cells, const MaterialPair &materials)
  {
    Contact c;
    c.a       = std::cbrt(3.0 * load * radius / (4.0 * materials.contact_modulus()));
    c.p0      = 3.0 * load / (2.0 * M_PI * c.a * c.a);
    c.grid    = SurfaceGrid::centred(cells, cells, 1.5 * c.a, 1.5 * c.a);
    c.delta_t = MindlinLoop(mu, load, c.a, materials.tangential_modulus()).gross_slip_displacement();
    return c;
  }

  /// Independent reference: the step's quadratic program
  ///   min 1/2 t^T C t - b^T t,  |t_i| <= g_i,  b = d + C t_prev,
  /// with C written out as a dense matrix over the whole grid, solved by FISTA
  /// with adaptive restart and projection onto the discs, to round-off.
  class DenseReference
  {
  public:
    DenseReference(const SurfaceGrid &grid, const MaterialPair &materials)
      : grid(grid)
      , n(grid.size())
      , matrix(4 * n * n)
      , tau(2 * n, 0.0)
    {
      const TangentialCompliance compliance(grid, materials);
      const int                  wx = 2 * grid.nx - 1, wy = 2 * grid.ny - 1;
      std::vector<double>        kxx(wx * wy), kxy(wx * wy), kyy(wx * wy);
      for (int dj = 1 - grid.ny; dj < grid.ny; ++dj)
        for (int di = 1 - grid.nx; di < grid.nx; ++di)
          {
            const int k = (dj + grid.ny - 1) * wx + di + grid.nx - 1;
            kxx[k]      = compliance.kernel_xx(di, dj);
            kxy[k]      = compliance.kernel_xy(di, dj);
            kyy[k]      = compliance.kernel_yy(di, dj);
          }
      for (std::size_t a = 0; a < n; ++a)
        for (std::size_t b = 0; b < n; ++b)
          {
            const int di = static_cast<int>(a % grid.nx) - static_cast<int>(b % grid.nx);
            const int dj = static_cast<int>(a / grid.nx) - static_cast<int>(b / grid.nx);
            const int k  = (dj + grid.ny - 1) * wx + di + grid.nx - 1;
            entry(2 * a, 2 * b)         = kxx[k];
            entry(2 * a, 2 * b + 1)     = kxy[k];
            entry(2 * a + 1, 2 * b)     = kxy[k];
            entry(2 * a + 1, 2 * b + 1) = kyy[k];
          }
      // Lipschitz constant: the largest absolute row sum bounds lambda_max.
      for (std::size_t r = 0; r < 2 * n; ++r)
        {
          double sum = 0.0;
          for (std::size_t c = 0; c < 2 * n; ++c)
            sum += std::abs(entry(r, c));
          lipschitz = std::max(lipschitz, sum);
        }
    }

    /// One step; shift_x/y per cell.
    void advance(const Field &pressure, const Field &shift_x, const Field &shift_y)
    {
      std::vector<double> bound(n), b = product(tau);
      double              bound_max = 0.0;
      for (std::size_t c = 0; c < n; ++c)
        {
          bound[c] = mu * pressure[c];
          bound_max = std::max(bound_max, bound[c]);
          b[2 * c] += shift_x[c];
          b[2 * c + 1] += shift_y[c];
        }
      auto project = [&](std::vector<double> &t) {
        for (std::size_t c = 0; c < n; ++c)
          {
            const double magnitude = std::hypot(t[2 * c], t[2 * c + 1]);
            if (magnitude > bound[c])
              {
                const double scale = bound[c] > 0.0 ? bound[c] / magnitude : 0.0;
                t[2 * c] *= scale;
                t[2 * c + 1] *= scale;
              }
          }
      };
      std::vector<double> x = tau, x_old = tau, y = tau;
      project(x);
      x_old = y = x;
      double momentum = 1.0;
      for (int k = 0; k < 200000; ++k)
        {
          const auto gradient = product(y);
          for (std::size_t r = 0; r < 2 * n; ++r)
            x[r] = y[r] - (gradient[r] - b[r]) / lipschitz;
          project(x);
          double change = 0.0, restart = 0.0;
          for (std::size_t r = 0; r < 2 * n; ++r)
            {
              change = std::max(change, std::abs(x[r] - x_old[r]));
              restart += (gradient[r] - b[r]) * (x[r] - x_old[r]);
            }
          if (change < 1e-15 * bound_max && k > 10)
            break;
          const double next = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * momentum * momentum));
          const double beta = restart > 0.0 ? 0.0 : (momentum - 1.0) / next;
          momentum          = restart > 0.0 ? 1.0 : next;
          for (std::size_t r = 0; r < 2 * n; ++r)
            y[r] = x[r] + beta * (x[r] - x_old[r]);
          x_old = x;
        }
      tau = x;
    }

    double traction_x(std::size_t c) const { return tau[2 * c]; }
    double traction_y(std::size_t c) const { return tau[2 * c + 1]; }

  private:
    double &entry(std::size_t r, std::size_t c) { return matrix[r * 2 * n + c]; }
    std::vector<double> product(const std::vector<double> &t) const
    {
      std::vector<double> result(2 * n, 0.0);
      for (std::size_t r = 0; r < 2 * n; ++r)
        {
          double sum = 0.0;
          for (std::size_t c = 0; c < 2 * n; ++c)
            sum += matrix[r * 2 * n + c] * t[c];
          result[r] = sum;
        }
      return result;
    }

    SurfaceGrid         grid;
    std::size_t         n;
    std::vector<double> matrix;
    std::vector<double> tau;
    double              lipschitz = 0.0;
  };

  /// Largest |tau - tau_ref| over the grid.
  double difference(const PartialSlipSolver &solver, const DenseReference &reference)
  {
    double worst = 0.0;
    for (std::size_t c = 0; c < solver.grid().size(); ++c)
      worst = std::max(worst, std::hypot(solver.traction_x()[c] - reference.traction_x(c),
                                         solver.traction_y()[c] - reference.traction_y(c)));
    return worst;
  }

  /// Complementarity of the last step, checked from the solver's own output:
  /// returns the worst violation relative to the scales mu p0 (tractions) and
  /// C_self mu p0 (slip).
  double complementarity_violation(const PartialSlipSolver &solver, const Field &pressure, double slip_scale,
                                   double traction_scale)
  {
    double worst = 0.0;
    for (std::size_t c = 0; c < pressure.size(); ++c)
      {
        const double tx = solver.traction_x()[c], ty = solver.traction_y()[c];
        const double sx = solver.slip_increment_x()[c], sy = solver.slip_increment_y()[c];
        const double g = mu * pressure[c], magnitude = std::hypot(tx, ty);
        if (!(g > 0.0))
          {
            worst = std::max(worst, magnitude / traction_scale); // no traction without load
            continue;
          }
        worst = std::max(worst, (magnitude - g) / traction_scale); // inside the disc
        if (solver.slip_mask()[c])
          {
            worst = std::max(worst, std::abs(magnitude - g) / traction_scale);      // on the circle
            worst = std::max(worst, -(sx * tx + sy * ty) / (g * slip_scale));      // slip along tau
            worst = std::max(worst, std::abs(sx * ty - sy * tx) / (g * slip_scale)); // not across it
          }
        else
          worst = std::max(worst, std::hypot(sx, sy) / slip_scale); // reported slip of stick cells is 0
      }
    return worst;
  }
} // namespace

TEST(PartialSlipOperator, DcFftEqualsDirectSummation)
{
  // Dissimilar materials, rectangular cells, random tractions: exact to
  // round-off (DC-FFT is a linear, not a periodic, convolution).
  const SurfaceGrid          grid = SurfaceGrid::centred(13, 9, 1e-3, 0.4e-3);
  const TangentialCompliance compliance(grid, steel_on_aluminium);
  std::mt19937               random(5);
  std::uniform_real_distribution<double> traction(-1e8, 1e8);
  Field tx(grid.size()), ty(grid.size()), ux, uy, vx, vy;
  for (auto &t : tx)
    t = traction(random);
  for (auto &t : ty)
    t = traction(random);
  compliance.apply(tx, ty, ux, uy);
  compliance.apply_direct(tx, ty, vx, vy);
  double scale = 0.0, error = 0.0;
  for (std::size_t c = 0; c < grid.size(); ++c)
    {
      scale = std::max({scale, std::abs(vx[c]), std::abs(vy[c])});
      error = std::max({error, std::abs(ux[c] - vx[c]), std::abs(uy[c] - vy[c])});
    }
  EXPECT_LT(error / scale, 1e-12);

  // Symmetric block operator (Betti): <a, C b> = <C a, b>.
  Field ax(grid.size()), ay(grid.size());
  for (auto &t : ax)
    t = traction(random);
  for (auto &t : ay)
    t = traction(random);
  Field cax, cay;
  compliance.apply(ax, ay, cax, cay);
  double left = 0.0, right = 0.0;
  for (std::size_t c = 0; c < grid.size(); ++c)
    {
      left += ax[c] * ux[c] + ay[c] * uy[c];
      right += cax[c] * tx[c] + cay[c] * ty[c];
    }
  EXPECT_NEAR(left / right, 1.0, 1e-12);
}

TEST(PartialSlipOperator, KernelIsTheSumOfBothBodiesCerrutiCoefficients)
{
  const SurfaceGrid          grid = SurfaceGrid::centred(8, 8, 1e-3, 1e-3);
  const TangentialCompliance compliance(grid, steel_on_aluminium);
  const auto                &l = steel_on_aluminium.lower, &u = steel_on_aluminium.upper;
  for (const auto &[di, dj] : std::vector<std::pair<int, int>>{{0, 0}, {1, 0}, {2, 3}, {-3, 1}, {5, -7}})
    {
      const double x = di * grid.hx, y = dj * grid.hy, hx = 0.5 * grid.hx, hy = 0.5 * grid.hy;
      const auto   lx = rectangle_displacement_shear_x(x, y, hx, hy, l.shear_modulus(), l.poisson_ratio);
      const auto   ux = rectangle_displacement_shear_x(x, y, hx, hy, u.shear_modulus(), u.poisson_ratio);
      const auto   ly = rectangle_displacement_shear_y(x, y, hx, hy, l.shear_modulus(), l.poisson_ratio);
      const auto   uy = rectangle_displacement_shear_y(x, y, hx, hy, u.shear_modulus(), u.poisson_ratio);
      EXPECT_DOUBLE_EQ(compliance.kernel_xx(di, dj), lx.x + ux.x);
      EXPECT_DOUBLE_EQ(compliance.kernel_xy(di, dj), lx.y + ux.y);
      EXPECT_NEAR(compliance.kernel_xy(di, dj), ly.x + uy.x, 1e-12 * compliance.kernel_xx(0, 0));
      EXPECT_DOUBLE_EQ(compliance.kernel_yy(di, dj), ly.y + uy.y);
      // Even in the offset: the DC-FFT kernels have real transforms.
      EXPECT_NEAR(compliance.kernel_xy(-di, -dj), compliance.kernel_xy(di, dj), 1e-14 * compliance.kernel_xx(0, 0));
    }
  // Self-compliance of a square cell, per body (docs/references.md §4.1):
  // u_x = (1/(2 pi G)) ((1-nu) + 1) [F1]/2 ... with [F1] = 4h ln(1+sqrt 2) for
  // both terms at the centre: u_x = (2 - nu) 4h ln(1 + sqrt 2) / (4 pi G).
  const double h = grid.hx, f1 = 4.0 * h * std::log(1.0 + std::sqrt(2.0));
  const double expected = (2.0 - l.poisson_ratio) * f1 / (4.0 * M_PI * l.shear_modulus()) +
                          (2.0 - u.poisson_ratio) * f1 / (4.0 * M_PI * u.shear_modulus());
  EXPECT_NEAR(compliance.kernel_xx(0, 0) / expected, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(compliance.kernel_xy(0, 0), 0.0);
}

TEST(PartialSlipSolver, MatchesDenseReferenceOnARotatingShiftPath)
{
  // An elliptical shift path turns the slip direction through every angle:
  // the disc constraint, not a box. nu = 0.3 couples x and y.
  for (const MaterialPair &materials : {steel, steel_on_aluminium})
    {
      const Contact       c = hertz_contact(16, materials);
      const Field         p = c.pressure();
      PartialSlipSettings settings;
      settings.tolerance = 1e-12;
      PartialSlipSolver solver(c.grid, materials, settings);
      DenseReference    reference(c.grid, materials);
      const double      amplitude = 0.6 * c.delta_t, traction_scale = mu * c.p0;
      const TangentialCompliance compliance(c.grid, materials);
      const double slip_scale = compliance.kernel_xx(0, 0) * traction_scale;
      double       previous_x = 0.0, previous_y = 0.0;
      for (int step = 1; step <= 10; ++step)
        {
          const double phase = 2.0 * M_PI * step / 8.0;
          const double sx = amplitude * std::sin(phase), sy = 0.7 * amplitude * (1.0 - std::cos(phase));
          const auto  &result = solver.advance(p, mu, sx - previous_x, sy - previous_y);
          reference.advance(p, Field(p.size(), sx - previous_x), Field(p.size(), sy - previous_y));
          previous_x = sx, previous_y = sy;
          // The two solvers share only the influence coefficients; both are
          // converged to round-off, so they agree to round-off amplified by
          // the conditioning (measured 5e-12).
          EXPECT_LT(difference(solver, reference) / traction_scale, 1e-8) << "step " << step;
          EXPECT_LT(complementarity_violation(solver, p, slip_scale, traction_scale), 1e-9) << "step " << step;
          EXPECT_GE(result.dissipation, 0.0);
          EXPECT_GT(result.slip_cells, 0u);
        }
    }
}

TEST(PartialSlipSolver, MatchesDenseReferenceForTorsionAndAMovingContact)
{
  const Contact       c = hertz_contact(16, steel);
  PartialSlipSettings settings;
  settings.tolerance = 1e-12;
  PartialSlipSolver solver(c.grid, steel, settings);
  DenseReference    reference(c.grid, steel);
  const double      traction_scale = mu * c.p0;
  // Torsion: a per-cell shift of a small rigid rotation, loading and back.
  for (int step = 1; step <= 8; ++step)
    {
      const double angle = (step <= 4 ? 1.0 : -1.0) * 0.3 * c.delta_t / c.a;
      Field        dx(c.grid.size()), dy(c.grid.size());
      for (int j = 0; j < c.grid.ny; ++j)
        for (int i = 0; i < c.grid.nx; ++i)
          {
            dx[c.grid.index(i, j)] = -angle * c.grid.y(j);
            dy[c.grid.index(i, j)] = angle * c.grid.x(i);
          }
      const Field p = c.pressure();
      solver.advance(p, mu, dx, dy);
      reference.advance(p, dx, dy);
      EXPECT_LT(difference(solver, reference) / traction_scale, 1e-8) << "torsion step " << step;
    }
  // The contact moves by 0.4 cells a step while the shift grows: cells enter
  // and leave the contact, and the pressure under each cell changes.
  for (int step = 1; step <= 8; ++step)
    {
      const Field p = c.pressure(0.4 * step * c.grid.hx);
      const Field dx(c.grid.size(), 0.1 * c.delta_t), dy(c.grid.size(), 0.0);
      solver.advance(p, mu, dx, dy);
      reference.advance(p, dx, dy);
      EXPECT_LT(difference(solver, reference) / traction_scale, 1e-8) << "moving step " << step;
    }
}

TEST(PartialSlipSolver, FullStickIsLinearAndForceControlInvertsDisplacementControl)
{
  const Contact c = hertz_contact(24, steel);
  const Field   p = c.pressure();
  // A tiny shift sticks everywhere except the edge cells, whose bound mu p
  // is tiny too; doubling it doubles the interior traction.
  PartialSlipSolver small(c.grid, steel), twice(c.grid, steel);
  small.advance(p, mu, 1e-6 * c.delta_t, 0.0);
  twice.advance(p, mu, 2e-6 * c.delta_t, 0.0);
  const std::size_t centre = c.grid.index(12, 12);
  EXPECT_NEAR(twice.traction_x()[centre] / small.traction_x()[centre], 2.0, 1e-6);

  // Force control returns the shift that displacement control needs for
  // the same force, and the same tractions.
  PartialSlipSolver by_force(c.grid, steel), by_shift(c.grid, steel);
  const auto       &forced = by_force.advance_to_force(p, mu, 0.5 * mu * integrate(c.grid, p), 0.1 * mu * integrate(c.grid, p));
  const auto       &shifted = by_shift.advance(p, mu, forced.shift_x_increment, forced.shift_y_increment);
  EXPECT_NEAR(shifted.force_x / forced.force_x, 1.0, 1e-7);
  EXPECT_NEAR(shifted.force_y / forced.force_y, 1.0, 1e-6);
  EXPECT_NEAR(by_force.traction_x()[centre] / by_shift.traction_x()[centre], 1.0, 1e-6);
  EXPECT_GE(forced.force_iterations, 2);
  EXPECT_LE(forced.force_iterations, 20);
}

TEST(PartialSlipSolver, ExtremeInputsStayFiniteAndBounded)
{
  const Contact c = hertz_contact(24, steel);
  const Field   p = c.pressure();
  auto          check_bounded = [&](const PartialSlipSolver &solver, const Field &pressure, double friction) {
    for (std::size_t cell = 0; cell < pressure.size(); ++cell)
      {
        const double magnitude = std::hypot(solver.traction_x()[cell], solver.traction_y()[cell]);
        ASSERT_TRUE(std::isfinite(magnitude));
        ASSERT_LE(magnitude, friction * pressure[cell] * (1.0 + 1e-12));
      }
  };
  PartialSlipSolver solver(c.grid, steel);
  // No shift: no iteration, no traction.
  EXPECT_EQ(solver.advance(p, mu, 0.0, 0.0).iterations, 0);
  EXPECT_EQ(integrate(c.grid, solver.traction_x()), 0.0);
  // A huge shift (1 m): gross slip at every loaded cell, |Q| = mu P.
  const auto &huge = solver.advance(p, mu, 1.0, 0.0);
  check_bounded(solver, p, mu);
  EXPECT_NEAR(huge.force_x / (mu * integrate(c.grid, p)), 1.0, 1e-9);
  EXPECT_DOUBLE_EQ(solver.slip_area_fraction(), 1.0);
  // Then back by a tiny amount: every cell sticks again except where mu p
  // is smallest.
  solver.advance(p, mu, -1e-3 * c.delta_t, 0.0);
  check_bounded(solver, p, mu);
  EXPECT_LT(solver.slip_area_fraction(), 0.5);
  // The pressure halves: the stored traction is clamped to the new bound.
  Field half = p;
  for (auto &value : half)
    value *= 0.5;
  solver.advance(half, mu, 0.0, 0.0);
  check_bounded(solver, half, mu);
  // mu = 1.5 and mu = 0.
  solver.advance(p, 1.5, 0.5 * c.delta_t, 0.0);
  check_bounded(solver, p, 1.5);
  solver.advance(p, 0.0, 0.5 * c.delta_t, 0.0);
  check_bounded(solver, p, 0.0);
  EXPECT_EQ(solver.slip_area_fraction(), 0.0);
  // No load at all.
  solver.advance(c.grid.zeros(), mu, c.delta_t, 0.0);
  check_bounded(solver, c.grid.zeros(), mu);
  // One cell.
  PartialSlipSolver single(SurfaceGrid::centred(1, 1, 1e-4, 1e-4), steel);
  single.advance(Field{1e9}, mu, 1e-9, 0.0);
  EXPECT_GT(single.traction_x()[0], 0.0);
  EXPECT_LE(single.traction_x()[0], mu * 1e9);
}

TEST(PartialSlipSolver, RejectsBadInput)
{
  const Contact     c = hertz_contact(16, steel);
  const Field       p = c.pressure();
  PartialSlipSolver solver(c.grid, steel);
  EXPECT_THROW(solver.advance(Field(3, 1.0), mu, 1e-6, 0.0), std::invalid_argument);
  EXPECT_THROW(solver.advance(p, -0.1, 1e-6, 0.0), std::invalid_argument);
  EXPECT_THROW(solver.advance(p, mu, std::nan(""), 0.0), std::invalid_argument);
  EXPECT_THROW(solver.advance_to_force(p, mu, 1.01 * mu * integrate(c.grid, p), 0.0), std::invalid_argument);
  PartialSlipSettings bad;
  bad.tolerance = 0.0;
  EXPECT_THROW(PartialSlipSolver(c.grid, steel, bad), std::invalid_argument);
  // An iteration limit that cannot be met is an error, not a silent answer.
  PartialSlipSettings strict;
  strict.max_iterations = 2;
  PartialSlipSolver limited(c.grid, steel, strict);
  EXPECT_THROW(limited.advance(p, mu, 0.5 * c.delta_t, 0.0), std::runtime_error);
}

TEST(PartialSlipSolver, ExtrapolatedStartReachesTheSameSolutionInFewerIterations)
{
  // A monotone loading in equal steps, then a reversal and a step across:
  // from the last tractions or from the last two extrapolated, the same
  // solution to the tolerance (relative RMS traction error 1e-10 each), in
  // fewer iterations along the monotone part.
  const Contact       c = hertz_contact(32, steel);
  const Field         p = c.pressure();
  PartialSlipSettings plain;
  plain.tolerance               = 1e-10;
  PartialSlipSettings ahead     = plain;
  ahead.extrapolated_start      = true;
  PartialSlipSolver   reference(c.grid, steel, plain), solver(c.grid, steel, ahead);
  const double        step = 0.05 * c.delta_t;
  long                plain_iterations = 0, ahead_iterations = 0;
  for (const double shift : {step, step, step, step, step, step, step, step, -step, -step, 0.5 * step, 0.5 * step})
    {
      plain_iterations += reference.advance(p, mu, shift, 0.0).iterations;
      ahead_iterations += solver.advance(p, mu, shift, 0.0).iterations;
      double difference = 0.0, scale = 0.0;
      for (std::size_t k = 0; k < p.size(); ++k)
        {
          difference += std::pow(solver.traction_x()[k] - reference.traction_x()[k], 2) +
                        std::pow(solver.traction_y()[k] - reference.traction_y()[k], 2);
          scale += std::pow(reference.traction_x()[k], 2) + std::pow(reference.traction_y()[k], 2);
        }
      EXPECT_LT(std::sqrt(difference / scale), 1e-8) << "shift " << shift;
    }
  EXPECT_LT(ahead_iterations, plain_iterations);
}
