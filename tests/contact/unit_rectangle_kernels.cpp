// Uniform-rectangle kernels against docs/references.md §4.1 (surface
// displacements) and §4.2 (subsurface stresses), against adaptive quadrature of
// the Boussinesq and Cerruti point-force solutions of docs/references.md §3.2, and
// against identities they must satisfy (surface limits, parity, reflection,
// reciprocity, equilibrium).
#include <fretsim/contact/rectangle_kernels.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <vector>

using namespace fretsim::contact;

namespace
{
  using Stress6 = std::array<double, 6>; // Voigt xx, yy, zz, yz, xz, xy

  Stress6 as_array(const StressTensor &s) { return {s.xx, s.yy, s.zz, s.yz, s.xz, s.xy}; }

  // ---- point-force kernels, docs/references.md §3.2 (unit force at the origin) -------------

  /// Boussinesq: unit normal force into the body, converted from (r, theta, z).
  Stress6 boussinesq(double x, double y, double z, double nu)
  {
    const double r2 = x * x + y * y, r = std::sqrt(r2), rho = std::sqrt(r2 + z * z);
    const double rho5 = rho * rho * rho * rho * rho;
    const double sr = (1.0 / (2 * M_PI)) * ((1 - 2 * nu) / r2 * (1 - z / rho) - 3 * z * r2 / rho5);
    const double st = -(1.0 / (2 * M_PI)) * (1 - 2 * nu) * ((1 / r2) * (1 - z / rho) - z / (rho * rho * rho));
    const double sz = -3 * z * z * z / (2 * M_PI * rho5);
    const double trz = -3 * r * z * z / (2 * M_PI * rho5);
    const double c = x / r, s = y / r;
    return {sr * c * c + st * s * s, sr * s * s + st * c * c, sz, trz * s, trz * c, (sr - st) * s * c};
  }

  /// Cerruti: unit tangential force in +x on the surface.
  Stress6 cerruti(double x, double y, double z, double nu)
  {
    const double rho = std::sqrt(x * x + y * y + z * z), rho2 = rho * rho, rho3 = rho2 * rho, rho5 = rho3 * rho2;
    const double rz = rho + z, rz2 = rz * rz, m = 1 - 2 * nu, k = 1.0 / (2 * M_PI);
    const double sx = k * x / rho3 * (-3 * x * x / rho2 + m / rz2 * (rho2 - y * y - 2 * rho * y * y / rz));
    const double sy = k * x / rho3 * (-3 * y * y / rho2 + m / rz2 * (3 * rho2 - x * x - 2 * rho * x * x / rz));
    const double sz = -3 * x * z * z * k / rho5;
    const double txy = k * y / rho3 * (-3 * x * x / rho2 + m / rz2 * (-rho2 + x * x + 2 * rho * x * x / rz));
    const double tyz = -3 * x * y * z * k / rho5;
    const double txz = -3 * x * x * z * k / rho5;
    return {sx, sy, sz, tyz, txz, txy};
  }

  /// Cerruti rotated to a force in +y: reflection x <-> y.
  Stress6 cerruti_y(double x, double y, double z, double nu)
  {
    const Stress6 s = cerruti(y, x, z, nu);
    return {s[1], s[0], s[2], s[4], s[3], s[5]};
  }

  // ---- adaptive 2-D Gauss-Legendre quadrature ----------------------------------------

  // 8-point Gauss-Legendre nodes and weights on [-1, 1].
  const double gl_node[8]   = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
                               0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
  const double gl_weight[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873, 0.3626837833783620,
                               0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

  using Integrand = std::function<Stress6(double xi, double eta)>;

  Stress6 panel(const Integrand &f, double x0, double x1, double y0, double y1)
  {
    Stress6 sum{};
    const double hx = 0.5 * (x1 - x0), hy = 0.5 * (y1 - y0), cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j)
        {
          const Stress6 v = f(cx + hx * gl_node[i], cy + hy * gl_node[j]);
          for (int c = 0; c < 6; ++c)
            sum[c] += gl_weight[i] * gl_weight[j] * hx * hy * v[c];
        }
    return sum;
  }

