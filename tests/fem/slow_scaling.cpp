// Sizes, timings and memory of the paper's 6208 outer ring (parametric,
// raceway groove), quadratic elements, outer surface clamped as in a rigid
// housing, 100 MPa on the raceway: static solves at ~50k, ~200k and ~1M DoFs,
// one case per test so that ctest runs each in its own process and the peak
// resident memory (VmHWM) is that of the case. The checks are the solutions,
// not the times: CG+GAMG at the working tolerance against MUMPS (the exact
// algebraic solution up to round-off), iteration counts bounded. Each case
// prints one row of the table in docs/performance.md ("FE solves"):
//
//   build/tests/test_fem_slow_scaling --gtest_filter='Scaling.Ring50k'
//   build/tests/test_fem_slow_scaling --gtest_filter='Scaling.Ring200k'
//   mpirun -np 2 build/tests/test_fem_slow_scaling --gtest_filter='Scaling.Ring1M'
//
// Also: the lowest in-plane modes of the free ring against the thin-ring
// formula (a report: the real ring is thick, h/R ≈ 0.16, so the formula is off
// by several per cent — shear, rotary inertia and the groove are outside it).
#include "fem_test_environment.h"

#include <fretsim/fem/elastic_model.h>

#include <mpi.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

using namespace fretsim::fem;
using fretsim::fem_testing::relative_error;

namespace
{
  const Material steel{208e9, 0.3, 7850.0};

  /// Relative residual ‖f - K u‖ / ‖f‖ at which CG stops in these cases:
  /// energy and raceway displacement then agree with MUMPS to ~1e-10
  /// (measured below), far below the discretisation error of these meshes
  /// (the 50k, 200k and 1M energies differ by 4e-3 and 2.4e-3).
  constexpr double working_tolerance = 1e-8;

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

