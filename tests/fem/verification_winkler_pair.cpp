// Ring and housing both meshed, joined by the Winkler layer
// (WinklerPairNewmark, winkler_foundation.h): the full-FE reference of a run
// whose housing gives way.
//
// (a) Lamé, ring in housing. A plain ring (bore a, outer b) under internal
//     pressure p_i, in a housing (bore b, outer c) whose outside is held
//     radially (u_x = u_y = 0, u_z free), the layer k_n between them, δ_fit
//     = 0. Plane stress in both (σ_rr + σ_θθ constant, so ε_zz is and u_z =
//     ε_zz z: exact 3-D solutions with free side faces, and the outside's
//     axial freedom keeps it so). Per body, with σ_rr = A - B/r² and u_r =
//     ((1 - ν) A r + (1 + ν) B / r) / E (Timoshenko & Goodier §28):
//       ring u_r(b)    = α p_i - β p_w,  α = 2 a² b / (E (b² - a²)),
//                        β = ((1 - ν) b³ + (1 + ν) a² b) / (E (b² - a²));
//       housing u_r(b) = γ p_w,  γ = (1 - ν)(c² - b²) / (b E (1 + (1 - ν) c² / ((1 + ν) b²)))
//                        (from u_r(c) = 0, σ_rr(b) = -p_w);
//       layer p_w = k_n (u_ring - u_housing)  →  p_w = k_n α p_i / (1 + k_n (β + γ)).
//     The housing's give (γ) lowers p_w by 5.3 % (k_n = 5e12) and 6.2 %
//     (1e15) against a rigid foundation's: the test sees the housing.
// (b) A housing 10⁴ times stiffer than steel is the rigid foundation
//     (WinklerFoundationSolver, WinklerNewmark) under a ball, statically and
//     through a transient; the layer's resultant on the ring balances the
//     ball and the housing takes it equal and opposite.
// (c) With an interference that keeps every cell closed, the joint system
//     is linear and the trapezoidal rule conserves both bodies' ½vᵀMv +
//     ½uᵀKu plus the layer's energy to round-off, with one factorisation.
// (d) Under mpiexec -np 2 (fem.mpi_np2.verification_winkler_pair) the joint
//     solution of models distributed over both ranks equals that of models
//     on each rank alone.
#include "fem_test_environment.h"
#include "reduction/bearing_ring.h"

#include <fretsim/fem/winkler_foundation.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace fretsim::fem;
using fretsim::fem_testing::relative_error;

namespace
{
  const Material   steel{208e9, 0.3, 7850.0};
  constexpr double bore = 0.0341, outer = 0.040, housing_outer = 0.060, width = 0.018; // [m]

  CylinderGrid outer_grid(int nx, int ny) { return CylinderGrid::around(outer, width, nx, ny); }

  RingGeometry ring_geometry(bool grooved)
  {
    RingGeometry g;
    g.bore_radius  = bore;
    g.outer_radius = outer;
    g.width        = width;
    if (grooved)
      {
        g.groove_radius        = 0.006731;
        g.groove_bottom_radius = 0.03635;
      }
    return g;
  }

  /// Ring and housing models, the housing's outside held radially, and the
  /// layer's two grid maps.
  struct Pair
  {
    ElasticModel   ring, housing;
    SurfaceGridMap ring_map, housing_map;

    Pair(bool grooved, unsigned int circumferential, unsigned int radial, const CylinderGrid &grid,
         double housing_modulus = steel.youngs_modulus, Ranks ranks = Ranks::all)
      : ring(ring_mesh(grooved, circumferential, radial, ranks), {{MaterialId::ring, steel}}, 2)
      , housing(housing_mesh(circumferential, radial, ranks),
                {{MaterialId::housing, {housing_modulus, steel.poisson_ratio, steel.density}}}, 2,
                {{BoundaryId::housing_outer, true, true, false}})
      , ring_map(ring, BoundaryId::ring_outer, grid)
      , housing_map(housing, BoundaryId::housing_bore, grid)
    {}

