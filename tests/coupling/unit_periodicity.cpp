// periodicity_error, the summary's measure of how far the interface fields
// are from repeating each ball pass: exact values on constructed histories.
#include <fretsim/coupling/periodicity.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using fretsim::coupling::periodicity_error;

namespace
{
  /// `samples` fields of three cells, sampled every 0.25 (4 per period 1):
  /// a(t) = sin(2πt + c) + drift t on every cell c.
  std::vector<std::vector<double>> history(int samples, double drift)
  {
    std::vector<std::vector<double>> fields;
    for (int k = 0; k < samples; ++k)
      {
        const double t = 0.25 * k;
        std::vector<double> field(3);
        for (int c = 0; c < 3; ++c)
          field[c] = std::sin(2.0 * M_PI * t + c) + drift * t;
        fields.push_back(field);
      }
    return fields;
  }
} // namespace

TEST(Periodicity, ARepeatingHistoryHasNoError)
{
  // Whole periods of a sine: each sample equals the one a period before up
  // to the rounding of sin's argument.
  EXPECT_LT(periodicity_error(history(12, 0.0), 0.25, 1.0), 1e-14);
}

TEST(Periodicity, ADriftShowsAsItsChangeOverAPeriodAgainstTheLargestValue)
{
  // a(t) - a(t - 1) = drift exactly; the largest |a| over the last period
  // (samples 8..11, t = 2..2.75) is at t = 2.25, c = 0 (by hand:
  // sin(4.5π) + 0.1·2.25 = 1.225).
  const double drift = 0.1;
  double       largest = 0.0;
  for (int k = 8; k < 12; ++k)
    for (int c = 0; c < 3; ++c)
      largest = std::max(largest, std::abs(std::sin(2.0 * M_PI * 0.25 * k + c) + drift * 0.25 * k));
  EXPECT_NEAR(periodicity_error(history(12, drift), 0.25, 1.0), drift / largest, 1e-14);
  EXPECT_NEAR(largest, 1.225, 1e-14);
}

TEST(Periodicity, AHistoryShorterThanTwoPeriodsHasNoMeasure)
{
  // 7 samples hold less than two periods of 4: nothing to compare the last
  // period with, so no number (the summary says null), not a made-up 1.
  EXPECT_TRUE(std::isnan(periodicity_error(history(7, 0.0), 0.25, 1.0)));
  EXPECT_FALSE(std::isnan(periodicity_error(history(8, 0.0), 0.25, 1.0)));
}