  /// Quadtree refinement until the four children agree with the parent.
  Stress6 adaptive(const Integrand &f, double x0, double x1, double y0, double y1, const Stress6 &whole,
                   double tolerance, int depth)
  {
    const double xm = 0.5 * (x0 + x1), ym = 0.5 * (y0 + y1);
    const Stress6 a = panel(f, x0, xm, y0, ym), b = panel(f, xm, x1, y0, ym), c = panel(f, x0, xm, ym, y1),
                  d = panel(f, xm, x1, ym, y1);
    Stress6 sum{};
    double  change = 0.0, size = 0.0;
    for (int k = 0; k < 6; ++k)
      {
        sum[k] = a[k] + b[k] + c[k] + d[k];
        change = std::max(change, std::abs(sum[k] - whole[k]));
        size   = std::max(size, std::abs(sum[k]));
      }
    // Converged, or at the round-off floor of this panel's value.
    if (change < tolerance || change < 1e-14 * size || depth > 30)
      return sum;
    const Stress6 ra = adaptive(f, x0, xm, y0, ym, a, 0.5 * tolerance, depth + 1),
                  rb = adaptive(f, xm, x1, y0, ym, b, 0.5 * tolerance, depth + 1),
                  rc = adaptive(f, x0, xm, ym, y1, c, 0.5 * tolerance, depth + 1),
                  rd = adaptive(f, xm, x1, ym, y1, d, 0.5 * tolerance, depth + 1);
    for (int k = 0; k < 6; ++k)
      sum[k] = ra[k] + rb[k] + rc[k] + rd[k];
    return sum;
  }

  /// Integral of a point-force kernel over the patch [-a, a] x [-b, b], field
  /// at (x, y, z). The patch is first split at the field point's projection so
  /// that the near-singular peak sits on panel corners.
  Stress6 integrate_patch(const std::function<Stress6(double, double, double, double)> &kernel, double x, double y,
                          double z, double a, double b, double nu, double tolerance)
  {
    const Integrand f = [&](double xi, double eta) { return kernel(x - xi, y - eta, z, nu); };
    std::vector<double> xs{-a, a}, ys{-b, b};
    if (x > -a && x < a)
      xs.insert(xs.begin() + 1, x);
    if (y > -b && y < b)
      ys.insert(ys.begin() + 1, y);
    Stress6 total{};
    for (std::size_t i = 0; i + 1 < xs.size(); ++i)
      for (std::size_t j = 0; j + 1 < ys.size(); ++j)
        {
          const Stress6 whole = panel(f, xs[i], xs[i + 1], ys[j], ys[j + 1]);
          const Stress6 part  = adaptive(f, xs[i], xs[i + 1], ys[j], ys[j + 1], whole, tolerance, 0);
          for (int k = 0; k < 6; ++k)
            total[k] += part[k];
        }
    return total;
  }

  const double nu = 0.3;
} // namespace

// ---- docs/references.md §4.2 test values --------------------------------------------------

