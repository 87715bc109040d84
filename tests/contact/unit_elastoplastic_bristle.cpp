// Elastic–perfectly-plastic bristles (elastoplastic_bristle.h): the return
// mapping cell by cell, the true stick zone, boundedness and extreme inputs.
#include <fretsim/contact/bristle.h>
#include <fretsim/contact/elastoplastic_bristle.h>
#include <fretsim/contact/material.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

using namespace fretsim::contact;

namespace
{
  const double       mu = 0.53, load = 1250.0, radius = 0.05;
  const MaterialPair steel{{200e9, 0.3}, {200e9, 0.3}};
  const double       contact_radius = std::cbrt(3.0 * load * radius / (4.0 * steel.contact_modulus()));
  const double       peak_pressure  = 3.0 * load / (2.0 * M_PI * contact_radius * contact_radius);
  const double       stiffness =
    ElastoplasticBristleTraction::mindlin_stiffness(steel.tangential_modulus(), contact_radius);

  struct HertzOnGrid
  {
    SurfaceGrid grid;
    Field       pressure;
  };

  HertzOnGrid hertz_on_grid(int cells)
  {
    HertzOnGrid h{SurfaceGrid::centred(cells, cells, 1.5 * contact_radius, 1.5 * contact_radius), {}};
    h.pressure = h.grid.zeros();
    for (int j = 0; j < cells; ++j)
      for (int i = 0; i < cells; ++i)
        {
          const double r2 = (h.grid.x(i) * h.grid.x(i) + h.grid.y(j) * h.grid.y(j)) / (contact_radius * contact_radius);
          h.pressure[h.grid.index(i, j)] = peak_pressure * std::sqrt(std::max(0.0, 1.0 - r2));
        }
    return h;
  }

  /// Largest |tau| / (mu p) over loaded cells (HUGE_VAL for traction without
  /// load or a non-finite value).
  double worst_ratio(const ElastoplasticBristleTraction &bristles, const Field &pressure, double friction)
  {
    double worst = 0.0;
    for (std::size_t c = 0; c < pressure.size(); ++c)
      {
        const double magnitude = std::hypot(bristles.traction_x()[c], bristles.traction_y()[c]);
        if (!std::isfinite(magnitude))
          return HUGE_VAL;
        if (friction * pressure[c] > 0.0)
          worst = std::max(worst, magnitude / (friction * pressure[c]));
        else if (magnitude != 0.0)
          return HUGE_VAL;
      }
    return worst;
  }
} // namespace

TEST(ElastoplasticBristle, ReturnMappingOnOneCell)
{
  const auto                   grid = SurfaceGrid::centred(1, 1, 1e-4, 1e-4);
  const double                 k = 1e12, p = 1e8, mu_p = mu * p;
  ElastoplasticBristleTraction cell(grid, k);
  // Elastic: tau = k ds, exactly.
  cell.advance({p}, mu, 0.3 * mu_p / k, 0.4 * mu_p / k);
  EXPECT_DOUBLE_EQ(cell.traction_x()[0], 0.3 * mu_p);
  EXPECT_DOUBLE_EQ(cell.traction_y()[0], 0.4 * mu_p);
  EXPECT_EQ(cell.slip_mask()[0], 0);
  // Beyond the bound: returned radially onto |tau| = mu p along the trial.
  cell.advance({p}, mu, 0.9 * mu_p / k, 0.0); // trial (1.2, 0.4) mu p
  EXPECT_NEAR(std::hypot(cell.traction_x()[0], cell.traction_y()[0]) / mu_p, 1.0, 1e-15);
  EXPECT_NEAR(cell.traction_y()[0] / cell.traction_x()[0], 0.4 / 1.2, 1e-14);
  EXPECT_EQ(cell.slip_mask()[0], 1);
  // Reversal: sticks at once (a true stick zone: no slip below the bound).
  const double before = cell.traction_x()[0];
  cell.advance({p}, mu, -0.1 * mu_p / k, 0.0);
  EXPECT_NEAR(cell.traction_x()[0], before - 0.1 * mu_p, 1e-9 * mu_p);
  EXPECT_EQ(cell.slip_mask()[0], 0);
  // The pressure drops to a tenth: clamped to the new bound.
  cell.advance({0.1 * p}, mu, 0.0, 0.0);
  EXPECT_NEAR(std::hypot(cell.traction_x()[0], cell.traction_y()[0]) / (0.1 * mu_p), 1.0, 1e-15);
  // No pressure, no friction: no traction.
  cell.advance({0.0}, mu, 1.0, 0.0);
  EXPECT_EQ(cell.traction_x()[0], 0.0);
  cell.advance({p}, 0.0, 1.0, 0.0);
  EXPECT_EQ(cell.traction_x()[0], 0.0);
  EXPECT_THROW(ElastoplasticBristleTraction(grid, 0.0), std::invalid_argument);
  EXPECT_THROW(ElastoplasticBristleTraction(grid, HUGE_VAL), std::invalid_argument);
}

