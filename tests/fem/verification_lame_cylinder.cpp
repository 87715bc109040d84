// Thick-walled cylinder under internal pressure, plane strain (Lamé): bore
// displacement and hoop stress within 0.5 %, and the L2 displacement error
// converging at rate p+1 under refinement of the cross-section.
//
// Lamé solution (Timoshenko & Goodier, Theory of Elasticity, §28), inner
// radius a, outer b, internal pressure p, ε_zz = 0:
//   σ_rr = A - B/r²,  σ_θθ = A + B/r²,  A = p a²/(b² - a²),  B = p a² b²/(b² - a²)
//   u_r  = (1 + ν)/E · ((1 - 2ν) A r + B/r)
// Model: a quarter ring (symmetry planes x = 0 and y = 0) of one cell's
// thickness with u_z = 0 on both side faces, which is plane strain exactly.
#include "fem_test_environment.h"

#include <fretsim/fem/elastic_model.h>

#include <cmath>
#include <cstdio>

using namespace fretsim::fem;
using fretsim::fem_testing::relative_error;

namespace
{
  constexpr double a = 0.1, b = 0.2, width = 0.02; // [m]
  constexpr double E = 200e9, nu = 0.3, rho = 7800.0, p = 100e6;
  constexpr double A = p * a * a / (b * b - a * a), B = p * a * a * b * b / (b * b - a * a);

  double exact_u_r(double r) { return (1 + nu) / E * ((1 - 2 * nu) * A * r + B / r); }

  Vector3 exact_displacement(const Point3 &x)
  {
    const double r = std::hypot(x[0], x[1]), u = exact_u_r(r);
    return {u * x[0] / r, u * x[1] / r, 0.0};
  }

  struct Solution
  {
    CylindricalAverage bore;
    double             l2_error = 0.0;
    unsigned long      n_dofs   = 0;
  };

  Solution solve(unsigned int degree, unsigned int radial_cells, unsigned int circumferential_cells)
  {
    RingGeometry g;
    g.bore_radius  = a;
    g.outer_radius = b;
    g.width        = width;
    MeshDivisions d;
    d.radial_ring     = radial_cells;
    d.circumferential = circumferential_cells;
    d.axial           = 1;
    d.sector_angle    = 0.5 * M_PI;
    auto         mesh = std::make_shared<const Mesh>(Mesh::ring(g, d));
    ElasticModel model(mesh, {{MaterialId::ring, {E, nu, rho}}}, degree,
                       {{BoundaryId::side_faces, false, false, true},
                        {BoundaryId::sector_start, false, true, false},
                        {BoundaryId::sector_end, true, false, false}});
    StaticLoad load;
    load.pressures.push_back({BoundaryId::raceway, p});
    const DisplacementField u = model.solve_static(load);
    return {u.average_on_boundary(BoundaryId::raceway), u.l2_error(exact_displacement), model.n_dofs()};
  }
} // namespace

// Stresses are the FE gradients at the bore's face quadrature points, one
// order less accurate than displacements (the hoop stress error is 1.4 % at
// 4x8 cells, 0.4 % at 8x16): hence the finer mesh here.
TEST(LameCylinder, BoreDisplacementAndHoopStress)
{
  const Solution s          = solve(2, 16, 32);
  const double   hoop_exact = p * (b * b + a * a) / (b * b - a * a);
  std::printf("Q2, 16x32 cells, %lu DoFs: u_r(a) = %.6e m (exact %.6e, error %.2e), "
              "σ_θθ(a) = %.6e Pa (exact %.6e, error %.2e), σ_rr(a) = %.6e Pa\n",
              s.n_dofs, s.bore.u_r, exact_u_r(a), relative_error(s.bore.u_r, exact_u_r(a)), s.bore.s_tt, hoop_exact,
              relative_error(s.bore.s_tt, hoop_exact), s.bore.s_rr);
  EXPECT_LT(relative_error(s.bore.u_r, exact_u_r(a)), 0.005);
  EXPECT_LT(relative_error(s.bore.s_tt, hoop_exact), 0.005);
  EXPECT_LT(relative_error(-s.bore.s_rr, p), 0.02); // the traction, from gradients: one order less accurate
  EXPECT_LT(std::abs(s.bore.u_theta), 1e-6 * exact_u_r(a));
}

TEST(LameCylinder, L2ErrorConvergesAtRatePPlusOne)
{
  for (const unsigned int degree : {1u, 2u})
    {
      std::vector<double> errors, h;
      const unsigned int  levels = degree == 1 ? 4 : 3;
      for (unsigned int level = 0; level < levels; ++level)
        {
          const unsigned int n = 2u << level; // radial cells; twice as many around the quarter
          const Solution     s = solve(degree, n, 2 * n);
          errors.push_back(s.l2_error);
          h.push_back(1.0 / n);
          std::printf("Q%u  %2u x %2u cells  %6lu DoFs  L2 error %.4e", degree, n, 2 * n, s.n_dofs, s.l2_error);
          if (level > 0)
            std::printf("  rate %.3f", std::log2(errors[level - 1] / errors[level]));
          std::printf("\n");
        }
      // Asymptotic rate from the two finest meshes; the exact chart and a
      // mapping of the element's degree keep the geometry error at O(h^{p+1}).
      const double rate = std::log2(errors[levels - 2] / errors[levels - 1]);
      EXPECT_NEAR(rate, degree + 1.0, 0.1) << "Q" << degree;
    }
}
