// Mindlin–Deresiewicz loop against the check values of docs/references.md §2.
#include <fretsim/contact/material.h>
#include <fretsim/contact/mindlin.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace fretsim::contact;

namespace
{
  // Paper §4 case, two steel bodies (docs/references.md §2.3, "two elastic bodies" row).
  const double mu = 0.53, load = 1250.0, radius = 752.7676e-6;
  const MaterialPair steel{{200e9, 0.3}, {200e9, 0.3}};
  MindlinLoop paper_loop() { return MindlinLoop(mu, load, radius, steel.tangential_modulus()); }

  /// Loop area by fine trapezoidal integration of the two branches.
  double integrated_loop_area(const MindlinLoop &loop, double amplitude)
  {
    const int n = 200000;
    double    area = 0.0;
    for (int i = 0; i < n; ++i)
      {
        const double d0 = -amplitude + 2.0 * amplitude * i / n, d1 = -amplitude + 2.0 * amplitude * (i + 1) / n;
        const double reload = 0.5 * (loop.loop_force(d0, amplitude, false) + loop.loop_force(d1, amplitude, false));
        const double unload = 0.5 * (loop.loop_force(d0, amplitude, true) + loop.loop_force(d1, amplitude, true));
        area += (reload - unload) * (d1 - d0);
      }
    return area;
  }
} // namespace

TEST(Mindlin, PaperCaseMatchesReferenceTable)
{
  const auto loop = paper_loop();
  // delta_t = 3 mu P (2 - nu) / (8 G a) = 7.294 um (docs/references.md §2.3), 4 digits given.
  EXPECT_NEAR(loop.gross_slip_displacement(), 7.294e-6, 0.001e-6);
  const double amplitude = 2.241e-6;
  // Q* = 280.5 N, Q*/(mu P) = 0.4234 (table, 4 digits).
  EXPECT_NEAR(loop.force_amplitude(amplitude), 280.5, 0.1);
  EXPECT_NEAR(loop.force_amplitude(amplitude) / (mu * load), 0.4234, 1e-4);
  // c/a = 0.8323 (table).
  EXPECT_NEAR(loop.stick_radius(loop.force_amplitude(amplitude)), 0.8323, 1e-4);
  // W_d = 7.64e-5 J per cycle (table, 3 digits).
  EXPECT_NEAR(loop.dissipated_energy(amplitude), 7.64e-5, 0.01e-5);
}

TEST(Mindlin, ClosedFormEnergyEqualsLoopArea)
{
  const auto   loop = paper_loop();
  const double dt   = loop.gross_slip_displacement();
  // Partial slip and gross slip: the closed form (Johnson eq. 7.59 plus the
  // gross-slip strokes) equals the area between the branches; the trapezoidal
  // rule with 2e5 intervals is accurate to ~1e-8 relative.
  for (const double fraction : {0.05, 0.3073, 0.7, 0.99, 1.5, 3.0})
    EXPECT_NEAR(integrated_loop_area(loop, fraction * dt) / loop.dissipated_energy(fraction * dt), 1.0, 1e-6)
      << "amplitude " << fraction << " delta_t";
}

TEST(Mindlin, FrettingRegimeIndicatorsAtTransition)
{
  // Fouvry's energy ratio A = W/(4 delta* Q*) is exactly 0.2 at the gross-slip
  // transition, independent of mu, P and material (docs/references.md §2.2).
  const auto   loop = paper_loop();
  const double dt   = loop.gross_slip_displacement();
  EXPECT_NEAR(loop.dissipated_energy(dt) / (4.0 * dt * loop.force_amplitude(dt)), 0.2, 1e-12);
  // Loop opening ratio B = half width at Q = 0 over delta*: 2^(1/3) - 1 at the
  // transition. Find the unloading-branch zero crossing by bisection.
  double low = -dt, high = dt;
  for (int i = 0; i < 200; ++i)
    {
      const double mid = 0.5 * (low + high);
      (loop.loop_force(mid, dt, true) > 0.0 ? high : low) = mid;
    }
  EXPECT_NEAR(low / dt, std::cbrt(2.0) - 1.0, 1e-9);
}

TEST(Mindlin, BranchesCloseAndGrossSlipSaturates)
{
  const auto   loop = paper_loop();
  const double mu_P = mu * load;
  const double dt   = loop.gross_slip_displacement();
  for (const double amplitude : {0.2 * dt, 0.9 * dt, 2.0 * dt})
    {
      const double q_star = loop.force_amplitude(amplitude);
      // Both branches pass through the loop tips (+-delta*, +-Q*).
      EXPECT_NEAR(loop.loop_force(amplitude, amplitude, true), q_star, 1e-9 * mu_P);
      EXPECT_NEAR(loop.loop_force(-amplitude, amplitude, true), -q_star, 1e-9 * mu_P);
      EXPECT_NEAR(loop.loop_force(-amplitude, amplitude, false), -q_star, 1e-9 * mu_P);
      EXPECT_NEAR(loop.loop_force(amplitude, amplitude, false), q_star, 1e-9 * mu_P);
    }
  EXPECT_DOUBLE_EQ(loop.force_amplitude(2.0 * dt), mu_P);
  // Initial stiffness dQ/d(delta) = 8 G* a (Mindlin 1949).
  const double small = 1e-6 * dt;
  EXPECT_NEAR(loop.virgin_force(small) / small, 8.0 * steel.tangential_modulus() * radius, 1e-5 * 8.0 * steel.tangential_modulus() * radius);
}