TEST(ElastoplasticBristle, HasATrueStickZone)
{
  // One step from rest to delta: a cell slips exactly where k delta >= mu p,
  // i.e. outside r_s = a sqrt(1 - (k delta / mu p0)^2); inside it sticks with
  // tau = k delta < mu p. The exponential bristle law instead has
  // 0 < |tau| < mu p at every loaded cell and slips a little everywhere.
  const auto   h = hertz_on_grid(64);
  const double delta = 0.5 * mu * peak_pressure / stiffness; // half the gross-slip shift
  ElastoplasticBristleTraction bristles(h.grid, stiffness);
  bristles.advance(h.pressure, mu, delta, 0.0);
  std::size_t stick = 0, loaded = 0;
  for (std::size_t c = 0; c < h.grid.size(); ++c)
    {
      if (!(h.pressure[c] > 0.0))
        continue;
      ++loaded;
      const bool should_slip = stiffness * delta >= mu * h.pressure[c];
      EXPECT_EQ(bristles.slip_mask()[c], should_slip ? 1 : 0);
      if (!should_slip)
        {
          ++stick;
          EXPECT_DOUBLE_EQ(bristles.traction_x()[c], stiffness * delta);
        }
    }
  // Stick area fraction 1 - 1/4 ... of the Hertz disc: r_s^2/a^2 = 3/4.
  const double stick_fraction = static_cast<double>(stick) / loaded;
  EXPECT_NEAR(stick_fraction, 0.75, 0.02);
  EXPECT_NEAR(bristles.slip_area_fraction(h.pressure, mu), 1.0 - stick_fraction, 1e-15);
  // The next step back sticks everywhere.
  bristles.advance(h.pressure, mu, -0.01 * delta, 0.0);
  EXPECT_EQ(bristles.slip_area_fraction(h.pressure, mu), 0.0);
}

TEST(ElastoplasticBristle, BoundedOnRandomPathsWithChangingPressure)
{
  const auto                   h = hertz_on_grid(32);
  ElastoplasticBristleTraction bristles(h.grid, stiffness);
  std::mt19937                 random(11);
  std::uniform_real_distribution<double> shift(-2e-6, 2e-6), scale(0.3, 1.5);
  for (int step = 0; step < 200; ++step)
    {
      Field pressure = h.pressure;
      const double factor = scale(random);
      for (auto &p : pressure)
        p *= factor;
      bristles.advance(pressure, mu, shift(random), shift(random));
      ASSERT_LE(worst_ratio(bristles, pressure, mu), 1.0 + 1e-15) << "step " << step;
    }
}

TEST(ElastoplasticBristle, ExtremeCasesStayFiniteAndBounded)
{
  const auto h = hertz_on_grid(32);
  struct Case
  {
    double stiffness, friction, amplitude;
    int    steps_per_cycle;
  };
  const double delta_t = mu * peak_pressure / stiffness;
  for (const Case &c : {Case{1e6 * stiffness, mu, delta_t, 40}, Case{1e300, mu, delta_t, 40},
                        Case{stiffness, 0.0, delta_t, 40}, Case{stiffness, 1.5, delta_t, 40},
                        Case{stiffness, mu, 1e-20, 40}, Case{stiffness, mu, 1e3, 40},
                        Case{stiffness, mu, 10.0 * delta_t, 4}, Case{1e6 * stiffness, 1.5, 1e3, 4}})
    {
      ElastoplasticBristleTraction bristles(h.grid, c.stiffness);
      double                       previous = 0.0;
      for (int step = 1; step <= 2 * c.steps_per_cycle; ++step)
        {
          const double displacement = c.amplitude * std::sin(2.0 * M_PI * step / c.steps_per_cycle);
          bristles.advance(h.pressure, c.friction, displacement - previous, 0.5 * (displacement - previous));
          previous = displacement;
          ASSERT_LE(worst_ratio(bristles, h.pressure, c.friction), 1.0 + 1e-15)
            << "k " << c.stiffness << " mu " << c.friction << " amplitude " << c.amplitude;
        }
      const double force = integrate(h.grid, bristles.traction_x());
      EXPECT_TRUE(std::isfinite(force));
      EXPECT_LE(std::abs(force), c.friction * integrate(h.grid, h.pressure) * (1.0 + 1e-12));
    }
}
