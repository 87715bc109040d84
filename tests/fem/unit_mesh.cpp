// Parametric meshes: exact volumes and areas of ring, groove and housing, the
// named boundary ids, refinement that follows the groove arc, and Gmsh files
// with missing ids or inverted cells rejected with a clear message.
#include "fem_test_environment.h"

#include <fretsim/fem/mesh.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace fretsim::fem;
using fretsim::fem_testing::relative_error;

namespace
{
  // Exact values for the ring of the paper's bearing-like test ring (lengths in m).
  RingGeometry grooved_ring()
  {
    RingGeometry g;
    g.bore_radius          = 0.034;
    g.outer_radius         = 0.040;
    g.width                = 0.018;
    g.groove_radius        = 0.00673;
    g.groove_bottom_radius = 0.03635;
    return g;
  }

  double raceway_area(const RingGeometry &g)
  {
    const double zs = g.groove_half_width(), rc = g.groove_bottom_radius - g.groove_radius, rg = g.groove_radius;
    return 2.0 * M_PI * rg * (2.0 * rc * std::asin(zs / rg) + 2.0 * zs);
  }

  double ring_volume(const RingGeometry &g)
  {
    const double zs = g.groove_half_width(), rc = g.groove_bottom_radius - g.groove_radius, rg = g.groove_radius;
    const double r2_groove = 2.0 * zs * (rc * rc + rg * rg) - 2.0 * zs * zs * zs / 3.0 +
                             2.0 * rc * (zs * std::sqrt(rg * rg - zs * zs) + rg * rg * std::asin(zs / rg));
    return M_PI * (g.outer_radius * g.outer_radius * g.width - g.bore_radius * g.bore_radius * (g.width - 2.0 * zs) -
                   r2_groove);
  }

  unsigned int id(BoundaryId b) { return static_cast<unsigned int>(b); }
} // namespace

TEST(Mesh, PlainRingHasExactVolumeAndItsBoundaryIds)
{
  RingGeometry g;
  g.bore_radius  = 0.03;
  g.outer_radius = 0.04;
  g.width        = 0.02;
  MeshDivisions d;
  d.circumferential = 24;
  const Mesh        mesh = Mesh::ring(g, d);
  const MeshSummary s    = mesh.summary();
  EXPECT_EQ(s.n_cells, 24u * 2u * 4u);
  // Cubic mapping on the exact chart: geometry error ~ (2π/24)^4 ≈ 5e-3 of a
  // cell's sagitta, i.e. ~1e-7 relative.
  EXPECT_LT(relative_error(s.volume, M_PI * (0.04 * 0.04 - 0.03 * 0.03) * 0.02), 1e-6);
  EXPECT_LT(relative_error(s.boundary_area.at(id(BoundaryId::raceway)), 2 * M_PI * 0.03 * 0.02), 1e-6);
  EXPECT_LT(relative_error(s.boundary_area.at(id(BoundaryId::ring_outer)), 2 * M_PI * 0.04 * 0.02), 1e-6);
  EXPECT_LT(relative_error(s.boundary_area.at(id(BoundaryId::side_faces)), 2 * M_PI * (0.04 * 0.04 - 0.03 * 0.03)),
            1e-6);
  EXPECT_EQ(s.boundary_faces.size(), 3u); // raceway, outer, sides: nothing else, nothing untagged
  EXPECT_EQ(s.material_cells.at(static_cast<unsigned int>(MaterialId::ring)), s.n_cells);
}

TEST(Mesh, GroovedRingFollowsTheArcUnderRefinement)
{
  const RingGeometry g = grooved_ring();
  MeshDivisions      d;
  d.circumferential = 16;
  d.radial_ring     = 1;
  d.axial           = 2;
  d.axial_land      = 1;
  Mesh mesh = Mesh::ring(g, d);

  // Cubic mapping, but only 2 cells across the 97° groove arc: ~4e-5.
  const MeshSummary exact = mesh.summary(3);
  EXPECT_LT(relative_error(exact.volume, ring_volume(g)), 1e-4);
  EXPECT_LT(relative_error(exact.boundary_area.at(id(BoundaryId::raceway)), raceway_area(g)), 1e-4);
  EXPECT_LT(relative_error(exact.boundary_area.at(id(BoundaryId::ring_lands)),
                           2 * M_PI * g.bore_radius * (g.width - 2 * g.groove_half_width())),
            1e-5);

  // With straight-edged cells (mapping of degree 1) only the vertices carry
  // the geometry. If refinement put the new vertices on the arc, the raceway
  // area error falls like h² (×1/4 per refinement); on chords it would stall.
  std::vector<double> errors;
  for (unsigned int level = 0; level < 3; ++level)
    {
      errors.push_back(relative_error(mesh.summary(1).boundary_area.at(id(BoundaryId::raceway)), raceway_area(g)));
      mesh.refine_globally();
    }
  for (unsigned int k = 1; k < errors.size(); ++k)
    {
      const double rate = std::log2(errors[k - 1] / errors[k]);
      EXPECT_NEAR(rate, 2.0, 0.15) << "level " << k << " errors " << errors[k - 1] << " → " << errors[k];
    }
}

