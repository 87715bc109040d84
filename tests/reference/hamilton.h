#pragma once
// Stresses under a circular Hertz contact, for tests (docs/references.md §1.1,
// §3.1, §3.2). Independent of the library: closed forms only. Conventions of
// docs/references.md §0: z >= 0 into the body, tension positive, shear traction in +x.
// Components in the library's Voigt order xx, yy, zz, yz, xz, xy.
#include <array>
#include <cmath>

namespace fretsim::reference
{
  using Stress = std::array<double, 6>; // xx, yy, zz, yz, xz, xy

  /// Hamilton (1983) explicit stresses of the Hertz pressure p0 sqrt(1 - r^2/a^2)
  /// (docs/references.md §3.1), at any (x, y, z) with z > 0, or z = 0 off the rim.
  inline Stress hamilton_normal(double x, double y, double z, double a, double p0, double nu)
  {
    const double scale = p0 / a; // 3P / (2 pi a^3)
    const double r2    = x * x + y * y;
    if (r2 < 1e-24 * a * a)
      { // axis limit (docs/references.md §3.1)
        const double s = (1 + nu) * (z * std::atan2(a, z) - a) + a * a * a / (2 * (a * a + z * z));
        return {scale * s, scale * s, -scale * a * a * a / (a * a + z * z), 0.0, 0.0, 0.0};
      }
    const double A = r2 + z * z - a * a;
    const double S = std::sqrt(A * A + 4 * a * a * z * z);
    const double M = std::sqrt(0.5 * (S + A)), N = std::sqrt(std::max(0.0, 0.5 * (S - A)));
    const double phi = std::atan2(a, M);
    const double G = M * M - N * N + z * M - a * N, H = 2 * M * N + a * M + z * N;
    const double r4 = r2 * r2;
    const double bracket =
      (1 - nu) * N * z * z - (1 - 2 * nu) / 3 * (N * S + 2 * A * N + a * a * a) - nu * M * z * a;
    // M z a / S: S -> 0 only on the rim at z = 0, where z = 0 makes the term 0.
    const double mza_over_s = z > 0 ? M * z * a / S : 0.0;
    const double sx = (1 + nu) * z * phi +
                      (1 / r2) * ((y * y - x * x) / r2 * bracket - N * (x * x + 2 * nu * y * y) - x * x * mza_over_s);
    const double sy = (1 + nu) * z * phi +
                      (1 / r2) * ((x * x - y * y) / r2 * bracket - N * (y * y + 2 * nu * x * x) - y * y * mza_over_s);
    const double sz  = -N + (z > 0 ? a * z * M / S : 0.0);
    const double txy = x * y * (1 - 2 * nu) / r4 *
                         (-N * r2 + 2.0 / 3 * N * (S + 2 * A) - z * (z * N + a * M) + 2.0 / 3 * a * a * a) +
                       x * y * z / r4 * (-(z > 0 ? a * M * r2 / S : 0.0) - z * N + a * M);
    const double gh  = z > 0 ? z * H / (G * G + H * H) : 0.0;
    const double nos = z > 0 ? N / S : 0.0;
    const double tyz = -z * (y * nos - y * gh);
    const double txz = -z * (x * nos - x * gh);
    return {scale * sx, scale * sy, scale * sz, scale * tyz, scale * txz, scale * txy};
  }

  /// Frictionless Hertz on the axis (docs/references.md §1.1): sigma_z and sigma_r = sigma_theta.
  inline double hertz_axis_sigma_z(double z, double a, double p0) { return -p0 / (1 + z * z / (a * a)); }
  inline double hertz_axis_sigma_r(double z, double a, double p0, double nu)
  {
    if (z == 0.0)
      return -p0 * (1 + 2 * nu) / 2;
    return p0 * (-(1 + nu) * (1 - (z / a) * std::atan(a / z)) + 0.5 / (1 + z * z / (a * a)));
  }

  /// Hertz surface stresses (z = 0) anywhere on the surface (docs/references.md §1.1;
  /// outside the contact sigma_r = -sigma_theta = (1-2nu)/3 a^2/r^2 p0).
  inline Stress hertz_surface(double x, double y, double a, double p0, double nu)
  {
    const double r2 = x * x + y * y, rr = r2 / (a * a);
    double       sr, st, sz;
    if (rr < 1e-24)
      {
        sr = st = -(1 + 2 * nu) / 2 * p0;
        sz      = -p0;
      }
    else if (rr <= 1.0)
      {
        const double root = std::sqrt(1 - rr), edge = (1 - 2 * nu) / 3 / rr * (1 - root * root * root);
        sr = p0 * (edge - root);
        st = p0 * (-edge - 2 * nu * root);
        sz = -p0 * root;
      }
    else
      {
        sr = p0 * (1 - 2 * nu) / 3 / rr;
        st = -sr;
        sz = 0.0;
      }
    const double r = std::sqrt(r2), c = r > 0 ? x / r : 1.0, s = r > 0 ? y / r : 0.0;
    return {sr * c * c + st * s * s, sr * s * s + st * c * c, sz, 0.0, 0.0, (sr - st) * s * c};
  }

