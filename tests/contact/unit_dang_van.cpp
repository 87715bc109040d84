// Dang Van criterion (docs/theory.md §2.6) against the definitions and check values
// of docs/references.md §5: fatigue-limit cases, the three residual-stress
// centres, infinite risk, invariance, the eigenvalue routine against Eigen's
// iterative solver and the minimum enclosing ball against brute force.
#include <fretsim/contact/dang_van.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

using namespace fretsim::contact;

namespace
{
  // Paper material (docs/references.md §5.1): f_-1 = 690 MPa, t_-1 = 428 MPa.
  const double f_1 = 690e6, t_1 = 428e6;
  const double alpha_paper = 3.0 * (t_1 / f_1 - 0.5); // 0.360870
  const double beta_paper  = t_1;
  const DangVanConstants paper{alpha_paper, beta_paper};
  const double two_pi = 2.0 * M_PI;

  const ResidualStressCentre all_centres[] = {ResidualStressCentre::running_mean,
                                              ResidualStressCentre::last_cycle_mean,
                                              ResidualStressCentre::hypersphere};

  using History = std::function<StressTensor(std::size_t point, std::int64_t step)>;

  /// Runs `steps` steps of `history` on `points` points through the flat
  /// Voigt interface, checking after every step that no NaN appears.
  DangVanField run(std::size_t points, const DangVanSettings &settings, std::int64_t steps, const History &history,
                   const DangVanConstants &constants = paper)
  {
    DangVanField        field(points, constants, settings);
    std::vector<double> voigt(6 * points);
    for (std::int64_t n = 0; n < steps; ++n)
      {
        for (std::size_t p = 0; p < points; ++p)
          {
            const StressTensor s = history(p, n);
            for (int c = 0; c < 6; ++c)
              voigt[6 * p + c] = s[c];
          }
        field.add_step(voigt.data(), points);
        for (std::size_t p = 0; p < points; ++p)
          if (std::isnan(field.risk()[p]) || std::isnan(field.risk_max()[p]))
            ADD_FAILURE() << "NaN risk at step " << n << ", point " << p;
      }
    return field;
  }

  DangVanSettings with(ResidualStressCentre centre, int steps_per_cycle, int warmup_cycles = 0)
  {
    DangVanSettings s;
    s.centre          = centre;
    s.steps_per_cycle = steps_per_cycle;
    s.warmup_cycles   = warmup_cycles;
    return s;
  }

  StressTensor uniaxial(double value)
  {
    StressTensor s;
    s.xx = value;
    return s;
  }

  StressTensor shear_xy(double value)
  {
    StressTensor s;
    s.xy = value;
    return s;
  }

  double phase(std::int64_t step, int steps_per_cycle) { return two_pi * static_cast<double>(step) / steps_per_cycle; }

  /// R diag(a, b, c) R^T for the rotation with Euler angles (z, x', z'').
  StressTensor rotated(double a, double b, double c, double phi, double theta, double psi)
  {
    const double c1 = std::cos(phi), s1 = std::sin(phi), c2 = std::cos(theta), s2 = std::sin(theta),
                 c3 = std::cos(psi), s3 = std::sin(psi);
    const double r[3][3] = {{c1 * c3 - c2 * s1 * s3, -c1 * s3 - c2 * c3 * s1, s1 * s2},
                            {c3 * s1 + c1 * c2 * s3, c1 * c2 * c3 - s1 * s3, -c1 * s2},
                            {s2 * s3, c3 * s2, c2}};
    const double d[3]    = {a, b, c};
    double       m[3][3] = {};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k)
          m[i][j] += r[i][k] * d[k] * r[j][k];
    StressTensor s;
    s.xx = m[0][0];
    s.yy = m[1][1];
    s.zz = m[2][2];
    s.yz = 0.5 * (m[1][2] + m[2][1]);
    s.xz = 0.5 * (m[0][2] + m[2][0]);
    s.xy = 0.5 * (m[0][1] + m[1][0]);
    return s;
  }

  /// Uniaxial sigma_xx(n) (or shear tau_xy(n) when shear) with the running mean
  /// of docs/references.md §5 evaluated as a scalar: the mesoscopic deviator is that of
  /// (x_n - m_n) along the same axis, so tau = |x_n - m_n|/2 (uniaxial) or
  /// |x_n - m_n| (shear). Independent of the library's tensor machinery.
  double scalar_running_mean_risk_max(const std::function<double(std::int64_t)> &x, std::int64_t steps,
                                      std::int64_t first_counted, bool shear)
  {
    double sum = 0.0, worst = 0.0;
    for (std::int64_t n = 0; n < steps; ++n)
      {
        const double value = x(n);
        sum += value;
        const double mean  = sum / static_cast<double>(n + 1);
        const double tau   = shear ? std::abs(value - mean) : 0.5 * std::abs(value - mean);
        const double hydro = shear ? 0.0 : value / 3.0;
        if (n >= first_counted)
          worst = std::max(worst, tau / (beta_paper - alpha_paper * hydro));
      }
    return worst;
  }
} // namespace

// ---------------------------------------------------------------- constants

TEST(dang_van_constants, PaperMaterial)
{
  const DangVanConstants c = DangVanConstants::from_fatigue_limits(f_1, t_1);
  // docs/references.md §5.1: alpha = 3*428/690 - 1.5 = 0.360870 (6 digits given), beta = 428 MPa.
  EXPECT_NEAR(c.alpha, 0.360870, 5e-7);
  EXPECT_NEAR(c.alpha, 3.0 * 428.0 / 690.0 - 1.5, 1e-15); // same formula, round-off only
  EXPECT_EQ(c.beta, 428e6);
}

TEST(dang_van_constants, RejectsMeaninglessLimits)
{
  EXPECT_THROW(DangVanConstants::from_fatigue_limits(0.0, t_1), std::invalid_argument);
  EXPECT_THROW(DangVanConstants::from_fatigue_limits(f_1, -1.0), std::invalid_argument);
  EXPECT_THROW(DangVanConstants::from_fatigue_limits(std::nan(""), t_1), std::invalid_argument);
  EXPECT_THROW(DangVanConstants::from_fatigue_limits(f_1, std::numeric_limits<double>::infinity()),
               std::invalid_argument);
  // t/f < 1/2: alpha < 0.
  EXPECT_THROW(DangVanConstants::from_fatigue_limits(f_1, 0.49 * f_1), std::invalid_argument);
  // Swapped arguments (t > f).
  EXPECT_THROW(DangVanConstants::from_fatigue_limits(t_1, f_1), std::invalid_argument);
  try
    {
      DangVanConstants::from_fatigue_limits(t_1, f_1);
    }
  catch (const std::invalid_argument &e)
    {
      EXPECT_NE(std::string(e.what()).find("swapped"), std::string::npos) << e.what();
    }
  // The limits of the accepted range: t/f = 1/2 is Tresca (alpha = 0), t/f = 1 gives alpha = 1.5.
  EXPECT_EQ(DangVanConstants::from_fatigue_limits(f_1, 0.5 * f_1).alpha, 0.0);
  EXPECT_NEAR(DangVanConstants::from_fatigue_limits(f_1, f_1).alpha, 1.5, 1e-15);
}

TEST(dang_van_field, RejectsBadSetup)
{
  EXPECT_THROW(DangVanField(0, paper), std::invalid_argument);
  EXPECT_THROW(DangVanField(1, DangVanConstants{0.3, 0.0}), std::invalid_argument);
  EXPECT_THROW(DangVanField(1, DangVanConstants{-0.1, 4e8}), std::invalid_argument);
  EXPECT_THROW(DangVanField(1, DangVanConstants{std::nan(""), 4e8}), std::invalid_argument);
  EXPECT_THROW(DangVanField(1, paper, with(ResidualStressCentre::hypersphere, -1)), std::invalid_argument);
  EXPECT_THROW(DangVanField(1, paper, with(ResidualStressCentre::hypersphere, 4, -1)), std::invalid_argument);
}

