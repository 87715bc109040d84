// The bristle law's derivatives (contact::bristle_step with
// BristleStepDerivatives: by the slip, the pressure and the stiffness)
// against central finite differences of the law, in each of its regimes:
// sticking, slipping, clamped to the Coulomb limit.
#include <fretsim/contact/bristle.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>

using namespace fretsim::contact;

namespace
{
  const double stiffness = 4e13, mu = 0.11; // [Pa/m], [-]: the bearing scene's interface

  struct State
  {
    double tau_x, tau_y, pressure, slip_x, slip_y;
  };

  /// max |analytic - central difference| / max |analytic| over ∂τ'/∂ds,
  /// ∂τ'/∂p and ∂τ'/∂k.
  double derivative_error(const State &s, BristleUpdate update = BristleUpdate::implicit_euler)
  {
    BristleStepDerivatives analytic;
    bristle_step(s.tau_x, s.tau_y, stiffness, mu, s.pressure, s.slip_x, s.slip_y, false, analytic, update);
    const auto law = [&](double pressure, double slip_x, double slip_y, double k = stiffness) {
      return bristle_step(s.tau_x, s.tau_y, k, mu * pressure, slip_x, slip_y, update);
    };
    // Steps ~1e-6 of the slip and the pressure: the law is smooth in each regime.
    const double h_slip = 1e-6 * std::hypot(s.slip_x, s.slip_y), h_pressure = 1e-6 * s.pressure;
    double       difference = 0.0, scale = 0.0;
    const auto   compare    = [&](double exact, double numeric) {
      difference = std::max(difference, std::abs(exact - numeric));
      scale      = std::max(scale, std::abs(exact));
    };
    const BristleStep plus_x = law(s.pressure, s.slip_x + h_slip, s.slip_y),
                      minus_x = law(s.pressure, s.slip_x - h_slip, s.slip_y),
                      plus_y = law(s.pressure, s.slip_x, s.slip_y + h_slip),
                      minus_y = law(s.pressure, s.slip_x, s.slip_y - h_slip);
    compare(analytic.by_slip[0][0], (plus_x.x - minus_x.x) / (2.0 * h_slip));
    compare(analytic.by_slip[1][0], (plus_x.y - minus_x.y) / (2.0 * h_slip));
    compare(analytic.by_slip[0][1], (plus_y.x - minus_y.x) / (2.0 * h_slip));
    compare(analytic.by_slip[1][1], (plus_y.y - minus_y.y) / (2.0 * h_slip));
    const BristleStep plus_p = law(s.pressure + h_pressure, s.slip_x, s.slip_y),
                      minus_p = law(s.pressure - h_pressure, s.slip_x, s.slip_y);
    const double h_stiffness = 1e-6 * stiffness;
    const BristleStep plus_k = law(s.pressure, s.slip_x, s.slip_y, stiffness + h_stiffness),
                      minus_k = law(s.pressure, s.slip_x, s.slip_y, stiffness - h_stiffness);
    // Each pair's error relative to its own scale.
    const auto pair_error = [](double exact_x, double numeric_x, double exact_y, double numeric_y) {
      const double pair_difference = std::max(std::abs(exact_x - numeric_x), std::abs(exact_y - numeric_y)),
                   pair_scale      = std::max(std::abs(exact_x), std::abs(exact_y));
      return pair_scale > 0.0 ? pair_difference / pair_scale : pair_difference;
    };
    const double slip_error     = scale > 0.0 ? difference / scale : difference;
    const double pressure_error = pair_error(analytic.by_pressure[0], (plus_p.x - minus_p.x) / (2.0 * h_pressure),
                                             analytic.by_pressure[1], (plus_p.y - minus_p.y) / (2.0 * h_pressure));
    const double stiffness_error = pair_error(analytic.by_stiffness[0], (plus_k.x - minus_k.x) / (2.0 * h_stiffness),
                                              analytic.by_stiffness[1], (plus_k.y - minus_k.y) / (2.0 * h_stiffness));
    return std::max({slip_error, pressure_error, stiffness_error});
  }

