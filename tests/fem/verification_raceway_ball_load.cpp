// A ring under a ball load on its raceway, against a reference and under
// refinement. The quantity is the ring's outer-surface integral of the radial
// displacement, Q = ∫ u_r dS: what a housing feels of the ball, and smooth
// enough to converge (the displacement under the ball itself does not: the
// patch is far smaller than the cells).
//
// Reference (plain bore): by Betti's theorem, with state B = unit pressure on
// the outer surface, ∫ u_r^A dS = -Σ_q F_q · u^B(x_q). In plane strain with
// symmetry planes, B is Lamé's solution exactly (radial, u_z = 0, so the
// supports do no work in either state); at the bore r = a of a ring (a, b)
//   u_r^B(a) = -2 a b² (1 - ν²) / (E (b² - a²))  (Timoshenko & Goodier §28),
// and every patch force F_q is radial there: Q = Σ|F_q| · 2 a b²(1 - ν²)/(E(b² - a²)).
//
// Grooved ring (the 6208): no closed form; Q1 on three meshes converges at the
// rate of the B-state displacement at the load points (p + 1 = 2) and its
// Richardson extrapolation agrees with Q2 on the finer mesh.
#include "fem_test_environment.h"

#include <fretsim/fem/surface_point_map.h>

#include <cmath>
#include <cstdio>

using namespace fretsim::fem;
using fretsim::fem_testing::relative_error;

namespace
{
  const Material steel{208e9, 0.3, 7850.0};

  RingGeometry ring(const bool grooved)
  {
    RingGeometry g;
    g.bore_radius  = 0.0341;
    g.outer_radius = 0.040;
    g.width        = 0.018;
    if (grooved)
      {
        g.groove_radius        = 0.006731;
        g.groove_bottom_radius = 0.03635;
      }
    return g;
  }

  RacewayBallLoad ball(const bool grooved)
  {
    RacewayBallLoad b;
    b.ring                      = ring(grooved);
    b.angle                     = 0.25 * M_PI;
    b.contact_angle             = grooved ? 0.2 : 0.0;
    b.force                     = 5000.0;
    b.semi_axis_circumferential = 0.3e-3;
    b.semi_axis_transverse      = 2.0e-3;
    return b;
  }

  /// ∫ u_r dS over the outer surface of the quarter ring [m³].
  double outer_integral(const bool grooved, const unsigned int degree, const unsigned int refinements)
  {
    MeshDivisions d;
    d.radial_ring     = 2;
    d.circumferential = 12;
    d.axial           = grooved ? 4 : 6;
    d.axial_land      = 1;
    d.sector_angle    = 0.5 * M_PI;
    auto mesh         = std::make_shared<Mesh>(Mesh::ring(ring(grooved), d));
    mesh->refine_globally(refinements);
    ElasticModel model(mesh, {{MaterialId::ring, steel}}, degree,
                       {{BoundaryId::side_faces, false, false, true},
                        {BoundaryId::sector_start, false, true, false},
                        {BoundaryId::sector_end, true, false, false}});
    StaticLoad load;
    load.ball_loads.push_back(ball(grooved));
    const CylindricalAverage outer = model.solve_static(load).average_on_boundary(BoundaryId::ring_outer);
    std::printf("%s Q%u, %u refinements, %7lu DoFs: Q = %.9e m^3 (assembly %.2f s, solve %.2f s)\n",
                grooved ? "groove" : "plain ", degree, refinements, model.n_dofs(), outer.u_r * outer.area,
                model.timings().assemble_stiffness, model.timings().solve);
    return outer.u_r * outer.area;
  }
} // namespace

TEST(RacewayBallLoad, PlainBoreMatchesLameByReciprocity)
{
  const double a = 0.0341, b = 0.040, E = steel.youngs_modulus, nu = steel.poisson_ratio;
  double       radial_sum = 0.0;
  for (const Vector3 &f : raceway_patch_forces(ball(false)).forces)
    radial_sum += std::hypot(f[0], f[1], f[2]);
  const double reference = radial_sum * 2.0 * a * b * b * (1 - nu * nu) / (E * (b * b - a * a));

  std::vector<double> errors;
  for (unsigned int level = 0; level < 3; ++level)
    errors.push_back(relative_error(outer_integral(false, 1, level), reference));
  const double q2 = relative_error(outer_integral(false, 2, 1), reference);
  std::printf("reference %.9e m^3 (sum |F_q| = %.6f N); Q1 errors %.3e %.3e %.3e, Q2 error %.3e\n", reference,
              radial_sum, errors[0], errors[1], errors[2], q2);
  const double rate = std::log2(errors[1] / errors[2]);
  std::printf("Q1 rate %.2f (expected 2: the B state's displacement, O(h^(p+1)))\n", rate);
  EXPECT_NEAR(rate, 2.0, 0.3);
  EXPECT_LT(errors[2], 2e-3);
  EXPECT_LT(q2, 1e-3);
}

TEST(RacewayBallLoad, GroovedRingConvergesUnderRefinement)
{
  std::vector<double> q1;
  for (unsigned int level = 0; level < 3; ++level)
    q1.push_back(outer_integral(true, 1, level));
  const double q2       = outer_integral(true, 2, 1);
  const double rate     = std::log2((q1[1] - q1[0]) / (q1[2] - q1[1]));
  const double richardson = q1[2] + (q1[2] - q1[1]) / (std::pow(2.0, rate) - 1.0);
  std::printf("groove: Q1 rate %.2f, extrapolated %.9e m^3, Q2 %.9e m^3, difference %.3e\n", rate, richardson, q2,
              relative_error(richardson, q2));
  EXPECT_NEAR(rate, 2.0, 0.3);
  EXPECT_LT(relative_error(richardson, q2), 2e-3);
}