TEST(dang_van_field, CentreNames)
{
  for (const auto centre : all_centres)
    EXPECT_EQ(parse_residual_stress_centre(to_string(centre)), centre);
  try
    {
      parse_residual_stress_centre("mean");
      ADD_FAILURE() << "no exception";
    }
  catch (const std::invalid_argument &e)
    {
      EXPECT_NE(std::string(e.what()).find("hypersphere"), std::string::npos) << e.what();
    }
}

TEST(dang_van_field, RejectsBadStepsAndKeepsState)
{
  DangVanField        field(2, paper, with(ResidualStressCentre::last_cycle_mean, 0));
  std::vector<double> voigt(12, 1e8);
  EXPECT_THROW(field.end_cycle(), std::logic_error); // no step yet
  field.add_step(voigt.data(), 2);
  const std::vector<double> before = field.risk();
  EXPECT_THROW(field.add_step(voigt.data(), 3), std::invalid_argument);
  voigt[7] = std::nan("");
  EXPECT_THROW(field.add_step(voigt.data(), 2), std::invalid_argument);
  voigt[7] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(field.add_step(voigt.data(), 2), std::invalid_argument);
  StressField wrong;
  wrong.resize(1, 1, 3);
  EXPECT_THROW(field.add_step(wrong), std::invalid_argument);
  EXPECT_EQ(field.step_count(), 1);
  EXPECT_EQ(field.risk(), before);
  field.end_cycle();
  EXPECT_THROW(field.end_cycle(), std::logic_error); // empty cycle
  EXPECT_EQ(field.complete_cycles(), 1);
}

// ------------------------------------------------------ principal stresses

TEST(dang_van_eigenvalues, ExactCases)
{
  // Diagonal, pure shear and hydrostatic states: round-off only.
  StressTensor d;
  d.xx = -3e8, d.yy = 5e8, d.zz = 1e8;
  const auto l = principal_stresses(d);
  EXPECT_NEAR(l[0], 5e8, 1e-6);
  EXPECT_NEAR(l[1], 1e8, 1e-6);
  EXPECT_NEAR(l[2], -3e8, 1e-6);
  EXPECT_NEAR(tresca_shear(d), 4e8, 1e-6);
  EXPECT_NEAR(tresca_shear(shear_xy(-2e8)), 2e8, 1e-6);
  StressTensor h;
  h.xx = h.yy = h.zz = 7e8;
  EXPECT_EQ(tresca_shear(h), 0.0);
  EXPECT_NEAR(principal_stresses(h)[2], 7e8, 1e-6);
}

TEST(dang_van_eigenvalues, AgreeWithEigenIncludingRepeatedValues)
{
  // Random symmetric A = Q diag(l1, l1 + gap (l1 - l3), l3) Q^T, Q random
  // orthogonal, gap from well separated down to exactly repeated, with and
  // without a large hydrostatic part. Eigen's SelfAdjointEigenSolver::compute
  // (tridiagonal QR) and the library's routine are both backward stable, so
  // they agree to ~10 eps |A| where the library rotates (two values within
  // 0.2 % of the spread); above that its closed form keeps ~40 eps (measured
  // worst 1.2e-14). 1e-12 |A| leaves a factor ~90 and is stricter
  // than the 1e-9 required; a closed form down to repeated values loses
  // ~sqrt(eps) and fails it. (Eigen's closed-form computeDirect misses this by far:
  // 1e-8 at repeated values.)
  std::mt19937_64                  rng(20240611);
  std::normal_distribution<double> normal;
  double                           worst = 0.0;
  for (const double gap : {1.0, 0.3, 1e-2, 1e-3, 1e-4, 1e-6, 1e-8, 1e-10, 1e-13, 0.0})
    for (int trial = 0; trial < 2000; ++trial)
      {
        const double l1 = 3e8 * normal(rng), l3 = 3e8 * normal(rng);
        const double l2 = l1 + (trial % 2 ? gap : -gap) * std::abs(l1 - l3);
        const double offset = trial % 3 == 0 ? 3e9 * normal(rng) : 0.0;
        const StressTensor a =
          rotated(l1 + offset, l2 + offset, l3 + offset, two_pi * normal(rng), two_pi * normal(rng), two_pi * normal(rng));
        const auto   ours = principal_stresses(a);
        const auto   ref  = detail::principal_stresses_reference(a);
        const double norm = std::max(std::abs(ref[0]), std::abs(ref[2]));
        for (int k = 0; k < 3; ++k)
          worst = std::max(worst, std::abs(ours[k] - ref[k]) / norm);
        worst = std::max(worst, std::abs(tresca_shear(a) - 0.5 * (ref[0] - ref[2])) / norm);
        EXPECT_GE(ours[0], ours[1]);
        EXPECT_GE(ours[1], ours[2]);
      }
  EXPECT_LT(worst, 1e-12);
}

TEST(dang_van_eigenvalues, NewtonLodeFactorEqualsTheTrigonometricForm)
{
  // g(x) = sin(acos(x)/3 + pi/3) by Newton's method against the long double
  // trigonometric value on 200001 points of [-1, 1]. The double trigonometric
  // form is within 2.5e-16 there; so is Newton's (measured 2.5e-16); 3e-16
  // fails if one Newton step is dropped (2e-11).
  double worst = 0.0, worst_trigonometric = 0.0;
  for (int k = 0; k <= 200000; ++k)
    {
      const double      x         = -1.0 + k / 100000.0;
      const long double reference = std::sin(std::acos(static_cast<long double>(x)) / 3 + std::acos(-1.0L) / 3);
      worst = std::max(worst, static_cast<double>(std::abs(detail::lode_tresca_factor(x) - reference)));
      worst_trigonometric =
        std::max(worst_trigonometric, static_cast<double>(std::abs(std::sin(std::acos(x) / 3.0 + M_PI / 3.0) - reference)));
    }
  EXPECT_LT(worst, 3e-16);
  EXPECT_LT(worst_trigonometric, 3e-16);
  EXPECT_EQ(detail::lode_tresca_factor(1.0), detail::lode_tresca_factor(-1.0));
  EXPECT_NEAR(detail::lode_tresca_factor(0.0), 1.0, 2.3e-16);
}

