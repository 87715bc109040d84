// Dang Van criterion against theory (docs/theory.md §2.6, docs/references.md §5): the
// paper's running-mean centre converges at first order in the number of
// cycles, and a sampled non-proportional cycle converges to the continuous
// maximum within the second-order sampling bound.
#include <fretsim/contact/dang_van.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace fretsim::contact;

namespace
{
  const double           f_1 = 690e6, t_1 = 428e6; // paper material, docs/references.md §5.1
  const DangVanConstants paper = DangVanConstants::from_fatigue_limits(f_1, t_1);

  DangVanSettings settings(ResidualStressCentre centre, int steps_per_cycle)
  {
    DangVanSettings s;
    s.centre          = centre;
    s.steps_per_cycle = steps_per_cycle;
    return s;
  }

  /// Least-squares slope of log y against log x.
  double log_slope(const std::vector<double> &x, const std::vector<double> &y)
  {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const double n = static_cast<double>(x.size());
    for (std::size_t k = 0; k < x.size(); ++k)
      {
        const double lx = std::log(x[k]), ly = std::log(y[k]);
        sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
      }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
  }
} // namespace

TEST(dang_van_verification, RunningMeanConvergesAtFirstOrderInCycles)
{
  // sigma_xx = f_-1 sin(wt): D_max = 1 - m_K, m_K the running mean at the
  // last tension peak, ~ 1/(2 pi (K - 3/4)) (docs/references.md §5.3 limit D = 1).
  // Over K = 8..256 the continuous model's slope is -1.03; assert -1 +- 0.1.
  const int           steps_per_cycle = 64;
  std::vector<double> cycles, error;
  for (int k = 8; k <= 256; k *= 2)
    {
      DangVanField field(1, paper, settings(ResidualStressCentre::running_mean, steps_per_cycle));
      for (int n = 0; n < k * steps_per_cycle; ++n)
        {
          StressTensor s;
          s.xx = f_1 * std::sin(2.0 * M_PI * n / steps_per_cycle);
          field.add_step(&s.xx, 1);
        }
      cycles.push_back(k);
      error.push_back(1.0 - field.risk_max()[0]);
      EXPECT_GT(error.back(), 0.0);
      // Continuous-time value, to 5 % (sampling shifts the mean slightly).
      EXPECT_NEAR(error.back() * 2.0 * M_PI * (k - 0.75), 1.0, 0.05) << k << " cycles";
    }
  EXPECT_NEAR(log_slope(cycles, error), -1.0, 0.1);
}

TEST(dang_van_verification, OutOfPhaseTensionTorsionConvergesWithSampling)
{
  // sigma_xx = 400 sin(wt + phi), tau_xy = 250 cos(wt + phi) MPa: an ellipse
  // in deviator space, centrally symmetric for even N, so both per-cycle
  // centres are 0 and tau(t) = sqrt(sigma^2/4 + tau_xy^2). Continuous maximum
  // of D(w) = sqrt(s^2/4 + t^2 c^2) / (beta - alpha s sin/3) found by a fine
  // scan plus Newton. A sample lies within pi/N of the maximiser, so
  // 0 <= D* - D_max(N) <= |D''| (pi/N)^2 / 2 (+10 % for the cubic term at
  // N = 32); the error times N^2 is then bounded, i.e. second order.
  const double sa = 400e6, ta = 250e6, phi = 0.123; // phi: the peak is not sampled
  const double alpha = paper.alpha, beta = paper.beta;
  auto         risk  = [&](double w) {
    const double s = sa * std::sin(w), t = ta * std::cos(w);
    return std::sqrt(0.25 * s * s + t * t) / (beta - alpha * s / 3.0);
  };
  double best = 0.0, w_star = 0.0;
  for (int k = 0; k < 100000; ++k)
    {
      const double w = 2.0 * M_PI * k / 100000;
      if (risk(w) > best)
        best = risk(w), w_star = w;
    }
  const double h = 1e-4;
  for (int it = 0; it < 20; ++it) // Newton on D'(w) = 0 by central differences
    {
      const double d1 = (risk(w_star + h) - risk(w_star - h)) / (2 * h);
      const double d2 = (risk(w_star + h) - 2 * risk(w_star) + risk(w_star - h)) / (h * h);
      w_star -= d1 / d2;
    }
  const double exact     = risk(w_star);
  const double curvature = std::abs((risk(w_star + h) - 2 * exact + risk(w_star - h)) / (h * h));
  EXPECT_GT(exact, 0.5);

  for (const auto centre : {ResidualStressCentre::last_cycle_mean, ResidualStressCentre::hypersphere})
    for (int n = 32; n <= 1024; n *= 2)
      {
        DangVanField field(1, paper, settings(centre, n));
        for (int step = 0; step < 2 * n; ++step)
          {
            const double w = 2.0 * M_PI * step / n + phi;
            StressTensor s;
            s.xx = sa * std::sin(w);
            s.xy = ta * std::cos(w);
            field.add_step(&s.xx, 1);
          }
        const double error = exact - field.risk_max()[0];
        EXPECT_GE(error, -1e-12) << to_string(centre) << ", N = " << n; // samples never exceed the maximum
        EXPECT_LE(error, 1.1 * 0.5 * curvature * (M_PI / n) * (M_PI / n)) << to_string(centre) << ", N = " << n;
      }
}
