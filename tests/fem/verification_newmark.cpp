// Hertz patch loads on the raceway and Newmark (average acceleration) under
// moving loads, on an outer ring with a plain bore (the raceway is then the
// cylinder the contact grid lies on), clamped at its outer surface:
//  - the patch's nodal forces carry its force P exactly (conservative Gᵀ);
//  - undamped free vibration keeps ½vᵀMv + ½uᵀKu to round-off (the
//    trapezoidal rule conserves the energy of a linear system exactly);
//  - two balls passing slowly (moving one semi-axis in 40 lowest periods)
//    give the static solution of the final position (static limit).
#include "fem_test_environment.h"

#include <fretsim/fem/elastic_model.h>
#include <fretsim/fem/surface_grid_map.h>
#include <fretsim/fem/transient.h>

#include <cmath>
#include <cstdio>

using namespace fretsim::fem;

namespace
{
  constexpr double bore = 0.0341, outer = 0.040, width = 0.018, force = 1000.0; // [m], [N]
  constexpr double a = 2e-3, b = 3e-3;                                            // patch semi-axes [m]
  const Material   steel{208e9, 0.3, 7850.0};

  struct Setup
  {
    std::shared_ptr<const Mesh> mesh;
    ElasticModel                model;
    CylinderGrid                grid;
    SurfaceGridMap              map;
    double                      period; ///< lowest natural period [s]
  };

  CylinderGrid raceway_grid()
  {
    CylinderGrid g;
    g.radius = bore;
    g.nx = 256, g.ny = 16;
    g.hx = 2 * M_PI * bore / g.nx, g.hy = width / g.ny;
    g.x_min = 0.0, g.y_min = -0.5 * width;
    return g;
  }

  std::unique_ptr<Setup> make_setup()
  {
    RingGeometry r;
    r.bore_radius  = bore;
    r.outer_radius = outer;
    r.width        = width;
    MeshDivisions d;
    d.circumferential = 24;
    d.radial_ring     = 1;
    d.axial           = 2;
    auto         mesh = std::make_shared<const Mesh>(Mesh::ring(r, d));
    ElasticModel model(mesh, {{MaterialId::ring, steel}}, 2, {{BoundaryId::ring_outer}});
    ModalSettings m;
    m.n_modes                = 1;
    m.shift_hz               = 1000.0;
    const double f1          = model.solve_modes(m).frequencies_hz.at(0);
    const CylinderGrid grid  = raceway_grid();
    SurfaceGridMap     map(model, BoundaryId::raceway, grid);
    return std::unique_ptr<Setup>(new Setup{mesh, std::move(model), grid, std::move(map), 1.0 / f1});
  }

  std::unique_ptr<Setup> shared;
  Setup &setup()
  {
    if (!shared)
      shared = make_setup();
    return *shared;
  }

  /// The load of balls centred at arc lengths `x` on the mid-plane.
  struct BallLoad
  {
    GridTractions t;
    StaticLoad    load;
    BallLoad(const CylinderGrid &grid, const SurfaceGridMap &map, const std::vector<double> &x)
    {
      std::vector<HertzPatch> patches;
      for (const double xi : x)
        patches.push_back({xi, 0.0, a, b, force});
      t = hertz_patch_tractions(grid, patches);
      load.grid_tractions.push_back({&map, &t});
    }
  };
} // namespace

class Newmark : public ::testing::Test
{
public:
  static void TearDownTestSuite() { shared.reset(); }
};