TEST(RectangleKernels, ReferenceTestValues)
{
  // docs/references.md §4.2: unit load, nu = 0.3, a = 0.5, b = 0.3, values given to 7
  // decimals in the order [sx, sy, sz, txy, tyz, txz]: tolerance half a unit
  // in the last digit plus round-off.
  struct Row
  {
    double x, y, z;
    bool   tangential;
    double expected[6];
  };
  const Row rows[] = {
    {0.2, 0.1, 0.3, false, {-0.1598029, -0.0988496, -0.7201834, -0.0101009, -0.0923260, -0.0707651}},
    {0.2, 0.1, 0.3, true, {-0.1496109, 2.7735e-5, -0.0707651, -0.0483475, -0.0147774, -0.2465218}},
    {0.9, -0.4, 0.25, false, {-0.0457323, -0.0291383, -0.0110708, 0.0127891, 0.0135454, -0.0259759}},
    {0.9, -0.4, 0.25, true, {-0.1842220, -0.0262625, -0.0259759, 0.0799816, 0.0325733, -0.0673077}},
  };
  for (const Row &row : rows)
    {
      const StressTensor s = row.tangential ? rectangle_stress_shear_x(row.x, row.y, row.z, 0.5, 0.3, nu)
                                            : rectangle_stress_pressure(row.x, row.y, row.z, 0.5, 0.3, nu);
      const double got[6] = {s.xx, s.yy, s.zz, s.xy, s.yz, s.xz};
      for (int c = 0; c < 6; ++c)
        EXPECT_NEAR(got[c], row.expected[c], 6e-8)
          << (row.tangential ? "shear" : "pressure") << " at (" << row.x << ", " << row.y << ", " << row.z
          << ") component " << c;
    }
}

// ---- quadrature of the point-force kernels ----------------------------------------

TEST(RectangleKernels, AgreeWithQuadratureOfPointForceKernels)
{
  // Field points inside, close to the edges and corners and outside, at depths
  // from 0.005 to 3 (patch half-widths 0.5 x 0.3). The adaptive quadrature is
  // driven to 1e-12 absolute (measured agreement ~2e-13); the closed forms
  // must agree to 1e-10 relative to the largest component magnitude of that
  // load (floor 1e-3).
  const double a = 0.5, b = 0.3;
  const double points[][2] = {{0.0, 0.0},  {0.2, 0.1},   {-0.35, 0.22}, {0.49, -0.29}, {0.51, 0.0},  {0.9, -0.4},
                              {-1.3, 0.7}, {0.05, -0.8}, {2.5, 2.0},    {-0.6, -0.31}, {0.3, 0.45},  {-4.0, 0.2}};
  const double depths[] = {0.005, 0.02, 0.1, 0.3, 0.75, 3.0};
  double       worst[3] = {0, 0, 0};
  for (const auto &p : points)
    for (const double z : depths)
      {
        const RectangleStresses closed = rectangle_stresses(p[0], p[1], z, a, b, nu);
        const Stress6 reference[3] = {integrate_patch(boussinesq, p[0], p[1], z, a, b, nu, 1e-12),
                                      integrate_patch(cerruti, p[0], p[1], z, a, b, nu, 1e-12),
                                      integrate_patch(cerruti_y, p[0], p[1], z, a, b, nu, 1e-12)};
        const Stress6 got[3] = {as_array(closed.pressure), as_array(closed.shear_x), as_array(closed.shear_y)};
        for (int load = 0; load < 3; ++load)
          {
            double scale = 1e-3;
            for (int c = 0; c < 6; ++c)
              scale = std::max(scale, std::abs(reference[load][c]));
            for (int c = 0; c < 6; ++c)
              {
                const double error = std::abs(got[load][c] - reference[load][c]) / scale;
                worst[load]        = std::max(worst[load], error);
                EXPECT_LT(error, 1e-9) << "load " << load << " component " << c << " at (" << p[0] << ", " << p[1]
                                       << ", " << z << "): closed " << got[load][c] << " quadrature "
                                       << reference[load][c];
              }
          }
      }
  std::printf("max relative error vs quadrature: pressure %.2e, shear x %.2e, shear y %.2e\n", worst[0], worst[1],
              worst[2]);
}

// ---- surface limits -----------------------------------------------------------------

