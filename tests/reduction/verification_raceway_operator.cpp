// The raceway ball operator (reduced_model.h) on a small grooved 6208 ring
// (24 cells round, Q2), reduced with the outer surface as boundary (n_cc = 30,
// m = 12), 48 ball positions (two per cell: at cell edges and mid-cell):
//  (a) each row equals CraigBampton::project_load of the same unit ball: the
//      definition, reached by another path (load vector assembled and
//      projected on T, against basis fields sampled at the patch points);
//  (b) work and energy: the work of a ball through the operator equals the
//      energy of the expanded field on the full FE stiffness (Clapeyron); the
//      work of a pair of opposite balls on the library's own reduced solution
//      of another pair equals the operator's reciprocal (Betti); and r·q is
//      an outward approach: positive under an outward pair, negative 90° from
//      it (ovalisation, as in thin-ring theory);
//  (c) rotational symmetry: a unit ball's approach is the same at every ψ_k
//      up to the mesh's discreteness;
//  (d) footprints that follow the load: the row the run interpolates between
//      the Hertz ellipses of a few loads (coupling::footprint_blend) against
//      the row projected directly for the exact ellipse of the load.
// A single ball on the free ring is relieved by its rigid-body inertia
// (Reduced::relieved), or taken with its opposite one, so that the shifted
// static solve's rigid-body response does not swamp the elastic one.
#include "fem/fem_test_environment.h"
#include "reduction/bearing_ring.h"

#include <fretsim/contact/material.h>
#include <fretsim/coupling/bearing.h>
#include <fretsim/fem/surface_point_map.h>
#include <fretsim/reduction/reduced_model.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

using namespace fretsim;

namespace
{
  constexpr unsigned int n_angles = 48;
  constexpr double       footprint_circumferential = 0.3e-3, footprint_transverse = 1.3e-3; // [m]

  fem::RacewayBallLoad ball(const double angle, const double force)
  {
    fem::RacewayBallLoad b;
    b.ring                      = reduction_testing::ring_6208_geometry();
    b.angle                     = angle;
    b.force                     = force;
    b.semi_axis_circumferential = footprint_circumferential;
    b.semi_axis_transverse      = footprint_transverse;
    return b;
  }

  /// The reduced ring, built once for all tests of this file.
  struct Reduced
  {
    fem::ElasticModel            model;
    reduction::ReductionSettings settings;
    reduction::CraigBampton      cb;
    reduction::ReducedMatrices   matrices;
    reduction::RacewayOperators  raceway;
    Eigen::MatrixXd              shifted; ///< K_r - σ M_r, σ of the static solves
    Eigen::MatrixXd              mass;
    Eigen::MatrixXd              rigid;   ///< the six rigid-body modes of (K_r, M_r), M_r-normalised

    Reduced()
      : model(reduction_testing::ring_6208(24, 1, 2, 1), {{fem::MaterialId::ring, reduction_testing::bearing_steel}}, 2)
      , settings(make_settings())
      , cb(model, settings)
      , matrices(cb.run())
      , raceway(reduction::raceway_operators(cb, model, reduction_testing::ring_6208_geometry(), n_angles,
                                             {{footprint_circumferential, footprint_transverse, 0.0}}))
    {
      const auto n      = static_cast<Eigen::Index>(matrices.size());
      mass              = Eigen::Map<const Eigen::MatrixXd>(matrices.mass.data(), n, n);
      const double sigma = -std::pow(2.0 * M_PI * settings.static_shift_hz, 2);
      const Eigen::MatrixXd stiffness = Eigen::Map<const Eigen::MatrixXd>(matrices.stiffness.data(), n, n);
      shifted = stiffness - sigma * mass;
      const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(stiffness, mass);
      rigid = modes.eigenvectors().leftCols(6);
    }

    static reduction::ReductionSettings make_settings()
    {
      reduction::ReductionSettings s;
      s.coupling_surfaces                 = {fem::BoundaryId::ring_outer};
      s.n_characteristic_constraint_modes = 30;
      s.n_fixed_interface_modes           = 12;
      return s;
    }

