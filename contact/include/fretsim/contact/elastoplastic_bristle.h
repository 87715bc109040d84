#pragma once
#include <fretsim/contact/surface_grid.h>

#include <vector>

namespace fretsim::contact
{
  /// Tangential traction by elastic–perfectly-plastic bristles: at
  /// every cell an independent spring of stiffness k [Pa/m] in series with a
  /// Coulomb slider,
  ///     dtau = k ds        while |tau| < mu p   (stick),
  ///     |tau| = mu p, tau along the sliding     (slip),
  /// advanced per step by the exact return mapping (closest-point projection
  /// onto the disc |tau| <= mu p, which is backward Euler and exact for a
  /// straight slip increment):
  ///     trial = tau^n + k ds;  tau^{n+1} = trial                   if |trial| <= mu p,
  ///                            tau^{n+1} = mu p trial / |trial|    otherwise.
  /// Unlike the exponential law of BristleTraction (which slips a little
  /// everywhere), the stick zone is real: cells below the bound do not slip
  /// at all, and the model is Iwan's parallel assembly of Jenkins elements, so
  /// its loops obey Masing's rule like Mindlin–Deresiewicz. With the
  /// calibration k = 8 G*/(pi a) on a Hertz pressure its virgin curve is
  /// Q/(mu P) = (3/2)(u - u^3/3), u = delta/delta_t, and it reaches gross slip
  /// at exactly Mindlin's delta_t = 3 mu P/(16 G* a) (Mindlin: 1 - (1-u)^{3/2}).
  ///
  /// ds is the increment of the imposed rigid shift (the relative displacement
  /// of remote points, upper body over lower); the bristles carry all the
  /// compliance (no elastic half-space). Same interface and sign convention as
  /// BristleTraction: the traction acts on the lower body, along +ds for
  /// sticking bristles.
  class ElastoplasticBristleTraction
  {
  public:
    /// stiffness: tangential foundation stiffness k [Pa/m], positive and finite.
    ElastoplasticBristleTraction(const SurfaceGrid &grid, double stiffness);

    /// Mindlin calibration k = 8 G* / (pi a) [Pa/m] (as BristleTraction).
    static double mindlin_stiffness(double tangential_modulus, double contact_radius);

    /// One step with the same shift increment (dx, dy) [m] at every cell.
    void advance(const Field &pressure, double friction_coefficient, double slip_x, double slip_y);
    /// One step with a shift increment per cell [m].
    void advance(const Field &pressure, double friction_coefficient, const Field &slip_x, const Field &slip_y);

    void reset();

    const Field &traction_x() const { return tau_x; } ///< [Pa], on the lower body
    const Field &traction_y() const { return tau_y; } ///< [Pa]
    double       stiffness() const { return k; }

    /// |tau| / (mu p) per cell, 0 outside the contact.
    Field effective_friction(const Field &pressure, double friction_coefficient) const;
    /// Fraction of the loaded cells that are on the slip bound after the last
    /// advance (exact: the return mapping's verdict, no tolerance).
    double slip_area_fraction(const Field &pressure, double friction_coefficient) const;
    /// 1 where the last advance left the cell on the bound |tau| = mu p.
    const std::vector<unsigned char> &slip_mask() const { return slipping; }

  private:
    void advance_cell(std::size_t c, double mu_p, double slip_x, double slip_y);

    SurfaceGrid                grid;
    double                     k;
    Field                      tau_x;
    Field                      tau_y;
    std::vector<unsigned char> slipping;
  };
} // namespace fretsim::contact
