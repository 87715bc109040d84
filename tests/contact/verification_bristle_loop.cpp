// The bristle fretting loop on the paper §4 case (docs/references.md §1.2, §2.3):
// against an independent semi-analytic bristle solution (tight), against the
// Mindlin–Deresiewicz loop (the model difference, measured and bounded), and
// the gross-slip limit.
#include "reference/bristle_reference.h"

#include <fretsim/contact/bristle.h>
#include <fretsim/contact/fretting_loop.h>
#include <fretsim/contact/material.h>
#include <fretsim/contact/mindlin.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace fretsim::contact;

namespace
{
  const double       mu = 0.53, load = 1250.0, radius = 0.05, paper_amplitude = 2.241e-6;
  const MaterialPair steel{{200e9, 0.3}, {200e9, 0.3}};
  const double       contact_radius = std::cbrt(3.0 * load * radius / (4.0 * steel.contact_modulus()));
  const double       peak_pressure  = 3.0 * load / (2.0 * M_PI * contact_radius * contact_radius);
  const double       stiffness = BristleTraction::mindlin_stiffness(steel.tangential_modulus(), contact_radius);

  struct LoopRun
  {
    std::vector<double> displacement, force, reference_force; // one entry per step, step 0 included
    LoopMetrics         metrics;
  };

  /// The grid bristle model under delta = A sin(2 pi t), Hertz pressure at cell centres.
  LoopRun run_grid_loop(double amplitude, int cells, int steps_per_cycle, int cycles, double friction = mu)
  {
    const auto grid     = SurfaceGrid::centred(cells, cells, 1.5 * contact_radius, 1.5 * contact_radius);
    Field      pressure = grid.zeros();
    for (int j = 0; j < cells; ++j)
      for (int i = 0; i < cells; ++i)
        {
          const double r2 = (grid.x(i) * grid.x(i) + grid.y(j) * grid.y(j)) / (contact_radius * contact_radius);
          pressure[grid.index(i, j)] = peak_pressure * std::sqrt(std::max(0.0, 1.0 - r2));
        }
    BristleTraction       bristles(grid, stiffness);
    const HarmonicSliding sliding{amplitude, 1.0};
    const MindlinLoop     mindlin(friction, load, contact_radius, steel.tangential_modulus());
    FrettingLoop          loop(steps_per_cycle);
    LoopRun               run;
    loop.add(0.0, 0.0);
    run.displacement.push_back(0.0);
    run.force.push_back(0.0);
    double previous = 0.0;
    for (int step = 1; step <= cycles * steps_per_cycle; ++step)
      {
        const double displacement = sliding.displacement(static_cast<double>(step) / steps_per_cycle);
        bristles.advance(pressure, friction, displacement - previous, 0.0);
        const double force = integrate(grid, bristles.traction_x());
        loop.add(displacement, force);
        run.displacement.push_back(displacement);
        run.force.push_back(force);
        previous = displacement;
      }
    run.metrics = loop.last_cycle(friction * load, mindlin, amplitude);
    return run;
  }

  /// The same history through the closed-form per-point solution.
  std::vector<double> radial_reference(const std::vector<double> &displacement)
  {
    fretsim::reference::RadialBristleLoop reference(peak_pressure, contact_radius, mu, stiffness);
    std::vector<double> force{0.0};
    for (std::size_t i = 1; i < displacement.size(); ++i)
      force.push_back(reference.advance(displacement[i] - displacement[i - 1]));
    return force;
  }

  double max_difference(const std::vector<double> &a, const std::vector<double> &b)
  {
    double result = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
      result = std::max(result, std::abs(a[i] - b[i]));
    return result;
  }
} // namespace

TEST(BristleLoop, MatchesSemiAnalyticBristleSolutionAndConvergesInTime)
{
  // Grid + implicit Euler against the exact per-point exponential law: the
  // difference is the time-discretisation error (first order) plus the grid
  // quadrature of the Hertz pressure (fixed at 128^2).
  std::vector<double> errors;
  for (const int steps : {100, 200, 400, 800})
    {
      const auto run       = run_grid_loop(paper_amplitude, 128, steps, 2);
      const auto reference = radial_reference(run.displacement);
      errors.push_back(max_difference(run.force, reference) / (mu * load));
    }
  // Observed rate of the time error: first order (implicit Euler), +-0.15
  // because the fixed grid error (~1e-4 mu P) starts to show at 800 steps.
  EXPECT_NEAR(std::log2(errors[0] / errors[1]), 1.0, 0.15);
  EXPECT_NEAR(std::log2(errors[1] / errors[2]), 1.0, 0.15);
  // At the scene's default 200 steps a cycle the loop is within 1 % of mu P of
  // the exact bristle law.
  EXPECT_LT(errors[1], 1e-2);
}