  // Central differences with a 1e-6 relative step: truncation ~1e-12, rounding
  // ~1e-10 of the derivative's scale.
  const double tolerance = 1e-6;
} // namespace

TEST(BristleDerivatives, SlipPressureAndStiffnessDerivativesMatchFiniteDifferencesWhileSticking)
{
  // k |ds| well below μp: the law is close to the spring τ + k ds.
  EXPECT_LT(derivative_error({2e6, -1e6, 1e8, 1e-9, 5e-10}), tolerance);
}

TEST(BristleDerivatives, SlipPressureAndStiffnessDerivativesMatchFiniteDifferencesWhileSlipping)
{
  // k |ds| of the order of μp: the denominator 1 + k |ds| / (μp) matters.
  EXPECT_LT(derivative_error({5e6, 3e6, 1e8, 3e-7, -2e-7}), tolerance);
}

TEST(BristleDerivatives, SlipPressureAndStiffnessDerivativesMatchFiniteDifferencesOnTheCoulombClamp)
{
  // The stored traction exceeds the new limit (the pressure dropped): τ' = μp n/|n|.
  EXPECT_LT(derivative_error({3e7, 2e7, 1e8, 1e-9, 2e-9}), tolerance);
}

TEST(BristleDerivatives, TheExponentialUpdatesDerivativesMatchFiniteDifferences)
{
  // The same three regimes (sticking, λ = k|ds|/(μp) ≈ 0.04; slipping, λ ≈ 1.3;
  // the Coulomb clamp), and a slip deep into saturation (λ ≈ 8).
  for (const State &state : {State{2e6, -1e6, 1e8, 1e-9, 5e-10}, State{5e6, 3e6, 1e8, 3e-7, -2e-7},
                             State{3e7, 2e7, 1e8, 1e-9, 2e-9}, State{5e6, 3e6, 1e8, 2e-6, 8e-7}})
    EXPECT_LT(derivative_error(state, BristleUpdate::exponential), tolerance) << state.slip_x;
}

TEST(BristleDerivatives, NoLoadNoTractionAndNoDerivative)
{
  BristleStepDerivatives derivatives;
  const BristleStep next = bristle_step(1e6, 1e6, stiffness, mu, 0.0, 1e-6, 0.0, false, derivatives);
  EXPECT_EQ(next.x, 0.0);
  EXPECT_EQ(next.y, 0.0);
  for (const auto &row : derivatives.by_slip)
    for (const double value : row)
      EXPECT_EQ(value, 0.0);
  EXPECT_EQ(derivatives.by_pressure[0], 0.0);
  EXPECT_EQ(derivatives.by_pressure[1], 0.0);
  EXPECT_EQ(derivatives.by_stiffness[0], 0.0);
  EXPECT_EQ(derivatives.by_stiffness[1], 0.0);
}

TEST(BristleDerivatives, SlidingOnAtZeroSlipTakesTheDerivativeAlongTheTraction)
{
  // At ds = 0 on a sliding cell the law barely moves along τ: ∂τ'/∂ds τ̂ = k τ̂ - k |τ|/(μp) τ̂.
  const double           pressure = 1e8, tau = 0.95 * mu * pressure;
  BristleStepDerivatives derivatives;
  bristle_step(tau, 0.0, stiffness, mu, pressure, 0.0, 0.0, true, derivatives);
  EXPECT_NEAR(derivatives.by_slip[0][0], stiffness * (1.0 - 0.95), 1e-12 * stiffness);
  EXPECT_NEAR(derivatives.by_slip[1][1], stiffness, 1e-12 * stiffness);
  EXPECT_EQ(derivatives.by_slip[0][1], 0.0);
  EXPECT_EQ(derivatives.by_slip[1][0], 0.0);
}
