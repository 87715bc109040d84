// ShiftedStaticSolver: (K - σM) u = f with one factorisation for many loads.
//  * σ = 0 on a supported body is the plain static solve (ElasticModel::
//    solve_static, MUMPS on the same K): equal to round-off.
//  * A free ring under a self-equilibrated load (two opposite balls): with
//    u = Σ_k φ_k c_k / (ω_k² + s), s = (2π f_s)², c_k = φ_kᵀf (no rigid-body
//    part since c_rigid = 0), the energy E(s) = ½uᵀKu = ½ Σ c_k² ω_k² / (ω_k² + s)²
//    falls with s, and d ln E / ds ≥ -2/ω_1². So between shifts f_a < f_b
//        0 < 1 - E_b/E_a ≤ 2 (f_b² - f_a²) / f_1²,
//    f_1 the lowest elastic frequency (from the model's own modal solve): the
//    shift changes the solution by (f_s/f_1)² only.
//  * Several loads with the one factorisation: the solution is linear in f
//    (to round-off amplified by the free ring's rigid-body modes, 1/|σ|).
//  * Loads solved as blocks of right-hand sides give each load's single
//    solve (the same factor, another order of the same operations), on a
//    supported quarter ring and on a free ring with inertia relief, with
//    block boundaries inside the list. ctest runs these again under
//    `mpiexec -np 2` (fem.mpi_np2.unit_shifted_static_solver), where the
//    matrices and the blocks are distributed.
#include "fem_test_environment.h"
#include "reduction/bearing_ring.h"

#include <fretsim/fem/shifted_static_solver.h>
#include <fretsim/fem/stress_sampler.h>
#include <fretsim/fem/surface_point_map.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

using namespace fretsim::fem;

namespace
{
  const Material &steel = fretsim::reduction_testing::bearing_steel;

  RingGeometry ring_6208() { return fretsim::reduction_testing::ring_6208_geometry(); }

  RacewayBallLoad ball(double angle, double force) { return fretsim::reduction_testing::raceway_ball_6208(angle, force); }

  std::shared_ptr<const Mesh> full_ring()
  {
    MeshDivisions d;
    d.circumferential = 24;
    d.radial_ring     = 1;
    d.axial           = 2;
    d.axial_land      = 1;
    return std::make_shared<const Mesh>(Mesh::ring(ring_6208(), d));
  }

  /// A quarter ring held by symmetry planes and plane strain: K is regular.
  ElasticModel supported_quarter_ring(unsigned int degree)
  {
    MeshDivisions d;
    d.circumferential = 8;
    d.radial_ring     = 1;
    d.axial           = 2;
    d.axial_land      = 1;
    d.sector_angle    = 0.5 * M_PI;
    return ElasticModel(std::make_shared<const Mesh>(Mesh::ring(ring_6208(), d)), {{MaterialId::ring, steel}}, degree,
                        {{BoundaryId::side_faces, false, false, true},
                         {BoundaryId::sector_start, false, true, false},
                         {BoundaryId::sector_end, true, false, false}});
  }

  /// A solution seen through displacements at points of the outer surface
  /// and stresses at points inside the wall, between the angles [0, sector].
  class Probe
  {
  public:
    Probe(const ElasticModel &model, double sector)
      : outer(model, grid(0.040, {-0.008, -0.003, 0.0, 0.003, 0.008}, sector), BoundaryId::ring_outer)
      , inside(model, grid_pair(sector))
    {}

    struct Values
    {
      std::vector<double> displacement, stress;
    };

    Values operator()(const DisplacementField &u) const
    {
      Values v;
      for (const Vector3 &x : outer.interpolate(u))
        v.displacement.insert(v.displacement.end(), x.begin(), x.end());
      v.stress = inside.evaluate(u);
      return v;
    }

