// Closed-form Hertz solutions against docs/references.md §1.
#include <fretsim/contact/hertz.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace fretsim::contact;

namespace
{
  // Two steel bodies, E = 200 GPa, nu = 0.3 (docs/references.md §1.2).
  const double steel_contact_modulus = 200e9 / (2.0 * (1.0 - 0.3 * 0.3));

  /// B(m)/((1-m) D(m)) by the midpoint rule on [0, pi/2]. The integrands are
  /// smooth, even and pi-periodic, so the rule converges exponentially; with
  /// 4000 points it is exact to round-off for m <= 0.9. Shares no code with
  /// the library's series / std::comp_ellint evaluation.
  double curvature_ratio_by_quadrature(double m)
  {
    const int n = 4000;
    double    b = 0.0, d = 0.0;
    for (int i = 0; i < n; ++i)
      {
        const double theta = (i + 0.5) * 0.5 * M_PI / n, s = std::sin(theta), c = std::cos(theta);
        const double root = std::sqrt(1.0 - m * s * s);
        b += c * c / root;
        d += s * s / root;
      }
    return b / ((1.0 - m) * d);
  }
} // namespace

TEST(HertzCircular, PaperCase)
{
  const auto hertz = HertzCircular::solve(1250.0, 0.05, steel_contact_modulus);
  // docs/references.md §1.2: E* = 109.89 GPa, a = 752.8 um, p0 = 1053.2 MPa,
  // delta = 11.33 um; tolerances are half a unit in the last quoted digit.
  EXPECT_NEAR(steel_contact_modulus, 109.89e9, 0.005e9);
  EXPECT_NEAR(hertz.contact_radius, 752.8e-6, 0.05e-6);
  EXPECT_NEAR(hertz.peak_pressure, 1053.2e6, 0.05e6);
  EXPECT_NEAR(hertz.approach, 11.33e-6, 0.005e-6);
  // Identities of docs/references.md §1.1, exact up to round-off.
  const double a = hertz.contact_radius;
  EXPECT_NEAR(hertz.peak_pressure, 3.0 * 1250.0 / (2.0 * M_PI * a * a), 1e-12 * hertz.peak_pressure);
  EXPECT_NEAR(hertz.approach, a * a / 0.05, 1e-12 * hertz.approach);
  EXPECT_NEAR(hertz.peak_pressure, std::cbrt(6.0 * 1250.0 * std::pow(steel_contact_modulus / 0.05, 2) / std::pow(M_PI, 3)),
              1e-12 * hertz.peak_pressure);
}

TEST(HertzCircular, PressureProfileCarriesTheLoad)
{
  const auto   hertz = HertzCircular::solve(1250.0, 0.05, steel_contact_modulus);
  const double a     = hertz.contact_radius;
  EXPECT_DOUBLE_EQ(hertz.pressure(0.0, 0.0), hertz.peak_pressure);
  EXPECT_EQ(hertz.pressure(a, 0.0), 0.0);
  EXPECT_EQ(hertz.pressure(0.8 * a, 0.7 * a), 0.0);
  EXPECT_NEAR(hertz.pressure(0.6 * a, 0.0), 0.8 * hertz.peak_pressure, 1e-12 * hertz.peak_pressure);
  // Radial midpoint rule in s = r^2 (p = p0 sqrt(1 - s/a^2), dA = pi ds); the
  // square-root end point limits it to ~n^-1.5, i.e. ~1e-7 for n = 1e5.
  const int n     = 100000;
  double    force = 0.0;
  for (int i = 0; i < n; ++i)
    {
      const double r = a * std::sqrt((i + 0.5) / n);
      force += hertz.pressure(r, 0.0) * M_PI * a * a / n;
    }
  EXPECT_NEAR(force / 1250.0, 1.0, 1e-6);
}

