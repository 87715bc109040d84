// Shrink fit: an outer ring pressed into a housing with radial interference δ.
// Interface pressure against Lamé's shrink-fit formula within 1 %.
//
// How the interference is imposed: ring and housing share the nodes of the
// interface radius R (bonded), and the ring carries the in-plane expansion
// eigenstrain e = δ/R (fem::InPlaneExpansion). In linear theory this is
// exactly the fit: the free ring would grow by e·(x, y, 0) without stress, so
// the bond imposes the radial jump δ at R (and nothing tangentially, where the
// axisymmetric fit has no shear anyway). Frictional contact is not modelled.
//
// Plane strain (u_z = 0 on the side faces), quarter model. Lamé for a hollow
// shaft (a, R) in a hub (R, c) with plane-strain constants E' = E/(1 - ν²),
// ν' = ν/(1 - ν) (Timoshenko & Goodier §28; Shigley, press and shrink fits):
//   p = δ / ( R/E'_h ((c² + R²)/(c² - R²) + ν'_h) + R/E'_r ((R² + a²)/(R² - a²) - ν'_r) )
#include "fem_test_environment.h"

#include <fretsim/fem/elastic_model.h>

#include <cmath>
#include <cstdio>

using namespace fretsim::fem;
using fretsim::fem_testing::relative_error;

TEST(ShrinkFit, InterfacePressureMatchesLame)
{
  const double   a = 0.0341, R = 0.040, c = 0.060, width = 0.01, delta = 10e-6; // [m]
  const Material steel{208e9, 0.30, 7850.0}, cast_iron{110e9, 0.28, 7200.0};

  auto plane_strain = [](const Material &m) {
    return std::pair{m.youngs_modulus / (1 - m.poisson_ratio * m.poisson_ratio),
                     m.poisson_ratio / (1 - m.poisson_ratio)};
  };
  const auto [Er, nur] = plane_strain(steel);
  const auto [Eh, nuh] = plane_strain(cast_iron);
  const double p_exact = delta / (R / Eh * ((c * c + R * R) / (c * c - R * R) + nuh) +
                                  R / Er * ((R * R + a * a) / (R * R - a * a) - nur));

  RingGeometry ring;
  ring.bore_radius  = a;
  ring.outer_radius = R;
  ring.width        = width;
  const HousingGeometry housing{R, c, width};
  MeshDivisions         d;
  d.radial_ring     = 8;
  d.radial_housing  = 8;
  d.circumferential = 32;
  d.axial           = 1;
  d.sector_angle    = 0.5 * M_PI;
  auto         mesh = std::make_shared<const Mesh>(Mesh::ring_in_housing(ring, housing, d));
  ElasticModel model(mesh, {{MaterialId::ring, steel}, {MaterialId::housing, cast_iron}}, 2,
                     {{BoundaryId::side_faces, false, false, true},
                      {BoundaryId::sector_start, false, true, false},
                      {BoundaryId::sector_end, true, false, false}});
  StaticLoad fit;
  fit.expansions.push_back({MaterialId::ring, delta / R});
  const DisplacementField u = model.solve_static(fit);

  const CylindricalAverage in_housing = u.average_on_interface(MaterialId::housing, MaterialId::ring);
  const CylindricalAverage in_ring    = u.average_on_interface(MaterialId::ring, MaterialId::housing);
  const double             p_fe       = -0.5 * (in_housing.s_rr + in_ring.s_rr);
  std::printf("%lu DoFs: interface pressure %.6e Pa (housing side %.6e, ring side %.6e), Lamé %.6e Pa, "
              "error %.2e\n",
              model.n_dofs(), p_fe, -in_housing.s_rr, -in_ring.s_rr, p_exact, relative_error(p_fe, p_exact));
  EXPECT_LT(relative_error(p_fe, p_exact), 0.01);
  EXPECT_LT(relative_error(-in_housing.s_rr, p_exact), 0.01);
  EXPECT_LT(relative_error(-in_ring.s_rr, p_exact), 0.01);
  EXPECT_LT(relative_error(in_housing.area, 0.5 * M_PI * R * width), 1e-6);

  // The housing bore opens by u_h(R) = p R/E'_h ((c² + R²)/(c² - R²) + ν'_h).
  const double u_housing = p_exact * R / Eh * ((c * c + R * R) / (c * c - R * R) + nuh);
  std::printf("housing bore u_r %.6e m, Lamé %.6e m, error %.2e\n", in_housing.u_r, u_housing,
              relative_error(in_housing.u_r, u_housing));
  EXPECT_LT(relative_error(in_housing.u_r, u_housing), 0.01);
  // The free housing outer surface carries no radial stress.
  EXPECT_LT(std::abs(u.average_on_boundary(BoundaryId::housing_outer).s_rr), 0.01 * p_exact);
}
