// Sizes and timings of the paper's 6208 outer ring (parametric, raceway
// groove), quadratic elements: static solves at ~60k and ~190k DoFs (outer
// surface clamped as in a rigid housing, a pressure on the raceway), and the
// lowest in-plane modes of the free ring against the thin-ring formula (a
// report: the real ring is thick, h/R ≈ 0.16, so the formula is off by several
// per cent — shear, rotary inertia and the groove are outside it).
#include "fem_test_environment.h"

#include <fretsim/fem/elastic_model.h>

#include <cmath>
#include <cstdio>

using namespace fretsim::fem;
using fretsim::fem_testing::relative_error;

namespace
{
  const Material steel{208e9, 0.3, 7850.0};

  RingGeometry ring_6208()
  {
    RingGeometry g; // meshes/bearing_6208_outer_ring.geo
    g.bore_radius          = 0.0341;
    g.outer_radius         = 0.040;
    g.width                = 0.018;
    g.groove_radius        = 0.53 * 0.0127;
    g.groove_bottom_radius = (0.060 + 0.0127) / 2;
    return g;
  }

  MeshDivisions divisions(unsigned int around, unsigned int radial, unsigned int groove, unsigned int land)
  {
    MeshDivisions d;
    d.circumferential = around;
    d.radial_ring     = radial;
    d.axial           = groove;
    d.axial_land      = land;
    return d;
  }
} // namespace

TEST(Scaling, StaticSolvesOfThe6208Ring)
{
  struct Case
  {
    MeshDivisions d;
    bool          direct_too;
  };
  for (const Case &c : {Case{divisions(96, 2, 6, 2), true}, Case{divisions(144, 4, 8, 2), false}})
    {
      auto         mesh = std::make_shared<const Mesh>(Mesh::ring(ring_6208(), c.d));
      ElasticModel model(mesh, {{MaterialId::ring, steel}}, 2, {{BoundaryId::ring_outer}});
      StaticLoad   load;
      load.pressures.push_back({BoundaryId::raceway, 100e6});
      for (const LinearSolver solver : {LinearSolver::cg_gamg, LinearSolver::cg_amg, LinearSolver::direct})
        {
          if (solver == LinearSolver::direct && !c.direct_too)
            continue;
          SolverSettings s;
          s.type                  = solver;
          const double energy     = model.solve_static(load, s).strain_energy();
          const Timings &t        = model.timings();
          std::printf("%lu cells, %lu DoFs, %s: setup %.2f s, assemble K %.2f s, load %.2f s, solve %.2f s "
                      "(%u iterations), energy %.10e J\n",
                      mesh->summary(1).n_cells, model.n_dofs(), solver == LinearSolver::direct ? "MUMPS" : solver == LinearSolver::cg_gamg ? "CG+GAMG(rigid)" : "CG+BoomerAMG",
                      t.setup_dofs, t.assemble_stiffness, t.assemble_load, t.solve, t.iterations, energy);
        }
    }
}

TEST(Scaling, InPlaneModesOfThe6208RingAgainstTheThinRingFormula)
{
  const RingGeometry g = ring_6208();
  auto               mesh = std::make_shared<const Mesh>(Mesh::ring(g, divisions(96, 2, 6, 2)));
  ElasticModel       model(mesh, {{MaterialId::ring, steel}}, 2);
  ModalSettings      settings;
  settings.n_modes          = 12;
  const ModalSolution modes = model.solve_modes(settings);
  std::printf("%lu DoFs, mass assembly %.2f s, modal solve %.2f s, %u rigid-body modes\n", model.n_dofs(),
              model.timings().assemble_mass, modes.seconds, modes.n_rigid_body_modes);
  EXPECT_EQ(modes.n_rigid_body_modes, 6u);

  // Thin-ring reference with the land-to-outer rectangle (groove ignored).
  const double h = g.outer_radius - g.bore_radius, R = 0.5 * (g.outer_radius + g.bore_radius);
  const double base = std::sqrt(steel.youngs_modulus * h * h / 12.0 / (steel.density * std::pow(R, 4)));
  std::vector<double> in_plane;
  for (unsigned int k = 0; k < modes.frequencies_hz.size(); ++k)
    if (modes.shapes[k].mass_fractions()[2] < 0.05)
      in_plane.push_back(modes.frequencies_hz[k]);
  for (unsigned int n = 2; n <= 4 && 2 * (n - 2) + 1 < in_plane.size(); ++n)
    {
      const double thin = base * n * (n * n - 1.0) / std::sqrt(n * n + 1.0) / (2.0 * M_PI);
      const double fe   = in_plane[2 * (n - 2)];
      std::printf("n = %u: FE %.1f Hz, thin ring %.1f Hz, difference %+.1f %%\n", n, fe, thin,
                  100.0 * (fe - thin) / thin);
    }
}
