// The bristle traction model (paper eq. 4, docs/theory.md §2.3): implicit Euler
// accuracy, boundedness and extreme cases.
#include <fretsim/contact/bristle.h>
#include <fretsim/contact/fretting_loop.h>
#include <fretsim/contact/material.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

using namespace fretsim::contact;

namespace
{
  const double mu = 0.53, load = 1250.0, radius = 0.05;
  const MaterialPair steel{{200e9, 0.3}, {200e9, 0.3}};

  struct HertzOnGrid
  {
    SurfaceGrid grid;
    Field       pressure;
    double      contact_radius;
  };

  /// Hertz pressure sampled at cell centres (docs/references.md §1.1).
  HertzOnGrid hertz_on_grid(int cells)
  {
    const double a  = std::cbrt(3.0 * load * radius / (4.0 * steel.contact_modulus()));
    const double p0 = 3.0 * load / (2.0 * M_PI * a * a);
    HertzOnGrid  h{SurfaceGrid::centred(cells, cells, 1.5 * a, 1.5 * a), {}, a};
    h.pressure = h.grid.zeros();
    for (int j = 0; j < cells; ++j)
      for (int i = 0; i < cells; ++i)
        {
          const double r2 = (h.grid.x(i) * h.grid.x(i) + h.grid.y(j) * h.grid.y(j)) / (a * a);
          h.pressure[h.grid.index(i, j)] = p0 * std::sqrt(std::max(0.0, 1.0 - r2));
        }
    return h;
  }

  /// Largest |tau| / (mu p) over loaded cells, and whether every value is finite.
  double worst_traction_ratio(const BristleTraction &bristles, const Field &pressure, double friction,
                              bool &all_finite)
  {
    double worst = 0.0;
    all_finite   = true;
    for (std::size_t c = 0; c < pressure.size(); ++c)
      {
        const double magnitude = std::hypot(bristles.traction_x()[c], bristles.traction_y()[c]);
        all_finite             = all_finite && std::isfinite(magnitude);
        if (friction * pressure[c] > 0.0)
          worst = std::max(worst, magnitude / (friction * pressure[c]));
        else if (magnitude != 0.0)
          worst = HUGE_VAL; // traction without pressure or friction
      }
    return worst;
  }
} // namespace

TEST(Bristle, ImplicitEulerConvergesAtFirstOrderToTheExponentialLaw)
{
  // One loaded cell, monotonic slip s: exact tau = mu p (1 - exp(-k s / (mu p))).
  const SurfaceGrid grid = SurfaceGrid::centred(1, 1, 1e-3, 1e-3);
  const double      mu_p = 500e6, k = 1e14, total_slip = 3.0 * mu_p / k;
  const double      exact = mu_p * (1.0 - std::exp(-k * total_slip / mu_p));
  std::vector<double> errors;
  for (const int steps : {50, 100, 200, 400})
    {
      BristleTraction bristles(grid, k);
      for (int n = 0; n < steps; ++n)
        bristles.advance({mu_p}, 1.0, total_slip / steps, 0.0);
      errors.push_back(std::abs(bristles.traction_x()[0] - exact) / mu_p);
    }
  // Implicit Euler is first order: the error halves with the step (rate 1 +- 0.1).
  for (std::size_t i = 1; i < errors.size(); ++i)
    EXPECT_NEAR(std::log2(errors[i - 1] / errors[i]), 1.0, 0.1);
  EXPECT_LT(errors.back(), 2e-3);
}

TEST(Bristle, TheExponentialUpdateIsTheLawsOwnAnswerHoweverTheSlipIsDivided)
{
  // Along a straight slip: mu p (1 - exp(-k s / (mu p))) from rest in one
  // step, and the same in two unequal ones (to round-off). Along a path that
  // turns (3 mu p/k out, then 1.2 mu p/k back and 0.8 mu p/k across) it
  // agrees, a leg per step, with implicit Euler's limit as each leg's
  // substeps are refined: the error halves with them (first order; measured
  // 7.0e-4 of mu p at 250 substeps a leg, 8.8e-5 at 2 000: bound 2e-4).
  const double mu_p = 500e6, k = 1e14, unit = mu_p / k;
  const double exact = mu_p * (1.0 - std::exp(-3.0));
  const auto   whole = bristle_step(0.0, 0.0, k, mu_p, 3.0 * unit, 0.0, BristleUpdate::exponential);
  const auto   first = bristle_step(0.0, 0.0, k, mu_p, 0.7 * unit, 0.0, BristleUpdate::exponential);
  const auto   then  = bristle_step(first.x, first.y, k, mu_p, 2.3 * unit, 0.0, BristleUpdate::exponential);
  EXPECT_NEAR(whole.x, exact, 1e-12 * mu_p);
  EXPECT_NEAR(then.x, exact, 1e-12 * mu_p);
  EXPECT_EQ(whole.y, 0.0);
  const std::vector<std::pair<double, double>> legs{{3.0 * unit, 0.0}, {-1.2 * unit, 0.0}, {0.0, 0.8 * unit}};
  BristleStep exponential{0.0, 0.0};
  for (const auto &[x, y] : legs)
    exponential = bristle_step(exponential.x, exponential.y, k, mu_p, x, y, BristleUpdate::exponential);
  std::vector<double> errors;
  for (const int substeps : {250, 500, 1000, 2000})
    {
      BristleStep euler{0.0, 0.0};
      for (const auto &[x, y] : legs)
        for (int n = 0; n < substeps; ++n)
          euler = bristle_step(euler.x, euler.y, k, mu_p, x / substeps, y / substeps);
      errors.push_back(std::hypot(euler.x - exponential.x, euler.y - exponential.y) / mu_p);
    }
  std::printf("implicit Euler against the exponential steps at 250..2000 substeps a leg: %.3g %.3g %.3g %.3g of mu p\n",
              errors[0], errors[1], errors[2], errors[3]);
  for (std::size_t i = 1; i < errors.size(); ++i)
    EXPECT_NEAR(std::log2(errors[i - 1] / errors[i]), 1.0, 0.1);
  EXPECT_LT(errors.back(), 2e-4);
}