TEST(dang_van_field, BlockStepEqualsThePointwiseDefinition)
{
  // The field's step (blocks of points, vectorised, Jacobi for near-repeated
  // principal values) against D = tresca_shear(Sigma - dev(M_n)) /
  // (beta - alpha sigma_H) per point with the running mean M_n in deviator
  // coordinates: 3 layers of 23 x 29 points (blocks end inside layers),
  // random states mixed with repeated principal values, zero deviators and
  // pure hydrostatic tension. The same operations in both: equal to 1e-15
  // relative (measured 0: only a compiler contracting differently could part them).
  const int         layers = 3, ny = 23, nx = 29, steps = 7;
  const std::size_t n = static_cast<std::size_t>(layers) * ny * nx;
  std::mt19937_64   rng(5);
  std::normal_distribution<double> normal;
  DangVanField                     field(n, paper, with(ResidualStressCentre::running_mean, 0));
  std::vector<std::array<double, 5>> mean(n, std::array<double, 5>{});
  StressField                      stress;
  stress.resize(layers, ny, nx);
  double worst = 0.0;
  std::size_t repeated = 0;
  for (int step = 0; step < steps; ++step)
    {
      std::vector<double> expected(n);
      for (int l = 0; l < layers; ++l)
        for (int j = 0; j < ny; ++j)
          for (int i = 0; i < nx; ++i)
            {
              const std::size_t p    = (static_cast<std::size_t>(l) * ny + j) * nx + i;
              StressTensor      s;
              const int         kind = static_cast<int>(p % 5);
              if (kind == 0) // repeated principal values: axisymmetric about an axis fixed per point
                {
                  const double side = 3e8 * normal(rng);
                  s = rotated(side, side, 2e8 * normal(rng), 0.1 * p, 0.37 * p, 0.0);
                }
              else if (kind == 1) // the same state every step: w = 0 from the first step on
                s.xx = 1e8, s.yy = -2e8, s.xy = 5e7;
              else if (kind == 2) // hydrostatic tension beyond beta / alpha: D infinite
                s.xx = s.yy = s.zz = 2e9;
              else
                for (int c = 0; c < 6; ++c)
                  s[c] = 2e8 * normal(rng);
              for (int c = 0; c < 6; ++c)
                stress.at(l, c, j, i) = s[c];
              const auto u = detail::deviator_coordinates(s);
              double     w[5];
              for (int d = 0; d < 5; ++d)
                {
                  mean[p][d] += (u[d] - mean[p][d]) * (1.0 / static_cast<double>(step + 1));
                  w[d] = u[d] - mean[p][d];
                }
              const StressTensor centred = detail::deviator_from_coordinates({w[0], w[1], w[2], w[3], w[4]});
              const auto         values  = detail::principal_stresses_reference(centred);
              const double       spread  = values[0] - values[2];
              repeated += spread > 0.0 && std::min(values[0] - values[1], values[1] - values[2]) < 1e-6 * spread;
              const double denominator = beta_paper - alpha_paper * ((s.xx + s.yy + s.zz) * (1.0 / 3.0));
              expected[p] = denominator > 0.0 ? detail::tresca_shear_of_deviator(w) / denominator
                                              : std::numeric_limits<double>::infinity();
            }
      field.add_step(stress);
      for (std::size_t p = 0; p < n; ++p)
        if (std::isinf(expected[p]))
          ASSERT_EQ(field.risk()[p], expected[p]) << p;
        else
          worst = std::max(worst, std::abs(field.risk()[p] - expected[p]) / std::max(expected[p], 1e-300));
    }
  EXPECT_GT(repeated, n / 10); // the Jacobi branch is exercised
  EXPECT_LT(worst, 1e-15);
}

TEST(dang_van_eigenvalues, DeviatorCoordinatesAreOrthonormal)
{
  // |u|^2 = s:s (docs/references.md §5.2's sqrt2 scaling of the shears), and the
  // inverse map gives back the deviator: exact up to round-off.
  StressTensor s;
  s.xx = 1.1e8, s.yy = -2.3e8, s.zz = 0.7e8, s.yz = 0.4e8, s.xz = -1.9e8, s.xy = 0.6e8;
  const double mean = (s.xx + s.yy + s.zz) / 3.0;
  const double d[6] = {s.xx - mean, s.yy - mean, s.zz - mean, s.yz, s.xz, s.xy};
  const double ss   = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 2 * (d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);
  const auto   u    = detail::deviator_coordinates(s);
  double       uu   = 0.0;
  for (const double v : u)
    uu += v * v;
  EXPECT_NEAR(uu / ss, 1.0, 1e-14);
  const StressTensor back = detail::deviator_from_coordinates(u);
  for (int c = 0; c < 6; ++c)
    EXPECT_NEAR(back[c], d[c], 1e-15 * 3e8);
}

// -------------------------------------------------- fatigue-limit check cases

TEST(dang_van_field, FullyReversedBendingAtTheLimit)
{
  // sigma_xx = f_-1 sin(wt): D = 1 (docs/references.md §5.3), attained at the
  // tension peak where tau = f/2, sigma_H = f/3 and beta - alpha f/3 = f/2.
  const int    steps_per_cycle = 64, cycles = 200; // peaks sampled exactly (64 divisible by 4)
  const History history = [&](std::size_t, std::int64_t n) { return uniaxial(f_1 * std::sin(phase(n, steps_per_cycle))); };

  // Per-cycle centres: the path is the segment +-f about 0, so the centre is 0
  // from cycle 2 on and D_max = 1 to round-off (1e-12).
  for (const auto centre : {ResidualStressCentre::last_cycle_mean, ResidualStressCentre::hypersphere})
    EXPECT_NEAR(run(1, with(centre, steps_per_cycle), 3 * steps_per_cycle, history).risk_max()[0], 1.0, 1e-12)
      << to_string(centre);

  // Running mean (paper eq. 5): the mean of sin over the steps so far is
  // positive, m ~ 1/(2 pi (k - 3/4)) at the k-th tension peak, so D_max =
  // 1 - m approaches 1 from below like 1/n. After K = 200 cycles the
  // continuous-time bound is 1/(2 pi 199.25) = 8.0e-4; assert within 1e-3,
  // and equal to the scalar evaluation of the same running mean to 1e-12.
  const auto   field    = run(1, with(ResidualStressCentre::running_mean, steps_per_cycle), cycles * steps_per_cycle, history);
  const double expected = scalar_running_mean_risk_max(
    [&](std::int64_t n) { return f_1 * std::sin(phase(n, steps_per_cycle)); }, cycles * steps_per_cycle, 0, false);
  EXPECT_NEAR(field.risk_max()[0], expected, 1e-12);
  EXPECT_LE(field.risk_max()[0], 1.0);
  EXPECT_GT(field.risk_max()[0], 1.0 - 1e-3);
  // Set at the last tension peak (the running-mean error is smallest there).
  EXPECT_EQ(field.risk_max_step()[0], (cycles - 1) * steps_per_cycle + steps_per_cycle / 4);
}

TEST(dang_van_field, FullyReversedBendingAtHalfTheLimit)
{
  // Amplitude A = f/2: D = (A/2) / (beta - alpha A/3) at the tension peak,
  // = (f/4)/(t - alpha f/6) = (f/4)/(t/2 + f/4) (alpha f/6 = t/2 - f/4), so the
  // expected 0.446 agrees: 172.5/386.5 = 0.446313 (compression peak:
  // 172.5/469.5 = 0.367). Per-cycle centres: round-off (1e-12).
  const int     steps_per_cycle = 64;
  const double  expected        = (f_1 / 4) / (t_1 / 2 + f_1 / 4);
  const History history = [&](std::size_t, std::int64_t n) { return uniaxial(0.5 * f_1 * std::sin(phase(n, steps_per_cycle))); };
  EXPECT_NEAR(expected, 0.446313, 5e-7);
  EXPECT_NEAR(expected, (f_1 / 4) / (t_1 - alpha_paper * f_1 / 6), 1e-15);
  for (const auto centre : {ResidualStressCentre::last_cycle_mean, ResidualStressCentre::hypersphere})
    {
      const auto field = run(1, with(centre, steps_per_cycle), 4 * steps_per_cycle, history);
      EXPECT_NEAR(field.risk_max()[0], expected, 1e-12) << to_string(centre);
      // Every cycle from the second repeats the same value; the first occurrence
      // (cycle 2's tension peak) is kept, cycle 1 is not counted.
      EXPECT_EQ(field.risk_max_step()[0], steps_per_cycle + steps_per_cycle / 4) << to_string(centre);
    }
  // Running mean: after the first cycle D = expected (1 - m) at the tension
  // peaks, m < 1/(2 pi (k - 3/4)), so with 200 warm-up cycles D_max is below
  // the limit value by < 8e-4 relative: assert 1e-3.
  const auto settled =
    run(1, with(ResidualStressCentre::running_mean, steps_per_cycle, 200), 201 * steps_per_cycle, history);
  EXPECT_LE(settled.risk_max()[0], expected);
  EXPECT_NEAR(settled.risk_max()[0] / expected, 1.0, 1e-3);
  // Without warm-up the paper's estimator overshoots in cycle 1: near
  // wt = 4 pi/3 the mean is still +0.36 A while sigma = -0.87 A, giving D =
  // 0.454, 1.8 % above the limit value (at amplitude f it is 0.85 < 1, so
  // there the transient is harmless). Scalar evaluation of the same
  // recursion, round-off only (1e-12).
  const auto   raw       = run(1, with(ResidualStressCentre::running_mean, steps_per_cycle), 2 * steps_per_cycle, history);
  const double transient = scalar_running_mean_risk_max(
    [&](std::int64_t n) { return 0.5 * f_1 * std::sin(phase(n, steps_per_cycle)); }, 2 * steps_per_cycle, 0, false);
  EXPECT_NEAR(raw.risk_max()[0], transient, 1e-12);
  EXPECT_NEAR(raw.risk_max()[0], 0.4544, 1e-4);
  EXPECT_LT(raw.risk_max_step()[0], steps_per_cycle);
}

