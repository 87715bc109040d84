// The superposed stresses of a fretting history (fretting_run.h: with the
// exact masing traction each step's stresses are composed from those of the
// virgin levels and the reversals) against the reference path, a stress
// evaluation of each step's traction, on the paper case (configs/
// paper_concentrated.prm) on a coarse grid.
#include <fretsim/contact/fretting_run.h>

#include <gtest/gtest.h>
#include <omp.h>

#include "reference/paper_fretting_case.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>
#include <vector>

using namespace fretsim::contact;

namespace
{
  FrettingCase paper_case()
  {
    FrettingCase c = fretsim::reference::paper_fretting_case(3);
    // Every point computed: the mirror (verification_fretting_mirror) would
    // put the solvers' asymmetry into the comparison.
    c.mirror_symmetry = false;
    return c;
  }

  struct Difference
  {
    double stress = 0.0; ///< max |sigma - sigma_ref| over points, components and steps / max |sigma_ref|
    double risk   = 0.0; ///< max |D(t) - D_ref(t)| over points and steps
  };

  /// Both paths step by step.
  Difference compare(FrettingRun &superposed, FrettingRun &reference)
  {
    Difference difference;
    double     largest = 0.0, stress = 0.0;
    while (!reference.finished())
      {
        superposed.advance();
        reference.advance();
        const auto &a = superposed.stress().values, &b = reference.stress().values;
        for (std::size_t k = 0; k < b.size(); ++k)
          {
            largest = std::max(largest, std::abs(b[k]));
            stress  = std::max(stress, std::abs(a[k] - b[k]));
          }
        const auto &da = superposed.risk_now(), &db = reference.risk_now();
        for (std::size_t p = 0; p < db.size(); ++p)
          difference.risk = std::max(difference.risk, std::abs(da[p] - db[p]));
      }
    difference.stress = stress / largest;
    return difference;
  }
  struct Comparison
  {
    Difference  difference;
    RiskMaximum superposed, reference;
    double      von_mises_superposed = 0.0, von_mises_reference = 0.0;
  };

  /// The case with the stresses composed (the default) against a stress
  /// evaluation per step, on the same grid.
  Comparison superposed_against_reference(FrettingCase c, const SurfaceGrid &grid)
  {
    FrettingRun superposed(c, grid);
    c.superposed_stresses = false;
    FrettingRun reference(c, grid);
    EXPECT_TRUE(superposed.stresses_superposed());
    EXPECT_FALSE(reference.stresses_superposed());
    Comparison result;
    result.difference           = compare(superposed, reference);
    result.superposed           = superposed.risk_maximum();
    result.reference            = reference.risk_maximum();
    result.von_mises_superposed = superposed.von_mises_max();
    result.von_mises_reference  = reference.von_mises_max();
    return result;
  }
} // namespace

// Stresses are linear in the traction, so composing them as the traction is
// composed changes only the rounding: per value a few additions and the FFT
// evaluator's round-off of each part, ~1e-16 of the largest stress each.
// Measured at most 2.6e-16 of the largest stress over the two tests, and up
// to 1.1e-14 in D (D ~ 0.7): where two principal values lie close the Dang
// Van step's closed form keeps 40 eps (unit_dang_van), so D amplifies the
// stresses' round-off, by how much depending on the traction's last digits.
// Tolerances 1e-14 for the stresses and 3e-14 for D, with a sliding along x
// and one at an angle (both traction components), and a bulk stress on top.
TEST(FrettingRunSuperposition, EqualsAStressEvaluationPerStep)
{
  for (const double direction : {0.0, 0.6})
    {
      FrettingCase c      = paper_case();
      c.sliding_direction = direction;
      c.bulk_stress.static_surface[0]    = 1e8;
      c.bulk_stress.amplitude_surface[2] = 5e7;
      const Comparison result = superposed_against_reference(c, fretting_grid(c, 24, 24, 1.5));
      EXPECT_LT(result.difference.stress, 1e-14) << direction;
      EXPECT_LT(result.difference.risk, 3e-14) << direction;
      const RiskMaximum &a = result.superposed, &b = result.reference;
      EXPECT_NEAR(a.value, b.value, 1e-14 * b.value) << direction;
      EXPECT_EQ(a.step, b.step);
      EXPECT_EQ(a.layer, b.layer);
      EXPECT_EQ(a.i, b.i);
      EXPECT_EQ(a.j, b.j);
      EXPECT_NEAR(result.von_mises_superposed, result.von_mises_reference, 1e-14 * result.von_mises_reference);
    }
}

// Four cycles (Masing's memory pushing and closing reversals) with 26 steps a
// cycle: the level spacing, a quarter cycle's shift over 6.5, puts steps
// between levels at uneven weights. Same tolerances and reasons as above.
TEST(FrettingRunSuperposition, EqualsTheReferenceWithUnevenSteps)
{
  FrettingCase c    = paper_case();
  c.cycles          = 4;
  c.steps_per_cycle = 26;
  const Comparison result = superposed_against_reference(c, fretting_grid(c, 16, 16, 1.5));
  EXPECT_LT(result.difference.stress, 1e-14);
  EXPECT_LT(result.difference.risk, 1e-14);
  EXPECT_NEAR(result.superposed.value, result.reference.value, 1e-14);
}