TEST(BristleLoop, PaperCaseAgainstMindlinDeresiewicz)
{
  const auto   run     = run_grid_loop(paper_amplitude, 128, 200, 8);
  const double mindlin_amplitude = MindlinLoop(mu, load, contact_radius, steel.tangential_modulus())
                                     .force_amplitude(paper_amplitude);
  // Mindlin: Q* = 280.5 N (docs/references.md §2.3). The exponential bristle law
  // slips a little everywhere, so its amplitude is lower: measured 272.6 N with
  // the semi-analytic solution, i.e. 2.8 % below; allow 4 %.
  EXPECT_NEAR(run.metrics.force_amplitude / mindlin_amplitude, 0.972, 0.012);
  // Whole-loop model difference, max |Q - Q_MD| / (mu P): 0.086 with the
  // semi-analytic bristle solution; the bristle model is not Mindlin's, so
  // this is a measured bound, not a convergence target.
  EXPECT_GT(run.metrics.error_vs_reference, 0.06);
  EXPECT_LT(run.metrics.error_vs_reference, 0.10);
  // The loop is steady after 8 cycles: the stored traction of the centre
  // cells forgets its start by a factor ~0.2 a cycle (measured change 7e-6 mu P
  // at cycle 8, 5e-4 at cycle 5).
  EXPECT_LT(run.metrics.change_from_previous_cycle, 2e-5);
}

TEST(BristleLoop, ModelDifferenceVanishesQuadraticallyAtSmallAmplitude)
{
  // Both laws start with the same stiffness 8 G* a (the calibration), so
  // their difference starts at second order in u = delta*/delta_t. The edge
  // of the contact, where p -> 0, saturates at any amplitude and adds a
  // logarithmic correction: measured rates 1.71 (u = 1/16 -> 1/32) and 1.78
  // (1/32 -> 1/64), independent of the time step. A wrong calibration would
  // leave a first-order term (rate 1).
  const double delta_t = MindlinLoop(mu, load, contact_radius, steel.tangential_modulus()).gross_slip_displacement();
  const double coarse  = run_grid_loop(delta_t / 16, 96, 400, 3).metrics.error_vs_reference;
  const double fine    = run_grid_loop(delta_t / 32, 96, 400, 3).metrics.error_vs_reference;
  EXPECT_GT(std::log2(coarse / fine), 1.6);
  EXPECT_LT(std::log2(coarse / fine), 2.1);
  EXPECT_LT(fine, 3e-3); // 0.00197 measured
}

TEST(BristleLoop, DissipatedEnergyMatchesTheBristleLaw)
{
  // Loop area of the grid model against the same integral of the
  // semi-analytic bristle solution at 800 steps a cycle (1 %: the time error).
  const auto run       = run_grid_loop(paper_amplitude, 128, 800, 3);
  const auto reference = radial_reference(run.displacement);
  double     work      = 0.0;
  const std::size_t begin = run.displacement.size() - 801;
  for (std::size_t i = begin + 1; i < run.displacement.size(); ++i)
    work += 0.5 * (reference[i] + reference[i - 1]) * (run.displacement[i] - run.displacement[i - 1]);
  EXPECT_NEAR(run.metrics.dissipated_energy / std::abs(work), 1.0, 1e-2);
  // And it exceeds Mindlin's 7.64e-5 J (docs/references.md §2.3) several times over:
  // the exponential law dissipates in the whole contact, not only the annulus.
  EXPECT_GT(run.metrics.dissipated_energy, 3.0 * 7.64e-5);
}

TEST(BristleLoop, GrossSlipAboveTransitionGivesCoulombForce)
{
  // delta* = 3 mu P (2 - nu) / (8 G a) = 7.29 um; far above it |Q| = mu P.
  const auto run = run_grid_loop(100e-6, 64, 200, 2);
  // The grid integral of the Hertz pressure differs from P by the cell
  // quadrature error (< 0.5 % at 64^2), and the exponential law approaches
  // mu p as exp(-k s / mu p): both well under 1 %.
  EXPECT_NEAR(run.metrics.force_amplitude / (mu * load), 1.0, 1e-2);
  double peak = 0.0;
  for (const double force : run.force)
    peak = std::max(peak, std::abs(force));
  EXPECT_NEAR(peak / (mu * load), run.metrics.force_amplitude / (mu * load), 1e-9);
}