TEST(dang_van_field, FullyReversedTorsionAtTheLimit)
{
  // tau_xy = t_-1 sin(wt): sigma_H = 0, tau = t, D = 1 (docs/references.md §5.3).
  const int     steps_per_cycle = 64;
  const History history = [&](std::size_t, std::int64_t n) { return shear_xy(t_1 * std::sin(phase(n, steps_per_cycle))); };
  for (const auto centre : {ResidualStressCentre::last_cycle_mean, ResidualStressCentre::hypersphere})
    EXPECT_NEAR(run(1, with(centre, steps_per_cycle), 3 * steps_per_cycle, history).risk_max()[0], 1.0, 1e-12)
      << to_string(centre);
  // Running mean: in torsion the error sits at the reversed peak, D = 1 + m,
  // so the transient of the first cycles (D = 1.21 at the first reversed
  // peak) would dominate D_max: skip 200 warm-up cycles; then D_max =
  // 1 + 1/(2 pi 200.75) = 1 + 7.9e-4 in continuous time; assert the scalar
  // evaluation to 1e-12 and the limit to 1e-3.
  const int  cycles = 220, warmup = 200;
  const auto field =
    run(1, with(ResidualStressCentre::running_mean, steps_per_cycle, warmup), cycles * steps_per_cycle, history);
  const double expected =
    scalar_running_mean_risk_max([&](std::int64_t n) { return t_1 * std::sin(phase(n, steps_per_cycle)); },
                                 cycles * steps_per_cycle, warmup * steps_per_cycle, true);
  EXPECT_NEAR(field.risk_max()[0], expected, 1e-12);
  EXPECT_GE(field.risk_max()[0], 1.0);
  EXPECT_LT(field.risk_max()[0], 1.0 + 1e-3);
  EXPECT_GE(field.risk_max_step()[0], warmup * steps_per_cycle);
}

TEST(dang_van_field, PulsatingTensionCheckValue)
{
  // sigma_xx from 0 to 600 MPa: centre = mean = midpoint, tau_max = 150 MPa at
  // sigma_H = 200 MPa, D = 150/(428 - 0.36087*200) = 0.421554 (docs/references.md §5.3,
  // 6 digits). Per-cycle centres to round-off; the running mean after 200
  // cycles to 1e-3: its error is <= 300 MPa/(pi K) in the mean, i.e.
  // <= 150/(pi K)/355.8 = 6.7e-4 in D.
  const int     steps_per_cycle = 64;
  const double  exact           = 150e6 / (t_1 - alpha_paper * 200e6);
  const History history         = [&](std::size_t, std::int64_t n) {
    return uniaxial(300e6 * (1.0 - std::cos(phase(n, steps_per_cycle))));
  };
  EXPECT_NEAR(exact, 0.421554, 5e-7);
  for (const auto centre : {ResidualStressCentre::last_cycle_mean, ResidualStressCentre::hypersphere})
    EXPECT_NEAR(run(1, with(centre, steps_per_cycle), 3 * steps_per_cycle, history).risk_max()[0], exact, 1e-12)
      << to_string(centre);
  const auto field =
    run(1, with(ResidualStressCentre::running_mean, steps_per_cycle, 200), 201 * steps_per_cycle, history);
  EXPECT_NEAR(field.risk_max()[0], exact, 1e-3);
}

// ---------------------------------------------------------- constant stress

TEST(dang_van_field, ConstantStressHasNoRisk)
{
  // A constant state is its own centre: D = 0 exactly from the first step for
  // the running mean (M_1 = Sigma_1) and the provisional centre of cycle 1,
  // and from cycle 2 for the per-cycle centres (a mean of equal values and the
  // ball of one point). Allow 1e-15 for the mean's round-off.
  StressTensor s;
  s.xx = 2e8, s.yy = -1e8, s.zz = 5e7, s.yz = 3e7, s.xz = -4e7, s.xy = 6e7;
  for (const auto centre : all_centres)
    {
      const auto field = run(1, with(centre, 10), 30, [&](std::size_t, std::int64_t) { return s; });
      EXPECT_LE(field.risk()[0], 1e-15) << to_string(centre);
      EXPECT_LE(field.risk_max()[0], 1e-15) << to_string(centre);
    }
}

TEST(dang_van_field, SwitchedOnConstantStressDecaysUnderTheRunningMean)
{
  // Zero for k steps, then constant Sigma: M_n = (n - k)/n Sigma, so the
  // mesoscopic deviator is (k/n) dev Sigma and D_n = (k/n) tau(Sigma) /
  // (beta - alpha sigma_H): decays like 1/n to 0 (round-off 1e-12). The
  // per-cycle centres give 0 once a cycle holds only the constant.
  const int    k = 50, steps = 10000;
  StressTensor s;
  s.xx = 3e8, s.yy = 1e8, s.xy = 1.2e8;
  const History history = [&](std::size_t, std::int64_t n) { return n < k ? StressTensor{} : s; };
  const double  hydro   = (s.xx + s.yy + s.zz) / 3.0;
  const double  full    = tresca_shear(s) / (beta_paper - alpha_paper * hydro);
  const auto    field   = run(1, with(ResidualStressCentre::running_mean, 0), steps, history);
  EXPECT_NEAR(field.risk()[0], full * k / steps, 1e-12);
  EXPECT_LT(field.risk()[0], 0.01 * full);
  for (const auto centre : {ResidualStressCentre::last_cycle_mean, ResidualStressCentre::hypersphere})
    EXPECT_LE(run(1, with(centre, k), 3 * k, history).risk()[0], 1e-15) << to_string(centre);
}

// --------------------------------------------- the three centres compared

TEST(dang_van_field, CentresAgreeOnHarmonicCycles)
{
  // Point 0: proportional with a mean, sigma_xx = 150 + 300 sin, tau_xy =
  // 50 + 100 sin [MPa]; point 1: non-proportional, sigma_xx = 150 + 300 sin,
  // tau_xy = 100 + 180 cos (an ellipse in deviator space whose major axis ends
  // are sampled). For both, the cycle mean, the running mean's limit and the
  // enclosing ball's centre coincide (the path is centrally symmetric).
  // Per-cycle centres agree to round-off (1e-12). The running mean after 300
  // warm-up cycles is off by <= |amplitude|/(pi K) ~ 0.3 MPa in the centre,
  // so by ~0.3/350 ~ 1e-3 of D at most: assert 1e-3.
  const int     steps_per_cycle = 48;
  const History history         = [&](std::size_t p, std::int64_t n) {
    const double w = phase(n, steps_per_cycle);
    StressTensor s;
    s.xx = 150e6 + 300e6 * std::sin(w);
    s.xy = p == 0 ? 50e6 + 100e6 * std::sin(w) : 100e6 + 180e6 * std::cos(w);
    return s;
  };
  const auto mean_field = run(2, with(ResidualStressCentre::last_cycle_mean, steps_per_cycle), 3 * steps_per_cycle, history);
  const auto ball_field = run(2, with(ResidualStressCentre::hypersphere, steps_per_cycle), 3 * steps_per_cycle, history);
  const auto running =
    run(2, with(ResidualStressCentre::running_mean, steps_per_cycle, 300), 301 * steps_per_cycle, history);
  for (int p = 0; p < 2; ++p)
    {
      EXPECT_GT(mean_field.risk_max()[p], 0.3); // a non-trivial state
      EXPECT_NEAR(ball_field.risk_max()[p], mean_field.risk_max()[p], 1e-12) << p;
      EXPECT_NEAR(running.risk_max()[p], mean_field.risk_max()[p], 1e-3) << p;
    }
}