TEST(RectangleKernels, SurfaceValuesInsideAndOutsideThePatch)
{
  const double a = 0.5, b = 0.3;
  // Equilibrium with the applied traction (docs/references.md §0): sigma_zz = -p and
  // sigma_xz = -q_x inside, 0 outside; no normal stress from shear and no
  // shear stress from pressure. Exact up to round-off of the atan sums.
  const double inside[][2]  = {{0.0, 0.0}, {0.3, -0.2}, {-0.45, 0.25}};
  const double outside[][2] = {{0.7, 0.0}, {0.3, -0.5}, {-2.0, 1.0}};
  for (const auto &p : inside)
    {
      const RectangleStresses s = rectangle_stresses(p[0], p[1], 0.0, a, b, nu);
      EXPECT_NEAR(s.pressure.zz, -1.0, 1e-14);
      EXPECT_NEAR(s.pressure.xz, 0.0, 1e-14);
      EXPECT_NEAR(s.pressure.yz, 0.0, 1e-14);
      EXPECT_NEAR(s.shear_x.xz, -1.0, 1e-14);
      EXPECT_NEAR(s.shear_x.zz, 0.0, 1e-14);
      EXPECT_NEAR(s.shear_x.yz, 0.0, 1e-14);
      EXPECT_NEAR(s.shear_y.yz, -1.0, 1e-14);
      EXPECT_NEAR(s.shear_y.zz, 0.0, 1e-14);
      EXPECT_NEAR(s.shear_y.xz, 0.0, 1e-14);
    }
  for (const auto &p : outside)
    {
      const RectangleStresses s = rectangle_stresses(p[0], p[1], 0.0, a, b, nu);
      EXPECT_NEAR(s.pressure.zz, 0.0, 1e-14);
      EXPECT_NEAR(s.shear_x.xz, 0.0, 1e-14);
      EXPECT_NEAR(s.shear_y.yz, 0.0, 1e-14);
    }
  // Every component is continuous as z -> 0 away from the edges: the z = 0
  // branch (atan2 limits, z-terms dropped) must match z = 1e-9, where the
  // fields differ by O(z) (1e-9 times the gradient, gradients here are O(10)).
  for (const auto &p : {inside[0], inside[1], inside[2], outside[0], outside[1], outside[2]})
    {
      const RectangleStresses s0 = rectangle_stresses(p[0], p[1], 0.0, a, b, nu);
      const RectangleStresses s1 = rectangle_stresses(p[0], p[1], 1e-9, a, b, nu);
      for (int c = 0; c < 6; ++c)
        {
          EXPECT_NEAR(s0.pressure[c], s1.pressure[c], 1e-7) << "pressure component " << c;
          EXPECT_NEAR(s0.shear_x[c], s1.shear_x[c], 1e-7) << "shear x component " << c;
          EXPECT_NEAR(s0.shear_y[c], s1.shear_y[c], 1e-7) << "shear y component " << c;
        }
    }
  // On the patch edge the surface pressure kernel gives the mean of both sides.
  EXPECT_NEAR(rectangle_stress_pressure(a, 0.0, 0.0, a, b, nu).zz, -0.5, 1e-14);
}

TEST(RectangleKernels, LongStripTendsToPlaneStrain)
{
  // A patch 2000 times longer than wide is a strip: at its centre line the
  // surface pressure field is sigma_xx = sigma_zz = -p and, in plane strain,
  // sigma_yy = nu (sigma_xx + sigma_zz) = -2 nu p (Johnson §2.6). The finite
  // length changes these by O(a/b) = 1e-3.
  const double a = 0.5, b = 1000.0;
  const StressTensor s = rectangle_stress_pressure(0.1, 0.0, 0.0, a, b, nu);
  EXPECT_NEAR(s.zz, -1.0, 1e-12);
  EXPECT_NEAR(s.xx, -1.0, 1e-3);
  EXPECT_NEAR(s.yy, -2.0 * nu, 1e-3);
  // Below the strip centre (Johnson eq. 2.43 for a uniform strip load at x = 0):
  // sigma_zz = -(p/pi)(2 alpha + sin 2 alpha) with tan alpha = a/z; same O(a/b).
  const double z = 0.4, alpha = std::atan(a / z);
  EXPECT_NEAR(rectangle_stress_pressure(0.0, 0.0, z, a, b, nu).zz, -(2 * alpha + std::sin(2 * alpha)) / M_PI, 1e-3);
  EXPECT_NEAR(rectangle_stress_pressure(0.0, 0.0, z, a, b, nu).xx, -(2 * alpha - std::sin(2 * alpha)) / M_PI, 1e-3);
}

