// The exact traction by Masing's superposition (masing_traction.h) against
// the incremental exact solver it replaces, step by step, and its memory rule,
// gross slip and refusals.
#include <fretsim/contact/fretting_loop.h>
#include <fretsim/contact/masing_traction.h>
#include <fretsim/contact/material.h>
#include <fretsim/contact/partial_slip.h>

#include "reference/hertz_field.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

using namespace fretsim::contact;

namespace
{
  const double       a = 0.75e-3, p0 = 1.06e9;
  const MaterialPair steel{{200e9, 0.3}, {200e9, 0.3}};

  SurfaceGrid grid() { return SurfaceGrid::centred(32, 32, 1.6 * a, 1.6 * a); }

  Field hertz(const SurfaceGrid &g) { return fretsim::reference::hertz_pressure_field(g, a, p0); }

  double largest_difference(const Field &u, const Field &v)
  {
    double result = 0.0;
    for (std::size_t c = 0; c < u.size(); ++c)
      result = std::max(result, std::abs(u[c] - v[c]));
    return result;
  }

  struct Differences
  {
    double rms_traction = 0.0; ///< largest over steps of the RMS over loaded cells, over mu p0
    double force        = 0.0; ///< largest over steps, over mu P
  };

  /// The superposition against the incremental solver over two cycles of
  /// harmonic sliding, 40 steps a cycle, virgin levels every amplitude / 50.
  Differences harmonic_difference(double mu, double amplitude, double direction, const MaterialPair &materials)
  {
    const auto          g = grid();
    const Field         p = hertz(g);
    PartialSlipSolver   exact(g, materials);
    PartialSlipSettings settings;
    settings.masing_level_spacing = amplitude / 50;
    MasingTraction        masing(g, materials, settings);
    const int             steps = 40;
    const HarmonicSliding sliding{amplitude, 1.0};
    const double          mu_P = mu * integrate(g, p);
    double                previous = 0.0;
    Differences           worst;
    for (int n = 1; n <= 2 * steps; ++n)
      {
        const double d = sliding.displacement(double(n) / steps), inc = d - previous;
        previous       = d;
        exact.advance(p, mu, inc * std::cos(direction), inc * std::sin(direction));
        masing.advance(p, mu, inc * std::cos(direction), inc * std::sin(direction));
        double sum = 0.0;
        int    loaded = 0;
        for (std::size_t c = 0; c < p.size(); ++c)
          if (p[c] > 0.0)
            {
              sum += std::pow(exact.traction_x()[c] - masing.traction_x()[c], 2) +
                     std::pow(exact.traction_y()[c] - masing.traction_y()[c], 2);
              ++loaded;
            }
        worst.rms_traction = std::max(worst.rms_traction, std::sqrt(sum / loaded) / (mu * p0));
        const double force = std::hypot(integrate(g, exact.traction_x()) - integrate(g, masing.traction_x()),
                                        integrate(g, exact.traction_y()) - integrate(g, masing.traction_y()));
        worst.force = std::max(worst.force, force / mu_P);
      }
    return worst;
  }
} // namespace

TEST(MasingTraction, FollowsTheIncrementalExactSolverThroughTwoCycles)
{
  // Partial slip of the paper's steel pair (gross slip at 7.3 um), along x,
  // y and 30 degrees. What differs: the linear interpolation between virgin
  // levels (the slip front moves between two levels) and the neglected Poisson
  // cross compliance. Measured at 32 x 32 cells: RMS 2.0e-3 mu p0 (x and
  // y), 2.8e-3 (30 degrees); force 2.7e-5 and 5.2e-5 mu P.
  for (const double direction : {0.0, M_PI / 2, M_PI / 6})
    {
      const auto d = harmonic_difference(0.53, 2.241e-6, direction, steel);
      EXPECT_LT(d.rms_traction, 4e-3) << direction;
      EXPECT_LT(d.force, 1e-4) << direction;
    }
}