TEST(dang_van_field, CentresDifferOnADwellCycle)
{
  // sigma_xx = 600 MPa for 80 % of each cycle and 0 for the rest. The path is
  // the segment from dev(0) to dev(600 MPa xx):
  //  - enclosing ball: centre at the midpoint (300 MPa), tau = 150 MPa at both
  //    ends; D = 150/(428 - 0.36087*200) = 0.421554 (at the 600 MPa dwell);
  //  - cycle mean: centre at 480 MPa; at 600 MPa tau = 60 MPa, D = 60/355.83 =
  //    0.168622, at 0 tau = 240 MPa, sigma_H = 0, D = 240/428 = 0.560748.
  // The mean-based D_max is higher by 0.139193 (x1.330) and sits at the
  // unloaded instants; the ball's at the dwell. The running mean tends to
  // the cycle mean (error ~ 0.11/K in D after K cycles: 1e-3 for K = 200).
  const int     steps_per_cycle = 100;
  const History history = [&](std::size_t, std::int64_t n) { return uniaxial(n % steps_per_cycle < 20 ? 0.0 : 600e6); };
  const double  denominator = t_1 - alpha_paper * 200e6;
  const double  ball_risk = 150e6 / denominator, mean_risk = 240e6 / t_1;
  EXPECT_NEAR(ball_risk, 0.421554, 5e-7);
  EXPECT_NEAR(mean_risk, 0.560748, 5e-7);
  EXPECT_NEAR(mean_risk - ball_risk, 0.139193, 5e-7);

  const auto ball  = run(1, with(ResidualStressCentre::hypersphere, steps_per_cycle), 3 * steps_per_cycle, history);
  const auto mean  = run(1, with(ResidualStressCentre::last_cycle_mean, steps_per_cycle), 3 * steps_per_cycle, history);
  const auto runm  = run(1, with(ResidualStressCentre::running_mean, steps_per_cycle, 200), 201 * steps_per_cycle, history);
  EXPECT_NEAR(ball.risk_max()[0], ball_risk, 1e-12);
  EXPECT_NEAR(mean.risk_max()[0], mean_risk, 1e-12);
  EXPECT_NEAR(runm.risk_max()[0], mean_risk, 1e-3);
  EXPECT_NEAR(mean.risk_max()[0] - ball.risk_max()[0], 0.139193, 1e-6);
  EXPECT_GE(ball.risk_max_step()[0] % steps_per_cycle, 20); // at the dwell
  EXPECT_LT(mean.risk_max_step()[0] % steps_per_cycle, 20); // unloaded
}

// ------------------------------------------------------------ infinite risk

TEST(dang_van_field, NonPositiveDenominatorIsInfiniteAndCounted)
{
  // alpha = 0.5, beta = 400 MPa: beta - alpha sigma_H <= 0 from sigma_H =
  // 800 MPa (exactly representable, so the boundary case is exactly 0).
  const DangVanConstants c{0.5, 400e6};
  const int              steps_per_cycle = 8;
  const History          history = [&](std::size_t p, std::int64_t n) {
    const double w = phase(n, steps_per_cycle);
    StressTensor s;
    switch (p)
      {
        case 0: // always above: hydrostatic 1 GPa with a cyclic shear
          s.xx = s.yy = s.zz = 1e9;
          s.xy = 1e8 * std::sin(w);
          break;
        case 1: // exactly at the boundary, no shear: 0/0 must not appear
          s.xx = s.yy = s.zz = 800e6;
          break;
        case 2: // crosses it at part of the cycle only (ends below it)
          s.xx = s.yy = s.zz = 500e6 * (1.0 - std::cos(w));
          break;
        default: // an ordinary point
          s.xx = 2e8 * std::sin(w);
      }
    return s;
  };
  for (const auto centre : all_centres)
    {
      const auto field = run(4, with(centre, steps_per_cycle), 3 * steps_per_cycle, history, c);
      const double inf = std::numeric_limits<double>::infinity();
      EXPECT_EQ(field.risk()[0], inf);
      EXPECT_EQ(field.risk()[1], inf);
      EXPECT_TRUE(std::isfinite(field.risk()[2])); // last step: sigma_H = 0
      EXPECT_TRUE(std::isfinite(field.risk()[3]));
      EXPECT_EQ(field.infinite_risk_count(), 2u) << to_string(centre);
      EXPECT_EQ(field.risk_max()[2], inf);
      EXPECT_TRUE(std::isfinite(field.risk_max()[3]));
      EXPECT_EQ(field.infinite_risk_max_count(), 3u) << to_string(centre);
    }
}

// ------------------------------------------------------------- invariance

TEST(dang_van_field, RotatedStateGivesTheSameRisk)
{
  // Non-proportional principal-axis history diag(a(t), b(t), c(t)) and the
  // same history in rotated axes: tau, sigma_H, the means and the ball are
  // invariant, so D(t) agrees at every step. Round-off of the rotation and
  // the two eigenvalue paths (closed form / Jacobi): 1e-12 relative.
  const int     steps_per_cycle = 40;
  auto          principal = [&](std::int64_t n) {
    const double w = phase(n, steps_per_cycle);
    return std::array<double, 3>{3e8 + 2e8 * std::sin(w), -1e8 + 1.5e8 * std::cos(w), 0.5e8 * std::sin(2 * w)};
  };
  const History history = [&](std::size_t p, std::int64_t n) {
    const auto l = principal(n);
    return p == 0 ? rotated(l[0], l[1], l[2], 0.0, 0.0, 0.0) : rotated(l[0], l[1], l[2], 0.7, 1.1, -2.3);
  };
  for (const auto centre : all_centres)
    {
      DangVanField        field(2, paper, with(centre, steps_per_cycle));
      std::vector<double> voigt(12);
      double              worst = 0.0;
      for (std::int64_t n = 0; n < 3 * steps_per_cycle; ++n)
        {
          for (std::size_t p = 0; p < 2; ++p)
            for (int c = 0; c < 6; ++c)
              voigt[6 * p + c] = history(p, n)[c];
          field.add_step(voigt.data(), 2);
          worst = std::max(worst, std::abs(field.risk()[1] - field.risk()[0]) / std::max(field.risk()[0], 1e-3));
        }
      EXPECT_LT(worst, 1e-12) << to_string(centre);
      EXPECT_NEAR(field.risk_max()[1], field.risk_max()[0], 1e-12 * field.risk_max()[0]) << to_string(centre);
      EXPECT_GT(field.risk_max()[0], 0.1);
    }
}

// ------------------------------------------------------- interfaces, state