  private:
    static std::vector<Point3> grid(double r, const std::vector<double> &zs, double sector)
    {
      std::vector<Point3> points;
      for (int i = 0; i < 15; ++i)
        for (const double z : zs)
          {
            const double theta = sector * (i + 0.37) / 15.0; // off the mesh's cell faces
            points.push_back({r * std::cos(theta), r * std::sin(theta), z});
          }
      return points;
    }
    static std::vector<Point3> grid_pair(double sector)
    {
      std::vector<Point3> points = grid(0.037, {-0.003, 0.0, 0.003}, sector), more = grid(0.0385, {0.0}, sector);
      points.insert(points.end(), more.begin(), more.end());
      return points;
    }

    SurfacePointMap outer;
    StressSampler   inside;
  };

  /// max |a - b| / max |b|.
  double max_relative_difference(const std::vector<double> &a, const std::vector<double> &b)
  {
    double difference = 0.0, size = 0.0;
    for (std::size_t i = 0; i < b.size(); ++i)
      {
        difference = std::max(difference, std::abs(a[i] - b[i]));
        size       = std::max(size, std::abs(b[i]));
      }
    return difference / size;
  }

  /// Each load solved alone and in blocks of three (blocks of 3, 3 and 1
  /// for seven loads) and in the default blocks: the largest difference of
  /// the probe's displacements and stresses relative to the single solve's.
  double block_against_single(ElasticModel &model, ShiftedStaticSolver &solver, const std::vector<StaticLoad> &loads,
                              double sector)
  {
    const Probe                 probe(model, sector);
    std::vector<Probe::Values> single;
    std::vector<Vector3>        forces;
    for (const StaticLoad &load : loads)
      {
        single.push_back(probe(solver.solve(load)));
        forces.push_back(solver.last_net_force());
      }
    const std::size_t small_block = 3;
    EXPECT_EQ(loads.size() % small_block, 1u); // block boundaries inside, and a last block of one
    std::vector<std::size_t> order;
    double                   worst = 0.0;
    solver.solve_each(
      loads,
      [&](std::size_t i, const DisplacementField &u) {
        order.push_back(i);
        const Probe::Values v = probe(u);
        worst = std::max({worst, max_relative_difference(v.displacement, single[i].displacement),
                          max_relative_difference(v.stress, single[i].stress)});
      },
      small_block);
    EXPECT_EQ(order.size(), loads.size());
    for (std::size_t i = 0; i < order.size(); ++i)
      EXPECT_EQ(order[i], i);
    // after a block: the resultant of its last load
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(solver.last_net_force()[k], forces.back()[k]);
    std::size_t solved = 0; // and in the default block, all loads in one
    solver.solve_each(loads, [&](std::size_t i, const DisplacementField &u) {
      ++solved;
      const Probe::Values v = probe(u);
      worst = std::max({worst, max_relative_difference(v.displacement, single[i].displacement),
                        max_relative_difference(v.stress, single[i].stress)});
    });
    EXPECT_EQ(solved, loads.size());
    return worst;
  }
} // namespace

TEST(ShiftedStaticSolver, ZeroShiftIsThePlainStaticSolve)
{
  ElasticModel model = supported_quarter_ring(2);
  StaticLoad load;
  load.ball_loads.push_back(ball(0.25 * M_PI, 2000.0));
  const DisplacementField plain = model.solve_static(load);
  ShiftedStaticSolver     solver(model, 0.0);
  EXPECT_EQ(solver.shift(), 0.0);
  const DisplacementField shifted = solver.solve(load);
  // Reference: the same Cholesky factorisation of the same K; round-off only.
  EXPECT_LT(fretsim::fem_testing::relative_error(shifted.strain_energy(), plain.strain_energy()), 1e-10);
  const double a = shifted.average_on_boundary(BoundaryId::raceway).u_r;
  const double b = plain.average_on_boundary(BoundaryId::raceway).u_r;
  EXPECT_LT(std::abs(a - b), 1e-10 * std::abs(b));
}