    Eigen::VectorXd row(const unsigned int k) const
    {
      const auto n = static_cast<Eigen::Index>(matrices.size());
      return Eigen::Map<const Eigen::VectorXd>(raceway.approach.data() + (k % n_angles) * n, n);
    }
    /// r_k + r_{k + n/2}: a unit pair of opposite balls.
    Eigen::VectorXd pair(const unsigned int k) const { return row(k) + row(k + n_angles / 2); }
    Eigen::VectorXd solve(const Eigen::VectorXd &force) const { return shifted.ldlt().solve(force); }
    /// The load with the d'Alembert forces of the rigid-body acceleration it
    /// gives a free ring added (inertia relief): self-equilibrated, so its
    /// response is elastic only. Without it, the shifted solve's response to
    /// a single ball is a rigid translation Q / (|σ| m) (~0.1 m per N at
    /// 1 Hz) that swamps the µm of elastic approach.
    Eigen::VectorXd relieved(const Eigen::VectorXd &force) const
    {
      return force - mass * (rigid * (rigid.transpose() * force));
    }
  };
} // namespace

/// Builds the reduced ring once for the suite and frees it before PETSc ends.
class RacewayOperator : public ::testing::Test
{
protected:
  static void SetUpTestSuite() { instance = std::make_unique<Reduced>(); }
  static void TearDownTestSuite() { instance.reset(); }
  static const Reduced &reduced() { return *instance; }

private:
  static inline std::unique_ptr<Reduced> instance;
};

TEST_F(RacewayOperator, RowsAreTheProjectedUnitBallLoads)
{
  const Reduced &r = reduced();
  ASSERT_EQ(r.raceway.angles.size(), n_angles);
  ASSERT_EQ(r.raceway.approach.size(), n_angles * r.matrices.size());
  ASSERT_EQ(r.raceway.footprints.size(), 1u);
  EXPECT_EQ(r.raceway.footprints[0].semi_axis_transverse, footprint_transverse);
  EXPECT_FALSE(r.raceway.follows_load());
  double worst = 0.0;
  for (unsigned int k = 0; k < n_angles; ++k)
    {
      EXPECT_DOUBLE_EQ(r.raceway.angles[k], 2.0 * M_PI * k / n_angles);
      fem::StaticLoad load;
      load.ball_loads.push_back(ball(2.0 * M_PI * k / n_angles, 1.0));
      const std::vector<double> projected = r.cb.project_load(load);
      const Eigen::VectorXd     expected  = Eigen::Map<const Eigen::VectorXd>(projected.data(), projected.size());
      worst = std::max(worst, (r.row(k) - expected).cwiseAbs().maxCoeff() / expected.cwiseAbs().maxCoeff());
    }
  std::printf("max |r_k - T^T f_k| / max |T^T f_k| over %u angles: %.2e\n", n_angles, worst);
  // The same ~64 x 81 products summed in another order (round-off), with
  // each patch point located in a cell by the same search.
  EXPECT_LT(worst, 1e-12);
}

