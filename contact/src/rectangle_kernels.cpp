// Uniform-rectangle kernels of the elastic half-space.
//
// Notation: field point (x, y, z), patch [-a, a] x [-b, b]. A load density
// f(x - xi, y - eta) integrated over the patch equals the corner difference
// [F] = F(x+a, y+b) - F(x+a, y-b) - F(x-a, y+b) + F(x-a, y-b) of any F with
// d2F/dXdY = f; x-derivatives of the integral are corner differences of the
// Y-antiderivative of f, and so on. With X, Y the corner offsets and
// rho^2 = X^2 + Y^2 + z^2:
//
// Pressure (Boussinesq potentials, Johnson §3.2; docs/references.md §4.2 form)
//   V   = int 1/rho,       psi = int ln(rho + z)      (over the patch)
//   V_z   = -[atan(X Y / (z rho))]
//   psi_xx = [atan(X Y (rho - z) / (X^2 rho + Y^2 z))]   (atan(Y/X) - atan(Y z/(X rho)) combined)
//   psi_xy = [ln(rho + z)]
//   V_xx = -[X Y / ((X^2 + z^2) rho)],  V_xy = [1/rho],  V_xz = -[z Y / ((X^2 + z^2) rho)]
//   V_zz = -V_xx - V_yy (harmonic)
//   sigma_xx = (2 nu V_z - (1-2nu) psi_xx - z V_xx)/2pi,  sigma_zz = (V_z - z V_zz)/2pi,
//   sigma_xy = -((1-2nu) psi_xy + z V_xy)/2pi,  sigma_yz = -z V_yz/2pi,  sigma_xz = -z V_xz/2pi.
//
// Shear traction in +x (derived here from the Cerruti point-force stresses of
// docs/references.md §3.2). With 1/rho and Omega = z ln(rho + z) - rho (harmonic,
// Omega_x = -x/(rho + z)), the point-force stresses are
//   sigma_xx = (-3x^3/rho^5 + (1-2nu) Omega_xyy)/2pi
//   sigma_yy = (-3x y^2/rho^5 + (1-2nu) Omega_xxx)/2pi
//   sigma_xy = (-3x^2 y/rho^5 - (1-2nu) Omega_xxy)/2pi
//   sigma_zz = -z d_xz(1/rho)/2pi,  sigma_xz = (-z d_xx(1/rho) + d_z(1/rho))/2pi,  sigma_yz = -z d_xy(1/rho)/2pi
// and -3x^3/rho^5 = d_x(x^2/rho^3) + 2 d_x(1/rho), -3x y^2/rho^5 = d_x(y^2/rho^3),
// -3x^2 y/rho^5 = d_y(x^2/rho^3), which integrate over the patch to
//   sigma_xx = [X^2 Y/((X^2+z^2) rho) + 2 ln(Y + rho) - (1-2nu) Y/(rho + z)]/2pi
//   sigma_yy = [ln(Y + rho) - Y/rho + (1-2nu)(Y/(rho + z) - ln(Y + rho))]/2pi
//   sigma_xy = [ln(X + rho) - X/rho + (1-2nu) X/(rho + z)]/2pi
//   sigma_zz = -z V_xz/2pi (= the pressure's sigma_xz: reciprocity),
//   sigma_xz = -(z V_xx - V_z)/2pi,  sigma_yz = -z V_xy/2pi.
// The shear-y kernel is the reflection x <-> y of the shear-x kernel.
#include <fretsim/contact/rectangle_kernels.h>

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <vector>

namespace fretsim::contact
{
  namespace
  {
    constexpr double inv_two_pi = 0.5 / M_PI;

    /// ln(s + rho) without cancellation for s < 0: (rho + s)(rho - s) = rho^2 - s^2.
    double log_sum(double s, double rho, double rho_squared_minus_s_squared)
    {
      return s >= 0.0 ? std::log(s + rho) : std::log(rho_squared_minus_s_squared / (rho - s));
    }

    const int corner_sign[4] = {1, -1, -1, 1};

    template <typename Function>
    auto corner_difference(double x, double y, double half_x, double half_y, Function &&corner)
    {
      // Corner order matches corner_sign: (x+a, y+b), (x+a, y-b), (x-a, y+b), (x-a, y-b).
      auto result = corner(x + half_x, y + half_y);
      auto c1 = corner(x + half_x, y - half_y), c2 = corner(x - half_x, y + half_y),
           c3 = corner(x - half_x, y - half_y);
      result -= c1;
      result -= c2;
      result += c3;
      return result;
    }

    void check_poisson_ratio(double poisson_ratio)
    {
      if (!(poisson_ratio > -1.0 && poisson_ratio <= 0.5))
        throw std::invalid_argument("rectangle kernel: Poisson's ratio must lie in (-1, 0.5]");
    }