TEST(Bristle, TheExponentialUpdateStaysFiniteAndWithinCoulombAtExtremes)
{
  // Stiffness 1e8..1e26 Pa/m, Coulomb limits 1e-3..1e9 Pa, slips 1e-15..1e-2 m
  // in turning directions, starting tractions up to twice the limit (a
  // pressure drop): the traction and its derivatives finite, |τ'| <= μp to
  // round-off.
  double worst = 0.0;
  bool   finite = true;
  for (const double k : {1e8, 1e14, 1e20, 1e26})
    for (const double mu_p : {1e-3, 1.0, 1e6, 1e9})
      for (const double slip : {1e-15, 1e-9, 1e-6, 1e-2})
        for (int turn = 0; turn < 8; ++turn)
          {
            const double angle = 0.8 * turn, start = 0.25 * turn * mu_p;
            const auto   next = bristle_step(start, -0.5 * start, k, mu_p, slip * std::cos(angle), slip * std::sin(angle),
                                             BristleUpdate::exponential);
            BristleStepDerivatives derivatives;
            bristle_step(start, -0.5 * start, k, 1.0, mu_p, slip * std::cos(angle), slip * std::sin(angle), turn % 2,
                         derivatives, BristleUpdate::exponential);
            finite = finite && std::isfinite(next.x) && std::isfinite(next.y);
            for (const auto &row : derivatives.by_slip)
              finite = finite && std::isfinite(row[0]) && std::isfinite(row[1]);
            finite = finite && std::isfinite(derivatives.by_pressure[0]) && std::isfinite(derivatives.by_stiffness[1]);
            worst  = std::max(worst, std::hypot(next.x, next.y) / mu_p);
          }
  EXPECT_TRUE(finite);
  EXPECT_LE(worst, 1.0 + 1e-12);
}

TEST(Bristle, MindlinCalibrationGivesMindlinInitialStiffness)
{
  // k = 8 G*/(pi a): k * pi a^2 = 8 G* a (docs/theory.md §2.3). On the grid the
  // loaded area is the cell count, so allow the grid's area error (0.5 % at 128^2).
  const auto   h = hertz_on_grid(128);
  const double k = BristleTraction::mindlin_stiffness(steel.tangential_modulus(), h.contact_radius);
  BristleTraction bristles(h.grid, k);
  const double    tiny_slip = 1e-12; // far below mu p / k: pure stick
  bristles.advance(h.pressure, mu, tiny_slip, 0.0);
  const double stiffness = integrate(h.grid, bristles.traction_x()) / tiny_slip;
  EXPECT_NEAR(stiffness / (8.0 * steel.tangential_modulus() * h.contact_radius), 1.0, 5e-3);
}

TEST(Bristle, TractionFollowsSlipDirectionIsotropically)
{
  const auto   h = hertz_on_grid(48);
  const double k = BristleTraction::mindlin_stiffness(steel.tangential_modulus(), h.contact_radius);
  BristleTraction along_x(h.grid, k), diagonal(h.grid, k);
  const double    s = 2e-6 / std::sqrt(2.0);
  for (int n = 0; n < 20; ++n)
    {
      along_x.advance(h.pressure, mu, 2e-6 / 20, 0.0);
      diagonal.advance(h.pressure, mu, s / 20, s / 20);
    }
  const double q_x = integrate(h.grid, along_x.traction_x());
  const double q_d = std::hypot(integrate(h.grid, diagonal.traction_x()), integrate(h.grid, diagonal.traction_y()));
  // The vector law is isotropic: same magnitude to round-off.
  EXPECT_NEAR(q_d / q_x, 1.0, 1e-12);
  EXPECT_NEAR(integrate(h.grid, diagonal.traction_x()), integrate(h.grid, diagonal.traction_y()), 1e-9 * q_x);
}