TEST_F(RacewayOperator, WorkEqualsEnergyAndIsReciprocal)
{
  const Reduced &r     = reduced();
  const double   force = 2000.0; // [N], a loaded 6208 ball
  const double   sigma = -std::pow(2.0 * M_PI * r.settings.static_shift_hz, 2);

  // Clapeyron: a ball at ψ_5 (off every symmetry line of the mesh), relieved
  // by its rigid-body inertia; the work of that load (Q r_5 through the
  // operator, and the d'Alembert forces) against the energy of the expanded
  // field u = T q on the full FE stiffness, plus the shift's share
  // -σ qᵀ M_r q. (The d'Alembert forces do no work on an elastic q; apart,
  // the ball's work would carry the round-off rigid part of q, ~1e-10 in
  // the M_r norm, times the ball's large rigid-body load.)
  const Eigen::VectorXd        load   = r.relieved(force * r.row(5));
  const Eigen::VectorXd        q      = r.solve(load);
  const double                 work   = load.dot(q);
  const fem::DisplacementField u      = r.cb.expand(std::vector<double>(q.data(), q.data() + q.size()));
  const double                 energy = 2.0 * u.strain_energy() - sigma * q.dot(r.mass * q);
  std::printf("2 kN ball at %.1f deg: work %.12e J, 2 x energy %.12e J (relative difference %.1e)\n",
              r.raceway.angles[5] * 180 / M_PI, work, energy, std::abs(work / energy - 1.0));
  // K_r = TᵀKT to round-off (symmetric to 1e-14 before symmetrisation;
  // measured 1.4e-13 here).
  EXPECT_LT(std::abs(work / energy - 1.0), 1e-10);

  // Betti: the library's own reduced solution of a pair of opposite balls at
  // 0/180° (its load assembled and projected, not the operator), worked on
  // by a pair at 45/225° through a point map at that pair's patch points,
  // against the operator's reciprocal: the first pair on the solution of
  // the second.
  fem::StaticLoad first;
  for (const unsigned int k : {0u, n_angles / 2})
    first.ball_loads.push_back(ball(2.0 * M_PI * k / n_angles, force));
  std::vector<fem::Point3>  points;
  std::vector<fem::Vector3> forces;
  for (const unsigned int k : {n_angles / 8, n_angles / 8 + n_angles / 2})
    {
      const fem::PatchForces patch = fem::raceway_patch_forces(ball(2.0 * M_PI * k / n_angles, force));
      points.insert(points.end(), patch.points.begin(), patch.points.end());
      forces.insert(forces.end(), patch.forces.begin(), patch.forces.end());
    }
  const fem::SurfacePointMap      map(r.model, points, fem::BoundaryId::raceway);
  const std::vector<fem::Vector3> u_first = map.interpolate(r.cb.reduced_static(first, r.matrices));
  double                          work_second_on_first = 0.0;
  for (std::size_t p = 0; p < points.size(); ++p)
    for (unsigned int d = 0; d < 3; ++d)
      work_second_on_first += forces[p][d] * u_first[p][d];
  const double work_first_on_second = force * r.pair(0).dot(r.solve(force * r.pair(n_angles / 8)));
  std::printf("Betti, pairs at 0/180 and 45/225 deg: %.12e J (library solve, point map) vs %.12e J (operator), "
              "relative difference %.1e\n",
              work_second_on_first, work_first_on_second, std::abs(work_second_on_first / work_first_on_second - 1.0));
  // Round-off of two solves of the same dense system and of sums of ~10⁴
  // terms (measured 2e-14).
  EXPECT_LT(std::abs(work_second_on_first / work_first_on_second - 1.0), 1e-11);

  // Outward approach: the pair pushes the raceway out under the balls, and
  // the ring ovalises, drawing it in 90° away. Thin-ring theory (Roark, ring
  // under two opposite forces): radial displacement 90° away / under the
  // loads = -(2/π - 1/2) / (π/4 - 2/π) = -0.918; the thick grooved ring's
  // local compliance under the balls makes the magnitude smaller.
  const Eigen::VectorXd q_pair = r.solve(force * r.pair(0));
  const double          under = r.row(0).dot(q_pair), aside = r.row(n_angles / 4).dot(q_pair);
  std::printf("pair at 0/180 deg: approach under the balls %.4e m, 90 deg away %.4e m (ratio %.3f; thin ring "
              "-0.918)\n",
              under, aside, aside / under);
  EXPECT_GT(under, 0.0);
  EXPECT_LT(aside / under, -0.8);
  EXPECT_GT(aside / under, -0.918);
}

TEST_F(RacewayOperator, ApproachIsTheSameAllRound)
{
  const Reduced      &r = reduced();
  std::vector<double> compliance; // a unit ball's approach, inertia-relieved [m/N]
  for (unsigned int k = 0; k < n_angles; ++k)
    compliance.push_back(r.row(k).dot(r.solve(r.relieved(r.row(k)))));
  const auto [low, high] = std::minmax_element(compliance.begin(), compliance.end());
  double per_cell = 0.0; // the mesh repeats every cell, i.e. every second ψ_k
  for (unsigned int k = 0; k < n_angles; ++k)
    per_cell = std::max(per_cell, std::abs(compliance[(k + 2) % n_angles] / compliance[k] - 1.0));
  std::printf("unit ball approach: %.6e .. %.6e m/N (spread %.2e); at a cell edge %.6e, mid-cell %.6e; "
              "repeating per cell to %.1e\n",
              *low, *high, *high / *low - 1.0, compliance[0], compliance[1], per_cell);
  // Half a cell's rotation moves the patch from a cell edge to a cell
  // middle, where the Q2 shape functions take the same load onto other
  // nodes: the mesh's discreteness, measured 2.6e-3 (24 cells round).
  EXPECT_LT(*high / *low - 1.0, 5e-3);
  // A whole cell's rotation maps the mesh onto itself; what is left
  // (measured 5.8e-7 on one rank, 7.9e-7 on two) is where each patch's
  // points land (a point within the search tolerance of a cell face may be
  // placed in either cell) and the reduced basis's own symmetry.
  EXPECT_LT(per_cell, 1e-5);
}