// ---- identities ------------------------------------------------------------------------

TEST(RectangleKernels, ParityReflectionAndReciprocity)
{
  const double a = 0.4, b = 0.25, z = 0.3;
  // Parity under x -> -x and y -> -y: pressure is even in x for xx, yy, zz,
  // yz and odd for xz, xy; even in y for xx, yy, zz, xz and odd for yz, xy.
  // Shear x flips its x parity (the load reverses), shear y its y parity.
  // These hold to round-off (1e-15 relative, tolerance 1e-13).
  const int px[6] = {1, 1, 1, 1, -1, -1}, py[6] = {1, 1, 1, -1, 1, -1};
  for (const auto &p : {std::array<double, 2>{0.3, 0.2}, std::array<double, 2>{-0.7, 0.55}})
    {
      const RectangleStresses s   = rectangle_stresses(p[0], p[1], z, a, b, nu);
      const RectangleStresses smx = rectangle_stresses(-p[0], p[1], z, a, b, nu);
      const RectangleStresses smy = rectangle_stresses(p[0], -p[1], z, a, b, nu);
      for (int c = 0; c < 6; ++c)
        {
          EXPECT_NEAR(smx.pressure[c], px[c] * s.pressure[c], 1e-13);
          EXPECT_NEAR(smy.pressure[c], py[c] * s.pressure[c], 1e-13);
          EXPECT_NEAR(smx.shear_x[c], -px[c] * s.shear_x[c], 1e-13);
          EXPECT_NEAR(smy.shear_x[c], py[c] * s.shear_x[c], 1e-13);
          EXPECT_NEAR(smx.shear_y[c], px[c] * s.shear_y[c], 1e-13);
          EXPECT_NEAR(smy.shear_y[c], -py[c] * s.shear_y[c], 1e-13);
        }
      // Shear y is shear x reflected in the plane x = y (with a <-> b).
      const StressTensor qy = rectangle_stress_shear_y(p[0], p[1], z, a, b, nu);
      const StressTensor qx = rectangle_stress_shear_x(p[1], p[0], z, b, a, nu);
      EXPECT_NEAR(qy.xx, qx.yy, 1e-13);
      EXPECT_NEAR(qy.yy, qx.xx, 1e-13);
      EXPECT_NEAR(qy.zz, qx.zz, 1e-13);
      EXPECT_NEAR(qy.yz, qx.xz, 1e-13);
      EXPECT_NEAR(qy.xz, qx.yz, 1e-13);
      EXPECT_NEAR(qy.xy, qx.xy, 1e-13);
      // Reciprocity (docs/references.md §3.2): Cerruti sigma_zz equals Boussinesq
      // tau_xz, both -3 x z^2 / (2 pi rho^5); so the rectangle kernels agree.
      const RectangleStresses sp = rectangle_stresses(p[0], p[1], z, a, b, nu);
      EXPECT_NEAR(sp.shear_x.zz, sp.pressure.xz, 1e-15);
      EXPECT_NEAR(sp.shear_y.zz, sp.pressure.yz, 1e-15);
      EXPECT_NEAR(sp.shear_y.xz, sp.shear_x.yz, 1e-15);
    }
}

