// Numerical normal contact (Polonsky & Keer CG + DC-FFT) against Hertz,
// docs/references.md §1.1-1.3, with observed convergence rates.
#include <fretsim/contact/hertz.h>
#include <fretsim/contact/normal_contact.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

using namespace fretsim::contact;

namespace
{
  // Paper case (docs/references.md §1.2): R = 50 mm, P = 1250 N, steel on steel.
  const double sphere_radius = 0.05, paper_load = 1250.0;
  const double steel_modulus = 200e9 / (2.0 * (1.0 - 0.3 * 0.3)); // E*

  /// Undeformed separation of two paraboloids, x^2/2Rx + y^2/2Ry.
  Field paraboloid_gap(const SurfaceGrid &grid, double radius_x, double radius_y)
  {
    Field gap(grid.size());
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        gap[grid.index(i, j)] = grid.x(i) * grid.x(i) / (2.0 * radius_x) + grid.y(j) * grid.y(j) / (2.0 * radius_y);
    return gap;
  }

  double peak(const Field &field)
  {
    double m = 0.0;
    for (const double v : field)
      m = std::max(m, v);
    return m;
  }

  /// Least-squares slope of log(error) against log(h).
  double observed_rate(const std::vector<double> &h, const std::vector<double> &error)
  {
    double mean_x = 0.0, mean_y = 0.0;
    for (std::size_t k = 0; k < h.size(); ++k)
      {
        mean_x += std::log(h[k]) / h.size();
        mean_y += std::log(error[k]) / h.size();
      }
    double sxy = 0.0, sxx = 0.0;
    for (std::size_t k = 0; k < h.size(); ++k)
      {
        sxy += (std::log(h[k]) - mean_x) * (std::log(error[k]) - mean_y);
        sxx += (std::log(h[k]) - mean_x) * (std::log(h[k]) - mean_x);
      }
    return sxy / sxx;
  }

  /// Circular Hertz problem on n x n cells covering [-1.5a, 1.5a]^2.
  struct CircularCase
  {
    HertzCircular       hertz;
    SurfaceGrid         grid;
    NormalContactResult result;
  };

  CircularCase solve_circular(int n, double load)
  {
    CircularCase c{HertzCircular::solve(load, sphere_radius, steel_modulus), {}, {}};
    const double half_width = 1.5 * c.hertz.contact_radius;
    c.grid                  = SurfaceGrid::centred(n, n, half_width, half_width);
    const NormalContactSolver solver(c.grid, steel_modulus);
    c.result = solver.solve(paraboloid_gap(c.grid, sphere_radius, sphere_radius), load);
    return c;
  }
} // namespace

TEST(NormalContact, PaperCaseReproducesHertzOn128)
{
  const auto   c = solve_circular(128, paper_load);
  const auto  &r = c.result;
  const double a = c.hertz.contact_radius;
  // Numerical contact radius: the radius of the circle with the same area as
  // the cells carrying pressure, sqrt(A/pi). Hertz within 1 % (asked for;
  // measured 0.36 %, the quantisation of the boundary to cells of h = a/43).
  const double contact_radius = std::sqrt(r.contact_area / M_PI);
  EXPECT_NEAR(contact_radius / a, 1.0, 1e-2);
  // Peak pressure within 1 % (asked for; measured 0.011 %, O(h^2)).
  EXPECT_NEAR(peak(r.pressure) / c.hertz.peak_pressure, 1.0, 1e-2);
  // Approach delta = a^2/R within 1 % (measured 0.002 %).
  EXPECT_NEAR(r.approach / c.hertz.approach, 1.0, 1e-2);
  // Force balance sum p A = P is enforced every iteration: round-off.
  EXPECT_NEAR(integrate(c.grid, r.pressure) / paper_load, 1.0, 1e-10);
  // The solver's own convergence measure is below its tolerance (default 1e-10).
  EXPECT_LT(r.residual, 1e-10);
  std::printf("[ info ] 128^2: a %.3e, p0 %+.3e, delta %+.3e relative; %d iterations\n", contact_radius / a - 1.0,
              peak(r.pressure) / c.hertz.peak_pressure - 1.0, r.approach / c.hertz.approach - 1.0, r.iterations);

  // Independent check of the reported state with the O(N^2) direct sum:
  // h = h0 - delta + K p vanishes on the contact set and is >= 0 elsewhere, to
  // the solver tolerance (1e-10 RMS relative) amplified to a max norm (1e-8).
  const Field initial_gap = paraboloid_gap(c.grid, sphere_radius, sphere_radius);
  const NormalContactSolver solver(c.grid, steel_modulus);
  Field                     displacement;
  solver.deflection().apply_direct(r.pressure, displacement);
  double worst_contact = 0.0, worst_separation = 0.0;
  for (std::size_t k = 0; k < displacement.size(); ++k)
    {
      const double gap = initial_gap[k] - r.approach + displacement[k];
      EXPECT_GE(r.pressure[k], 0.0);
      EXPECT_GE(r.gap[k], 0.0);
      if (r.pressure[k] > 0.0)
        {
          worst_contact = std::max(worst_contact, std::abs(gap));
          EXPECT_EQ(r.gap[k], 0.0);
        }
      else
        {
          worst_separation = std::min(worst_separation, gap);
          EXPECT_NEAR(r.gap[k], gap, 1e-8 * r.approach);
        }
    }
  EXPECT_LT(worst_contact, 1e-8 * r.approach);
  EXPECT_GT(worst_separation, -1e-8 * r.approach);
}