namespace
{
  /// The Hertz ellipse of a 6208 ball on the outer raceway (the scene's
  /// bearing: 12.7 mm balls on a 60 mm pitch circle, f_o = 0.53, steel).
  coupling::OuterContactEllipse ellipse_6208()
  {
    coupling::BearingGeometry b;
    const fem::RingGeometry   ring = reduction_testing::ring_6208_geometry();
    b.ball_diameter                = 0.0127;
    b.pitch_diameter               = 2.0 * ring.groove_bottom_radius - b.ball_diameter;
    b.outer_groove_conformity      = ring.groove_radius / b.ball_diameter;
    const contact::ElasticMaterial steel{reduction_testing::bearing_steel.youngs_modulus,
                                         reduction_testing::bearing_steel.poisson_ratio};
    return coupling::outer_contact_ellipse(b, contact::MaterialPair{steel, steel}.contact_modulus());
  }

  reduction::BallFootprint hertz_footprint(const coupling::OuterContactEllipse &e, double load)
  {
    const double scale = std::cbrt(load);
    return {scale * e.semi_axis_rolling_per_newton_cube_root, scale * e.semi_axis_transverse_per_newton_cube_root,
            load};
  }
} // namespace

TEST_F(RacewayOperator, LoadFollowingRowIsTheProjectedHertzPatchOfTheLoad)
{
  // The row of a ball between the tabulated footprints, interpolated as the
  // run interpolates it (coupling::footprint_blend), against the row
  // projected for the exact Hertz ellipse of its load
  // (CraigBampton::project_load). The error is measured against what the
  // footprint changes: the exact row's difference from a point load's (the
  // ellipse of 10⁻⁹ of the largest load). 39 loads spread over the table,
  // with three, five and seven footprints.
  const Reduced                      &r       = reduced();
  const coupling::OuterContactEllipse ellipse = ellipse_6208();
  const auto                          n       = static_cast<Eigen::Index>(r.matrices.size());
  const unsigned int                  k       = 5; // off the mesh's symmetry lines
  const auto project = [&](const reduction::BallFootprint &footprint) {
    fem::StaticLoad load;
    load.ball_loads.push_back(
      reduction::unit_ball(reduction_testing::ring_6208_geometry(), 2.0 * M_PI * k / n_angles, footprint));
    const std::vector<double> g = r.cb.project_load(load);
    return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(g.data(), n));
  };
  double default_error = 0.0;
  for (const unsigned int count : {3u, 5u, 7u})
    {
      std::vector<reduction::BallFootprint> footprints;
      for (const double load : ellipse.footprint_loads(coupling::static_limit_peak_pressure, count))
        footprints.push_back(hertz_footprint(ellipse, load));
      const reduction::RacewayOperators following =
        reduction::raceway_operators(r.cb, r.model, reduction_testing::ring_6208_geometry(), n_angles, footprints);
      ASSERT_TRUE(following.follows_load());
      const Eigen::VectorXd point = project(footprints.front());
      double                worst = 0.0, worst_of_row = 0.0, worst_load = 0.0;
      for (int i = 1; i < 40; ++i)
        {
          const double                   load  = footprints.back().load * i / 40.0;
          const coupling::FootprintBlend blend = coupling::footprint_blend(following.footprint_loads(), load);
          Eigen::VectorXd                interpolated = Eigen::VectorXd::Zero(n);
          for (std::size_t m = 0; m < blend.count; ++m)
            interpolated += blend.weights[m] * Eigen::Map<const Eigen::VectorXd>(
                                                 following.approach.data() + ((blend.first + m) * n_angles + k) * n, n);
          const Eigen::VectorXd exact = project(following.footprint_at(load));
          const double          error = (interpolated - exact).cwiseAbs().maxCoeff();
          if (error / (exact - point).cwiseAbs().maxCoeff() > worst)
            {
              worst      = error / (exact - point).cwiseAbs().maxCoeff();
              worst_load = load;
            }
          worst_of_row = std::max(worst_of_row, error / exact.cwiseAbs().maxCoeff());
        }
      std::printf("%u footprints up to %.0f N: interpolated row against the exact ellipse's, worst %.2e of the "
                  "footprint's effect (at %.0f N), %.2e of the row\n",
                  count, footprints.back().load, worst, worst_load, worst_of_row);
      if (count == 7) // Model/Ball footprints' default
        default_error = worst;
    }
  // Measured 2.98e-4 with seven footprints (8.3e-3 with three, 1.03e-3 with
  // five); linear interpolation between five, in Q^{1/3} or Q^{2/3}, gave
  // 6.4e-2 and 7.1e-2.
  EXPECT_LT(default_error, 1e-3);
}
