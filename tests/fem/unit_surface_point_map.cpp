// SurfacePointMap and ball loads on the raceway groove: conservation (the
// nodal forces carry the ball load exactly), consistency (u_p = H u, and the
// work Σ F_p·u_p equals fᵀu), reciprocity between two balls, exact
// interpolation of a linear field, and the same numbers on one and two ranks
// (ctest runs this program again as fem.mpi_np2.unit_surface_point_map).
#include "fem_test_environment.h"

#include <fretsim/fem/surface_point_map.h>

#include <cmath>
#include <cstdio>

using namespace fretsim::fem;
using fretsim::fem_testing::relative_error;

namespace
{
  const Material steel{208e9, 0.3, 7850.0};

  /// The 6208 outer ring (ring_housing.cpp defaults), a quarter of it.
  RingGeometry ring_6208()
  {
    RingGeometry g;
    g.bore_radius          = 0.0341;
    g.outer_radius         = 0.040;
    g.width                = 0.018;
    g.groove_radius        = 0.006731;
    g.groove_bottom_radius = 0.03635;
    return g;
  }

  /// Quarter ring, plane strain (side faces u_z = 0) and symmetry planes:
  /// no rigid-body motion left.
  ElasticModel quarter_ring(const unsigned int degree, const Ranks ranks = Ranks::all)
  {
    MeshDivisions d;
    d.radial_ring     = 2;
    d.circumferential = 12;
    d.axial           = 4;
    d.axial_land      = 1;
    d.sector_angle    = 0.5 * M_PI;
    return ElasticModel(std::make_shared<const Mesh>(Mesh::ring(ring_6208(), d, ranks)),
                        {{MaterialId::ring, steel}}, degree,
                        {{BoundaryId::side_faces, false, false, true},
                         {BoundaryId::sector_start, false, true, false},
                         {BoundaryId::sector_end, true, false, false}});
  }

  /// A 6208 ball (D_w = 12.7 mm) under 5 kN: Hertz semi-axes about 0.3 mm
  /// along the rolling direction and 2 mm across the groove.
  RacewayBallLoad ball(const double angle, const double contact_angle)
  {
    RacewayBallLoad b;
    b.ring                      = ring_6208();
    b.angle                     = angle;
    b.contact_angle             = contact_angle;
    b.force                     = 5000.0;
    b.semi_axis_circumferential = 0.3e-3;
    b.semi_axis_transverse      = 2.0e-3;
    return b;
  }