TEST(HertzCircular, NormalDisplacementSatisfiesTheContactCondition)
{
  const double R = 0.05, P = 1250.0;
  const auto   hertz = HertzCircular::solve(P, R, steel_contact_modulus);
  const double a     = hertz.contact_radius;
  // Inside the contact the deformed gap r^2/2R - delta + u_z vanishes
  // (Johnson §3.4 / §4.2); outside it is positive. Round-off only.
  for (const double r : {0.0, 0.3 * a, 0.77 * a, a})
    EXPECT_NEAR(hertz.normal_displacement(r / std::sqrt(2.0), r / std::sqrt(2.0)), hertz.approach - r * r / (2.0 * R),
                1e-12 * hertz.approach)
      << "r/a = " << r / a;
  for (const double r : {1.0001 * a, 1.2 * a, 3.0 * a})
    EXPECT_GT(r * r / (2.0 * R) - hertz.approach + hertz.normal_displacement(r, 0.0), 0.0) << "r/a = " << r / a;
  // Continuity at r = a of the two branches of docs/references.md §1.1, to
  // first order in the step.
  const double inside = hertz.normal_displacement(a * (1.0 - 1e-9), 0.0);
  const double outside = hertz.normal_displacement(a * (1.0 + 1e-9), 0.0);
  EXPECT_NEAR(inside, outside, 1e-7 * inside);
  // Far field: the Boussinesq point load, u_z = P/(pi E* r), with a relative
  // correction of order (a/r)^2 = 1e-6 at r = 1000 a.
  const double r = 1000.0 * a;
  EXPECT_NEAR(hertz.normal_displacement(0.0, r) * M_PI * steel_contact_modulus * r / P, 1.0, 1e-5);
}

TEST(HertzCircular, ZeroLoadAndInvalidInput)
{
  const auto hertz = HertzCircular::solve(0.0, 0.05, steel_contact_modulus);
  EXPECT_EQ(hertz.contact_radius, 0.0);
  EXPECT_EQ(hertz.peak_pressure, 0.0);
  EXPECT_EQ(hertz.pressure(0.0, 0.0), 0.0);
  EXPECT_EQ(hertz.normal_displacement(1e-3, 0.0), 0.0);
  EXPECT_THROW(HertzCircular::solve(-1.0, 0.05, steel_contact_modulus), std::invalid_argument);
  EXPECT_THROW(HertzCircular::solve(1.0, 0.0, steel_contact_modulus), std::invalid_argument);
  EXPECT_THROW(HertzElliptical::solve(1.0, 0.05, -0.05, steel_contact_modulus), std::invalid_argument);
}

TEST(HertzElliptical, EllipticityMatchesExactTable)
{
  // docs/references.md §1.3 table, "k exact", "E exact" and "F = K exact" columns,
  // quoted to 5 decimals: tolerance half a unit of the last digit.
  struct Row
  {
    double alpha, k, e, f;
  };
  for (const Row row : {Row{1, 1.00000, 1.57080, 1.57080}, Row{2, 1.58580, 1.29715, 1.95211},
                        Row{4, 2.50071, 1.15059, 2.35952}, Row{6, 3.25046, 1.10036, 2.60400},
                        Row{10, 4.49945, 1.05988, 2.91420}, Row{20, 6.92868, 1.02958, 3.33419},
                        Row{50, 12.07115, 1.01161, 3.88207}, Row{100, 18.18710, 1.00573, 4.28950}})
    {
      const double Rx = 0.01, Ry = row.alpha * Rx;
      const auto   hertz = HertzElliptical::solve(100.0, Rx, Ry, steel_contact_modulus);
      const double k     = hertz.semi_axis_y / hertz.semi_axis_x; // major axis along the larger radius
      EXPECT_NEAR(k, row.k, 5e-6) << "alpha_r = " << row.alpha;
      const double modulus = std::sqrt(1.0 - 1.0 / (k * k));
      EXPECT_NEAR(std::comp_ellint_2(modulus), row.e, 5e-6) << "alpha_r = " << row.alpha;
      EXPECT_NEAR(std::comp_ellint_1(modulus), row.f, 5e-6) << "alpha_r = " << row.alpha;
      if (row.alpha > 1.0)
        {
          // Johnson §4.2 relation B/A = [E/(1-e^2) - K]/(K - E) with the
          // library's k, evaluated independently: satisfied to round-off
          // amplified by the condition of k -> alpha (~1e-12).
          const double K = std::comp_ellint_1(modulus), E = std::comp_ellint_2(modulus);
          EXPECT_NEAR((k * k * E - K) / (K - E) / row.alpha, 1.0, 1e-11) << "alpha_r = " << row.alpha;
        }
    }
}

