#include <fretsim/contact/elastoplastic_bristle.h>
#include <fretsim/contact/bristle.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fretsim::contact
{
  ElastoplasticBristleTraction::ElastoplasticBristleTraction(const SurfaceGrid &grid, double stiffness)
    : grid(grid)
    , k(stiffness)
    , tau_x(grid.zeros())
    , tau_y(grid.zeros())
    , slipping(grid.size(), 0)
  {
    if (!(stiffness > 0.0) || !std::isfinite(stiffness))
      throw std::invalid_argument("elastoplastic bristle stiffness must be positive and finite");
  }

  double ElastoplasticBristleTraction::mindlin_stiffness(double tangential_modulus, double contact_radius)
  {
    // The same calibration as the exponential bristles: both models start
    // with Mindlin's initial tangential stiffness 8 G* a.
    return BristleTraction::mindlin_stiffness(tangential_modulus, contact_radius);
  }

  void ElastoplasticBristleTraction::reset()
  {
    std::fill(tau_x.begin(), tau_x.end(), 0.0);
    std::fill(tau_y.begin(), tau_y.end(), 0.0);
    std::fill(slipping.begin(), slipping.end(), 0);
  }

  void ElastoplasticBristleTraction::advance_cell(std::size_t c, double mu_p, double slip_x, double slip_y)
  {
    if (!(mu_p > 0.0))
      {
        // No pressure or no friction: nothing is transmitted; a loaded
        // frictionless cell slips freely.
        tau_x[c]    = 0.0;
        tau_y[c]    = 0.0;
        slipping[c] = 0;
        return;
      }
    // Elastic predictor.
    double trial_x = k * slip_x, trial_y = k * slip_y;
    if (!std::isfinite(trial_x) || !std::isfinite(trial_y))
      {
        // k ds overflowed: the spring is stretched far beyond the bound and
        // the cell slides along ds.
        const double slip = std::hypot(slip_x, slip_y);
        tau_x[c]          = mu_p * slip_x / slip;
        tau_y[c]          = mu_p * slip_y / slip;
        slipping[c]       = 1;
        return;
      }
    trial_x += tau_x[c];
    trial_y += tau_y[c];
    double magnitude = std::hypot(trial_x, trial_y);
    if (!std::isfinite(magnitude))
      {
        // Only the direction matters beyond the bound: rescale before |.|.
        trial_x *= 0x1p-600;
        trial_y *= 0x1p-600;
        magnitude = std::hypot(trial_x, trial_y);
      }
    else if (magnitude <= mu_p)
      {
        // Stick (also a previously slipping cell that unloads).
        tau_x[c]    = trial_x;
        tau_y[c]    = trial_y;
        slipping[c] = magnitude == mu_p;
        return;
      }
    // Plastic corrector: return to the disc along the radius (closest point).
    tau_x[c]    = mu_p * (trial_x / magnitude);
    tau_y[c]    = mu_p * (trial_y / magnitude);
    slipping[c] = 1;
  }

  void ElastoplasticBristleTraction::advance(const Field &pressure, double friction_coefficient, double slip_x,
                                             double slip_y)
  {
    if (pressure.size() != grid.size())
      throw std::invalid_argument("elastoplastic bristle: pressure size does not match the grid");
    for (std::size_t c = 0; c < grid.size(); ++c)
      advance_cell(c, friction_coefficient * pressure[c], slip_x, slip_y);
  }

  void ElastoplasticBristleTraction::advance(const Field &pressure, double friction_coefficient, const Field &slip_x,
                                             const Field &slip_y)
  {
    if (pressure.size() != grid.size() || slip_x.size() != grid.size() || slip_y.size() != grid.size())
      throw std::invalid_argument("elastoplastic bristle: field sizes do not match the grid");
    for (std::size_t c = 0; c < grid.size(); ++c)
      advance_cell(c, friction_coefficient * pressure[c], slip_x[c], slip_y[c]);
  }

  Field ElastoplasticBristleTraction::effective_friction(const Field &pressure, double friction_coefficient) const
  {
    return contact::effective_friction(tau_x, tau_y, pressure, friction_coefficient);
  }

  double ElastoplasticBristleTraction::slip_area_fraction(const Field &pressure, double friction_coefficient) const
  {
    std::size_t loaded = 0, slipping_cells = 0;
    for (std::size_t c = 0; c < grid.size(); ++c)
      if (pressure[c] > 0.0)
        {
          ++loaded;
          if (slipping[c] || !(friction_coefficient * pressure[c] > 0.0))
            ++slipping_cells;
        }
    return loaded == 0 ? 0.0 : static_cast<double>(slipping_cells) / static_cast<double>(loaded);
  }
} // namespace fretsim::contact