  double seconds_since(std::chrono::steady_clock::time_point start)
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  /// Peak resident memory of this process [bytes] (VmHWM), summed over the ranks.
  double peak_memory_all_ranks()
  {
    std::ifstream status("/proc/self/status");
    std::string   line;
    double        kib = 0.0;
    while (std::getline(status, line))
      if (line.rfind("VmHWM:", 0) == 0)
        kib = std::stod(line.substr(6));
    double sum = 0.0;
    MPI_Allreduce(&kib, &sum, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    return sum * 1024.0;
  }

  struct Solved
  {
    double energy      = 0.0; ///< ½ uᵀ K u [J]
    double raceway_u_r = 0.0; ///< mean radial displacement of the raceway [m]
  };

  const char *name_of(LinearSolver s)
  {
    return s == LinearSolver::direct ? "MUMPS" : s == LinearSolver::cg_gamg ? "CG+GAMG" : "CG+BoomerAMG";
  }

  struct Solve
  {
    LinearSolver type;
    double       relative_tolerance;
  };

  /// Builds the ring, solves with each of `solves` in turn and prints a table
  /// row per solve; returns the results and iteration counts in that order.
  /// The peak memory is the process's so far: put the leanest solver first.
  std::vector<Solved> run(const char *label, const MeshDivisions &d, const std::vector<Solve> &solves,
                          std::vector<unsigned int> &iterations)
  {
    const auto mesh_start = std::chrono::steady_clock::now();
    auto       mesh       = std::make_shared<const Mesh>(Mesh::ring(ring_6208(), d));
    const double mesh_seconds = seconds_since(mesh_start);
    ElasticModel model(mesh, {{MaterialId::ring, steel}}, 2, {{BoundaryId::ring_outer}});
    StaticLoad   load;
    load.pressures.push_back({BoundaryId::raceway, 100e6});
    std::vector<Solved> results;
    for (const Solve &solve : solves)
      {
        SolverSettings s;
        s.type                    = solve.type;
        s.relative_tolerance      = solve.relative_tolerance;
        const DisplacementField u = model.solve_static(load, s);
        const double memory       = peak_memory_all_ranks();
        results.push_back({u.strain_energy(), u.average_on_boundary(BoundaryId::raceway).u_r});
        iterations.push_back(model.timings().iterations);
        const Timings &t = model.timings();
        char tolerance[32] = "";
        if (solve.type != LinearSolver::direct)
          std::snprintf(tolerance, sizeof tolerance, " %.0e", solve.relative_tolerance);
        if (mesh->rank() == 0)
          std::printf("| %s | %lu | %u | %s%s | %.2f | %.2f | %.2f | %.2f | %.2f | %u | %.2f |\n"
                      "    (energy %.10e J, mean raceway u_r %.10e m)\n",
                      label, model.n_dofs(), mesh->n_ranks(), name_of(solve.type), tolerance, mesh_seconds,
                      t.setup_dofs, t.assemble_stiffness, t.solve,
                      mesh_seconds + t.setup_dofs + t.assemble_stiffness + t.assemble_load + t.solve, t.iterations,
                      memory / 1e9, results.back().energy, results.back().raceway_u_r);
        std::fflush(stdout);
      }
    return results;
  }

  void print_header()
  {
    if (ParallelEnvironment::rank() == 0)
      std::printf("| case | DoFs | ranks | solver, tolerance | mesh [s] | DoFs+sparsity [s] | assemble K [s] | "
                  "solve [s] | total [s] | iterations | peak memory [GB] |\n");
  }
} // namespace

// ~50k DoFs: every solver, both iterative ones against MUMPS.
TEST(Scaling, Ring50k)
{
  print_header();
  std::vector<unsigned int> iterations;
  const auto                r = run("50k", divisions(80, 2, 6, 2),
                                    {{LinearSolver::cg_gamg, working_tolerance},
                                     {LinearSolver::cg_amg, working_tolerance},
                                     {LinearSolver::direct, 0.0}},
                                    iterations);
  const Solved &direct = r[2];
  for (unsigned int k = 0; k < 2; ++k)
    {
      // Reference MUMPS. Measured ≤ 2e-10 (energy, raceway u_r) after a
      // residual of 1e-8; 1e-7 leaves room for other round-off.
      EXPECT_LT(relative_error(r[k].energy, direct.energy), 1e-7) << k;
      EXPECT_LT(relative_error(r[k].raceway_u_r, direct.raceway_u_r), 1e-7) << k;
    }
  EXPECT_LE(iterations[0], 45u); // measured 27: GAMG with the rigid-body modes is mesh-independent
  EXPECT_LE(iterations[1], 30u); // measured 11 (BoomerAMG counts the preconditioned residual)
}

// ~200k DoFs, the design's speed target (static solve < 30 s including
// assembly on the 2-core machine): GAMG at the working tolerance and at the
// default 1e-10, against MUMPS.
TEST(Scaling, Ring200k)
{
  print_header();
  std::vector<unsigned int> iterations;
  const auto                r = run("200k", divisions(144, 4, 8, 2),
                                    {{LinearSolver::cg_gamg, working_tolerance},
                                     {LinearSolver::cg_gamg, 1e-10},
                                     {LinearSolver::direct, 0.0}},
                                    iterations);
  for (unsigned int k = 0; k < 2; ++k)
    {
      // Reference MUMPS; measured ≤ 1e-10 at 1e-8, as at 50k.
      EXPECT_LT(relative_error(r[k].energy, r[2].energy), 1e-7) << k;
      EXPECT_LT(relative_error(r[k].raceway_u_r, r[2].raceway_u_r), 1e-7) << k;
      EXPECT_LE(iterations[k], 60u) << k; // measured 30 and 37
    }
}

// ~1M DoFs, run under `mpirun -np 2` (ctest: fem.mpi_np2.slow_scaling_1M;
// skipped on one rank). MUMPS does not fit in reasonable time here: the
// algebraic reference is the same CG+GAMG driven to a residual of 1e-11, and
// the 200k mesh's MUMPS energy bounds the discretisation.
TEST(Scaling, Ring1M)
{
  // Registered in ctest only under mpiexec -np 2 (fem_tests.cmake).
  ASSERT_GE(ParallelEnvironment::n_ranks(), 2u) << "the ~1M-DoF case runs under mpirun -np 2";
  print_header();
  std::vector<unsigned int> iterations;
  const auto                r = run("1M", divisions(320, 6, 12, 4),
                                    {{LinearSolver::cg_gamg, working_tolerance}, {LinearSolver::cg_gamg, 1e-11}},
                                    iterations);
  EXPECT_LT(relative_error(r[0].energy, r[1].energy), 1e-7);
  EXPECT_LT(relative_error(r[0].raceway_u_r, r[1].raceway_u_r), 1e-7);
  EXPECT_LE(iterations[0], 60u); // measured 39 (and 52 to 1e-11)
  // Ring200k's MUMPS energy, 2.0004130069e-01 J: the finer mesh is more
  // compliant under the same pressure, by less than the 4e-3 that separates
  // the 50k and 200k meshes.
  const double energy_200k = 2.0004130069e-01;
  EXPECT_GT(r[1].energy, energy_200k * (1.0 - 1e-6));
  EXPECT_LT(r[1].energy, energy_200k * (1.0 + 4e-3));
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