TEST(NormalContact, PressureErrorConvergesWithGridRefinement)
{
  // Errors against p_Hertz at the cell centres, normalised by p0, on
  // n = 32 ... 256 cells over [-1.5a, 1.5a]^2; rates are least-squares slopes
  // of log(error) vs log(h) over the seven grids.
  //
  // Expected rates for piecewise-constant elements (docs/references.md §6.3 finds
  // O(h^2) in the interior): the pressure has a square-root edge, so the
  // O(a/h) cells cut by the contact boundary carry errors O(p0 sqrt(h/a)).
  // Hence RMS over the grid ~ h^1, mean absolute ~ h^1.5, maximum ~ h^0.5,
  // and O(h^2) for the peak and for the maximum over r < 0.8a. The boundary
  // cut varies irregularly with n, so single ratios are noisy; the fitted
  // rates are asserted 0.15-0.2 below theory (measured: RMS 0.97, mean 1.48,
  // max 0.36, interior 2.08, peak 1.98).
  std::vector<double> h, rms_error, mean_error, max_error, interior_error, peak_error;
  for (const int n : {32, 48, 64, 96, 128, 192, 256})
    {
      const auto   c = solve_circular(n, paper_load);
      const double a = c.hertz.contact_radius, p0 = c.hertz.peak_pressure;
      double       sum_squares = 0.0, sum_abs = 0.0, worst = 0.0, worst_interior = 0.0;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          {
            const double x = c.grid.x(i), y = c.grid.y(j);
            const double e = std::abs(c.result.pressure[c.grid.index(i, j)] - c.hertz.pressure(x, y)) / p0;
            sum_squares += e * e;
            sum_abs += e;
            worst = std::max(worst, e);
            if (std::hypot(x, y) < 0.8 * a)
              worst_interior = std::max(worst_interior, e);
          }
      h.push_back(c.grid.hx / a);
      rms_error.push_back(std::sqrt(sum_squares / c.grid.size()));
      mean_error.push_back(sum_abs / c.grid.size());
      max_error.push_back(worst);
      interior_error.push_back(worst_interior);
      peak_error.push_back(std::abs(peak(c.result.pressure) / p0 - 1.0));
      std::printf("[ info ] n %3d: rms %.3e mean %.3e max %.3e interior %.3e peak %.3e, %d iterations\n", n,
                  rms_error.back(), mean_error.back(), max_error.back(), interior_error.back(), peak_error.back(),
                  c.result.iterations);
      // Polonsky & Keer report iteration counts that grow slowly with N;
      // measured 27 (32^2) to 72 (256^2). 150 flags a regression.
      EXPECT_LT(c.result.iterations, 150) << "n = " << n;
    }
  const double rms_rate = observed_rate(h, rms_error), mean_rate = observed_rate(h, mean_error),
               max_rate = observed_rate(h, max_error), interior_rate = observed_rate(h, interior_error),
               peak_rate = observed_rate(h, peak_error);
  std::printf("[ info ] rates: rms %.2f mean %.2f max %.2f interior %.2f peak %.2f\n", rms_rate, mean_rate, max_rate,
              interior_rate, peak_rate);
  EXPECT_GT(rms_rate, 0.8);      // theory 1
  EXPECT_GT(mean_rate, 1.3);     // theory 1.5
  EXPECT_GT(max_rate, 0.25);     // theory 0.5, the noisiest
  EXPECT_GT(interior_rate, 1.8); // theory 2
  EXPECT_GT(peak_rate, 1.8);     // theory 2
  // And the finest grid is accurate in absolute terms (measured 6.7e-4).
  EXPECT_LT(rms_error.back(), 1e-3);
}

