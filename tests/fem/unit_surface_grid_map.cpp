// The grid ↔ FE operator pair: Hᵀ conserves the grid's total force, H and Hᵀ
// are transposes (the tractions' work on the interpolated displacements is the
// nodal forces' work, 2 × strain energy), and H interpolates consistently (a
// Lamé field comes back at the grid points with the FE accuracy).
#include "fem_test_environment.h"

#include <fretsim/fem/surface_grid_map.h>

#include <cmath>
#include <cstdio>
#include <random>

using namespace fretsim::fem;
using fretsim::fem_testing::relative_error;

namespace
{
  constexpr double a = 0.0341, b = 0.040, width = 0.018;
  const Material   steel{208e9, 0.3, 7850.0};

  ElasticModel quarter_ring(unsigned int degree)
  {
    RingGeometry g;
    g.bore_radius  = a;
    g.outer_radius = b;
    g.width        = width;
    MeshDivisions d;
    d.radial_ring     = 2;
    d.circumferential = 12;
    d.axial           = 3;
    d.sector_angle    = 0.5 * M_PI;
    return ElasticModel(std::make_shared<const Mesh>(Mesh::ring(g, d)), {{MaterialId::ring, steel}}, degree,
                        {{BoundaryId::side_faces, false, false, true},
                         {BoundaryId::sector_start, false, true, false},
                         {BoundaryId::sector_end, true, false, false}});
  }

  /// 45 × 7 cells over the quarter's outer surface, a margin left at the edges.
  CylinderGrid outer_grid()
  {
    CylinderGrid g;
    g.radius = b;
    g.nx     = 45;
    g.ny     = 7;
    g.x_min  = 0.05 * b;
    g.hx     = (0.5 * M_PI - 0.1) * b / g.nx;
    g.y_min  = -0.4 * width;
    g.hy     = 0.8 * width / g.ny;
    return g;
  }

  GridTractions random_tractions(const CylinderGrid &g)
  {
    std::mt19937                           rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    GridTractions                          t;
    for (std::size_t k = 0; k < g.size(); ++k)
      {
        t.pressure.push_back(100e6 * u(rng));
        t.shear_x.push_back(20e6 * (u(rng) - 0.5));
        t.shear_y.push_back(10e6 * (u(rng) - 0.5));
      }
    return t;
  }
} // namespace

TEST(SurfaceGridMap, ForcesAreConservativeAndTransposeOfInterpolation)
{
  for (const unsigned int degree : {1u, 2u})
    {
      ElasticModel         model = quarter_ring(degree);
      const SurfaceGridMap map(model, BoundaryId::ring_outer, outer_grid());
      const GridTractions  t = random_tractions(map.grid());

      // Conservation: the shape functions sum to one at every grid point.
      const Vector3 total = map.total_force(t), nodal = map.nodal_force_sum(t);
      for (unsigned int c = 0; c < 3; ++c)
        EXPECT_NEAR(nodal[c], total[c], 1e-12 * std::abs(total[0])) << "component " << c;

      // Transpose: Σ A t·u_grid = uᵀ Hᵀ A t = uᵀ f = uᵀ K u = 2 U.
      StaticLoad load;
      load.grid_tractions.push_back({&map, &t});
      const DisplacementField u    = model.solve_static(load);
      const GridDisplacements ug   = map.interpolate(u);
      double                  work = 0.0;
      for (std::size_t k = 0; k < map.grid().size(); ++k)
        work += map.grid().cell_area() * (-t.pressure[k] * ug.u_r[k] + t.shear_x[k] * ug.u_theta[k] +
                                          t.shear_y[k] * ug.u_z[k]);
      std::printf("Q%u: total force (%.6e, %.6e, %.6e) N, work %.12e J, 2U %.12e J\n", degree, total[0], total[1],
                  total[2], work, 2.0 * u.strain_energy());
      // A direct solve: the identity holds to round-off.
      EXPECT_LT(relative_error(work, 2.0 * u.strain_energy()), 1e-9);
    }
}

TEST(SurfaceGridMap, InterpolatesALameFieldConsistently)
{
  // Uniform external pressure as a grid load on the whole quarter: Lamé
  // plane strain, u_r(b) = -(1 + ν)/E · p b ((1 - 2ν) b² + a²)/(b² - a²).
  ElasticModel model = quarter_ring(2);
  CylinderGrid g;
  g.radius = b;
  g.nx     = 60;
  g.ny     = 6;
  g.hx     = 0.5 * M_PI * b / g.nx;
  g.y_min  = -0.5 * width;
  g.hy     = width / g.ny;
  const SurfaceGridMap map(model, BoundaryId::ring_outer, g);
  const double         p = 10e6, E = steel.youngs_modulus, nu = steel.poisson_ratio;
  GridTractions        t{std::vector<double>(g.size(), p), std::vector<double>(g.size(), 0.0),
                  std::vector<double>(g.size(), 0.0)};
  StaticLoad           load;
  load.grid_tractions.push_back({&map, &t});
  const GridDisplacements ug = map.interpolate(model.solve_static(load));
  const double exact = -(1 + nu) / E * p * b * ((1 - 2 * nu) * b * b + a * a) / (b * b - a * a);
  double       worst = 0.0;
  for (std::size_t k = 0; k < g.size(); ++k)
    worst = std::max(worst, relative_error(ug.u_r[k], exact));
  std::printf("u_r(b): exact %.6e m, grid (%.6e ... ), worst relative error %.2e\n", exact, ug.u_r[0], worst);
  // Midpoint sampling of a uniform pressure is exact per FE face only up to
  // the face's quadrature; 60 × 6 samples on 12 × 3 faces: ~1e-3.
  EXPECT_LT(worst, 5e-3);
}