TEST(Bristle, PressureDropClampsToCoulomb)
{
  const SurfaceGrid grid = SurfaceGrid::centred(1, 1, 1e-3, 1e-3);
  BristleTraction   bristles(grid, 1e14);
  bristles.advance({1e9}, 0.5, 1e-5, 0.0); // slides: tau -> 0.5 GPa
  bristles.advance({1e8}, 0.5, 0.0, 0.0);  // load drops tenfold, no slip
  EXPECT_NEAR(bristles.traction_x()[0], 0.5e8, 1e-6 * 0.5e8);
  bristles.advance({0.0}, 0.5, 0.0, 0.0);  // separation: no traction
  EXPECT_EQ(bristles.traction_x()[0], 0.0);
}

// Stiff and extreme cases (required: bristle stiffness 1e6 x calibrated, mu = 0
// and 1.5, amplitude 1e-9 m and 100 um, time steps from T/1e4 to T/4):
// traction finite and |tau| <= mu p everywhere.
struct ExtremeCase
{
  double stiffness_factor, friction, amplitude;
  int    steps_per_cycle;
};

class BristleExtremes : public ::testing::TestWithParam<ExtremeCase>
{};

TEST_P(BristleExtremes, TractionStaysFiniteAndWithinCoulomb)
{
  const auto   c = GetParam();
  const auto   h = hertz_on_grid(32);
  const double k = c.stiffness_factor * BristleTraction::mindlin_stiffness(steel.tangential_modulus(), h.contact_radius);
  BristleTraction      bristles(h.grid, k);
  const HarmonicSliding sliding{c.amplitude, 1.0};
  double previous = 0.0, worst = 0.0;
  bool   finite = true;
  for (int step = 1; step <= 2 * c.steps_per_cycle; ++step)
    {
      const double displacement = sliding.displacement(static_cast<double>(step) / c.steps_per_cycle);
      bristles.advance(h.pressure, c.friction, displacement - previous, 0.0);
      previous = displacement;
      bool step_finite = true;
      worst            = std::max(worst, worst_traction_ratio(bristles, h.pressure, c.friction, step_finite));
      finite           = finite && step_finite;
    }
  EXPECT_TRUE(finite);
  // |tau| <= mu p up to round-off in the division (1e-12 relative).
  EXPECT_LE(worst, 1.0 + 1e-12);
  const double force = integrate(h.grid, bristles.traction_x());
  EXPECT_LE(std::abs(force), c.friction * integrate(h.grid, h.pressure) * (1.0 + 1e-12));
}

INSTANTIATE_TEST_SUITE_P(
  StiffAndExtreme, BristleExtremes,
  ::testing::Values(ExtremeCase{1e6, 0.53, 2.241e-6, 200}, ExtremeCase{1e6, 0.53, 2.241e-6, 4},
                    ExtremeCase{1.0, 0.0, 2.241e-6, 200}, ExtremeCase{1.0, 1.5, 2.241e-6, 200},
                    ExtremeCase{1.0, 0.53, 1e-9, 200}, ExtremeCase{1.0, 0.53, 100e-6, 200},
                    ExtremeCase{1.0, 0.53, 2.241e-6, 10000}, ExtremeCase{1.0, 0.53, 2.241e-6, 4},
                    ExtremeCase{1e6, 1.5, 100e-6, 4}, ExtremeCase{1e-6, 0.53, 1e-9, 10000}));

TEST(Bristle, VeryStiffBristlesReachCoulombInOneStep)
{
  // k |ds| / (mu p) -> infinity: the implicit step lands on tau = mu p along
  // the slip without overflow, however large k is.
  const SurfaceGrid grid = SurfaceGrid::centred(1, 1, 1e-3, 1e-3);
  BristleTraction   bristles(grid, 1e300);
  bristles.advance({1e9}, 0.5, -1e-3, 1e-3);
  EXPECT_NEAR(bristles.traction_x()[0], -0.5e9 / std::sqrt(2.0), 1e-6 * 0.5e9);
  EXPECT_NEAR(bristles.traction_y()[0], 0.5e9 / std::sqrt(2.0), 1e-6 * 0.5e9);
}

TEST(Bristle, FrictionlessContactSlipsEverywhere)
{
  const auto      h = hertz_on_grid(16);
  BristleTraction bristles(h.grid, 1e14);
  bristles.advance(h.pressure, 0.0, 1e-6, 0.0);
  EXPECT_EQ(integrate(h.grid, bristles.traction_x()), 0.0);
  EXPECT_DOUBLE_EQ(bristles.slip_area_fraction(h.pressure, 0.0), 1.0);
}