TEST(NormalContact, EllipticalContactsMatchExactHertz)
{
  // Rx = 50 mm, Ry/Rx = 1, 2, 4, 10 (and the transposed 1/4), P = 1250 N. The
  // grid is aligned with the ellipse: 128 x 128 cells over
  // [-1.5 a_x, 1.5 a_x] x [-1.5 a_y, 1.5 a_y], so each semi-axis spans ~43
  // cells whatever the ellipticity (cells have aspect ratio a_y/a_x).
  // Numerical semi-axes from the second moments of the contact set, exact for
  // an ellipse: a_x = 2 sqrt(<x^2>), with each cell's own h^2/12.
  for (const double ratio : {1.0, 2.0, 4.0, 10.0, 0.25})
    {
      const double radius_x = sphere_radius, radius_y = ratio * sphere_radius;
      const auto   hertz    = HertzElliptical::solve(paper_load, radius_x, radius_y, steel_modulus);
      const auto   grid     = SurfaceGrid::centred(128, 128, 1.5 * hertz.semi_axis_x, 1.5 * hertz.semi_axis_y);
      const NormalContactSolver solver(grid, steel_modulus);
      const auto result = solver.solve(paraboloid_gap(grid, radius_x, radius_y), paper_load);

      double second_moment_x = 0.0, second_moment_y = 0.0, n_contact = 0.0;
      for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i)
          if (result.pressure[grid.index(i, j)] > 0.0)
            {
              second_moment_x += grid.x(i) * grid.x(i) + grid.hx * grid.hx / 12.0;
              second_moment_y += grid.y(j) * grid.y(j) + grid.hy * grid.hy / 12.0;
              n_contact += 1.0;
            }
      const double semi_axis_x = 2.0 * std::sqrt(second_moment_x / n_contact);
      const double semi_axis_y = 2.0 * std::sqrt(second_moment_y / n_contact);
      std::printf("[ info ] Ry/Rx %5.2f: a_x %+.2e a_y %+.2e p0 %+.2e delta %+.2e, %d iterations\n", ratio,
                  semi_axis_x / hertz.semi_axis_x - 1.0, semi_axis_y / hertz.semi_axis_y - 1.0,
                  peak(result.pressure) / hertz.peak_pressure - 1.0, result.approach / hertz.approach - 1.0,
                  result.iterations);
      // Semi-axes within 1 % (measured <= 0.55 %: boundary quantisation as in
      // the circular case), peak pressure and approach within 1 % (measured
      // 0.011 % and 0.002 %).
      EXPECT_NEAR(semi_axis_x / hertz.semi_axis_x, 1.0, 1e-2) << "Ry/Rx = " << ratio;
      EXPECT_NEAR(semi_axis_y / hertz.semi_axis_y, 1.0, 1e-2) << "Ry/Rx = " << ratio;
      EXPECT_NEAR(peak(result.pressure) / hertz.peak_pressure, 1.0, 1e-2) << "Ry/Rx = " << ratio;
      EXPECT_NEAR(result.approach / hertz.approach, 1.0, 1e-2) << "Ry/Rx = " << ratio;
      // Force balance: round-off.
      EXPECT_NEAR(integrate(grid, result.pressure) / paper_load, 1.0, 1e-10) << "Ry/Rx = " << ratio;
    }
}