TEST(HertzElliptical, NearlyCircularRootIsAccurate)
{
  // Small eccentricity uses the series for (K - E)/m: check the ellipticity
  // equation with an independent quadrature (exact to ~1e-15, see
  // curvature_ratio_by_quadrature) on both sides of the series/std switch
  // (m = 0.05, alpha ~ 1.04).
  for (const double alpha : {1.0 + 1e-12, 1.0 + 1e-6, 1.001, 1.03, 1.037, 1.038, 1.05, 1.5, 3.0})
    {
      const auto   hertz = HertzElliptical::solve(10.0, 0.02, 0.02 * alpha, steel_contact_modulus);
      const double k     = hertz.semi_axis_y / hertz.semi_axis_x;
      const double m     = 1.0 - 1.0 / (k * k);
      // The ratio alpha - 1 is reproduced to 1e-9 relative (bisection to
      // round-off in ln k; 1e-12 absolute in alpha when alpha - 1 < 1e-3).
      EXPECT_NEAR(curvature_ratio_by_quadrature(m) - 1.0, alpha - 1.0, std::max(1e-9 * (alpha - 1.0), 1e-14))
        << "alpha_r = " << alpha;
    }
  // Series limit: m = 4(alpha - 1)/3 + O((alpha-1)^2), so (k - 1)/(alpha - 1)
  // -> 2/3 with a relative correction of order alpha - 1 = 1e-6.
  const double alpha = 1.0 + 1e-6;
  const auto   hertz = HertzElliptical::solve(10.0, 0.02, 0.02 * alpha, steel_contact_modulus);
  EXPECT_NEAR((hertz.semi_axis_y / hertz.semi_axis_x - 1.0) / (alpha - 1.0), 2.0 / 3.0, 1e-5);
}

TEST(HertzElliptical, DeepGrooveBallBearingExample)
{
  // docs/references.md §1.3 worked example, "exact" row: ball d = 7.938 mm,
  // dm = 38.5 mm, f_i = 0.52, W = 1000 N, steel. The row is quoted to 5-6
  // digits; 1e-3 relative as asked for.
  const double d = 7.938e-3, dm = 38.5e-3, f = 0.52, W = 1000.0;
  const double Rx = d * (dm - d) / (2.0 * dm), Ry = f * d / (2.0 * f - 1.0);
  EXPECT_NEAR(Rx, 3.15066e-3, 1e-8);
  EXPECT_NEAR(Ry, 103.194e-3, 1e-6);
  const auto hertz = HertzElliptical::solve(W, Rx, Ry, steel_contact_modulus);
  EXPECT_NEAR(hertz.semi_axis_y / hertz.semi_axis_x / 9.3612, 1.0, 1e-3);
  EXPECT_NEAR(hertz.semi_axis_y / 1333.22e-6, 1.0, 1e-3);
  EXPECT_NEAR(hertz.semi_axis_x / 142.42e-6, 1.0, 1e-3);
  EXPECT_NEAR(hertz.approach / 11.831e-6, 1.0, 1e-3);
  EXPECT_NEAR(hertz.peak_pressure / 2514.6e6, 1.0, 1e-3);

  // Johnson's equivalent form (docs/references.md §1.3): delta = 3 W K/(2 pi a E*)
  // and a^3 = 3 W (K - E)/(2 pi E* A e^2) with A = 1/(2 Ry), a the major
  // semi-axis; the two forms are algebraically identical (round-off).
  const double a = hertz.semi_axis_y, k = a / hertz.semi_axis_x;
  const double e2 = 1.0 - 1.0 / (k * k), K = std::comp_ellint_1(std::sqrt(e2)), E = std::comp_ellint_2(std::sqrt(e2));
  EXPECT_NEAR(hertz.approach / (3.0 * W * K / (2.0 * M_PI * a * steel_contact_modulus)), 1.0, 1e-10);
  EXPECT_NEAR(a * a * a / (3.0 * W * (K - E) / (2.0 * M_PI * steel_contact_modulus * e2 / (2.0 * Ry))), 1.0, 1e-10);
}