TEST(dang_van_field, StressFieldLayoutMatchesVoigtInput)
{
  // Point p = (layer ny + j) nx + i in both interfaces; identical arithmetic.
  const int   layers = 2, ny = 3, nx = 4, steps_per_cycle = 12;
  StressField stress;
  stress.resize(layers, ny, nx);
  const std::size_t n = static_cast<std::size_t>(layers) * ny * nx;
  for (const auto centre : all_centres)
    {
      DangVanField        from_field(n, paper, with(centre, steps_per_cycle));
      DangVanField        from_voigt(n, paper, with(centre, steps_per_cycle));
      std::vector<double> voigt(6 * n);
      for (int step = 0; step < 3 * steps_per_cycle; ++step)
        {
          const double w = phase(step, steps_per_cycle);
          for (int l = 0; l < layers; ++l)
            for (int j = 0; j < ny; ++j)
              for (int i = 0; i < nx; ++i)
                {
                  const std::size_t p = (static_cast<std::size_t>(l) * ny + j) * nx + i;
                  for (int c = 0; c < 6; ++c)
                    {
                      const double v = 1e7 * ((c + 1) * std::sin(w + 0.3 * p) + 0.5 * c * std::cos(2 * w + i - j + l));
                      stress.at(l, c, j, i) = v;
                      voigt[6 * p + c]      = v;
                    }
                }
          from_field.add_step(stress);
          from_voigt.add_step(voigt.data(), n);
          ASSERT_EQ(from_field.risk(), from_voigt.risk()) << to_string(centre);
        }
      EXPECT_EQ(from_field.risk_max(), from_voigt.risk_max());
      EXPECT_EQ(from_field.risk_max_step(), from_voigt.risk_max_step());
    }
}

TEST(dang_van_field, BlockSourceEqualsTheStressField)
{
  // The same steps given as a field and made block by block by a source
  // (layers of 700 points: blocks end inside layers): the same values reach
  // the same arithmetic, so D and D_max are equal bit for bit.
  const int   layers = 3, ny = 20, nx = 35, steps_per_cycle = 8;
  StressField stress;
  stress.resize(layers, ny, nx);
  const std::size_t plane = static_cast<std::size_t>(ny) * nx, n = layers * plane;
  for (const auto centre : all_centres)
    {
      DangVanField from_field(n, paper, with(centre, steps_per_cycle));
      DangVanField from_source(n, paper, with(centre, steps_per_cycle));
      for (int step = 0; step < 3 * steps_per_cycle; ++step)
        {
          const double w = phase(step, steps_per_cycle);
          for (int l = 0; l < layers; ++l)
            for (int j = 0; j < ny; ++j)
              for (int i = 0; i < nx; ++i)
                for (int c = 0; c < 6; ++c)
                  stress.at(l, c, j, i) = 1e8 * ((c + 1) * std::sin(w + 0.01 * (i + nx * j)) + 0.5 * c * std::cos(2 * w + l));
          from_field.add_step(stress);
          from_source.add_step(plane, [&](std::size_t layer, std::size_t first, std::size_t count, double *const *out) {
            ASSERT_LE(count, DangVanField::block_size);
            for (int c = 0; c < 6; ++c)
              for (std::size_t k = 0; k < count; ++k)
                out[c][k] = stress.values[(layer * 6 + c) * plane + first + k];
          });
          ASSERT_EQ(from_field.risk(), from_source.risk()) << to_string(centre);
        }
      EXPECT_EQ(from_field.risk_max(), from_source.risk_max());
      EXPECT_EQ(from_field.risk_max_step(), from_source.risk_max_step());
    }
  DangVanField field(n, paper);
  EXPECT_THROW(field.add_step(plane + 1, [](std::size_t, std::size_t, std::size_t, double *const *) {}),
               std::invalid_argument);
  EXPECT_EQ(field.step_count(), 0);
  // A non-finite value is reported after the step.
  EXPECT_THROW(field.add_step(plane,
                              [](std::size_t layer, std::size_t first, std::size_t count, double *const *out) {
                                for (int c = 0; c < 6; ++c)
                                  std::fill(out[c], out[c] + count, 1e8);
                                if (layer == 2 && first == 0)
                                  out[4][count - 1] = std::numeric_limits<double>::quiet_NaN();
                              }),
               std::invalid_argument);
}

TEST(dang_van_field, StepBatchesEqualStepByStep)
{
  // Batches of 1 to 11 steps (crossing cycle ends, the warm-up's end and
  // the per-cycle centres' changes) against one step at a time: the same
  // arithmetic per point and step, so D, D_max and its step are equal bit
  // for bit.
  const int         layers = 2, ny = 9, nx = 40, steps_per_cycle = 8, cycles = 4;
  const std::size_t plane = static_cast<std::size_t>(ny) * nx, n = layers * plane;
  const auto value = [&](int step, std::size_t layer, int c, std::size_t cell) {
    const double w = phase(step, steps_per_cycle);
    return 1e8 * ((c + 1) * std::sin(w + 0.013 * cell) + 0.5 * c * std::cos(2 * w + layer)) + (c < 3 ? 5e7 : 0.0);
  };
  for (const auto centre : all_centres)
    for (const int warmup : {0, 1})
      {
        DangVanField by_step(n, paper, with(centre, steps_per_cycle, warmup));
        DangVanField batched(n, paper, with(centre, steps_per_cycle, warmup));
        int          done = 0;
        for (int batch = 1; done < cycles * steps_per_cycle; batch = batch % 11 + 1)
          {
            const int count = std::min(batch, cycles * steps_per_cycle - done);
            for (int k = 0; k < count; ++k)
              by_step.add_step(plane, [&](std::size_t layer, std::size_t first, std::size_t size, double *const *out) {
                for (int c = 0; c < 6; ++c)
                  for (std::size_t q = 0; q < size; ++q)
                    out[c][q] = value(done + k, layer, c, first + q);
              });
            batched.add_steps(plane, static_cast<std::size_t>(count),
                              [&](std::size_t step, std::size_t layer, std::size_t first, std::size_t size,
                                  double *const *out) {
                                ASSERT_LE(size, DangVanField::block_size);
                                for (int c = 0; c < 6; ++c)
                                  for (std::size_t q = 0; q < size; ++q)
                                    out[c][q] = value(done + static_cast<int>(step), layer, c, first + q);
                              });
            done += count;
            ASSERT_EQ(by_step.step_count(), batched.step_count());
            ASSERT_EQ(by_step.complete_cycles(), batched.complete_cycles());
            ASSERT_EQ(by_step.risk(), batched.risk()) << to_string(centre) << " after step " << done;
            ASSERT_EQ(by_step.infinite_risk_count(), batched.infinite_risk_count());
          }
        EXPECT_EQ(by_step.risk_max(), batched.risk_max()) << to_string(centre);
        EXPECT_EQ(by_step.risk_max_step(), batched.risk_max_step()) << to_string(centre);
      }
  // A non-finite value is reported after the batch, which counts.
  DangVanField field(n, paper);
  EXPECT_THROW(field.add_steps(plane, 3,
                               [](std::size_t step, std::size_t layer, std::size_t first, std::size_t count,
                                  double *const *out) {
                                 for (int c = 0; c < 6; ++c)
                                   std::fill(out[c], out[c] + count, 1e8);
                                 if (step == 1 && layer == 1 && first == 0)
                                   out[2][0] = std::numeric_limits<double>::infinity();
                               }),
               std::invalid_argument);
  EXPECT_EQ(field.step_count(), 3);
  EXPECT_THROW(field.add_steps(plane + 1, 2, [](std::size_t, std::size_t, std::size_t, std::size_t, double *const *) {}),
               std::invalid_argument);
}