    static std::shared_ptr<const Mesh> ring_mesh(bool grooved, unsigned int circumferential, unsigned int radial,
                                                 Ranks ranks)
    {
      MeshDivisions d;
      d.circumferential = circumferential;
      d.radial_ring     = radial;
      d.axial           = 2;
      d.axial_land      = 1;
      return std::make_shared<const Mesh>(Mesh::ring(ring_geometry(grooved), d, ranks));
    }

    static std::shared_ptr<const Mesh> housing_mesh(unsigned int circumferential, unsigned int radial, Ranks ranks)
    {
      MeshDivisions d;
      d.circumferential = circumferential;
      d.radial_housing  = radial;
      d.axial           = 2;
      return std::make_shared<const Mesh>(Mesh::housing({outer, housing_outer, width}, d, ranks));
    }
  };

  RacewayBallLoad ball(double angle, double force) { return fretsim::reduction_testing::raceway_ball_6208(angle, force); }

  double mean(const std::vector<double> &values)
  {
    double sum = 0.0;
    for (const double v : values)
      sum += v;
    return sum / static_cast<double>(values.size());
  }

  double max_difference(const std::vector<double> &a, const std::vector<double> &b)
  {
    double worst = 0.0;
    for (std::size_t c = 0; c < a.size(); ++c)
      worst = std::max(worst, std::abs(a[c] - b[c]));
    return worst;
  }
} // namespace

// (a) Measured: the grid's mean pressure within 8.7e-5 (k_n = 5e12) and
// 7.7e-6 (1e15) of the closed form on the 48 x 2 x 2 Q2 meshes, 192 x 8
// grid; tolerance 1e-3, a sixth of the housing's effect.
TEST(WinklerPair, LameRingInAHousingHeldAtItsOutside)
{
  const double E = steel.youngs_modulus, nu = steel.poisson_ratio, p_i = 100e6;
  const double a = bore, b = outer, c = housing_outer;
  const double alpha = 2.0 * a * a * b / (E * (b * b - a * a));
  const double beta  = ((1.0 - nu) * b * b * b + (1.0 + nu) * a * a * b) / (E * (b * b - a * a));
  const double gamma = (1.0 - nu) * (c * c - b * b) / (b * E * (1.0 + (1.0 - nu) * c * c / ((1.0 + nu) * b * b)));
  Pair         pair(false, 48, 2, outer_grid(192, 8));
  StaticLoad   load;
  load.pressures.push_back({BoundaryId::raceway, p_i});
  for (const double k_n : {5e12, 1e15})
    {
      const double       exact = k_n * alpha * p_i / (1.0 + k_n * (beta + gamma));
      const double       rigid = k_n * alpha * p_i / (1.0 + k_n * beta);
      WinklerPairNewmark joint(pair.ring, pair.ring_map, pair.housing, pair.housing_map, {k_n, 0.0}, 1e-6, load);
      const auto        &start = joint.start();
      const double       error = relative_error(mean(start.pressure), exact);
      std::printf("k_n = %.1e: p_w = %.6e Pa (rigid housing %.6e), grid mean error %.2e, contact %.3f, %u solves, "
                  "%lu joint DoFs, %.2f s\n",
                  k_n, exact, rigid, error, start.contact_fraction(), start.iterations, joint.n_dofs(), start.seconds);
      EXPECT_EQ(start.contact_fraction(), 1.0);
      EXPECT_LT(error, 1e-3);
      EXPECT_GT(relative_error(rigid, exact), 0.02); // the housing's give matters here
    }
}