TEST(Mesh, RingInHousingAndSectors)
{
  const RingGeometry g = grooved_ring();
  HousingGeometry    h{g.outer_radius, 0.06, g.width};
  MeshDivisions      d;
  d.circumferential = 6;
  d.sector_angle    = 0.5 * M_PI;
  const MeshSummary s = Mesh::ring_in_housing(g, h, d).summary();
  EXPECT_LT(relative_error(s.material_volume.at(1), 0.25 * ring_volume(g)), 1e-5);
  EXPECT_LT(relative_error(s.material_volume.at(2), 0.25 * M_PI * (0.06 * 0.06 - 0.04 * 0.04) * g.width), 1e-6);
  // The bonded interface is interior: no ring_outer or housing_bore faces.
  for (const auto b : {BoundaryId::raceway, BoundaryId::ring_lands, BoundaryId::housing_outer,
                       BoundaryId::side_faces, BoundaryId::sector_start, BoundaryId::sector_end})
    EXPECT_EQ(s.boundary_faces.count(id(b)), 1u) << to_string(b);
  EXPECT_EQ(s.boundary_faces.count(id(BoundaryId::ring_outer)), 0u);
  EXPECT_EQ(s.boundary_faces.count(id(BoundaryId::housing_bore)), 0u);
  // A cut face: the ring cross-section and the housing annulus section.
  const double cut = (0.06 - g.bore_radius) * g.width - (s.boundary_area.at(id(BoundaryId::sector_start)));
  EXPECT_GT(cut, 0.0); // the groove takes a little out of the rectangle
  EXPECT_LT(relative_error(s.boundary_area.at(id(BoundaryId::sector_start)),
                           s.boundary_area.at(id(BoundaryId::sector_end))),
            1e-10);

  const MeshSummary hs = Mesh::housing(h, MeshDivisions{}).summary();
  EXPECT_LT(relative_error(hs.boundary_area.at(id(BoundaryId::housing_bore)), 2 * M_PI * 0.04 * g.width), 1e-6);
}

TEST(Mesh, BadParametersAreRejected)
{
  RingGeometry g = grooved_ring();
  g.groove_radius = 0.001; // shallower than the groove depth: the arc cannot reach the lands
  EXPECT_THROW(Mesh::ring(g, MeshDivisions{}), std::invalid_argument);
  MeshDivisions d;
  d.circumferential = 2;
  EXPECT_THROW(Mesh::ring(grooved_ring(), d), std::invalid_argument);
}

namespace
{
  // One unit cube as a Gmsh 2.2 file: 8 nodes, 6 tagged quadrilaterals
  // (physical tags given), one hexahedron with physical volume 1.
  std::string one_hex_msh(const std::vector<unsigned int> &face_tags, const std::string &hex_nodes)
  {
    std::string s = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8\n"
                    "1 1 0 0\n2 2 0 0\n3 2 1 0\n4 1 1 0\n5 1 0 1\n6 2 0 1\n7 2 1 1\n8 1 1 1\n$EndNodes\n$Elements\n";
    const char *faces[6] = {"1 4 3 2", "5 6 7 8", "1 2 6 5", "2 3 7 6", "3 4 8 7", "4 1 5 8"};
    s += std::to_string(7) + "\n";
    for (unsigned int f = 0; f < 6; ++f)
      s += std::to_string(f + 1) + " 3 2 " + std::to_string(face_tags[f]) + " " + std::to_string(f + 1) + " " +
           faces[f] + "\n";
    s += "7 5 2 1 1 " + hex_nodes + "\n$EndElements\n";
    return s;
  }