TEST(dang_van_field, ProportionalPulsatingFieldMatchesClosedForm)
{
  // 3 x 32 x 32 = 3072 points (above the OpenMP threshold, so the parallel
  // path runs) fed as a StressField, each Sigma(t) = lambda(t) P with its own
  // random peak tensor P and lambda = (1 - cos wt)/2 in [0, 1] (sampled at 0 and
  // 1). The centre is P/2 for every option, so tau(t) = |lambda - 1/2| tau(P)
  // and D_max = (tau(P)/2) / (beta - alpha max(sigma_H(P), 0)) (the endpoints
  // maximise D for beta > alpha sigma_H/2). Per-cycle centres: round-off,
  // 1e-12 relative.
  const int         layers = 3, ny = 32, nx = 32, steps_per_cycle = 16;
  const std::size_t n = static_cast<std::size_t>(layers) * ny * nx;
  std::mt19937_64                        rng(5);
  std::uniform_real_distribution<double> uniform(-2.5e8, 2.5e8);
  std::vector<StressTensor>              peak(n);
  for (auto &p : peak)
    for (int c = 0; c < 6; ++c)
      p[c] = uniform(rng);
  for (const auto centre : {ResidualStressCentre::last_cycle_mean, ResidualStressCentre::hypersphere})
    {
      DangVanField field(n, paper, with(centre, steps_per_cycle));
      StressField  stress;
      stress.resize(layers, ny, nx);
      for (int step = 0; step < 3 * steps_per_cycle; ++step)
        {
          const double lambda = 0.5 * (1.0 - std::cos(phase(step, steps_per_cycle)));
          for (int l = 0; l < layers; ++l)
            for (int j = 0; j < ny; ++j)
              for (int i = 0; i < nx; ++i)
                for (int c = 0; c < 6; ++c)
                  stress.at(l, c, j, i) = lambda * peak[(static_cast<std::size_t>(l) * ny + j) * nx + i][c];
          field.add_step(stress);
        }
      double worst = 0.0;
      for (std::size_t p = 0; p < n; ++p)
        {
          const double hydro    = (peak[p].xx + peak[p].yy + peak[p].zz) / 3.0;
          const double expected = 0.5 * tresca_shear(peak[p]) / (beta_paper - alpha_paper * std::max(hydro, 0.0));
          worst                 = std::max(worst, std::abs(field.risk_max()[p] / expected - 1.0));
        }
      EXPECT_LT(worst, 1e-12) << to_string(centre);
      EXPECT_EQ(field.infinite_risk_max_count(), 0u);
    }
}

TEST(dang_van_field, ManualCycleEndsEqualAutomaticOnesAndResetRestarts)
{
  const int     steps_per_cycle = 16;
  const History history         = [&](std::size_t p, std::int64_t n) {
    const double w = phase(n, steps_per_cycle);
    StressTensor s;
    s.xx = 2e8 * std::sin(w) + 1e8 * p;
    s.yz = 1e8 * std::cos(w) * std::cos(w);
    return s;
  };
  for (const auto centre : all_centres)
    {
      const auto          automatic = run(3, with(centre, steps_per_cycle), 4 * steps_per_cycle, history);
      DangVanField        manual(3, paper, with(centre, 0));
      std::vector<double> voigt(18);
      for (int pass = 0; pass < 2; ++pass)
        {
          for (std::int64_t n = 0; n < 4 * steps_per_cycle; ++n)
            {
              for (std::size_t p = 0; p < 3; ++p)
                for (int c = 0; c < 6; ++c)
                  voigt[6 * p + c] = history(p, n)[c];
              manual.add_step(voigt.data(), 3);
              if ((n + 1) % steps_per_cycle == 0)
                manual.end_cycle();
            }
          EXPECT_EQ(manual.complete_cycles(), 4);
          EXPECT_EQ(manual.risk(), automatic.risk()) << to_string(centre) << " pass " << pass;
          EXPECT_EQ(manual.risk_max(), automatic.risk_max()) << to_string(centre) << " pass " << pass;
          EXPECT_EQ(manual.risk_max_step(), automatic.risk_max_step()) << to_string(centre);
          manual.reset(); // the second pass must repeat the first exactly
          EXPECT_EQ(manual.step_count(), 0);
        }
    }
}

TEST(dang_van_field, WarmupAndMaximumBookkeeping)
{
  const int     steps_per_cycle = 16;
  const History history = [&](std::size_t, std::int64_t n) { return uniaxial(3e8 * std::sin(phase(n, steps_per_cycle))); };
  // Per-cycle centres: nothing is counted in cycle 1.
  auto field = run(1, with(ResidualStressCentre::hypersphere, steps_per_cycle), steps_per_cycle - 1, history);
  EXPECT_FALSE(field.maximum_active());
  EXPECT_EQ(field.risk_max_step()[0], -1);
  EXPECT_EQ(field.risk_max()[0], 0.0);
  EXPECT_GT(field.risk()[0], 0.0); // D(t) is reported with the provisional centre
  // Running mean with 2 warm-up cycles: the maximum starts at step 32.
  field = run(1, with(ResidualStressCentre::running_mean, steps_per_cycle, 2), 3 * steps_per_cycle, history);
  EXPECT_GE(field.risk_max_step()[0], 2 * steps_per_cycle);
  field.reset_maximum();
  EXPECT_EQ(field.risk_max_step()[0], -1);
  // The hypersphere's path store is reserved up front: 5 doubles per point and step.
  const DangVanField big(1000, paper, with(ResidualStressCentre::hypersphere, 200));
  EXPECT_GE(big.memory_bytes(), 1000u * 200u * 5u * sizeof(double));
}

// ------------------------------------------------- minimum enclosing ball

namespace
{
  using Point = std::array<double, 5>;

  double distance(const Point &a, const double *b)
  {
    double s = 0.0;
    for (int k = 0; k < 5; ++k)
      s += (a[k] - b[k]) * (a[k] - b[k]);
    return std::sqrt(s);
  }

  std::vector<double> flatten(const std::vector<Point> &points)
  {
    std::vector<double> flat;
    for (const auto &p : points)
      flat.insert(flat.end(), p.begin(), p.end());
    return flat;
  }

  /// Independent brute force: for every subset U (<= 6 points), the sphere
  /// through U centred in aff(U) (Gauss elimination with partial pivoting);
  /// the MEB is the unique one whose centre has barycentric weights >= 0 and
  /// which holds every point (KKT). Slack 1e-12: ~1000 times the round-off of
  /// the elimination, so only the exact ball passes.
  bool brute_force_ball(const std::vector<Point> &points, Point &centre, double &radius)
  {
    const int m = static_cast<int>(points.size());
    for (unsigned mask = 1; mask < (1u << m); ++mask)
      {
        std::vector<int> u;
        for (int i = 0; i < m; ++i)
          if (mask & (1u << i))
            u.push_back(i);
        const int k = static_cast<int>(u.size()) - 1;
        if (k > 5)
          continue;
        std::vector<std::vector<double>> a(k, std::vector<double>(k + 1));
        std::vector<Point>               v(k);
        for (int j = 0; j < k; ++j)
          for (int d = 0; d < 5; ++d)
            v[j][d] = points[u[j + 1]][d] - points[u[0]][d];
        for (int i = 0; i < k; ++i)
          {
            for (int j = 0; j < k; ++j)
              for (int d = 0; d < 5; ++d)
                a[i][j] += 2.0 * v[i][d] * v[j][d];
            for (int d = 0; d < 5; ++d)
              a[i][k] += v[i][d] * v[i][d];
          }
        bool singular = false;
        for (int c = 0; c < k && !singular; ++c)
          {
            int pivot = c;
            for (int r = c + 1; r < k; ++r)
              if (std::abs(a[r][c]) > std::abs(a[pivot][c]))
                pivot = r;
            std::swap(a[c], a[pivot]);
            if (std::abs(a[c][c]) < 1e-9 * std::abs(a[0][0]) + 1e-300)
              singular = true;
            for (int r = 0; r < k && !singular; ++r)
              if (r != c)
                {
                  const double f = a[r][c] / a[c][c];
                  for (int j = c; j <= k; ++j)
                    a[r][j] -= f * a[c][j];
                }
          }
        if (singular)
          continue;
        Point  c      = points[u[0]];
        double weight = 1.0;
        bool   inside = true;
        for (int j = 0; j < k; ++j)
          {
            const double mu = a[j][k] / a[j][j];
            weight -= mu;
            inside = inside && mu >= -1e-12;
            for (int d = 0; d < 5; ++d)
              c[d] += mu * v[j][d];
          }
        if (!inside || weight < -1e-12)
          continue;
        const double r     = distance(points[u[0]], c.data());
        bool         holds = true;
        for (const auto &p : points)
          holds = holds && distance(p, c.data()) <= r * (1 + 1e-12) + 1e-14;
        if (holds)
          {
            centre = c;
            radius = r;
            return true;
          }
      }
    return false;
  }
} // namespace