// (b) Measured: the stiff housing's static pressure within 3.5e-6 of the
// rigid foundation's peak, the transient's within 5.3e-5 after 20 steps; the
// layer's resultant on each body within 3e-10 Q of ∓Q e_r(ψ) (the 1 Hz
// shift's inertia term). Tolerances 1e-3 and 1e-7. A steel housing lowers
// the peak by 15 % (4.14e7 against 4.90e7 Pa) and the far side opens
// (contact 0.54 against 0.68).
TEST(WinklerPair, AStiffHousingIsTheRigidFoundation)
{
  const double       Q = 2000.0, psi = 0.5 * M_PI, dt = 5e-6, sweep = 0.05; // [N], [rad], [s], [rad]
  const CylinderGrid grid = outer_grid(72, 6);
  Pair               stiff(true, 24, 1, grid, 1e4 * steel.youngs_modulus), steel_housing(true, 24, 1, grid);
  const WinklerLayer layer{1e15, 0.0};
  StaticLoad         load;
  load.ball_loads.push_back(ball(psi, Q));

  WinklerPairNewmark joint(stiff.ring, stiff.ring_map, stiff.housing, stiff.housing_map, layer, dt, load);
  WinklerNewmark     rigid(stiff.ring, stiff.ring_map, layer, dt, load);
  const double       peak        = rigid.foundation().peak_pressure();
  const double       static_diff = max_difference(joint.start().pressure, rigid.foundation().pressure);

  const std::vector<double> zero(grid.size(), 0.0);
  const GridTractions       layer_pressure{joint.start().pressure, zero, zero};
  const Vector3             on_ring = stiff.ring_map.total_force(layer_pressure);
  const Vector3             on_housing = stiff.housing_map.total_force(layer_pressure);
  for (int k = 1; k <= 20; ++k)
    {
      load.ball_loads.back() = ball(psi + sweep * k / 20, Q);
      joint.advance(load);
      rigid.advance(load);
    }
  const double transient_diff = max_difference(joint.foundation().pressure, rigid.foundation().pressure);

  StaticLoad at_start;
  at_start.ball_loads.push_back(ball(psi, Q));
  WinklerPairNewmark steel_joint(steel_housing.ring, steel_housing.ring_map, steel_housing.housing,
                                 steel_housing.housing_map, layer, dt, at_start);
  std::printf("stiff housing: static max |dp| %.2e of the rigid peak %.4e Pa, after 20 steps %.2e; ring force "
              "(%.2e, %.10e, %.1e) N, housing (%.2e, %.10e, %.1e) N; %u steps, %u solves, %u factorisations; "
              "steel housing: peak %.4e Pa, contact %.3f (rigid %.3f)\n",
              static_diff / peak, peak, transient_diff / rigid.foundation().peak_pressure(), on_ring[0], on_ring[1],
              on_ring[2], on_housing[0], on_housing[1], on_housing[2], joint.steps(), joint.solves(),
              joint.factorisations(), steel_joint.start().peak_pressure(), steel_joint.start().contact_fraction(),
              rigid.foundation().contact_fraction());
  EXPECT_LT(static_diff, 1e-3 * peak);
  EXPECT_LT(transient_diff, 1e-3 * rigid.foundation().peak_pressure());
  for (int k = 0; k < 3; ++k)
    {
      const double ball_force = k == 0 ? Q * std::cos(psi) : k == 1 ? Q * std::sin(psi) : 0.0;
      EXPECT_LT(std::abs(on_ring[k] + ball_force), 1e-7 * Q) << "component " << k;
      EXPECT_LT(std::abs(on_housing[k] - ball_force), 1e-7 * Q) << "component " << k;
    }
  // A steel housing gives way under the ball: a lower peak.
  EXPECT_LT(steel_joint.start().peak_pressure(), 0.9 * peak);
  EXPECT_EQ(joint.steps(), 20u);
}