    StressTensor component(const detail::CornerValues &values, int load)
    {
      StressTensor s;
      for (int c = 0; c < stress_component_count; ++c)
        s[c] = values.value[load][c];
      return s;
    }
  } // namespace

  double StressTensor::operator[](int component) const
  {
    switch (component)
      {
        case StressComponent::xx: return xx;
        case StressComponent::yy: return yy;
        case StressComponent::zz: return zz;
        case StressComponent::yz: return yz;
        case StressComponent::xz: return xz;
        case StressComponent::xy: return xy;
      }
    throw std::out_of_range("StressTensor: component index outside 0..5");
  }

  double &StressTensor::operator[](int component)
  {
    switch (component)
      {
        case StressComponent::xx: return xx;
        case StressComponent::yy: return yy;
        case StressComponent::zz: return zz;
        case StressComponent::yz: return yz;
        case StressComponent::xz: return xz;
        case StressComponent::xy: return xy;
      }
    throw std::out_of_range("StressTensor: component index outside 0..5");
  }

  namespace detail
  {
    CornerValues rectangle_stress_corner(double X, double Y, double z, double nu)
    {
      const double X2 = X * X, Y2 = Y * Y, z2 = z * z;
      const double rho     = std::sqrt(X2 + Y2 + z2);
      const double r2x     = X2 + z2; // rho^2 - Y^2
      const double r2y     = Y2 + z2; // rho^2 - X^2
      const double inv_rho = 1.0 / rho;
      const double rho_z   = rho + z;
      const double rho_minus_z = (X2 + Y2) / rho_z; // no cancellation deep below the corner
      const double log_x = log_sum(X, rho, r2y), log_y = log_sum(Y, rho, r2x), log_z = std::log(rho_z);
      const double XY = X * Y;

      // Solid-angle term: [T] -> 2 pi inside and 0 outside as z -> 0; atan2 with
      // a non-negative second argument is atan(ratio) with the z = 0 limit built in.
      const double T   = std::atan2(XY, z * rho);
      const double Axx = std::atan2(XY * rho_minus_z, X2 * rho + Y2 * z);
      const double Ayy = std::atan2(XY * rho_minus_z, Y2 * rho + X2 * z);

      // Second derivatives of V, already multiplied by z: they only enter as
      // z V_ij, and at z = 0 these products vanish (V_ij itself is singular on
      // the corner lines there).
      double zVxx = 0.0, zVyy = 0.0, zVxy = 0.0, zVxz = 0.0, zVyz = 0.0;
      // X^2 Y / ((X^2 + z^2) rho) and its mirror; their z -> 0 limits are Y/rho, X/rho.
      double x2y = Y * inv_rho, y2x = X * inv_rho;
      if (z > 0.0)
        {
          const double over_rx = 1.0 / (r2x * rho), over_ry = 1.0 / (r2y * rho);
          zVxx = -z * XY * over_rx;
          zVyy = -z * XY * over_ry;
          zVxy = z * inv_rho;
          zVxz = -z2 * Y * over_rx;
          zVyz = -z2 * X * over_ry;
          x2y  = X2 * Y * over_rx;
          y2x  = Y2 * X * over_ry;
        }
      const double zVzz = -zVxx - zVyy;
      const double m    = 1.0 - 2.0 * nu;

      CornerValues c;
      double *p = c.value[0], *qx = c.value[1], *qy = c.value[2];
      p[xx] = inv_two_pi * (-2.0 * nu * T - m * Axx - zVxx);
      p[yy] = inv_two_pi * (-2.0 * nu * T - m * Ayy - zVyy);
      p[zz] = inv_two_pi * (-T - zVzz);
      p[xy] = -inv_two_pi * (m * log_z + zVxy);
      p[yz] = -inv_two_pi * zVyz;
      p[xz] = -inv_two_pi * zVxz;

      qx[xx] = inv_two_pi * (x2y + 2.0 * log_y - m * Y / rho_z);
      qx[yy] = inv_two_pi * (log_y - Y * inv_rho + m * (Y / rho_z - log_y));
      qx[xy] = inv_two_pi * (log_x - X * inv_rho + m * X / rho_z);
      qx[zz] = p[xz];
      qx[xz] = -inv_two_pi * (zVxx + T);
      qx[yz] = -inv_two_pi * zVxy;

      qy[yy] = inv_two_pi * (y2x + 2.0 * log_x - m * X / rho_z);
      qy[xx] = inv_two_pi * (log_x - X * inv_rho + m * (X / rho_z - log_x));
      qy[xy] = inv_two_pi * (log_y - Y * inv_rho + m * Y / rho_z);
      qy[zz] = p[yz];
      qy[yz] = -inv_two_pi * (zVyy + T);
      qy[xz] = qx[yz];
      return c;
    }
  } // namespace detail