  std::string write_scratch(const std::string &name, const std::string &text)
  {
    const auto path = std::filesystem::temp_directory_path() /
                      ("fretsim-fem-" + std::to_string(::getpid()) + "-" + name);
    std::ofstream(path) << text;
    return path.string();
  }

  std::string error_of(const std::string &path, const std::vector<BoundaryId> &required)
  {
    try
      {
        Mesh::from_gmsh(path, required, Ranks::this_one);
      }
    catch (const MeshError &e)
      {
        return e.what();
      }
    return "";
  }
} // namespace

TEST(GmshMesh, ReadsTagsAndRejectsBadFiles)
{
  const std::string good = write_scratch("good.msh", one_hex_msh({1, 3, 6, 6, 6, 6}, "1 2 3 4 5 6 7 8"));
  const Mesh        mesh = Mesh::from_gmsh(good, {BoundaryId::raceway, BoundaryId::ring_outer}, Ranks::this_one);
  const MeshSummary s    = mesh.summary(1);
  EXPECT_EQ(s.n_cells, 1u);
  EXPECT_EQ(s.boundary_faces.at(id(BoundaryId::side_faces)), 4u);

  const std::string missing = error_of(good, {BoundaryId::raceway, BoundaryId::housing_bore});
  EXPECT_NE(missing.find("required boundaries are missing: housing_bore (4)"), std::string::npos) << missing;
  EXPECT_NE(missing.find(good), std::string::npos) << missing;

  const std::string untagged = write_scratch("untagged.msh", one_hex_msh({1, 3, 0, 6, 6, 6}, "1 2 3 4 5 6 7 8"));
  EXPECT_NE(error_of(untagged, {}).find("1 boundary faces carry no physical surface tag"), std::string::npos)
    << error_of(untagged, {});

  // Top and bottom swapped: a mirrored hexahedron with negative volume, which
  // GridIn repairs by renumbering (the geometry is fine); accepted.
  const std::string mirrored = write_scratch("mirrored.msh", one_hex_msh({1, 3, 6, 6, 6, 6}, "5 6 7 8 1 2 3 4"));
  EXPECT_EQ(error_of(mirrored, {}), "");
  EXPECT_NEAR(Mesh::from_gmsh(mirrored, {}, Ranks::this_one).summary(1).volume, 1.0, 1e-12);
  // Two nodes of the bottom face swapped: a twisted (self-intersecting) cell
  // that no renumbering repairs.
  const std::string twisted = write_scratch("twisted.msh", one_hex_msh({1, 3, 6, 6, 6, 6}, "1 2 4 3 5 6 7 8"));
  const std::string message = error_of(twisted, {});
  EXPECT_NE(message.find("inverted or degenerate"), std::string::npos) << message;

  EXPECT_NE(error_of("/nonexistent/ring.msh", {}).find("no such mesh file"), std::string::npos);
}

TEST(GmshMesh, ShippedBearing6208OuterRing)
{
  // meshes/bearing_6208_outer_ring.geo: its dimensions, repeated here.
  RingGeometry g;
  g.bore_radius          = 0.0341;
  g.outer_radius         = 0.040;
  g.width                = 0.018;
  g.groove_radius        = 0.53 * 0.0127;
  g.groove_bottom_radius = (0.060 + 0.0127) / 2;
  const Mesh mesh = Mesh::from_gmsh(FRETSIM_SOURCE_DIR "/meshes/bearing_6208_outer_ring.msh",
                                    {BoundaryId::raceway, BoundaryId::ring_lands, BoundaryId::ring_outer,
                                     BoundaryId::side_faces});
  const MeshSummary s = mesh.summary(1);
  EXPECT_EQ(s.n_cells, 64u * 3u * 10u);
  EXPECT_EQ(s.boundary_faces.size(), 4u);
  // Straight-edged cells: chords of 5.6° around (area deficit ≈ (π/64)²/6 =
  // 4e-4) and of 16° across the groove arc (length deficit ≈ 0.28²/24 = 3.3e-3;
  // the 6 circular segments the chords leave add ≈ 4e-3 of the ring volume).
  EXPECT_LT(relative_error(s.volume, ring_volume(g)), 5e-3);
  EXPECT_LT(relative_error(s.boundary_area.at(id(BoundaryId::raceway)), raceway_area(g)), 6e-3);
  EXPECT_LT(relative_error(s.boundary_area.at(id(BoundaryId::ring_outer)), 2 * M_PI * g.outer_radius * g.width),
            2e-3);
}
