// Richardson extrapolation with its error bar, against sequences whose limit
// is known in closed form.
#include <fretsim/contact/grid_convergence.h>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using fretsim::contact::richardson_estimate;

namespace
{
  // D(h) = limit - c h^q on h = 1, 2, 4.
  double power_law(double h, double limit, double c, double q) { return limit - c * std::pow(h, q); }
} // namespace

TEST(GridConvergence, ExactPowerLawRecoversTheLimitAndTheOrder)
{
  for (const double q : {0.5, 0.7, 1.0, 2.0})
    {
      const auto e = richardson_estimate(power_law(1, 0.78, 0.1, q), power_law(2, 0.78, 0.1, q),
                                         power_law(4, 0.78, 0.1, q));
      EXPECT_NEAR(e.observed_order, q, 1e-12) << q; // round-off of three values
      EXPECT_NEAR(e.converged, 0.78, 1e-12) << q;
      EXPECT_TRUE(e.asymptotic);
      // The bar is 1.25 times the extrapolation D_inf - D_h = c h^q.
      EXPECT_NEAR(e.error_estimate, 1.25 * 0.1, 1e-12) << q;
    }
}

TEST(GridConvergence, AHigherOrderTermStaysInsideTheBar)
{
  // D(h) = 1 - 0.2 h^0.7 - 0.05 h^1.4: the leading term dominates but the
  // three-grid order is off; the true limit must still lie within the bar.
  auto d = [](double h) { return 1.0 - 0.2 * std::pow(h, 0.7) - 0.05 * std::pow(h, 1.4); };
  for (const double h : {0.05, 0.2, 0.5})
    {
      const auto e = richardson_estimate(d(h), d(2 * h), d(4 * h));
      EXPECT_LE(std::abs(e.converged - 1.0), e.error_estimate) << h;
    }
}

TEST(GridConvergence, OscillatingSequenceKeepsTheFinestValueWithAWideBar)
{
  const auto e = richardson_estimate(0.70, 0.66, 0.68);
  EXPECT_EQ(e.converged, 0.70);
  EXPECT_FALSE(e.asymptotic);
  EXPECT_TRUE(std::isnan(e.observed_order));
  EXPECT_NEAR(e.error_estimate, 3.0 * 0.04, 1e-15);
}

TEST(GridConvergence, StalledSequenceAssumesTheSlowestOrder)
{
  // Differences 0.06 then 0.061: an order near 0, below the 0.3 believed.
  const auto e = richardson_estimate(0.629, 0.568, 0.507);
  EXPECT_FALSE(e.asymptotic);
  const double correction = 0.061 / (std::pow(2.0, 0.3) - 1.0);
  EXPECT_NEAR(e.converged, 0.629 + correction, 1e-12);
  EXPECT_NEAR(e.error_estimate, 3.0 * correction, 1e-12);
}

TEST(GridConvergence, EqualValuesHaveNoError)
{
  const auto e = richardson_estimate(0.5, 0.5, 0.5);
  EXPECT_EQ(e.converged, 0.5);
  EXPECT_EQ(e.error_estimate, 0.0);
}

TEST(GridConvergence, BadInputIsRefused)
{
  EXPECT_THROW(richardson_estimate(NAN, 0.5, 0.4), std::invalid_argument);
  fretsim::contact::RichardsonSettings s;
  s.refinement_ratio = 1.0;
  EXPECT_THROW(richardson_estimate(0.6, 0.5, 0.4, s), std::invalid_argument);
}