  namespace
  {
    struct CornerSum
    {
      detail::CornerValues v;
      CornerSum &operator+=(const CornerSum &o) { return apply(o, 1.0); }
      CornerSum &operator-=(const CornerSum &o) { return apply(o, -1.0); }
      CornerSum &apply(const CornerSum &o, double sign)
      {
        for (int l = 0; l < 3; ++l)
          for (int c = 0; c < stress_component_count; ++c)
            v.value[l][c] += sign * o.v.value[l][c];
        return *this;
      }
    };
  } // namespace

  RectangleStresses rectangle_stresses(double x, double y, double z, double half_x, double half_y,
                                       double poisson_ratio)
  {
    check_poisson_ratio(poisson_ratio);
    if (!(z >= 0.0))
      throw std::invalid_argument("rectangle kernel: depth z must be >= 0 (z points into the body)");
    if (!(half_x > 0.0 && half_y > 0.0))
      throw std::invalid_argument("rectangle kernel: patch half widths must be positive");
    const CornerSum sum = corner_difference(x, y, half_x, half_y, [&](double X, double Y) {
      return CornerSum{detail::rectangle_stress_corner(X, Y, z, poisson_ratio)};
    });
    return {component(sum.v, 0), component(sum.v, 1), component(sum.v, 2)};
  }

  StressTensor rectangle_stress_pressure(double x, double y, double z, double half_x, double half_y,
                                         double poisson_ratio)
  {
    return rectangle_stresses(x, y, z, half_x, half_y, poisson_ratio).pressure;
  }

  StressTensor rectangle_stress_shear_x(double x, double y, double z, double half_x, double half_y,
                                        double poisson_ratio)
  {
    return rectangle_stresses(x, y, z, half_x, half_y, poisson_ratio).shear_x;
  }

  StressTensor rectangle_stress_shear_y(double x, double y, double z, double half_x, double half_y,
                                        double poisson_ratio)
  {
    return rectangle_stresses(x, y, z, half_x, half_y, poisson_ratio).shear_y;
  }

  namespace detail
  {
    int kernel_parity_x(int load, int component)
    {
      const int pressure = (component == xz || component == xy) ? -1 : 1;
      return load == 1 ? -pressure : pressure;
    }

    int kernel_parity_y(int load, int component)
    {
      const int pressure = (component == yz || component == xy) ? -1 : 1;
      return load == 2 ? -pressure : pressure;
    }

    double CellKernelTable::operator()(int load, int component, int di, int dj) const
    {
      const int sign = (di < 0 ? kernel_parity_x(load, component) : 1) * (dj < 0 ? kernel_parity_y(load, component) : 1);
      return sign * row(load, component, std::abs(dj))[std::abs(di)];
    }

    CellKernelTable cell_kernel_table(int nx, int ny, double hx, double hy, double z, double poisson_ratio)
    {
      check_poisson_ratio(poisson_ratio);
      if (nx < 1 || ny < 1 || !(hx > 0.0) || !(hy > 0.0) || !(z >= 0.0))
        throw std::invalid_argument("cell kernel table: needs nx, ny >= 1, positive cell sizes and depth >= 0");
      // Corner lattice: X_m = (m - 1/2) hx, m = 0..nx, so that the cell at
      // offset di >= 0 has its corners at m = di and di + 1.
      const int    lx = nx + 1, ly = ny + 1;
      const int    n_values = 3 * stress_component_count;
      std::vector<double> lattice(static_cast<std::size_t>(lx) * ly * n_values);
#pragma omp parallel for schedule(dynamic, 4)
      for (int n = 0; n < ly; ++n)
        for (int m = 0; m < lx; ++m)
          {
            const CornerValues c = rectangle_stress_corner((m - 0.5) * hx, (n - 0.5) * hy, z, poisson_ratio);
            double *out = &lattice[(static_cast<std::size_t>(n) * lx + m) * n_values];
            for (int k = 0; k < n_values; ++k)
              out[k] = c.value[k / stress_component_count][k % stress_component_count];
          }
      CellKernelTable table;
      table.nx = nx;
      table.ny = ny;
      table.values.resize(static_cast<std::size_t>(n_values) * nx * ny);
      auto corner = [&](int m, int n, int k) { return lattice[(static_cast<std::size_t>(n) * lx + m) * n_values + k]; };
#pragma omp parallel for schedule(static)
      for (int dj = 0; dj < ny; ++dj)
        for (int k = 0; k < n_values; ++k)
          {
            double *out = table.values.data() + (static_cast<std::size_t>(k) * ny + dj) * nx;
            for (int di = 0; di < nx; ++di)
              out[di] = corner(di + 1, dj + 1, k) - corner(di + 1, dj, k) - corner(di, dj + 1, k) + corner(di, dj, k);
          }
      return table;
    }
  } // namespace detail