// (c) Measured: energy constant to 7.9e-15 over 40 steps; tolerance 1e-9.
TEST(WinklerPair, NewmarkConservesEnergyWhileEveryCellStaysClosed)
{
  Pair               pair(true, 24, 1, outer_grid(72, 6));
  const WinklerLayer layer{2.6e13, 20e-6}; // every cell stays closed (as in verification_winkler_foundation.cpp)
  StaticLoad         loaded;
  loaded.ball_loads.push_back(ball(0.5 * M_PI, 1000.0));
  WinklerPairNewmark free(pair.ring, pair.ring_map, pair.housing, pair.housing_map, layer, 2e-6, loaded);
  const auto         start_u_r = pair.ring_map.interpolate(free.ring_displacement()).u_r;
  const StaticLoad   unloaded;
  free.advance(unloaded); // the trapezoidal step averages the old and new load: energy changes once
  const double energy = free.energy();
  double       worst  = 0.0;
  for (int k = 0; k < 40; ++k)
    {
      free.advance(unloaded);
      worst = std::max(worst, std::abs(free.energy() - energy));
      EXPECT_EQ(free.foundation().contact_fraction(), 1.0);
    }
  const auto   u_r   = pair.ring_map.interpolate(free.ring_displacement()).u_r;
  double       scale = 0.0;
  for (const double u : start_u_r)
    scale = std::max(scale, std::abs(u));
  const double moved = max_difference(u_r, start_u_r);
  const auto   bore_u_r      = pair.housing_map.interpolate(free.housing_displacement()).u_r;
  const double housing_moved = *std::max_element(bore_u_r.begin(), bore_u_r.end());
  std::printf("free vibration: energy %.6e J, largest change %.2e of it, ring u_r moved %.2e of max, housing bore "
              "u_r up to %.3e m, %u factorisations in %u solves\n",
              energy, worst / std::abs(energy), moved / scale, housing_moved, free.factorisations(), free.solves());
  EXPECT_LT(worst, 1e-9 * std::abs(energy));
  EXPECT_GT(moved, 1e-2 * scale);  // it does vibrate
  EXPECT_GT(housing_moved, 1e-8);  // the fit pushes the housing out (µm-scale)
  EXPECT_EQ(free.factorisations(), 1u);
}

TEST(WinklerPair, BadInputIsRejected)
{
  Pair               pair(false, 8, 1, outer_grid(16, 2));
  const WinklerLayer layer{1e15, 0.0};
  const StaticLoad   none;
  EXPECT_THROW(WinklerPairNewmark(pair.ring, pair.ring_map, pair.housing, pair.housing_map, layer, 0.0, none),
               std::invalid_argument);
  EXPECT_THROW(WinklerPairNewmark(pair.ring, pair.ring_map, pair.housing, pair.housing_map, {0.0, 0.0}, 1e-6, none),
               std::invalid_argument);
  // Both maps on outer-surface-like directions, a map of the other model, grids of other sizes.
  EXPECT_THROW(WinklerPairNewmark(pair.ring, pair.ring_map, pair.ring, pair.ring_map, layer, 1e-6, none),
               std::invalid_argument);
  EXPECT_THROW(WinklerPairNewmark(pair.ring, pair.housing_map, pair.housing, pair.ring_map, layer, 1e-6, none),
               std::invalid_argument);
  const SurfaceGridMap coarse(pair.housing, BoundaryId::housing_bore, outer_grid(8, 2));
  EXPECT_THROW(WinklerPairNewmark(pair.ring, pair.ring_map, pair.housing, coarse, layer, 1e-6, none),
               std::invalid_argument);
}

// (d) Reference: the same joint system summed in another order (round-off).
TEST(WinklerPair, SameOnOneAndTwoRanks)
{
  const auto solve = [](Ranks ranks) {
    Pair       pair(true, 24, 1, outer_grid(72, 6), steel.youngs_modulus, ranks);
    StaticLoad load;
    load.ball_loads = {ball(0.5 * M_PI, 2000.0), ball(0.5 * M_PI + 0.7, 1200.0)};
    WinklerPairNewmark joint(pair.ring, pair.ring_map, pair.housing, pair.housing_map, {1e15, 0.0}, 5e-6, load);
    load.ball_loads.back() = ball(0.5 * M_PI + 0.72, 1200.0);
    joint.advance(load);
    std::printf("rank %u/%u (%s): peak %.10e Pa, contact %.4f\n", ParallelEnvironment::rank(),
                ParallelEnvironment::n_ranks(), ranks == Ranks::all ? "all ranks" : "this rank",
                joint.foundation().peak_pressure(), joint.foundation().contact_fraction());
    return joint.foundation();
  };
  const WinklerGridSolution all = solve(Ranks::all), alone = solve(Ranks::this_one);
  EXPECT_EQ(all.active, alone.active);
  EXPECT_LT(max_difference(all.pressure, alone.pressure), 1e-9 * alone.peak_pressure());
}