TEST(RectangleKernels, SatisfyEquilibrium)
{
  // div sigma = 0 below the surface, checked with 4th-order central
  // differences (step 1e-3, truncation ~1e-12 times 5th derivatives of O(100)
  // near the patch): residual below 1e-7 against stress gradients of O(1).
  const double a = 0.5, b = 0.3, h = 1e-3;
  const double points[][3] = {{0.1, 0.05, 0.2}, {0.6, -0.4, 0.3}, {-1.1, 0.2, 0.5}};
  for (const auto &p : points)
    for (int load = 0; load < 3; ++load)
      {
        auto sigma = [&](double x, double y, double z) {
          const RectangleStresses s = rectangle_stresses(x, y, z, a, b, nu);
          return load == 0 ? s.pressure : load == 1 ? s.shear_x : s.shear_y;
        };
        auto d = [&](int axis, int component) {
          double e[3] = {0, 0, 0};
          e[axis]     = h;
          auto at     = [&](double k) { return sigma(p[0] + k * e[0], p[1] + k * e[1], p[2] + k * e[2])[component]; };
          return (-at(2) + 8 * at(1) - 8 * at(-1) + at(-2)) / (12 * h);
        };
        EXPECT_NEAR(d(0, xx) + d(1, xy) + d(2, xz), 0.0, 1e-7) << "load " << load;
        EXPECT_NEAR(d(0, xy) + d(1, yy) + d(2, yz), 0.0, 1e-7) << "load " << load;
        EXPECT_NEAR(d(0, xz) + d(1, yz) + d(2, zz), 0.0, 1e-7) << "load " << load;
      }
}

TEST(RectangleKernels, CellTableMatchesPointKernels)
{
  // The evaluators' kernel table (corner lattice, one quadrant plus parity)
  // against the point-wise kernels at every offset of a small non-square grid,
  // including z = 0: same formulas, corner sums in another order, so 1e-13
  // relative to the largest entry of the component.
  const int    nx = 9, ny = 6;
  const double hx = 0.7, hy = 0.45;
  for (const double z : {0.0, 0.2, 1.5})
    {
      const detail::CellKernelTable table = detail::cell_kernel_table(nx, ny, hx, hy, z, nu);
      for (int load = 0; load < 3; ++load)
        for (int c = 0; c < 6; ++c)
          {
            double scale = 1e-300;
            for (int dj = 0; dj < ny; ++dj)
              for (int di = 0; di < nx; ++di)
                scale = std::max(scale, std::abs(table.row(load, c, dj)[di]));
            for (int dj = -(ny - 1); dj < ny; ++dj)
              for (int di = -(nx - 1); di < nx; ++di)
                {
                  const RectangleStresses s = rectangle_stresses(di * hx, dj * hy, z, hx / 2, hy / 2, nu);
                  const StressTensor &expected = load == 0 ? s.pressure : load == 1 ? s.shear_x : s.shear_y;
                  EXPECT_NEAR(table(load, c, di, dj) / scale, expected[c] / scale, 1e-13)
                    << "load " << load << " component " << c << " offset (" << di << ", " << dj << ") z " << z;
                }
          }
    }
}

// ---- surface displacements, docs/references.md §4.1 ------------------------------------------

TEST(RectangleKernels, SurfaceDisplacementCheckNumbers)
{
  // docs/references.md §4.1 table: G = 1, nu = 0.3, patch [-0.5, 0.5] x [-0.3, 0.3];
  // 10 decimals given, tolerance one unit in the last place.
  struct Row
  {
    double x, y, uz_p, ux_q, uy_q, uz_q;
  };
  const Row rows[] = {{2.0, 1.0, 0.0302130593, 0.0404216307, 0.0051565831, 0.0076560410},
                      {0.7, -0.2, 0.1051774348, 0.1425780328, -0.0104597810, 0.0271119434},
                      {3.5, 2.2, 0.0162130350, 0.0211681986, 0.0031224317, 0.0039097489}};
  for (const Row &r : rows)
    {
      const SurfaceDisplacement up = rectangle_displacement_pressure(r.x, r.y, 0.5, 0.3, 1.0, nu);
      const SurfaceDisplacement uq = rectangle_displacement_shear_x(r.x, r.y, 0.5, 0.3, 1.0, nu);
      EXPECT_NEAR(up.z, r.uz_p, 1e-10);
      EXPECT_NEAR(uq.x, r.ux_q, 1e-10);
      EXPECT_NEAR(uq.y, r.uy_q, 1e-10);
      EXPECT_NEAR(uq.z, r.uz_q, 1e-10);
      // Betti: the tangential displacement from pressure is minus the normal
      // displacement from shear (docs/references.md §4.1, reciprocal coupling).
      EXPECT_NEAR(up.x, -uq.z, 1e-15);
      // Shear y is the reflection of shear x.
      const SurfaceDisplacement uqy = rectangle_displacement_shear_y(r.y, r.x, 0.3, 0.5, 1.0, nu);
      EXPECT_NEAR(uqy.y, uq.x, 1e-15);
      EXPECT_NEAR(uqy.x, uq.y, 1e-15);
      EXPECT_NEAR(uqy.z, uq.z, 1e-15);
    }
  // Self-influence at the centre of a square cell of side h:
  // [F1] = 4 h ln(1 + sqrt 2) = 3.5254943481 h (docs/references.md §4.1), 11 digits.
  const double h = 2e-4, G = 80e9;
  EXPECT_NEAR(rectangle_displacement_pressure(0.0, 0.0, h / 2, h / 2, G, nu).z / ((1 - nu) / (2 * M_PI * G) * h),
              3.5254943481, 1e-10);
}