TEST(NormalContact, ExtremeLoadsOnScaledGrids)
{
  // With the grid scaled to each load's Hertz radius the dimensionless problem
  // is identical, so p/p0 must agree with the paper load cell by cell up to
  // the solver tolerance (1e-10 gap error -> 1e-8 in pressure, generously).
  const auto reference = solve_circular(64, paper_load);
  for (const double load : {1e-6, 1e6})
    {
      const auto c = solve_circular(64, load);
      const auto &p = c.result.pressure;
      EXPECT_LT(c.result.residual, 1e-10) << "P = " << load;
      EXPECT_NEAR(integrate(c.grid, p) / load, 1.0, 1e-10) << "P = " << load; // round-off
      for (std::size_t k = 0; k < p.size(); ++k)
        {
          ASSERT_TRUE(std::isfinite(p[k]) && p[k] >= 0.0) << "P = " << load;
          EXPECT_NEAR(p[k] / c.hertz.peak_pressure, reference.result.pressure[k] / reference.hertz.peak_pressure, 1e-8)
            << "P = " << load << ", cell " << k;
        }
      EXPECT_NEAR(c.result.approach / c.hertz.approach, reference.result.approach / reference.hertz.approach, 1e-8)
        << "P = " << load;
    }
}

TEST(NormalContact, ExtremeLoadsOnThePaperGrid)
{
  // The paper-case grid (64^2 over +-1.5 x 752.8 um, h = 35 um) under loads
  // whose Hertz radius is far below (0.7 um) or far above (7 mm) the grid.
  const auto hertz = HertzCircular::solve(paper_load, sphere_radius, steel_modulus);
  const auto grid  = SurfaceGrid::centred(64, 64, 1.5 * hertz.contact_radius, 1.5 * hertz.contact_radius);
  const NormalContactSolver solver(grid, steel_modulus);
  const Field               initial_gap = paraboloid_gap(grid, sphere_radius, sphere_radius);
  for (const double load : {1e-6, 1e6})
    {
      const auto result = solver.solve(initial_gap, load);
      EXPECT_LT(result.residual, 1e-10) << "P = " << load;
      EXPECT_NEAR(integrate(grid, result.pressure) / load, 1.0, 1e-10) << "P = " << load; // round-off
      EXPECT_TRUE(std::isfinite(result.approach)) << "P = " << load;
      std::size_t n_contact = 0;
      for (const double p : result.pressure)
        {
          ASSERT_TRUE(std::isfinite(p) && p >= 0.0) << "P = " << load;
          n_contact += p > 0.0;
        }
      if (load < 1.0)
        {
          // The four cells around the origin have the same, lowest h0 and
          // share the load equally (by symmetry, to round-off).
          EXPECT_EQ(n_contact, 4u);
          EXPECT_NEAR(peak(result.pressure) * 4.0 * grid.cell_area() / load, 1.0, 1e-12);
        }
      else
        EXPECT_EQ(n_contact, grid.size()); // Hertz radius 7 mm >> the 1.1 mm grid
    }
}

TEST(NormalContact, ZeroLoadInvalidInputAndNonConvergence)
{
  const auto  grid        = SurfaceGrid::centred(16, 16, 1e-3, 1e-3);
  const Field initial_gap = paraboloid_gap(grid, sphere_radius, sphere_radius);
  const NormalContactSolver solver(grid, steel_modulus);

  const auto unloaded = solver.solve(initial_gap, 0.0);
  EXPECT_EQ(peak(unloaded.pressure), 0.0);
  EXPECT_EQ(unloaded.contact_area, 0.0);

  EXPECT_THROW(solver.solve(initial_gap, -1.0), std::invalid_argument);
  EXPECT_THROW(solver.solve(Field(3, 0.0), 1.0), std::invalid_argument);
  EXPECT_THROW(NormalContactSolver(grid, 0.0), std::invalid_argument);

  // Three iterations cannot reach 1e-10: this case (a = 0.75 mm on +-1 mm)
  // needs 21.
  const NormalContactSolver impatient(grid, steel_modulus, {1e-10, 3});
  EXPECT_THROW(impatient.solve(initial_gap, paper_load), std::runtime_error);
  EXPECT_NO_THROW(solver.solve(initial_gap, paper_load));
}
