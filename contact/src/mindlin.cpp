#include <fretsim/contact/mindlin.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fretsim::contact
{
  MindlinLoop::MindlinLoop(double friction_coefficient, double normal_load, double contact_radius,
                           double tangential_modulus)
    : mu_P(friction_coefficient * normal_load)
    , delta_t(3.0 * friction_coefficient * normal_load / (16.0 * tangential_modulus * contact_radius))
  {
    if (!(mu_P > 0.0))
      throw std::invalid_argument("Mindlin loop needs mu P > 0");
  }

  double MindlinLoop::virgin_force(double displacement) const
  {
    const double ratio = std::min(std::abs(displacement) / delta_t, 1.0);
    return std::copysign(mu_P * (1.0 - std::pow(1.0 - ratio, 1.5)), displacement);
  }

  double MindlinLoop::stick_radius(double tangential_force) const
  {
    const double ratio = std::min(std::abs(tangential_force) / mu_P, 1.0);
    return std::cbrt(1.0 - ratio); // in units of a
  }

  double MindlinLoop::force_amplitude(double displacement_amplitude) const
  {
    return virgin_force(std::abs(displacement_amplitude));
  }

  double MindlinLoop::loop_force(double displacement, double displacement_amplitude,
                                 bool unloading) const
  {
    const double amplitude = std::abs(displacement_amplitude);
    if (!unloading)
      // Reloading is the unloading branch mirrored through the origin
      // (Mindlin & Deresiewicz 1953; docs/references.md §2.2).
      return -loop_force(-displacement, amplitude, true);
    const double force_amplitude_ = force_amplitude(amplitude);
    // Unloading from (delta*, Q*): the slip annulus re-grows from the edge with
    // twice the virgin compliance, Q = Q* - 2 mu P [1 - (1 - d/(2 delta_t))^{3/2}].
    const double reversal = std::clamp(amplitude - displacement, 0.0, 2.0 * delta_t);
    return force_amplitude_ - 2.0 * mu_P * (1.0 - std::pow(1.0 - reversal / (2.0 * delta_t), 1.5));
  }

  double MindlinLoop::dissipated_energy(double displacement_amplitude) const
  {
    const double amplitude = std::abs(displacement_amplitude);
    const double q_star    = force_amplitude(amplitude) / mu_P;
    // Johnson (1985) eq. 7.59 form, W = mu P delta_t (24/5)[...] (docs/references.md §2.2).
    const double partial_slip =
      mu_P * delta_t * 24.0 / 5.0 *
      (1.0 - std::pow(1.0 - q_star, 5.0 / 3.0) -
       5.0 * q_star / 6.0 * (1.0 + std::pow(1.0 - q_star, 2.0 / 3.0)));
    // Beyond delta_t each half cycle adds a gross-slip stroke 2(delta* - delta_t) at |Q| = mu P.
    const double gross_slip = 4.0 * mu_P * std::max(amplitude - delta_t, 0.0);
    return partial_slip + gross_slip;
  }
} // namespace fretsim::contact
