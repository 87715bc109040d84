#include <fretsim/contact/hertz.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fretsim::contact
{
  namespace
  {
    void require_positive_finite(double value, const char *what)
    {
      if (!(value > 0.0) || !std::isfinite(value))
        throw std::invalid_argument(std::string("Hertz: ") + what + " must be positive and finite");
    }

    void require_load(double normal_load)
    {
      if (!(normal_load >= 0.0) || !std::isfinite(normal_load))
        throw std::invalid_argument("Hertz: the normal load must be non-negative and finite");
    }

    /// The associated complete elliptic integrals of parameter m = e^2:
    /// D(m) = int_0^{pi/2} sin^2/sqrt(1 - m sin^2) = (K - E)/m and
    /// B(m) = int_0^{pi/2} cos^2/sqrt(1 - m sin^2) = K - D.
    /// The ellipticity equation needs (K - E)/m, which cancels catastrophically
    /// for nearly circular contacts, so small m uses the power series instead.
    struct AssociatedIntegrals
    {
      double first_kind;  ///< K(m)
      double second_kind; ///< E(m)
      double d;           ///< D(m)
      double b;           ///< B(m)
    };

    AssociatedIntegrals associated_integrals(double m)
    {
      AssociatedIntegrals result{};
      if (m < 0.05)
        {
          // K - E = (pi/2) sum_{n>=1} c_n^2 m^n 2n/(2n-1), c_n = (2n-1)!!/(2n)!!,
          // from the term-by-term series of K and E. At m < 0.05 the terms fall
          // by at least 20x each, so 20 terms are far below round-off.
          double c = 1.0, m_power = 1.0, d_sum = 0.0, k_sum = 1.0;
          for (int n = 1; n <= 20; ++n)
            {
              c *= (2.0 * n - 1.0) / (2.0 * n);
              d_sum += c * c * m_power * (2.0 * n) / (2.0 * n - 1.0);
              m_power *= m;
              k_sum += c * c * m_power;
            }
          result.first_kind = 0.5 * M_PI * k_sum;
          result.d          = 0.5 * M_PI * d_sum;
          result.second_kind = result.first_kind - m * result.d;
        }
      else
        {
          // std::comp_ellint_* take the modulus k = sqrt(m), not the parameter.
          const double modulus = std::sqrt(m);
          result.first_kind    = std::comp_ellint_1(modulus);
          result.second_kind   = std::comp_ellint_2(modulus);
          result.d             = (result.first_kind - result.second_kind) / m;
        }
      result.b = result.first_kind - result.d;
      return result;
    }

    /// Curvature ratio B/A = R_large / R_small that an ellipse of parameter
    /// m = 1 - 1/k^2 (k = major/minor) carries (Johnson §4.2:
    /// B/A = [E/(1-e^2) - K]/(K - E) = B(m) / ((1 - m) D(m))).
    double curvature_ratio(double m)
    {
      const AssociatedIntegrals integrals = associated_integrals(m);
      return integrals.b / ((1.0 - m) * integrals.d);
    }
  } // namespace

  HertzCircular HertzCircular::solve(double normal_load, double radius, double contact_modulus)
  {
    require_load(normal_load);
    require_positive_finite(radius, "the radius");
    require_positive_finite(contact_modulus, "the contact modulus");

    HertzCircular hertz{};
    hertz.normal_load     = normal_load;
    hertz.radius          = radius;
    hertz.contact_modulus = contact_modulus;
    hertz.contact_radius  = std::cbrt(3.0 * normal_load * radius / (4.0 * contact_modulus));
    hertz.peak_pressure =
      normal_load > 0.0 ? 3.0 * normal_load / (2.0 * M_PI * hertz.contact_radius * hertz.contact_radius) : 0.0;
    hertz.approach = hertz.contact_radius * hertz.contact_radius / radius;
    return hertz;
  }

  double HertzCircular::pressure(double x, double y) const
  {
    const double a = contact_radius;
    const double r_squared = x * x + y * y;
    if (!(r_squared < a * a))
      return 0.0;
    return peak_pressure * std::sqrt(1.0 - r_squared / (a * a));
  }

  double HertzCircular::normal_displacement(double x, double y) const
  {
    const double a = contact_radius;
    if (!(a > 0.0))
      return 0.0;
    const double r = std::hypot(x, y);
    // Johnson (1985) §3.4, eqs. 3.41b/3.42b (docs/references.md §1.1).
    if (r <= a)
      return M_PI * peak_pressure * (2.0 * a * a - r * r) / (4.0 * a * contact_modulus);
    return peak_pressure / (2.0 * a * contact_modulus) *
           ((2.0 * a * a - r * r) * std::asin(a / r) + r * a * std::sqrt(1.0 - a * a / (r * r)));
  }

  HertzElliptical HertzElliptical::solve(double normal_load, double radius_x, double radius_y,
                                         double contact_modulus)
  {
    require_load(normal_load);
    require_positive_finite(radius_x, "radius_x");
    require_positive_finite(radius_y, "radius_y");
    require_positive_finite(contact_modulus, "the contact modulus");

    // The major axis lies along the flatter direction (the larger radius).
    const double radius_large = std::max(radius_x, radius_y);
    const double radius_small = std::min(radius_x, radius_y);
    const double ratio        = radius_large / radius_small; // Hamrock's alpha_r >= 1

    // Solve B(m)/((1-m)D(m)) = alpha_r for the ellipticity k = 1/sqrt(1-m).
    // The left side rises monotonically from 1 (m = 0) to infinity (m -> 1),
    // and k < alpha_r for alpha_r > 1, so u = ln k in [0, ln alpha_r] brackets
    // the root; bisection on u is slow but cannot fail and costs microseconds.
    double ellipticity = 1.0;
    if (ratio > 1.0)
      {
        auto parameter = [](double log_k) { return -std::expm1(-2.0 * log_k); }; // 1 - 1/k^2
        double low = 0.0, high = std::log(ratio);
        while (curvature_ratio(parameter(high)) < ratio)
          high *= 2.0; // never expected, but keeps the bracket honest
        for (int iteration = 0; iteration < 200; ++iteration)
          {
            const double mid = 0.5 * (low + high);
            if (!(mid > low && mid < high))
              break;
            (curvature_ratio(parameter(mid)) < ratio ? low : high) = mid;
          }
        ellipticity = std::exp(0.5 * (low + high));
      }
    const double m = ellipticity > 1.0 ? -std::expm1(-2.0 * std::log(ellipticity)) : 0.0;
    const AssociatedIntegrals integrals = associated_integrals(m);

    // Hamrock's exact form (docs/references.md §1.3) with E' = 2 E* and
    // 1/R = 1/Rx + 1/Ry.
    const double reduced_modulus = 2.0 * contact_modulus;
    const double combined_radius = 1.0 / (1.0 / radius_x + 1.0 / radius_y);
    const double k               = ellipticity;
    const double major = std::cbrt(6.0 * k * k * integrals.second_kind * normal_load * combined_radius /
                                   (M_PI * reduced_modulus));
    const double minor =
      std::cbrt(6.0 * integrals.second_kind * normal_load * combined_radius / (M_PI * k * reduced_modulus));
    const double load_term = normal_load / (M_PI * k * reduced_modulus);
    const double approach =
      integrals.first_kind * std::cbrt(9.0 / (2.0 * integrals.second_kind * combined_radius) * load_term * load_term);

    HertzElliptical hertz{};
    hertz.normal_load     = normal_load;
    hertz.radius_x        = radius_x;
    hertz.radius_y        = radius_y;
    hertz.contact_modulus = contact_modulus;
    hertz.semi_axis_x     = radius_x >= radius_y ? major : minor;
    hertz.semi_axis_y     = radius_x >= radius_y ? minor : major;
    hertz.peak_pressure   = normal_load > 0.0 ? 3.0 * normal_load / (2.0 * M_PI * major * minor) : 0.0;
    hertz.approach        = approach;
    return hertz;
  }

  double HertzElliptical::pressure(double x, double y) const
  {
    if (!(semi_axis_x > 0.0 && semi_axis_y > 0.0))
      return 0.0;
    const double xi = x / semi_axis_x, eta = y / semi_axis_y;
    const double s  = 1.0 - xi * xi - eta * eta;
    return s > 0.0 ? peak_pressure * std::sqrt(s) : 0.0;
  }

  Field sampled_hertz_pressure(const SurfaceGrid &grid, double semi_axis_x, double semi_axis_y, double peak)
  {
    Field pressure = grid.zeros();
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        {
          const double ex = grid.x(i) / semi_axis_x, ey = grid.y(j) / semi_axis_y;
          pressure[grid.index(i, j)] = peak * std::sqrt(std::max(0.0, 1.0 - ex * ex - ey * ey));
        }
    return pressure;
  }
} // namespace fretsim::contact
