#pragma once
// Reduced rings with known operators for the coupling tests.
#include <fretsim/coupling/ring_coupling.h>

#include <cmath>
#include <random>

namespace fretsim::coupling::synthetic
{
  /// A rigid ring of radius R, width B, mass m: coordinates (u_x, u_y, u_z, φ)
  /// (translations and the rotation about the axis). Interface: u_r = u_x cos θ
  /// + u_y sin θ, u_θ = -u_x sin θ + u_y cos θ + R φ, u_z; a unit outward ball
  /// load at ψ does the work u_x cos ψ + u_y sin ψ: r(ψ) = (cos ψ, sin ψ, 0, 0).
  inline ReducedRing rigid_ring(double radius, double width, double mass, int cells_around, int cells_across,
                                int raceway_angles = 720)
  {
    ReducedRing ring;
    ring.n = 4;
    ring.mass.assign(16, 0.0);
    ring.stiffness.assign(16, 0.0);
    ring.mass[0] = ring.mass[5] = ring.mass[10] = mass;
    ring.mass[15]                               = mass * radius * radius; // thin ring: I = m R²
    ring.lowest_elastic_frequency_hz            = 1000.0; // no elastic mode: only sets β, and K = 0
    ring.interface_radius                       = radius;
    ring.interface_grid.nx                      = cells_around;
    ring.interface_grid.ny                      = cells_across;
    ring.interface_grid.hx                      = 2.0 * M_PI * radius / cells_around;
    ring.interface_grid.hy                      = width / cells_across;
    ring.interface_grid.y_min                   = -0.5 * width;
    ring.interface_displacement.assign(ring.interface_grid.size() * 3 * 4, 0.0);
    for (int j = 0; j < cells_across; ++j)
      for (int i = 0; i < cells_around; ++i)
        {
          const double theta = ring.interface_grid.x(i) / radius;
          double      *row   = &ring.interface_displacement[ring.interface_grid.index(i, j) * 12];
          row[0] = std::cos(theta), row[1] = std::sin(theta);                          // u_r
          row[4] = -std::sin(theta), row[5] = std::cos(theta), row[7] = radius;        // u_θ
          row[10] = 1.0;                                                               // u_z
        }
    ring.raceway_angles = raceway_angles;
    for (int k = 0; k < raceway_angles; ++k)
      {
        const double psi = 2.0 * M_PI * k / raceway_angles;
        ring.raceway_approach.insert(ring.raceway_approach.end(), {std::cos(psi), std::sin(psi), 0.0, 0.0});
      }
    return ring;
  }

  /// A housing whose bore moves as a rigid circle (h_x, h_y) held by a
  /// spring of stiffness k [N/m] in x and y, mass m: u_r = h_x cos θ + h_y sin θ,
  /// u_θ = -h_x sin θ + h_y cos θ, u_z = 0 on the same grid as rigid_ring's.
  inline ReducedHousing sprung_housing(double radius, double width, double mass, double stiffness, int cells_around,
                                       int cells_across)
  {
    const ReducedRing rigid = rigid_ring(radius, width, mass, cells_around, cells_across, 4);
    ReducedHousing    housing;
    housing.n                = 2;
    housing.mass             = {mass, 0.0, 0.0, mass};
    housing.stiffness        = {stiffness, 0.0, 0.0, stiffness};
    housing.interface_radius = radius;
    housing.interface_grid   = rigid.interface_grid;
    for (std::size_t row = 0; row < rigid.interface_grid.size() * 3; ++row)
      housing.interface_displacement.insert(housing.interface_displacement.end(),
                                            {rigid.interface_displacement[row * 4], rigid.interface_displacement[row * 4 + 1]});
    return housing;
  }

  /// n coordinates with a diagonal mass (0.2) and stiffness (1e8 (j + 1)).
  inline void diagonal_structure(ReducedRing &ring, std::size_t n)
  {
    ring.n = n;
    ring.mass.assign(n * n, 0.0);
    ring.stiffness.assign(n * n, 0.0);
    for (std::size_t j = 0; j < n; ++j)
      {
        ring.mass[j * n + j]      = 0.2;
        ring.stiffness[j * n + j] = 1e8 * (j + 1);
      }
  }

  /// Random operators and an SPD mass/stiffness of size n (for transfer and
  /// derivative checks, not physics).
  inline ReducedRing random_ring(std::size_t n, int cells_around, int cells_across, unsigned seed)
  {
    std::mt19937                           generator(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    ReducedRing                            ring = rigid_ring(0.04, 0.018, 0.2, cells_around, cells_across, 16);
    diagonal_structure(ring, n);
    for (auto *values : {&ring.interface_displacement, &ring.raceway_approach})
      {
        values->resize((values == &ring.raceway_approach ? ring.raceway_angles : ring.interface_grid.size() * 3) * n);
        for (double &value : *values)
          value = uniform(generator);
      }
    // InterfaceContact keeps the interface operator in single precision;
    // values a float holds exactly let the tests compare it with the
    // double-precision arithmetic here at round-off level.
    for (double &value : ring.interface_displacement)
      value = static_cast<float>(value);
    return ring;
  }
} // namespace fretsim::coupling::synthetic
