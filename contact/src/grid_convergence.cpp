#include <fretsim/contact/grid_convergence.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace fretsim::contact
{
  RichardsonEstimate richardson_estimate(double fine, double medium, double coarse, const RichardsonSettings &s)
  {
    if (!std::isfinite(fine) || !std::isfinite(medium) || !std::isfinite(coarse))
      throw std::invalid_argument("richardson_estimate: the three values must be finite");
    if (!(s.refinement_ratio > 1.0) || !(s.min_order > 0.0) || !(s.max_order >= s.min_order))
      throw std::invalid_argument("richardson_estimate: expected a refinement ratio > 1 and 0 < min_order <= max_order");

    RichardsonEstimate result;
    const double       e_fine = fine - medium, e_coarse = medium - coarse;
    const double       ln_r = std::log(s.refinement_ratio);
    result.observed_order   = std::numeric_limits<double>::quiet_NaN();
    if (e_fine == 0.0 && e_coarse == 0.0)
      {
        result.converged  = fine;
        result.asymptotic = true;
        return result;
      }
    if (e_fine * e_coarse <= 0.0)
      {
        // Oscillating (or one difference zero): no power law to extrapolate;
        // keep the finest value and bound its error by the largest change.
        result.converged      = fine;
        result.error_estimate = s.fallback_safety * std::max(std::abs(e_fine), std::abs(e_coarse));
        return result;
      }
    result.observed_order = std::log(e_coarse / e_fine) / ln_r;
    result.asymptotic     = result.observed_order >= s.min_order;
    const double order    = std::clamp(result.observed_order, s.min_order, s.max_order);
    const double correction = e_fine / (std::pow(s.refinement_ratio, order) - 1.0);
    result.converged        = fine + correction;
    result.error_estimate   = (result.asymptotic ? s.safety_factor : s.fallback_safety) * std::abs(correction);
    return result;
  }
} // namespace fretsim::contact
