// The same numbers on one rank and on all ranks. ctest runs this program
// twice: as it is (one rank, where the comparison is trivially met) and as
// fem.mpi_np2.unit_parallel_consistency under `mpiexec -np 2`, where each
// test solves once distributed over both ranks (Ranks::all) and once on each
// rank alone (Ranks::this_one) and compares.
#include "fem_test_environment.h"

#include <fretsim/fem/elastic_model.h>

#include <cmath>
#include <cstdio>

using namespace fretsim::fem;
using fretsim::fem_testing::relative_error;

namespace
{
  const Material steel{208e9, 0.3, 7850.0};

  std::shared_ptr<const Mesh> quarter_cylinder(Ranks ranks)
  {
    RingGeometry g;
    g.bore_radius  = 0.0341;
    g.outer_radius = 0.040;
    g.width        = 0.018;
    g.groove_radius        = 0.00673;
    g.groove_bottom_radius = 0.03635;
    MeshDivisions d;
    d.radial_ring     = 2;
    d.circumferential = 8;
    d.axial           = 2;
    d.axial_land      = 1;
    d.sector_angle    = 0.5 * M_PI;
    return std::make_shared<const Mesh>(Mesh::ring(g, d, ranks));
  }

  StaticLoad pressure_load()
  {
    StaticLoad load;
    load.pressures = {{BoundaryId::raceway, 50e6}, {BoundaryId::ring_lands, 10e6}};
    return load;
  }

  double strain_energy(Ranks ranks, LinearSolver solver)
  {
    ElasticModel model(quarter_cylinder(ranks), {{MaterialId::ring, steel}}, 2,
                       {{BoundaryId::side_faces, false, false, true},
                        {BoundaryId::sector_start, false, true, false},
                        {BoundaryId::sector_end, true, false, false}});
    SolverSettings settings;
    settings.type = solver;
    const double energy =
      model.solve_static(pressure_load(), settings).strain_energy();
    std::printf("rank %u/%u: %s, %lu DoFs, energy %.15e J, %u iterations, assembly %.3f s, solve %.3f s\n",
                ParallelEnvironment::rank(), ParallelEnvironment::n_ranks(),
                ranks == Ranks::all ? "all ranks" : "this rank", model.n_dofs(), energy, model.timings().iterations,
                model.timings().assemble_stiffness, model.timings().solve);
    return energy;
  }

  std::vector<double> ring_frequencies(Ranks ranks)
  {
    RingGeometry g;
    g.bore_radius  = 0.098;
    g.outer_radius = 0.102;
    g.width        = 0.004;
    MeshDivisions d;
    d.circumferential = 32;
    d.radial_ring     = 1;
    d.axial           = 1;
    ElasticModel  model(std::make_shared<const Mesh>(Mesh::ring(g, d, ranks)), {{MaterialId::ring, steel}}, 2);
    ModalSettings settings;
    settings.n_modes = 8;
    return model.solve_modes(settings).frequencies_hz;
  }
} // namespace

TEST(ParallelConsistency, StaticStrainEnergy)
{
  const double all_direct  = strain_energy(Ranks::all, LinearSolver::direct);
  const double one_direct  = strain_energy(Ranks::this_one, LinearSolver::direct);
  const double all_iterative = strain_energy(Ranks::all, LinearSolver::cg_amg);
  // Direct solves differ only by round-off in a different elimination order.
  EXPECT_LT(relative_error(all_direct, one_direct), 1e-10);
  // CG stops at ‖r‖ ≤ 1e-10 ‖f‖; the energy error is quadratic in the
  // solution error, far below this bound.
  EXPECT_LT(relative_error(all_iterative, one_direct), 1e-8);
}

TEST(ParallelConsistency, RingFrequencies)
{
  const std::vector<double> all = ring_frequencies(Ranks::all);
  const std::vector<double> one = ring_frequencies(Ranks::this_one);
  ASSERT_EQ(all.size(), one.size());
  for (unsigned int k = 0; k < all.size(); ++k)
    {
      if (ParallelEnvironment::rank() == 0)
        std::printf("mode %u: %.9f Hz on %u ranks, %.9f Hz on one\n", k, all[k], ParallelEnvironment::n_ranks(),
                    one[k]);
      // Eigen-residual tolerance 1e-10: eigenvalues agree to about that.
      EXPECT_LT(relative_error(all[k], one[k]), 1e-8) << "mode " << k;
    }
}
