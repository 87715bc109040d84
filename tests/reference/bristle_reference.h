#pragma once
// Independent reference for the bristle model (paper eq. 4) under a uniform
// imposed slip history on a circular Hertz contact: each point follows the
// closed-form solution of dtau/ds = k (1 - tau sign(ds)/(mu p)), i.e. an
// exponential relaxation towards +-mu p over slip distance s, and the force is
// integrated over radius with fine midpoint quadrature. It shares no code with
// the grid implementation and has no time-discretisation error.
#include <cmath>
#include <vector>

namespace fretsim::reference
{
  class RadialBristleLoop
  {
  public:
    RadialBristleLoop(double peak_pressure, double contact_radius, double friction_coefficient,
                      double stiffness, int rings = 20000)
      : stiffness(stiffness)
    {
      for (int ring = 0; ring < rings; ++ring)
        {
          const double r = (ring + 0.5) / rings * contact_radius;
          mu_p.push_back(friction_coefficient * peak_pressure * std::sqrt(1.0 - r * r / (contact_radius * contact_radius)));
          area.push_back(2.0 * M_PI * r * contact_radius / rings);
          tau.push_back(0.0);
        }
    }

    /// Moves the slip by ds (one monotonic segment) and returns the force Q [N].
    double advance(double ds)
    {
      double force = 0.0;
      const double direction = ds >= 0.0 ? 1.0 : -1.0;
      for (std::size_t ring = 0; ring < tau.size(); ++ring)
        {
          const double limit = direction * mu_p[ring];
          tau[ring]          = limit + (tau[ring] - limit) * std::exp(-stiffness * std::abs(ds) / mu_p[ring]);
          force += tau[ring] * area[ring];
        }
      return force;
    }

  private:
    double              stiffness;
    std::vector<double> mu_p, area, tau;
  };
} // namespace fretsim::reference