  /// Surface stresses inside the contact (r <= a) of the Hertz-shaped shear
  /// traction q0 sqrt(1 - r^2/a^2) in +x (Johnson §7.1, Hamilton & Goodman
  /// 1966; docs/references.md §3.2).
  inline Stress hertz_shear_surface(double x, double y, double a, double q0, double nu)
  {
    const double r2 = (x * x + y * y) / (a * a);
    return {-M_PI * (4 + nu) * q0 * x / (8 * a),
            -3 * M_PI * nu * q0 * x / (8 * a),
            0.0,
            0.0,
            -q0 * std::sqrt(std::max(0.0, 1 - r2)),
            -M_PI * (2 - nu) * q0 * y / (8 * a)};
  }

  /// sigma_xz on the axis under the Hertz-shaped shear traction (docs/references.md §3.2).
  inline double hertz_shear_axis_tau_xz(double z, double a, double q0)
  {
    return -1.5 * q0 * (1 - (z / a) * std::atan2(a, z) - a * a / (3 * (a * a + z * z)));
  }

  /// Trailing-edge (x = -a, y = 0) surface sigma_x / p0 under full sliding
  /// q = mu p (Hamilton 1983; docs/references.md §3.2): (1-2nu)/3 + pi mu (4+nu)/8.
  inline double sliding_trailing_edge_sigma_x(double mu, double nu) { return (1 - 2 * nu) / 3 + M_PI * mu * (4 + nu) / 8; }

  /// docs/references.md §3.3: a = 1, nu = 0.3, stresses / p0, Q rows per unit mu
  /// (Hertz-shaped shear with q0 = p0 in +x). Components here reordered to
  /// xx, yy, zz, yz, xz, xy from the table's [sx, sy, sz, txy, tyz, txz].
  struct SlidingTableRow
  {
    double x, y, z;
    Stress normal, shear;
  };
  inline std::array<SlidingTableRow, 6> sliding_table()
  {
    auto voigt = [](double sx, double sy, double sz, double txy, double tyz, double txz) {
      return Stress{sx, sy, sz, tyz, txz, txy};
    };
    return {{
      {0.0, 0.0, 0.5, voigt(-0.180353, -0.180353, -0.800000, 0, 0, 0), voigt(0, 0, 0, 0, 0, -0.269638)},
      {0.3, 0.2, 0.4, voigt(-0.226646, -0.224683, -0.784723, -0.002356, -0.059799, -0.089699),
       voigt(-0.193998, -0.032328, -0.089699, -0.054214, -0.006835, -0.323594)},
      {-0.5, 0.0, 0.25, voigt(-0.320457, -0.325812, -0.792959, 0, 0, 0.119235),
       voigt(0.463974, 0.085871, 0.119235, 0, 0, -0.442809)},
      {0.8, -0.5, 0.3, voigt(-0.175283, -0.145165, -0.287740, 0.030890, 0.107858, -0.172572),
       voigt(-0.435485, -0.077482, -0.172572, 0.131838, 0.064688, -0.238543)},
      {1.2, 0.3, 0.2, voigt(-0.091015, -0.072369, -0.022802, -0.004972, -0.013261, -0.053042),
       voigt(-0.535098, -0.053715, -0.053042, -0.089016, -0.030846, -0.153851)},
      {0.0, 0.9, 0.1, voigt(-0.268384, -0.213880, -0.395422, 0, -0.151738, 0),
       voigt(0, 0, 0, -0.405358, 0, -0.279533)},
    }};
  }

  /// Principal stresses of a symmetric tensor (Voigt xx, yy, zz, yz, xz, xy),
  /// ascending, by the trigonometric closed form of the cubic.
  inline std::array<double, 3> principal_stresses(const Stress &s)
  {
    const double p1 = s[3] * s[3] + s[4] * s[4] + s[5] * s[5];
    const double q  = (s[0] + s[1] + s[2]) / 3;
    const double p2 = (s[0] - q) * (s[0] - q) + (s[1] - q) * (s[1] - q) + (s[2] - q) * (s[2] - q) + 2 * p1;
    const double p  = std::sqrt(p2 / 6);
    if (p == 0.0)
      return {q, q, q};
    const double b[6] = {(s[0] - q) / p, (s[1] - q) / p, (s[2] - q) / p, s[3] / p, s[4] / p, s[5] / p};
    // det of B with B = [[b0, b5, b4], [b5, b1, b3], [b4, b3, b2]]
    const double det = b[0] * (b[1] * b[2] - b[3] * b[3]) - b[5] * (b[5] * b[2] - b[3] * b[4]) +
                       b[4] * (b[5] * b[3] - b[1] * b[4]);
    const double r   = std::max(-1.0, std::min(1.0, det / 2));
    const double phi = std::acos(r) / 3;
    const double e1  = q + 2 * p * std::cos(phi);
    const double e3  = q + 2 * p * std::cos(phi + 2 * M_PI / 3);
    return {e3, 3 * q - e1 - e3, e1};
  }
} // namespace fretsim::reference