// Above the memory budget the run evaluates the stresses per step: the
// reference itself, bit for bit.
TEST(FrettingRunSuperposition, OverBudgetFallsBackToTheReference)
{
  FrettingCase c         = paper_case();
  c.cycles               = 1;
  c.superposition_budget = 1000;
  const SurfaceGrid grid = fretting_grid(c, 16, 16, 1.5);
  FrettingRun       limited(c, grid);
  c.superposed_stresses = false;
  FrettingRun reference(c, grid);
  EXPECT_FALSE(limited.stresses_superposed());
  while (!reference.finished())
    {
      limited.advance();
      reference.advance();
      ASSERT_EQ(limited.stress().values, reference.stress().values);
    }
  EXPECT_EQ(limited.risk_max(), reference.risk_max());
}

// Determinism: the superposed run on one thread and on two gives the same
// D(t), D_max and von Mises maximum bit for bit (each point's arithmetic
// does not depend on the thread that does it; maxima do not depend on the
// order). FFTW's estimated plans (the case sets them): measured ones may
// differ from run to run.
TEST(FrettingRunSuperposition, SameBitsOnOneAndTwoThreads)
{
  FrettingCase c = paper_case();
  c.cycles       = 2;
  // 48^2 cells on 4 layers: enough points for every parallel loop to split.
  const SurfaceGrid grid = fretting_grid(c, 48, 48, 1.5);
  const int         threads = omp_get_max_threads();
  std::vector<double> risk_max[2];
  double              von_mises[2];
  for (const int run_threads : {1, 2})
    {
      omp_set_num_threads(run_threads);
      FrettingRun run(c, grid);
      while (!run.finished())
        run.advance();
      risk_max[run_threads - 1]  = run.risk_max();
      von_mises[run_threads - 1] = run.von_mises_max();
    }
  omp_set_num_threads(threads);
  EXPECT_EQ(risk_max[0], risk_max[1]);
  EXPECT_EQ(von_mises[0], von_mises[1]);
}

// configs/paper_concentrated.prm solves the exact model's virgin levels to a
// relative traction error of 1e-6 instead of the default 1e-8 (a third fewer
// solver iterations). Against the 1e-8 solve on 64^2 cells, D_max agrees to
// 4.5e-8; 1e-6 relative is the accuracy the run's D_max is held to (on the
// shipped 128^2, 200 steps a cycle: 4.6e-9; risk_max_converged 1.7e-7).
TEST(FrettingRunSuperposition, TheShippedSolverToleranceKeepsDMax)
{
  FrettingCase c = paper_case();
  c.cycles       = 2; // the running-mean risk peaks in the first cycle
  const SurfaceGrid grid = fretting_grid(c, 64, 64, 1.5);
  double            risk[2];
  for (const int k : {0, 1})
    {
      c.exact.tolerance = k == 0 ? 1e-8 : 1e-6;
      risk[k]           = fretting_risk_maximum(c, grid).value;
    }
  EXPECT_NEAR(risk[1], risk[0], 1e-6 * risk[0]);
  EXPECT_NE(risk[1], risk[0]) << "the tolerance must reach the level solves";
}

// configs/paper_concentrated.prm also takes FFTW's estimated plans. Two runs
// with them give the same D_max bit for bit; against measured plans (whose
// choice, and so the solves' last digits, vary from process to process) the
// same 1e-6 of the shipped tolerance holds (measured 0.9e-8 and 4.8e-8 in two
// processes, on 64^2).
TEST(FrettingRunSuperposition, EstimatedPlansRepeatAndAgreeWithMeasuredOnes)
{
  FrettingCase c    = paper_case();
  c.cycles          = 2;
  c.exact.tolerance = 1e-6;
  const SurfaceGrid grid = fretting_grid(c, 64, 64, 1.5);
  const double      estimated = fretting_risk_maximum(c, grid).value;
  EXPECT_EQ(fretting_risk_maximum(c, grid).value, estimated);
  c.exact.measure_fft_plans            = true;
  c.stress_evaluator.measure_fft_plans = true;
  const double measured = fretting_risk_maximum(c, grid).value;
  EXPECT_NEAR(measured, estimated, 1e-6 * estimated);
}

// The scene lets the error estimate's thread evaluate the history's level
// stresses (FrettingRun::defer_level_stresses): a helper thread taking them
// while the run solves its levels gives the same risk field bit for bit.
TEST(FrettingRunSuperposition, DeferredLevelStressesOnAnotherThreadGiveTheSameRisk)
{
  FrettingCase      c    = paper_case();
  c.cycles               = 1;
  const SurfaceGrid grid = fretting_grid(c, 32, 32, 1.5);
  FrettingRun       alone(c, grid);
  while (!alone.finished())
    alone.advance();

  FrettingRun deferred(c, grid);
  deferred.defer_level_stresses(true);
  std::atomic<bool> stop{false};
  std::thread       helper([&] {
    omp_set_num_threads(1);
    while (!stop)
      deferred.help_with_level_stresses();
  });
  while (!deferred.finished())
    deferred.advance();
  const std::vector<double> risk = deferred.risk_max();
  stop = true;
  helper.join();
  EXPECT_EQ(risk, alone.risk_max());
  EXPECT_EQ(deferred.risk_maximum().value, alone.risk_maximum().value);
}