TEST(dang_van_ball, AnalyticCases)
{
  double c[5];
  // One point, repeated: radius 0 at the point.
  std::vector<Point> same(7, Point{1, 2, 3, 4, 5});
  EXPECT_EQ(detail::minimum_enclosing_ball(flatten(same).data(), same.size(), c), 0.0);
  EXPECT_EQ(c[4], 5.0);
  // Segment with interior points (a proportional path): the midpoint.
  std::vector<Point> segment;
  for (int i = 0; i <= 10; ++i)
    segment.push_back(Point{-1.0 + 0.3 * i, 2.0 - 0.1 * i, 0, 0, 0.5 * i});
  const double r = detail::minimum_enclosing_ball(flatten(segment).data(), segment.size(), c);
  EXPECT_NEAR(r, 0.5 * std::sqrt(3.0 * 3.0 + 1.0 * 1.0 + 5.0 * 5.0), 1e-14);
  EXPECT_NEAR(c[0], 0.5, 1e-14);
  EXPECT_NEAR(c[1], 1.5, 1e-14);
  EXPECT_NEAR(c[4], 2.5, 1e-14);
  // 360 points on a circle in a 2-D plane (cospherical, the out-of-phase
  // tension-torsion path) plus interior points: centre and radius of the circle.
  std::vector<Point> circle;
  for (int i = 0; i < 360; ++i)
    {
      const double t = two_pi * i / 360.0;
      circle.push_back(Point{1 + 2 * std::cos(t), 0, -3 + 2 * std::sin(t), 0, 7});
      circle.push_back(Point{1 + 1.5 * std::cos(3 * t), 0, -3 + 0.5 * std::sin(t), 0, 7});
    }
  EXPECT_NEAR(detail::minimum_enclosing_ball(flatten(circle).data(), circle.size(), c), 2.0, 1e-13);
  EXPECT_NEAR(c[0], 1.0, 1e-13);
  EXPECT_NEAR(c[2], -3.0, 1e-13);
  EXPECT_NEAR(c[1], 0.0, 1e-13);
  // Regular simplex in R^5: e_1..e_5 and (g, ..., g) with |e_i - g 1|^2 = 2,
  // i.e. 5 g^2 - 2 g - 1 = 0. The vertices are equidistant from their
  // centroid, which lies inside: the centre.
  std::vector<Point> simplex;
  const double       g = (1.0 - std::sqrt(6.0)) / 5.0;
  for (int i = 0; i < 5; ++i)
    {
      Point p{};
      p[i] = 1.0;
      simplex.push_back(p);
    }
  simplex.push_back(Point{g, g, g, g, g});
  Point centroid{};
  for (const auto &p : simplex)
    for (int d = 0; d < 5; ++d)
      centroid[d] += p[d] / 6.0;
  const double rs = detail::minimum_enclosing_ball(flatten(simplex).data(), simplex.size(), c);
  for (int d = 0; d < 5; ++d)
    EXPECT_NEAR(c[d], centroid[d], 1e-14);
  for (const auto &p : simplex)
    EXPECT_NEAR(distance(p, centroid.data()), rs, 1e-14);
  EXPECT_THROW(detail::minimum_enclosing_ball(nullptr, 0, c), std::invalid_argument);
}

TEST(dang_van_ball, MatchesBruteForceOnSmallSets)
{
  // 2-10 points: Gaussian, uniform, on a sphere (cospherical), in a plane,
  // with duplicates. Both are exact up to round-off (measured agreement
  // 1.7e-15 r); 1e-9 r leaves room for the brute force's pivoting on
  // nearly dependent subsets.
  std::mt19937_64                        rng(7);
  std::normal_distribution<double>       normal;
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int trial = 0; trial < 1500; ++trial)
    {
      std::vector<Point> points(2 + trial % 9);
      for (auto &p : points)
        {
          double norm = 0.0;
          for (auto &x : p)
            {
              x = trial % 4 == 0 ? uniform(rng) : normal(rng);
              norm += x * x;
            }
          if (trial % 5 == 0)
            for (auto &x : p)
              x /= std::sqrt(norm);
          if (trial % 7 == 0)
            p[2] = p[3] = p[4] = 0.0;
        }
      if (trial % 11 == 0)
        points[1] = points[0];
      Point  expected;
      double expected_radius = 0.0;
      ASSERT_TRUE(brute_force_ball(points, expected, expected_radius)) << trial;
      double       c[5];
      const double r = detail::minimum_enclosing_ball(flatten(points).data(), points.size(), c);
      EXPECT_NEAR(r, expected_radius, 1e-9 * expected_radius) << trial;
      EXPECT_LE(distance(expected, c), 1e-9 * expected_radius) << trial;
    }
}

TEST(dang_van_ball, OptimalOnLongPaths)
{
  // Multi-harmonic 5-D paths of 500 points (a sampled non-proportional
  // cycle). Optimality of the convex max-distance function: no move of the
  // centre by h = 1e-6 r in 2000 random directions, nor along the axes,
  // shrinks the ball (first-order change ~1e-6 r times a cosine; round-off of
  // the distances 1e-15 r, so a relative slack of 1e-13).
  std::mt19937_64                  rng(11);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 20; ++trial)
    {
      Point a, b, d, e;
      for (int k = 0; k < 5; ++k)
        a[k] = normal(rng), b[k] = normal(rng), d[k] = 0.4 * normal(rng), e[k] = normal(rng);
      std::vector<Point> points(500);
      for (int i = 0; i < 500; ++i)
        for (int k = 0; k < 5; ++k)
          {
            const double t = two_pi * i / 500.0;
            points[i][k]   = e[k] + a[k] * std::sin(t) + b[k] * std::cos(t) + d[k] * std::sin(2 * t + 1.0);
          }
      const auto   flat = flatten(points);
      double       c[5];
      const double r = detail::minimum_enclosing_ball(flat.data(), points.size(), c);
      auto         radius_at = [&](const double *x) {
        double worst = 0.0;
        for (const auto &p : points)
          worst = std::max(worst, distance(p, x));
        return worst;
      };
      EXPECT_NEAR(radius_at(c), r, 1e-15 * r);
      for (int dir = 0; dir < 2010; ++dir)
        {
          double step[5], norm = 0.0;
          for (int k = 0; k < 5; ++k)
            {
              step[k] = dir < 10 ? (k == dir / 2 ? (dir % 2 ? 1.0 : -1.0) : 0.0) : normal(rng);
              norm += step[k] * step[k];
            }
          double moved[5];
          for (int k = 0; k < 5; ++k)
            moved[k] = c[k] + 1e-6 * r * step[k] / std::sqrt(norm);
          EXPECT_GE(radius_at(moved), r * (1.0 - 1e-13)) << "trial " << trial << ", direction " << dir;
        }
    }
}