TEST(ShiftedStaticSolver, FreeRingSolutionDependsOnTheShiftOnlyAsItsSquareOverTheLowestMode)
{
  ElasticModel model(full_ring(), {{MaterialId::ring, steel}}, 2);
  ModalSettings modal;
  modal.n_modes          = 1;
  const double f_1       = model.solve_modes(modal).frequencies_hz.front();
  StaticLoad   opposite; // self-equilibrated: no rigid-body part
  opposite.ball_loads = {ball(0.5 * M_PI, 2000.0), ball(1.5 * M_PI, 2000.0)};

  ShiftedStaticSolver at_1hz(model, 1.0), at_2hz(model, 2.0);
  EXPECT_NEAR(at_1hz.shift(), -std::pow(2.0 * M_PI, 2), 1e-12);
  const double e_a = at_1hz.solve(opposite).strain_energy();
  const double e_b = at_2hz.solve(opposite).strain_energy();
  const double change = 1.0 - e_b / e_a;
  const double bound  = 2.0 * (4.0 - 1.0) / (f_1 * f_1);
  std::printf("f_1 = %.1f Hz, 1 - E(2 Hz)/E(1 Hz) = %.3e, bound 2 (f_b^2 - f_a^2)/f_1^2 = %.3e\n", f_1, change, bound);
  EXPECT_GT(change, 0.0);
  EXPECT_LE(change, bound);
}

TEST(ShiftedStaticSolver, OneFactorisationServesManyLoadsLinearly)
{
  ElasticModel        model(full_ring(), {{MaterialId::ring, steel}}, 1);
  ShiftedStaticSolver solver(model, 1.0);
  StaticLoad          a, b, both;
  a.ball_loads    = {ball(0.5 * M_PI, 2000.0), ball(1.5 * M_PI, 2000.0)};
  b.ball_loads    = {ball(0.0, 1500.0), ball(M_PI, 1500.0)};
  both.ball_loads = {a.ball_loads[0], a.ball_loads[1], b.ball_loads[0], b.ball_loads[1]};
  const double u_a    = solver.solve(a).average_on_boundary(BoundaryId::ring_outer).u_r;
  const double u_b    = solver.solve(b).average_on_boundary(BoundaryId::ring_outer).u_r;
  const double u_both = solver.solve(both).average_on_boundary(BoundaryId::ring_outer).u_r;
  EXPECT_GT(u_a, 0.0); // outward balls widen the ring on average
  // Reference: linearity of one factorised operator, up to round-off. On a
  // free body that round-off is amplified by the rigid-body modes: a load
  // residual δf ~ 1e-12 N (ε × the 7 kN summed) moves the ring by
  // δf / (|σ| m) = 1e-12 / (39.5 × 0.19 kg) ~ 1e-13 m; the bound is ten times that.
  std::printf("mean u_r: %.6e m, linearity defect %.2e m\n", u_both, std::abs(u_both - (u_a + u_b)));
  EXPECT_LT(std::abs(u_both - (u_a + u_b)), 1e-12);
  EXPECT_GT(solver.factorisation_seconds(), 0.0);
  EXPECT_GE(solver.last_solve_seconds(), 0.0);
}

