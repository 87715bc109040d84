#pragma once
// Closed-form Hertz solutions (Johnson 1985 §4.2; Hamrock's exact elliptic
// form, docs/references.md §1). SI units throughout.
#include <fretsim/contact/surface_grid.h>

namespace fretsim::contact
{
  /// Circular Hertz contact of a sphere of combined radius R on a flat.
  struct HertzCircular
  {
    double normal_load;     ///< P [N]
    double radius;          ///< combined radius of curvature R [m]
    double contact_modulus; ///< E* [Pa]
    double contact_radius;  ///< a [m]
    double peak_pressure;   ///< p0 [Pa]
    double approach;        ///< delta = a^2 / R [m]

    static HertzCircular solve(double normal_load, double radius, double contact_modulus);
    /// p(x, y) = p0 sqrt(1 - r^2/a^2) inside, 0 outside [Pa].
    double pressure(double x, double y) const;
    /// Combined normal surface displacement u_z(r) of both bodies [m].
    double normal_displacement(double x, double y) const;
  };

  /// Elliptical Hertz contact with principal radii Rx (along x) and Ry (along
  /// y), solved exactly with complete elliptic integrals (no curve fit).
  struct HertzElliptical
  {
    double normal_load;     ///< P [N]
    double radius_x;        ///< Rx [m]
    double radius_y;        ///< Ry [m]
    double contact_modulus; ///< E* [Pa]
    double semi_axis_x;     ///< semi-axis along x [m]
    double semi_axis_y;     ///< semi-axis along y [m]
    double peak_pressure;   ///< p0 = 3P / (2 pi ax ay) [Pa]
    double approach;        ///< mutual approach of distant points [m]

    static HertzElliptical solve(double normal_load, double radius_x, double radius_y,
                                 double contact_modulus);
    double pressure(double x, double y) const;
  };

  /// peak sqrt(1 - x^2/ax^2 - y^2/ay^2) at the cell centres of `grid`, 0
  /// outside the ellipse [Pa, or per unit peak].
  Field sampled_hertz_pressure(const SurfaceGrid &grid, double semi_axis_x, double semi_axis_y, double peak);
} // namespace fretsim::contact