  // ---------------------------------------------------------------- surface displacements

  namespace
  {
    struct DisplacementCorner
    {
      double x_log_y = 0.0; ///< X ln(Y + rho): [.] = int int X^2/rho^3 ... see F1, F2 in docs/references.md §4.1
      double y_log_x = 0.0; ///< Y ln(X + rho)
      double rho     = 0.0;
      double f4_x    = 0.0; ///< F4(X, Y): d2/dXdY = X / rho^2
      double f4_y    = 0.0; ///< F4(Y, X): d2/dXdY = Y / rho^2

      DisplacementCorner &operator+=(const DisplacementCorner &o) { return apply(o, 1.0); }
      DisplacementCorner &operator-=(const DisplacementCorner &o) { return apply(o, -1.0); }
      DisplacementCorner &apply(const DisplacementCorner &o, double sign)
      {
        x_log_y += sign * o.x_log_y;
        y_log_x += sign * o.y_log_x;
        rho += sign * o.rho;
        f4_x += sign * o.f4_x;
        f4_y += sign * o.f4_y;
        return *this;
      }
    };

    /// F4(X, Y) = (Y/2) ln(X^2 + Y^2) + X atan(Y/X); both terms tend to 0 on their axes.
    double f4(double X, double Y)
    {
      const double r2 = X * X + Y * Y;
      return (Y != 0.0 ? 0.5 * Y * std::log(r2) : 0.0) + (X != 0.0 ? X * std::atan(Y / X) : 0.0);
    }

    DisplacementCorner displacement_corner(double X, double Y)
    {
      DisplacementCorner c;
      c.rho = std::sqrt(X * X + Y * Y);
      // X ln(Y + rho) -> 0 as X -> 0 even where ln diverges (Y < 0).
      if (X != 0.0)
        c.x_log_y = X * log_sum(Y, c.rho, X * X);
      if (Y != 0.0)
        c.y_log_x = Y * log_sum(X, c.rho, Y * Y);
      c.f4_x = f4(X, Y);
      c.f4_y = f4(Y, X);
      return c;
    }

    DisplacementCorner displacement_corners(double x, double y, double half_x, double half_y, double shear_modulus,
                                            double poisson_ratio)
    {
      check_poisson_ratio(poisson_ratio);
      if (!(shear_modulus > 0.0))
        throw std::invalid_argument("rectangle kernel: shear modulus must be positive");
      if (!(half_x > 0.0 && half_y > 0.0))
        throw std::invalid_argument("rectangle kernel: patch half widths must be positive");
      return corner_difference(x, y, half_x, half_y, displacement_corner);
    }
  } // namespace

  SurfaceDisplacement rectangle_displacement_pressure(double x, double y, double half_x, double half_y,
                                                      double shear_modulus, double nu)
  {
    const auto   c = displacement_corners(x, y, half_x, half_y, shear_modulus, nu);
    const double g = 1.0 / (2.0 * M_PI * shear_modulus);
    // u_z = (1-nu)/(2 pi G) [F1]; u_x = -(1-2nu)/(4 pi G) [F4]: Boussinesq u_r points to the load.
    return {-0.5 * (1.0 - 2.0 * nu) * g * c.f4_x, -0.5 * (1.0 - 2.0 * nu) * g * c.f4_y,
            (1.0 - nu) * g * (c.x_log_y + c.y_log_x)};
  }

  SurfaceDisplacement rectangle_displacement_shear_x(double x, double y, double half_x, double half_y,
                                                     double shear_modulus, double nu)
  {
    const auto   c = displacement_corners(x, y, half_x, half_y, shear_modulus, nu);
    const double g = 1.0 / (2.0 * M_PI * shear_modulus);
    return {g * ((1.0 - nu) * c.x_log_y + c.y_log_x), -nu * g * c.rho, 0.5 * (1.0 - 2.0 * nu) * g * c.f4_x};
  }

  SurfaceDisplacement rectangle_displacement_shear_y(double x, double y, double half_x, double half_y,
                                                     double shear_modulus, double nu)
  {
    const auto   c = displacement_corners(x, y, half_x, half_y, shear_modulus, nu);
    const double g = 1.0 / (2.0 * M_PI * shear_modulus);
    return {-nu * g * c.rho, g * ((1.0 - nu) * c.y_log_x + c.x_log_y), 0.5 * (1.0 - 2.0 * nu) * g * c.f4_y};
  }
} // namespace fretsim::contact