TEST_F(Newmark, HertzPatchCarriesItsForce)
{
  auto        &s = setup();
  // Centred on θ = 0 where the grid wraps: both halves count.
  const auto   t     = hertz_patch_tractions(s.grid, {{0.0, 0.0, a, b, force}});
  const auto   total = s.map.total_force(t);
  const auto   nodal = s.map.nodal_force_sum(t);
  double       normal = 0.0;
  for (const double p : t.pressure)
    normal += p * s.grid.cell_area();
  EXPECT_NEAR(normal, force, 1e-9 * force); // Σ A p = P by construction: tight
  // Radially outward around θ = 0 (the ball pushes the ring outward): +x, less
  // the cosine of the patch's half-angle a/R ≈ 0.06 rad (0.03 % here).
  EXPECT_NEAR(total[0], force, 1e-3 * force);
  for (unsigned int c = 0; c < 3; ++c)
    EXPECT_NEAR(nodal[c], total[c], 1e-9 * force) << c; // Σ φ_i = 1: tight
  EXPECT_NEAR(total[1], 0.0, 1e-3 * force); // symmetric about θ = 0 up to the patch's own curvature
}

TEST_F(Newmark, UndampedFreeVibrationConservesEnergy)
{
  auto          &s = setup();
  BallLoad       ball(s.grid, s.map, {0.0});
  const auto     u0 = s.model.solve_static(ball.load);
  const double   e0 = u0.strain_energy();
  NewmarkIntegrator integrator(s.model, s.period / 20, StaticLoad{}, &u0);
  double         drift = 0.0, max_kinetic = 0.0;
  for (unsigned int n = 0; n < 200; ++n)
    {
      integrator.advance(StaticLoad{});
      const double e = integrator.kinetic_energy() + integrator.strain_energy();
      drift          = std::max(drift, std::abs(e - e0) / e0);
      max_kinetic    = std::max(max_kinetic, integrator.kinetic_energy());
    }
  std::printf("%lu DoFs, T1 = %.3e s, dt = T1/20, 200 steps: energy %.6e J, largest relative drift %.2e, "
              "largest kinetic share %.3f; factorisation %.3f s, steps %.3f s\n",
              s.model.n_dofs(), s.period, e0, drift, max_kinetic / e0, integrator.factorisation_seconds(),
              integrator.step_seconds());
  EXPECT_LT(drift, 1e-8);
  EXPECT_GT(max_kinetic, 0.5 * e0); // it does vibrate: energy goes back and forth
}

TEST_F(Newmark, SlowlyPassingBallsGiveTheStaticSolution)
{
  auto          &s  = setup();
  const double   half = M_PI * bore; // second ball opposite the first
  const unsigned steps = 200;
  const double   dt    = s.period / 5, speed = a / (steps * dt); // one semi-axis over 40 periods
  BallLoad       start(s.grid, s.map, {0.0, half});
  const auto     u0 = s.model.solve_static(start.load);
  NewmarkIntegrator integrator(s.model, dt, start.load, &u0);
  for (unsigned int n = 1; n <= steps; ++n)
    {
      BallLoad now(s.grid, s.map, {speed * n * dt, half + speed * n * dt});
      integrator.advance(now.load);
    }
  BallLoad   end(s.grid, s.map, {a, half + a});
  const auto dynamic = s.map.interpolate(integrator.displacement());
  const auto stat    = s.map.interpolate(s.model.solve_static(end.load));
  const auto before  = s.map.interpolate(u0);
  double     largest = 0.0, difference = 0.0, moved = 0.0;
  for (std::size_t k = 0; k < s.grid.size(); ++k)
    {
      largest    = std::max(largest, std::abs(stat.u_r[k]));
      difference = std::max(difference, std::abs(dynamic.u_r[k] - stat.u_r[k]));
      moved      = std::max(moved, std::abs(before.u_r[k] - stat.u_r[k]));
    }
  std::printf("balls moved %.1e m in %.3e s (%u steps): |u_r - u_r,static| <= %.2e of max |u_r| = %.3e m "
              "(the static field itself changed by %.2e)\n",
              a, steps * dt, steps, difference / largest, largest, moved / largest);
  EXPECT_LT(difference, 0.01 * largest);
  EXPECT_GT(moved, 5 * difference); // the test has teeth: the load really moved
}
