// Richardson extrapolation with its error bar, against sequences whose limit
// is known in closed form.
#include <fretsim/contact/grid_convergence.h>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using fretsim::contact::richardson_estimate;
using fretsim::contact::RichardsonSettings;

namespace
{
  // D(h) = limit - c h^q on h = 1, 2, 4.
  double power_law(double h, double limit, double c, double q) { return limit - c * std::pow(h, q); }
} // namespace

TEST(GridConvergence, PowerLawOfTheAssumedOrderIsExtrapolatedExactly)
{
  for (const double q : {0.5, 1.0, 2.0})
    {
      RichardsonSettings settings;
      settings.order = q;
      const auto e   = richardson_estimate(power_law(1, 0.78, 0.1, q), power_law(2, 0.78, 0.1, q),
                                           power_law(4, 0.78, 0.1, q), settings);
      EXPECT_NEAR(e.converged, 0.78, 1e-12) << q; // round-off of three values
      EXPECT_NEAR(e.observed_order, q, 1e-12) << q;
      EXPECT_TRUE(e.asymptotic);
      // The bar: the coarse difference carried to the limit, c (2^q - 1) 2^q / (2^q - 1).
      EXPECT_NEAR(e.error_estimate, 0.1 * std::pow(2.0, q), 1e-12) << q;
      EXPECT_LE(std::abs(e.converged - 0.78), e.error_estimate);
    }
}

TEST(GridConvergence, SlowerOrSlowingSequencesStayInsideTheBar)
{
  // The limit of sequences the square-root order does not fit: an order 0.3
  // law (the bar holds down to about 0.25), and a pre-asymptotic one (the 0.5
  // law plus a decaying bump) like the paper case's coarse grids.
  auto slow = [](double h) { return 1.0 - 0.2 * std::pow(h, 0.3); };
  auto bump = [](double h) { return 1.0 - 0.2 * std::sqrt(h) + 0.08 * h / (1.0 + h * h); };
  for (const double h : {0.05, 0.2, 0.5, 1.0})
    {
      const auto s = richardson_estimate(slow(h), slow(2 * h), slow(4 * h));
      EXPECT_LE(std::abs(s.converged - 1.0), s.error_estimate) << h;
      const auto b = richardson_estimate(bump(h), bump(2 * h), bump(4 * h));
      EXPECT_LE(std::abs(b.converged - 1.0), b.error_estimate) << h;
    }
}

TEST(GridConvergence, OscillatingSequenceHasNoOrderAndTheLargestDifferenceInTheBar)
{
  const auto e = richardson_estimate(0.70, 0.66, 0.68);
  EXPECT_TRUE(std::isnan(e.observed_order));
  EXPECT_FALSE(e.asymptotic);
  EXPECT_NEAR(e.converged, 0.70 + 0.04 / (std::sqrt(2.0) - 1.0), 1e-12);
  EXPECT_NEAR(e.error_estimate, 0.04 / (std::sqrt(2.0) - 1.0), 1e-12);
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
  RichardsonSettings s;
  s.refinement_ratio = 1.0;
  EXPECT_THROW(richardson_estimate(0.6, 0.5, 0.4, s), std::invalid_argument);
  s.refinement_ratio = 2.0;
  s.order            = 0.0;
  EXPECT_THROW(richardson_estimate(0.6, 0.5, 0.4, s), std::invalid_argument);
}