  double dot(const Vector3 &a, const Vector3 &b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

  /// Σ_p F_p · u_p.
  double work(const std::vector<Vector3> &forces, const std::vector<Vector3> &u)
  {
    double w = 0.0;
    for (std::size_t k = 0; k < forces.size(); ++k)
      w += dot(forces[k], u[k]);
    return w;
  }
} // namespace

TEST(SurfacePointMap, BallLoadIsConservedExactly)
{
  const RacewayBallLoad b     = ball(0.25 * M_PI, 0.2);
  const PatchForces     patch = raceway_patch_forces(b);
  const Vector3         n     = raceway_contact_normal(b.angle, b.contact_angle);
  Vector3               total{0.0, 0.0, 0.0};
  for (const Vector3 &f : patch.forces)
    for (unsigned int c = 0; c < 3; ++c)
      total[c] += f[c];
  for (const unsigned int degree : {1u, 2u})
    {
      ElasticModel          model = quarter_ring(degree);
      const SurfacePointMap map(model, patch.points, BoundaryId::raceway);
      const Vector3         nodal = map.nodal_force_sum(patch.forces);
      std::printf("Q%u: %zu patch points, nodal force (%.15e, %.15e, %.15e) N, Q n = (%.15e, %.15e, %.15e) N\n",
                  degree, map.n_points(), nodal[0], nodal[1], nodal[2], b.force * n[0], b.force * n[1],
                  b.force * n[2]);
      // Round-off only: the quadrature's shares sum to Q, every point force is
      // along n, and the shape functions sum to one at every point.
      for (unsigned int c = 0; c < 3; ++c)
        {
          EXPECT_NEAR(total[c], b.force * n[c], 1e-12 * b.force) << "component " << c;
          EXPECT_NEAR(nodal[c], b.force * n[c], 1e-12 * b.force) << "component " << c;
        }
      // The points move onto the discrete surface, no farther than it lies
      // from the exact groove: at most the sagitta of a Q1 cell's chord across
      // the groove arc, r_g (1 - cos(Δψ/2)) = 1.5e-4 m for Δψ = 0.42 rad (Q2 is
      // closer, and a point more than a quarter of a cell in is refused).
      double moved = 0.0;
      for (std::size_t k = 0; k < patch.points.size(); ++k)
        moved = std::max(moved, std::hypot(map.points()[k][0] - patch.points[k][0],
                                           map.points()[k][1] - patch.points[k][1],
                                           map.points()[k][2] - patch.points[k][2]));
      std::printf("Q%u: points moved onto the discrete surface by up to %.3e m\n", degree, moved);
      EXPECT_LT(moved, 1.5e-4);
    }
}

TEST(SurfacePointMap, WorkOfPointForcesIsTwiceTheStrainEnergy)
{
  for (const unsigned int degree : {1u, 2u})
    {
      ElasticModel          model = quarter_ring(degree);
      const RacewayBallLoad b     = ball(0.25 * M_PI, 0.2);
      const PatchForces     patch = raceway_patch_forces(b);
      const SurfacePointMap map(model, patch.points, BoundaryId::raceway);

      // The same load through StaticLoad::ball_loads and through the map.
      StaticLoad by_ball, by_map;
      by_ball.ball_loads.push_back(b);
      by_map.point_forces.push_back({&map, patch.forces});
      const DisplacementField u       = model.solve_static(by_ball);
      const DisplacementField u_map   = model.solve_static(by_map);
      const double            w       = work(patch.forces, map.interpolate(u));
      const double            energy  = u.strain_energy();
      std::printf("Q%u: %lu DoFs, work %.15e J, 2U %.15e J (by map %.15e J)\n", degree, model.n_dofs(), w,
                  2.0 * energy, 2.0 * u_map.strain_energy());
      // Σ F·(H u) = (Hᵀ F)ᵀ u = fᵀ u = uᵀ K u: exact up to the direct
      // solver's round-off (MUMPS, ~1e-13 here).
      EXPECT_LT(relative_error(w, 2.0 * energy), 1e-10);
      EXPECT_LT(relative_error(u_map.strain_energy(), energy), 1e-12);
      EXPECT_GT(w, 0.0);
    }
}

TEST(SurfacePointMap, TwoBallsAreReciprocal)
{
  // Betti: the work of ball A's forces on the displacements ball B causes
  // equals that of B's forces on A's: K symmetric and the same H both ways.
  ElasticModel          model = quarter_ring(2);
  const RacewayBallLoad a = ball(0.25 * M_PI - 0.3, 0.2), b = ball(0.25 * M_PI + 0.25, -0.1);
  const PatchForces     pa = raceway_patch_forces(a), pb = raceway_patch_forces(b);
  const SurfacePointMap map_a(model, pa.points, BoundaryId::raceway), map_b(model, pb.points, BoundaryId::raceway);
  StaticLoad            la, lb;
  la.ball_loads.push_back(a);
  lb.ball_loads.push_back(b);
  const DisplacementField ua = model.solve_static(la), ub = model.solve_static(lb);
  const double            w_ab = work(pa.forces, map_a.interpolate(ub)), w_ba = work(pb.forces, map_b.interpolate(ua));
  std::printf("F_A . u_B(A) = %.15e J, F_B . u_A(B) = %.15e J\n", w_ab, w_ba);
  EXPECT_LT(relative_error(w_ab, w_ba), 1e-10); // direct solver round-off
  EXPECT_GT(std::abs(w_ab), 1e-3 * 2.0 * ua.strain_energy()); // the balls do feel each other
}

TEST(SurfacePointMap, InterpolatesALinearFieldExactly)
{
  // A free in-plane expansion e (x, y, 0) satisfies every support of the
  // quarter ring, so it is the solution; isoparametric elements hold linear
  // fields exactly, and so must H at any point.
  const double e = 1e-4;
  for (const unsigned int degree : {1u, 2u})
    {
      ElasticModel      model = quarter_ring(degree);
      const PatchForces patch = raceway_patch_forces(ball(0.25 * M_PI, 0.3));
      std::vector<Point3> points = patch.points;
      points.push_back(raceway_contact_point(ring_6208(), 0.1, -0.4));
      const SurfacePointMap map(model, points, BoundaryId::raceway);
      StaticLoad            load;
      load.expansions.push_back({MaterialId::ring, e});
      const std::vector<Vector3> u = map.interpolate(model.solve_static(load));
      double                     worst = 0.0;
      for (std::size_t k = 0; k < u.size(); ++k)
        {
          const Point3 &x = map.points()[k];
          worst = std::max({worst, std::abs(u[k][0] - e * x[0]), std::abs(u[k][1] - e * x[1]), std::abs(u[k][2])});
        }
      std::printf("Q%u: worst |u - e x| = %.3e m (e R = %.3e m)\n", degree, worst, e * 0.036);
      EXPECT_LT(worst, 1e-10 * e * 0.036); // round-off of the direct solve
    }
}

TEST(SurfacePointMap, RejectsPointsOffTheBoundary)
{
  ElasticModel model = quarter_ring(1);
  const Point3 in_wall{0.037 * std::cos(0.5), 0.037 * std::sin(0.5), 0.0};
  const Point3 on_land{0.0341 * std::cos(0.5), 0.0341 * std::sin(0.5), 0.0085};
  const Point3 on_raceway = raceway_contact_point(ring_6208(), 0.5, 0.0);
  EXPECT_THROW(SurfacePointMap(model, {on_raceway, in_wall}, BoundaryId::raceway), std::invalid_argument);
  EXPECT_THROW(SurfacePointMap(model, {on_land}, BoundaryId::raceway), std::invalid_argument);
  EXPECT_NO_THROW(SurfacePointMap(model, {on_land}, BoundaryId::ring_lands));
  // A contact ellipse that runs over the groove edge (at 0.84 rad) is refused.
  EXPECT_THROW(raceway_patch_forces(ball(0.5, 0.7)), std::invalid_argument);
}

TEST(SurfacePointMap, SameNumbersOnOneAndTwoRanks)
{
  // Under mpiexec -np 2: the model distributed over both ranks against the
  // same model on each rank alone. Both solve directly (MUMPS), so they agree
  // to its round-off.
  std::vector<std::vector<Vector3>> results;
  for (const Ranks ranks : {Ranks::all, Ranks::this_one})
    {
      ElasticModel          model = quarter_ring(2, ranks);
      const RacewayBallLoad b     = ball(0.25 * M_PI + 0.1, 0.15);
      const PatchForces     patch = raceway_patch_forces(b);
      const SurfacePointMap map(model, patch.points, BoundaryId::raceway);
      StaticLoad            load;
      load.ball_loads.push_back(b);
      results.push_back(map.interpolate(model.solve_static(load)));
    }
  double worst = 0.0, scale = 0.0;
  for (std::size_t k = 0; k < results[0].size(); ++k)
    for (unsigned int c = 0; c < 3; ++c)
      {
        worst = std::max(worst, std::abs(results[0][k][c] - results[1][k][c]));
        scale = std::max(scale, std::abs(results[1][k][c]));
      }
  std::printf("rank %u/%u: worst difference %.3e m of %.3e m\n", ParallelEnvironment::rank(),
              ParallelEnvironment::n_ranks(), worst, scale);
  EXPECT_GT(scale, 0.0);
  EXPECT_LT(worst, 1e-10 * scale);
}
