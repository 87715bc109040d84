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
    if (!(s.refinement_ratio > 1.0) || !(s.order > 0.0) || !(s.safety_factor >= 0.0))
      throw std::invalid_argument("richardson_estimate: expected a refinement ratio > 1, an order > 0 and a "
                                  "safety factor >= 0");
    RichardsonEstimate result;
    const double       e_fine = fine - medium, e_coarse = medium - coarse;
    const double       gain   = std::pow(s.refinement_ratio, s.order) - 1.0;
    result.converged          = fine + e_fine / gain;
    result.error_estimate     = s.safety_factor * std::max(std::abs(e_fine), std::abs(e_coarse)) / gain;
    result.observed_order     = e_fine * e_coarse > 0.0 ? std::log(e_coarse / e_fine) / std::log(s.refinement_ratio) :
                                                          std::numeric_limits<double>::quiet_NaN();
    result.asymptotic = std::isfinite(result.observed_order) && std::abs(result.observed_order - s.order) <= 0.25;
    return result;
  }
} // namespace fretsim::contact
