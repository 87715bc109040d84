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
#include "fem_test_environment.h"
#include "reduction/bearing_ring.h"

#include <fretsim/fem/shifted_static_solver.h>

#include <cmath>
#include <cstdio>

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
} // namespace

TEST(ShiftedStaticSolver, ZeroShiftIsThePlainStaticSolve)
{
  // A quarter ring held by symmetry planes and plane strain: K is regular.
  MeshDivisions d;
  d.circumferential = 8;
  d.radial_ring     = 1;
  d.axial           = 2;
  d.axial_land      = 1;
  d.sector_angle    = 0.5 * M_PI;
  ElasticModel model(std::make_shared<const Mesh>(Mesh::ring(ring_6208(), d)), {{MaterialId::ring, steel}}, 2,
                     {{BoundaryId::side_faces, false, false, true},
                      {BoundaryId::sector_start, false, true, false},
                      {BoundaryId::sector_end, true, false, false}});
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
