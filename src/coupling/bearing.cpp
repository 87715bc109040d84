#include <fretsim/coupling/bearing.h>

#include <fretsim/contact/hertz.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace fretsim::coupling
{
  namespace
  {
    /// K of Q = K δ^{3/2} for principal relative radii (Rx, Ry): Hertz's
    /// approach scales as Q^{2/3}, so one solve at 1 N fixes K.
    double hertz_constant(double radius_x, double radius_y, double contact_modulus)
    {
      const auto unit = contact::HertzElliptical::solve(1.0, radius_x, radius_y, contact_modulus);
      return std::pow(unit.approach, -1.5);
    }
  } // namespace

  BallContactStiffness ball_contact_stiffness(const BearingGeometry &b, double contact_modulus)
  {
    const double d = b.ball_diameter, dm = b.pitch_diameter;
    if (!(d > 0.0) || !(dm > d))
      throw std::invalid_argument("bearing: the ball diameter must be positive and smaller than the pitch diameter");
    if (!(b.inner_groove_conformity > 0.5) || !(b.outer_groove_conformity > 0.5))
      throw std::invalid_argument("bearing: groove conformities must exceed 1/2 (a groove wider than the ball)");
    // Rolling direction: ball radius d/2 against the raceway radius (dm ∓ d)/2
    // (convex inner, concave outer); transverse: ball against the groove f d.
    const double inner_x = 1.0 / (2.0 / d + 2.0 / (dm - d));
    const double outer_x = 1.0 / (2.0 / d - 2.0 / (dm + d));
    const double inner_y = 1.0 / (2.0 / d - 1.0 / (b.inner_groove_conformity * d));
    const double outer_y = 1.0 / (2.0 / d - 1.0 / (b.outer_groove_conformity * d));
    BallContactStiffness k;
    k.inner    = hertz_constant(inner_x, inner_y, contact_modulus);
    k.outer    = hertz_constant(outer_x, outer_y, contact_modulus);
    // Same load through both: δ = δ_i + δ_o = (Q/K_i)^{2/3} + (Q/K_o)^{2/3}.
    k.combined = std::pow(std::pow(k.inner, -2.0 / 3.0) + std::pow(k.outer, -2.0 / 3.0), -1.5);
    return k;
  }

  double cage_speed(const BearingGeometry &b, double inner_ring_speed)
  {
    return 0.5 * inner_ring_speed * (1.0 - b.ball_diameter / b.pitch_diameter);
  }

  double outer_ball_pass_frequency(const BearingGeometry &b, double inner_ring_speed)
  {
    return cage_kinematics(b, inner_ring_speed).ball_pass_frequency;
  }

  CageKinematics cage_kinematics(const BearingGeometry &b, double inner_ring_speed)
  {
    const double cage = cage_speed(b, inner_ring_speed);
    return {cage, b.ball_count * cage / (2.0 * M_PI)};
  }

  BallLoad ball_load(double stiffness, double damping, double deflection, double deflection_rate)
  {
    BallLoad q;
    if (!(deflection > 0.0))
      return q;
    const double elastic = stiffness * std::pow(deflection, 1.5);
    const double factor  = 1.0 + 1.5 * damping * deflection_rate;
    if (factor <= 0.0)
      return q; // separating faster than the damping law allows: no tension
    q.load               = elastic * factor;
    q.by_deflection      = 1.5 * stiffness * std::sqrt(deflection) * factor;
    q.by_deflection_rate = elastic * 1.5 * damping;
    return q;
  }
} // namespace fretsim::coupling