TEST(RectangleKernels, SurfaceDisplacementsAgreeWithQuadrature)
{
  // The z = 0 Boussinesq and Cerruti displacements of docs/references.md §3.2 (G = 1)
  // integrated adaptively over the patch at points off the patch (the 1/rho
  // singularity inside is integrable but slow for this quadrature). 1e-10.
  const double a = 0.5, b = 0.3;
  auto displacements = [](double x, double y, double, double nu_) -> Stress6 {
    const double rho = std::sqrt(x * x + y * y), k = 1.0 / (4 * M_PI);
    const double r   = rho;
    // Boussinesq u_r (towards the load) at z = 0 and u_z; Cerruti u_x, u_y, u_z.
    const double ur = -k * (1 - 2 * nu_) / rho;
    return {ur * x / r,
            ur * y / r,
            k * 2 * (1 - nu_) / rho,
            k * (1 / rho + x * x / (rho * rho * rho) + (1 - 2 * nu_) * (1 / rho - x * x / (rho * rho * rho))),
            k * (x * y / (rho * rho * rho) - (1 - 2 * nu_) * x * y / (rho * rho * rho)),
            k * (1 - 2 * nu_) * x / (rho * rho)};
  };
  for (const auto &p : {std::array<double, 2>{0.9, 0.1}, std::array<double, 2>{-0.2, 0.8},
                        std::array<double, 2>{1.5, -1.2}})
    {
      const Stress6 q = integrate_patch(displacements, p[0], p[1], 0.0, a, b, nu, 1e-13);
      const SurfaceDisplacement up = rectangle_displacement_pressure(p[0], p[1], a, b, 1.0, nu);
      const SurfaceDisplacement uq = rectangle_displacement_shear_x(p[0], p[1], a, b, 1.0, nu);
      EXPECT_NEAR(up.x, q[0], 1e-10);
      EXPECT_NEAR(up.y, q[1], 1e-10);
      EXPECT_NEAR(up.z, q[2], 1e-10);
      EXPECT_NEAR(uq.x, q[3], 1e-10);
      EXPECT_NEAR(uq.y, q[4], 1e-10);
      EXPECT_NEAR(uq.z, q[5], 1e-10);
    }
}

TEST(RectangleKernels, RejectsBadArguments)
{
  EXPECT_THROW(rectangle_stress_pressure(0, 0, -1e-3, 1, 1, nu), std::invalid_argument);
  EXPECT_THROW(rectangle_stress_pressure(0, 0, 0.1, 0, 1, nu), std::invalid_argument);
  EXPECT_THROW(rectangle_stress_shear_x(0, 0, 0.1, 1, 1, 0.6), std::invalid_argument);
  EXPECT_THROW(rectangle_displacement_pressure(0, 0, 1, 1, 0.0, nu), std::invalid_argument);
}
