// The shipped ring-in-housing Gmsh mesh (meshes/bearing_6208_ring_in_housing.geo)
// read through Mesh::from_gmsh: cell counts, shared interface nodes (bonded,
// conforming), boundary ids, and volumes and areas against the parametric
// geometry the .geo states.
#include "fem_test_environment.h"

#include <fretsim/fem/mesh.h>

#include <array>
#include <cmath>
#include <vector>

using namespace fretsim::fem;
using fretsim::fem_testing::relative_error;

namespace
{
  // meshes/bearing_6208_ring_in_housing.geo: its dimensions, repeated here.
  RingGeometry ring_6208()
  {
    RingGeometry g;
    g.bore_radius          = 0.0341;
    g.outer_radius         = 0.040;
    g.width                = 0.018;
    g.groove_radius        = 0.53 * 0.0127;
    g.groove_bottom_radius = (0.060 + 0.0127) / 2;
    return g;
  }
  const double housing_outer_radius = 0.060;

  // Cells of the .geo: around, through ring / housing walls, groove, lands.
  const unsigned int n_around = 64, n_ring = 3, n_housing = 4, n_groove = 6, n_land = 2;

  unsigned int id(BoundaryId b) { return static_cast<unsigned int>(b); }
  unsigned int id(MaterialId m) { return static_cast<unsigned int>(m); }

  /// The ring's cross-section as the .geo meshes it, in the (r, z) plane:
  /// the groove arc (centre (rc, 0), radius rg, from the land at z = zs to
  /// z = -zs) is a chain of n_groove chords between points equally spaced in
  /// angle (a transfinite curve on a circle), the rest is straight.
  std::vector<std::array<double, 2>> ring_section(const RingGeometry &g)
  {
    const double zs = g.groove_half_width(), rg = g.groove_radius, rc = g.groove_bottom_radius - rg;
    const double alpha = std::atan2(zs, g.bore_radius - rc);
    std::vector<std::array<double, 2>> polygon{{g.bore_radius, -g.width / 2}, {g.outer_radius, -g.width / 2},
                                               {g.outer_radius, g.width / 2}, {g.bore_radius, g.width / 2}};
    for (unsigned int k = 0; k <= n_groove; ++k)
      {
        const double t = alpha - 2.0 * alpha * k / n_groove;
        polygon.push_back({rc + rg * std::cos(t), rg * std::sin(t)});
      }
    return polygon;
  }

  /// Volume of the polygon revolved about the z axis: 2π ∫ r dA (Pappus),
  /// with ∫ r dA = Σ (r_i + r_j)(r_i z_j - r_j z_i)/6 over the edges.
  double revolved_volume(const std::vector<std::array<double, 2>> &polygon)
  {
    double moment = 0.0;
    for (std::size_t i = 0; i < polygon.size(); ++i)
      {
        const auto &p = polygon[i], &q = polygon[(i + 1) % polygon.size()];
        moment += (p[0] + q[0]) * (p[0] * q[1] - q[0] * p[1]) / 6.0;
      }
    return 2.0 * M_PI * std::abs(moment);
  }

  /// Area swept by the chords of the groove (the last n_groove edges): a
  /// straight segment revolved is a conical band, π (r_i + r_j) L.
  double revolved_chords_area(const std::vector<std::array<double, 2>> &polygon)
  {
    double area = 0.0;
    for (std::size_t i = polygon.size() - n_groove - 1; i + 1 < polygon.size(); ++i)
      {
        const auto &p = polygon[i], &q = polygon[i + 1];
        area += M_PI * (p[0] + q[0]) * std::hypot(q[0] - p[0], q[1] - p[1]);
      }
    return area;
  }
} // namespace

TEST(GmshMesh, ShippedBearing6208RingInHousing)
{
  const RingGeometry g = ring_6208();
  const Mesh         mesh =
    Mesh::from_gmsh(FRETSIM_SOURCE_DIR "/meshes/bearing_6208_ring_in_housing.msh",
                    {BoundaryId::raceway, BoundaryId::ring_lands, BoundaryId::housing_outer, BoundaryId::side_faces},
                    Ranks::this_one);
  // Cubic mapping: the cylindrical manifold of Gmsh meshes makes every
  // circle about the axis exact (to ~1e-8); only the groove arc stays a chain
  // of straight chords in the (r, z) plane.
  const MeshSummary s = mesh.summary(3);

  const unsigned int n_axial = n_groove + 2 * n_land;
  EXPECT_EQ(s.material_cells.at(id(MaterialId::ring)), n_around * n_ring * n_axial);
  EXPECT_EQ(s.material_cells.at(id(MaterialId::housing)), n_around * n_housing * n_axial);
  // Bonded: ring outer surface and housing bore are interior faces, so no
  // face carries their ids (from_gmsh rejects untagged boundary faces, so a
  // non-conforming interface would already have thrown), and both bodies
  // share the interface nodes: Q1 DoFs = 3 × the nodes of one conforming mesh.
  EXPECT_EQ(s.boundary_faces.count(id(BoundaryId::ring_outer)), 0u);
  EXPECT_EQ(s.boundary_faces.count(id(BoundaryId::housing_bore)), 0u);
  EXPECT_EQ(s.boundary_faces.size(), 4u);
  const unsigned long nodes_per_section = (n_ring + n_housing + 1) * (n_axial + 1);
  EXPECT_EQ(mesh.n_dofs(1), 3ul * n_around * nodes_per_section);

  // Exact in the cubic mapping (cylinders and planes only): 1e-7, the
  // mapping's geometry error (unit_mesh.cpp measures ~1e-7 for 24 cells around).
  const double Rh = housing_outer_radius, Ro = g.outer_radius, Rs = g.bore_radius, B = g.width;
  const double zs = g.groove_half_width();
  EXPECT_LT(relative_error(s.material_volume.at(id(MaterialId::housing)), M_PI * (Rh * Rh - Ro * Ro) * B), 1e-7);
  EXPECT_LT(relative_error(s.boundary_area.at(id(BoundaryId::housing_outer)), 2 * M_PI * Rh * B), 1e-7);
  EXPECT_LT(relative_error(s.boundary_area.at(id(BoundaryId::side_faces)), 2 * M_PI * (Rh * Rh - Rs * Rs)), 1e-7);
  EXPECT_LT(relative_error(s.boundary_area.at(id(BoundaryId::ring_lands)), 2 * 2 * M_PI * Rs * (B / 2 - zs)), 1e-7);
  // The groove arc stays the chain of chords of the .geo's cross-section
  // (the cylindrical manifold interpolates linearly in r and z), so the ring
  // is that polygon revolved, exactly; the true arc would give 4.4e-3 more
  // raceway area and 5.2e-3 less ring volume.
  const auto section = ring_section(g);
  EXPECT_LT(relative_error(s.boundary_area.at(id(BoundaryId::raceway)), revolved_chords_area(section)), 1e-7);
  EXPECT_LT(relative_error(s.material_volume.at(id(MaterialId::ring)), revolved_volume(section)), 1e-7);
}