TEST(HertzElliptical, OrientationFollowsTheRadii)
{
  // Swapping Rx and Ry swaps the semi-axes and leaves p0 and delta unchanged.
  const auto along_y = HertzElliptical::solve(500.0, 0.01, 0.04, steel_contact_modulus);
  const auto along_x = HertzElliptical::solve(500.0, 0.04, 0.01, steel_contact_modulus);
  EXPECT_GT(along_y.semi_axis_y, along_y.semi_axis_x);
  EXPECT_DOUBLE_EQ(along_x.semi_axis_x, along_y.semi_axis_y);
  EXPECT_DOUBLE_EQ(along_x.semi_axis_y, along_y.semi_axis_x);
  EXPECT_DOUBLE_EQ(along_x.peak_pressure, along_y.peak_pressure);
  EXPECT_DOUBLE_EQ(along_x.approach, along_y.approach);
  // Pressure: p0 sqrt(1 - x^2/ax^2 - y^2/ay^2), p0 = 3P/(2 pi ax ay) (§1.3).
  const auto &h = along_x;
  EXPECT_NEAR(h.peak_pressure, 3.0 * 500.0 / (2.0 * M_PI * h.semi_axis_x * h.semi_axis_y), 1e-12 * h.peak_pressure);
  EXPECT_DOUBLE_EQ(h.pressure(0.0, 0.0), h.peak_pressure);
  EXPECT_NEAR(h.pressure(0.6 * h.semi_axis_x, 0.0), 0.8 * h.peak_pressure, 1e-12 * h.peak_pressure);
  EXPECT_NEAR(h.pressure(0.0, 0.6 * h.semi_axis_y), 0.8 * h.peak_pressure, 1e-12 * h.peak_pressure);
  EXPECT_EQ(h.pressure(0.0, 1.01 * h.semi_axis_y), 0.0);
  EXPECT_EQ(h.pressure(0.75 * h.semi_axis_x, 0.75 * h.semi_axis_y), 0.0);
}

TEST(HertzElliptical, CircularLimitEqualsCircular)
{
  // Rx = Ry = R is a sphere of radius R on a flat: Hamrock's 1/R = 2/R_sphere
  // reduces his formulas to Johnson's circular ones (round-off).
  for (const double load : {1e-6, 1250.0, 1e6})
    {
      const auto circle  = HertzCircular::solve(load, 0.05, steel_contact_modulus);
      const auto ellipse = HertzElliptical::solve(load, 0.05, 0.05, steel_contact_modulus);
      EXPECT_NEAR(ellipse.semi_axis_x / circle.contact_radius, 1.0, 1e-14);
      EXPECT_NEAR(ellipse.semi_axis_y / circle.contact_radius, 1.0, 1e-14);
      EXPECT_NEAR(ellipse.peak_pressure / circle.peak_pressure, 1.0, 1e-14);
      EXPECT_NEAR(ellipse.approach / circle.approach, 1.0, 1e-14);
      // Continuity of the elliptical solver just off the limit: first order in
      // alpha - 1 = 1e-9.
      const auto nearly = HertzElliptical::solve(load, 0.05, 0.05 * (1.0 + 1e-9), steel_contact_modulus);
      EXPECT_NEAR(nearly.approach / circle.approach, 1.0, 1e-8);
      EXPECT_NEAR(nearly.peak_pressure / circle.peak_pressure, 1.0, 1e-8);
    }
}
