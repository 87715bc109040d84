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

    void check_geometry(const BearingGeometry &b)
    {
      if (!(b.ball_diameter > 0.0) || !(b.pitch_diameter > b.ball_diameter))
        throw std::invalid_argument("bearing: the ball diameter must be positive and smaller than the pitch diameter");
      if (!(b.inner_groove_conformity > 0.5) || !(b.outer_groove_conformity > 0.5))
        throw std::invalid_argument("bearing: groove conformities must exceed 1/2 (a groove wider than the ball)");
    }

    /// Principal relative radii of the outer contact: rolling direction, ball
    /// d/2 against the concave raceway (dm + d)/2; transverse, ball against the groove f_o d.
    std::pair<double, double> outer_radii(const BearingGeometry &b)
    {
      const double d = b.ball_diameter, dm = b.pitch_diameter;
      return {1.0 / (2.0 / d - 2.0 / (dm + d)), 1.0 / (2.0 / d - 1.0 / (b.outer_groove_conformity * d))};
    }
  } // namespace

  BallContactStiffness ball_contact_stiffness(const BearingGeometry &b, double contact_modulus)
  {
    check_geometry(b);
    const double d = b.ball_diameter, dm = b.pitch_diameter;
    // Rolling direction: ball radius d/2 against the raceway radius (dm - d)/2
    // (convex inner); transverse: ball against the groove f d.
    const double inner_x = 1.0 / (2.0 / d + 2.0 / (dm - d));
    const double inner_y = 1.0 / (2.0 / d - 1.0 / (b.inner_groove_conformity * d));
    const auto [outer_x, outer_y] = outer_radii(b);
    BallContactStiffness k;
    k.inner    = hertz_constant(inner_x, inner_y, contact_modulus);
    k.outer    = hertz_constant(outer_x, outer_y, contact_modulus);
    // Same load through both: δ = δ_i + δ_o = (Q/K_i)^{2/3} + (Q/K_o)^{2/3}.
    k.combined = std::pow(std::pow(k.inner, -2.0 / 3.0) + std::pow(k.outer, -2.0 / 3.0), -1.5);
    return k;
  }

  OuterContactEllipse outer_contact_ellipse(const BearingGeometry &b, double contact_modulus)
  {
    check_geometry(b);
    const auto [radius_x, radius_y] = outer_radii(b);
    const auto unit = contact::HertzElliptical::solve(1.0, radius_x, radius_y, contact_modulus);
    return {unit.semi_axis_x, unit.semi_axis_y, unit.peak_pressure};
  }

  std::vector<double> OuterContactEllipse::footprint_loads(double peak_pressure_limit, unsigned int count) const
  {
    if (count < 3 || count % 2 == 0)
      throw std::invalid_argument("bearing: an odd number >= 3 of footprints (pieces of three)");
    // p0 ∝ Q^{1/3}: the limit is reached at (limit / p0(1 N))³; the scale
    // s ∝ Q^{1/3} equally spaced from a point load (10⁻³ of the largest
    // ellipse, 10⁻⁹ of its load: an ellipse needs semi-axes > 0).
    const double        top = std::pow(peak_pressure_limit / peak_pressure_per_newton_cube_root, 3.0);
    std::vector<double> loads;
    for (unsigned int i = 0; i < count; ++i)
      loads.push_back(top * std::pow(std::max(static_cast<double>(i) / (count - 1), 1e-3), 3.0));
    return loads;
  }

  FootprintBlend footprint_blend(const std::vector<double> &footprint_loads, double load)
  {
    const std::size_t count = footprint_loads.size();
    if (count < 2)
      return {};
    // Lagrange in the footprint's scale s ∝ Q^{1/3} over the piece of three
    // footprints (two with two) that holds Q, extrapolated beyond the last.
    // The row is not smooth in Q at a point load: the FE field's slopes jump
    // across the element faces the patch straddles, so the row grows as s
    // there, and smoothly as s² inside an element; a quadratic in s holds both.
    const double s     = std::cbrt(std::max(load, 0.0));
    std::size_t  below = 0;
    while (below + 2 < count && s > std::cbrt(footprint_loads[below + 1]))
      ++below;
    FootprintBlend blend;
    blend.count = std::min<std::size_t>(count, 3);
    blend.first = std::min(below - below % 2, count - blend.count);
    for (std::size_t m = 0; m < blend.count; ++m)
      {
        double weight = 1.0;
        for (std::size_t o = 0; o < blend.count; ++o)
          if (o != m)
            {
              const double node = std::cbrt(footprint_loads[blend.first + m]),
                           other = std::cbrt(footprint_loads[blend.first + o]);
              weight *= (s - other) / (node - other);
            }
        blend.weights[m] = weight;
      }
    return blend;
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
