// Free thin ring: the lowest in-plane flexural frequencies n = 2, 3, 4 against
// the inextensional thin-ring formula (Hoppe 1871; as tabulated for in-plane
// ring flexure in Blevins, Formulas for Natural Frequency and Mode Shape):
//   ω_n = sqrt(E I / (ρ A R⁴)) · n (n² - 1) / sqrt(n² + 1),
// R the centroid radius, I = b h³/12 for a radial thickness h and width b.
// With h/R = 0.04 shear and rotary inertia lower the frequencies by ~ (h/R)² n²
// ≈ 0.3 % at n = 4, below the 2 % tolerance. The 6 rigid-body modes of the
// free ring must come out at zero and be set apart.
#include "fem_test_environment.h"

#include <fretsim/fem/elastic_model.h>

#include <cmath>
#include <cstdio>

using namespace fretsim::fem;
using fretsim::fem_testing::relative_error;

TEST(RingModes, InPlaneFlexuralFrequenciesOfAThinRing)
{
  const double   R = 0.1, h = 0.004, b = 0.004; // centroid radius, radial thickness, width [m]
  const Material steel{200e9, 0.3, 7800.0};
  RingGeometry   g;
  g.bore_radius  = R - 0.5 * h;
  g.outer_radius = R + 0.5 * h;
  g.width        = b;
  MeshDivisions d;
  d.circumferential = 64;
  d.radial_ring     = 1;
  d.axial           = 1;
  auto         mesh = std::make_shared<const Mesh>(Mesh::ring(g, d));
  ElasticModel model(mesh, {{MaterialId::ring, steel}}, 2);

  ModalSettings settings;
  settings.n_modes          = 14;
  const ModalSolution modes = model.solve_modes(settings);
  EXPECT_EQ(modes.n_rigid_body_modes, 6u);
  ASSERT_EQ(modes.frequencies_hz.size(), 14u);

  // In-plane modes have (almost) no axial motion; the out-of-plane ones of a
  // square section sit within a few % of them, so classify, don't count.
  std::vector<double> in_plane;
  for (unsigned int k = 0; k < modes.frequencies_hz.size(); ++k)
    {
      const Vector3 share = modes.shapes[k].mass_fractions();
      std::printf("mode %2u  %9.3f Hz  z share %.2e\n", k, modes.frequencies_hz[k], share[2]);
      if (share[2] < 0.01)
        in_plane.push_back(modes.frequencies_hz[k]);
    }
  std::printf("%lu DoFs, modal solve %.2f s\n", model.n_dofs(), modes.seconds);

  const double base = std::sqrt(steel.youngs_modulus * b * h * h * h / 12.0 / (steel.density * b * h * std::pow(R, 4)));
  ASSERT_GE(in_plane.size(), 6u);
  for (unsigned int n = 2; n <= 4; ++n)
    {
      const double exact = base * n * (n * n - 1.0) / std::sqrt(n * n + 1.0) / (2.0 * M_PI);
      // Each n is a degenerate pair (cos nθ and sin nθ shapes).
      const double f1 = in_plane[2 * (n - 2)], f2 = in_plane[2 * (n - 2) + 1];
      std::printf("n = %u: FE %.3f / %.3f Hz, thin ring %.3f Hz, error %.2e\n", n, f1, f2, exact,
                  relative_error(0.5 * (f1 + f2), exact));
      EXPECT_LT(relative_error(f1, exact), 0.02) << "n = " << n;
      EXPECT_LT(relative_error(f2, exact), 0.02) << "n = " << n;
      EXPECT_LT(relative_error(f1, f2), 1e-6) << "n = " << n << ": the pair must be degenerate";
    }
}