TEST(ShiftedStaticSolver, InertiaReliefBalancesAnUnbalancedLoad)
{
  // One ball alone pushes the free ring away: 2 kN on 0.2 kg under a 1 Hz
  // shift would be a rigid motion of metres. With inertia relief the load is
  // balanced by the rigid-body inertia it would cause, and the answer is the
  // deformation alone. Checks (references in brackets):
  //  * the reported resultant is the ball's 2 kN along its contact normal
  //    (conservation of the patch forces: round-off);
  //  * a self-equilibrated pair is left as it is (relief removes Φᵀf ≈ 0:
  //    round-off);
  //  * relief is linear and the 24-cell mesh is symmetric under a rotation by
  //    π, so each ball of the opposite pair gets half the pair's mean outer
  //    u_r (round-off).
  ElasticModel        model(full_ring(), {{MaterialId::ring, steel}}, 2);
  ShiftedStaticSolver plain(model, 1.0), relieved(model, 1.0, true);
  StaticLoad          one, other, pair;
  one.ball_loads   = {ball(0.5 * M_PI, 2000.0)};
  other.ball_loads = {ball(1.5 * M_PI, 2000.0)};
  pair.ball_loads  = {one.ball_loads[0], other.ball_loads[0]};

  const double u_one = relieved.solve(one).average_on_boundary(BoundaryId::ring_outer).u_r;
  const Vector3 force = relieved.last_net_force(), moment = relieved.last_net_moment();
  EXPECT_NEAR(force[0], 0.0, 1e-9 * 2000.0);
  EXPECT_NEAR(force[1], 2000.0, 1e-9 * 2000.0);
  EXPECT_NEAR(force[2], 0.0, 1e-9 * 2000.0);
  EXPECT_NEAR(moment[2], 0.0, 1e-9 * 2000.0 * 0.04);
  const double u_other = relieved.solve(other).average_on_boundary(BoundaryId::ring_outer).u_r;
  const auto   u_pair  = relieved.solve(pair);
  const auto   u_pair_plain = plain.solve(pair);
  std::printf("mean outer u_r: one ball %.6e m, the other %.6e m, pair %.6e m\n", u_one, u_other,
              u_pair.average_on_boundary(BoundaryId::ring_outer).u_r);
  EXPECT_LT(fretsim::fem_testing::relative_error(u_pair.strain_energy(), u_pair_plain.strain_energy()), 1e-9);
  const double half = 0.5 * u_pair.average_on_boundary(BoundaryId::ring_outer).u_r;
  EXPECT_LT(std::abs(u_one - half), 1e-9 * std::abs(half));
  EXPECT_LT(std::abs(u_other - half), 1e-9 * std::abs(half));
}

TEST(ShiftedStaticSolver, BlocksOfLoadsGiveTheSingleSolvesOnASupportedRing)
{
  ElasticModel        model = supported_quarter_ring(2);
  ShiftedStaticSolver solver(model, 0.0);
  std::vector<StaticLoad> loads(7);
  for (std::size_t i = 0; i < 6; ++i)
    loads[i].ball_loads = {ball(0.5 * M_PI * (i + 0.5) / 6.0, 1000.0 + 300.0 * i)};
  loads[6].pressures = {{BoundaryId::raceway, 20e6}};
  // Reference: the single solves with the same factor; the block's
  // triangular solves add their terms in another order, so the two differ
  // by round-off (ε times a modest growth), far below 1e-12 of the field.
  const double difference = block_against_single(model, solver, loads, 0.5 * M_PI);
  std::printf("blocks against single solves (supported): max difference %.2e of the max norm\n", difference);
  EXPECT_LT(difference, 1e-12);
}

TEST(ShiftedStaticSolver, BlocksOfLoadsGiveTheSingleSolvesWithInertiaRelief)
{
  // Single balls: unbalanced, so without the relief of every column (before
  // and after the solve) the block's answer would be metres of rigid motion.
  ElasticModel            model(full_ring(), {{MaterialId::ring, steel}}, 2);
  ShiftedStaticSolver     solver(model, 1.0, true);
  std::vector<StaticLoad> loads(7);
  for (std::size_t i = 0; i < 6; ++i)
    loads[i].ball_loads = {ball(2.0 * M_PI * (i + 0.3) / 6.0, 1000.0 + 300.0 * i)};
  loads[6].ball_loads = {ball(0.2, 2000.0), ball(0.2 + M_PI, 2000.0)};
  // Reference as above: round-off. The relieved solution has no rigid-body
  // part to amplify it (both are projected onto the deformations).
  const double difference = block_against_single(model, solver, loads, 2.0 * M_PI);
  std::printf("blocks against single solves (free, relieved): max difference %.2e of the max norm\n", difference);
  EXPECT_LT(difference, 1e-12);
}