TEST(MasingTraction, DissimilarMaterialsAndGrossSlip)
{
  // Aluminium under steel (the solver neglects the normal-tangential coupling,
  // as the superposition does), and an amplitude of 2.4 times the gross-slip
  // one, where the slip front sweeps the contact fastest just before gross
  // slip and the interpolation errs most. Measured: aluminium RMS 4.8e-4 mu
  // p0, force 1.4e-5 mu P; gross slip RMS 1.6e-2 mu p0, force 5.1e-4 mu P.
  const MaterialPair aluminium_on_steel{{70e9, 0.33}, {200e9, 0.3}};
  const auto dissimilar = harmonic_difference(0.53, 2.241e-6, 0.0, aluminium_on_steel);
  EXPECT_LT(dissimilar.rms_traction, 1e-3);
  EXPECT_LT(dissimilar.force, 3e-5);
  const auto gross = harmonic_difference(0.3, 10e-6, 0.0, steel);
  EXPECT_LT(gross.rms_traction, 3e-2);
  EXPECT_LT(gross.force, 1e-3);
}

TEST(MasingTraction, AClosedInnerLoopRejoinsTheOuterBranch)
{
  // Load to 2 um, unload to 1 um, reload to 2 um (the inner loop closes), then
  // down to 1 um: the traction equals that of the path without the inner
  // loop (Masing's memory), to round-off.
  const auto     g = grid();
  const Field    p = hertz(g);
  MasingTraction with_loop(g, steel, PartialSlipSettings{}), without(g, steel, PartialSlipSettings{});
  for (const double inc : {0.5e-6, 0.5e-6, 0.5e-6, 0.5e-6})
    {
      with_loop.advance(p, 0.53, inc, 0.0);
      without.advance(p, 0.53, inc, 0.0);
    }
  for (const double inc : {-0.5e-6, -0.5e-6, 0.5e-6, 0.5e-6, -1.0e-6}) // inner loop, then down
    with_loop.advance(p, 0.53, inc, 0.0);
  without.advance(p, 0.53, -1.0e-6, 0.0);
  EXPECT_LT(largest_difference(with_loop.traction_x(), without.traction_x()), 1e-9 * p0);
  // Going on down past the mirror (-2 um) of the reversal at +2 um rejoins
  // the virgin curve: at -3.5 um the traction is the virgin one of a path
  // that went straight there (same 0.5 um levels; the solver's tolerance).
  for (const double inc : {-1.0e-6, -1.0e-6, -1.0e-6, -1.0e-6, -0.5e-6}) // from +1 um down to -3.5 um
    without.advance(p, 0.53, inc, 0.0);
  MasingTraction virgin_only(g, steel, PartialSlipSettings{});
  for (int n = 0; n < 7; ++n)
    virgin_only.advance(p, 0.53, -0.5e-6, 0.0);
  EXPECT_LT(largest_difference(without.traction_x(), virgin_only.traction_x()), 1e-6 * 0.53 * p0);
}

TEST(MasingTraction, RefusesWhatTheSuperpositionCannotDo)
{
  const auto     g = grid();
  Field          p = hertz(g);
  MasingTraction masing(g, steel, PartialSlipSettings{});
  masing.advance(p, 0.53, 1e-6, 0.0);
  EXPECT_THROW(masing.advance(p, 0.53, 0.0, 1e-6), std::logic_error); // the shift turns
  EXPECT_THROW(masing.advance(p, 0.4, 1e-6, 0.0), std::logic_error);  // mu changes
  Field other = p;
  other[g.index(g.nx / 2, g.ny / 2)] *= 1.01; // the centre of the contact
  EXPECT_THROW(masing.advance(other, 0.53, 1e-6, 0.0), std::logic_error); // the pressure changes
  masing.reset();
  EXPECT_NO_THROW(masing.advance(p, 0.4, 0.0, 1e-6));
}
