#pragma once
// Closed-form elastic fields of a uniform load on a rectangular patch of a
// half-space (Love 1929; Johnson, Contact Mechanics, §3.2-3.3; the Cerruti
// stresses integrated in closed form here, see rectangle_kernels.cpp).
// Conventions (docs/theory.md §6, docs/references.md §0): z >= 0 into the body,
// tension positive, pressure pushes into the body, shear traction acts on the
// body's surface in +x (+y), so that sigma_xz(z = 0) = -q_x inside the patch.

#include <cstddef>
#include <vector>

namespace fretsim::contact
{
  /// Voigt order xx, yy, zz, yz, xz, xy (docs/theory.md §6).
  enum StressComponent
  {
    xx = 0,
    yy,
    zz,
    yz,
    xz,
    xy
  };
  constexpr int stress_component_count = 6;

  /// A symmetric stress tensor [Pa, or per unit load].
  struct StressTensor
  {
    double xx = 0.0, yy = 0.0, zz = 0.0, yz = 0.0, xz = 0.0, xy = 0.0;

    double  operator[](int component) const;
    double &operator[](int component);
  };

  /// Stress at (x, y, z), relative to the patch centre, from a unit uniform
  /// load on the patch [-half_x, half_x] x [-half_y, half_y] of the surface.
  /// z >= 0; z = 0 gives the surface limit (inside and outside the patch; on
  /// the patch edges the pressure kernel returns the mean of the two sides and
  /// the shear kernels are log-singular there, as the continuum is).
  StressTensor rectangle_stress_pressure(double x, double y, double z, double half_x, double half_y,
                                         double poisson_ratio);
  /// Unit shear traction in +x on the body's surface.
  StressTensor rectangle_stress_shear_x(double x, double y, double z, double half_x, double half_y,
                                        double poisson_ratio);
  /// Unit shear traction in +y: the x kernel reflected in the plane x = y.
  StressTensor rectangle_stress_shear_y(double x, double y, double z, double half_x, double half_y,
                                        double poisson_ratio);

  /// The stresses of all three unit loads at one point, sharing the corner
  /// functions (what the evaluators tabulate).
  struct RectangleStresses
  {
    StressTensor pressure, shear_x, shear_y;
  };
  RectangleStresses rectangle_stresses(double x, double y, double z, double half_x, double half_y,
                                       double poisson_ratio);

  /// Surface displacement [m per Pa of load] of one body (docs/references.md
  /// §4.1) at (x, y, 0) relative to the patch centre; u_z positive into the body.
  struct SurfaceDisplacement
  {
    double x = 0.0, y = 0.0, z = 0.0;
  };
  SurfaceDisplacement rectangle_displacement_pressure(double x, double y, double half_x, double half_y,
                                                      double shear_modulus, double poisson_ratio);
  SurfaceDisplacement rectangle_displacement_shear_x(double x, double y, double half_x, double half_y,
                                                     double shear_modulus, double poisson_ratio);
  SurfaceDisplacement rectangle_displacement_shear_y(double x, double y, double half_x, double half_y,
                                                     double shear_modulus, double poisson_ratio);

  namespace detail
  {
    /// The stress of each unit load is a corner difference
    /// [C](x, y) = C(x+a, y+b) - C(x+a, y-b) - C(x-a, y+b) + C(x-a, y-b) of
    /// these per-corner values, indexed [load][component] with load 0 =
    /// pressure, 1 = shear x, 2 = shear y. Tabulating C on the lattice of cell
    /// corners gives every cell-offset kernel with one call per corner.
    struct CornerValues
    {
      double value[3][stress_component_count];
    };
    CornerValues rectangle_stress_corner(double corner_x, double corner_y, double z, double poisson_ratio);

    /// Parity of a kernel under x -> -x (y -> -y): +1 even, -1 odd. Pressure
    /// is even in x for xx, yy, zz, yz; the shear-x load flips every x parity
    /// (the load reverses), the shear-y load every y parity.
    int kernel_parity_x(int load, int component);
    int kernel_parity_y(int load, int component);

    /// Stress at cell centres from a unit load on one grid cell, for every
    /// non-negative cell offset (di, dj) = (field - load) at one depth; the
    /// other quadrants follow by parity. Built from one corner evaluation per
    /// cell corner of the lattice, so a table costs (nx+1)(ny+1) evaluations.
    struct CellKernelTable
    {
      int                 nx = 0, ny = 0;
      std::vector<double> values; ///< [load][component][dj][di], 0 <= di < nx, 0 <= dj < ny

      const double *row(int load, int component, int dj) const
      {
        return values.data() + ((static_cast<std::size_t>(load) * stress_component_count + component) * ny + dj) * nx;
      }
      /// Kernel at any offset, -nx < di < nx, -ny < dj < ny.
      double operator()(int load, int component, int di, int dj) const;
    };
    CellKernelTable cell_kernel_table(int nx, int ny, double hx, double hy, double z, double poisson_ratio);
  } // namespace detail
} // namespace fretsim::contact
