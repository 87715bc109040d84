// `fretsim mesh`: a parametric ring-in-housing and the shipped 6208 Gmsh mesh
// are written for ParaView with their boundary ids and reported (cells, DoFs
// counted by hand, ids); bad parameters and bad Gmsh files (missing ids,
// inverted cells) give one line of error, exit code 2 and nothing on disk.
#include "app/test_files.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <sstream>

using fretsim::test_files::read_text;
using fretsim::test_files::run_program;
using fretsim::test_files::scratch_directory;
using fretsim::test_files::write_text;

namespace
{
  std::string config(const std::string &mesh_section, const std::string &rest = "")
  {
    return "set Scene = ring_housing\nsubsection Mesh\n" + mesh_section + "end\n" + rest;
  }

  /// The boundary ids in a mesh_boundary.vtu (its one CellData array).
  std::set<int> ids_in(const std::filesystem::path &vtu)
  {
    const std::string text  = read_text(vtu);
    const auto        start = text.find('>', text.find("Name=\"boundary_id\"")) + 1;
    const auto        end   = text.find("</DataArray>", start);
    std::istringstream values(text.substr(start, end - start));
    std::set<int>      ids;
    for (int id; values >> id;)
      ids.insert(id);
    return ids;
  }

  /// One unit cube as a Gmsh 2.2 file with the given face tags and hexahedron node order.
  std::string one_hex_msh(const std::vector<unsigned int> &face_tags, const std::string &hex_nodes)
  {
    std::string s = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8\n"
                    "1 1 0 0\n2 2 0 0\n3 2 1 0\n4 1 1 0\n5 1 0 1\n6 2 0 1\n7 2 1 1\n8 1 1 1\n$EndNodes\n$Elements\n7\n";
    const char *faces[6] = {"1 4 3 2", "5 6 7 8", "1 2 6 5", "2 3 7 6", "3 4 8 7", "4 1 5 8"};
    for (unsigned int f = 0; f < 6; ++f)
      s += std::to_string(f + 1) + " 3 2 " + std::to_string(face_tags[f]) + " " + std::to_string(f + 1) + " " +
           faces[f] + "\n";
    return s + "7 5 2 1 1 " + hex_nodes + "\n$EndElements\n";
  }

  long count_lines(const std::string &text) { return std::count(text.begin(), text.end(), '\n'); }
} // namespace

TEST(MeshCommand, ParametricRingInHousing)
{
  const auto dir = scratch_directory("mesh-parametric");
  write_text(dir / "rh.prm",
             config("  set Bodies = ring_in_housing\n  set Element degree = 1\n",
                    "subsection Divisions\n  set Circumferential = 12\n  set Radial ring = 1\n"
                    "  set Radial housing = 1\n  set Axial = 2\n  set Axial land = 1\nend\n"));
  const auto result = run_program("mesh " + (dir / "rh.prm").string() + " -o " + (dir / "out").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  // 12 around x (1 + 1) radial x (1 + 2 + 1) axial cells; Q1 nodes:
  // 12 around x 3 radii x 5 axial planes, 3 components each.
  EXPECT_NE(result.output.find("cells:    96 hexahedra"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("DoFs:     540 (FE_Q1"), std::string::npos) << result.output;
  for (const std::string id : {"raceway", "ring_lands", "housing_outer", "side_faces"})
    EXPECT_NE(result.output.find(id), std::string::npos) << id << "\n" << result.output;
  EXPECT_EQ(result.output.find("ring_outer"), std::string::npos) << "the bonded interface is no boundary";
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "mesh.vtu"));
  EXPECT_EQ(ids_in(dir / "out" / "mesh_boundary.vtu"), (std::set<int>{1, 2, 5, 6}));
  EXPECT_NE(read_text(dir / "out" / "mesh.vtu").find("Name=\"material_id\""), std::string::npos);
}

TEST(MeshCommand, ShippedGmshMeshRelativeToTheConfiguration)
{
  const auto dir = scratch_directory("mesh-gmsh");
  const auto relative =
    std::filesystem::relative(std::filesystem::path(FRETSIM_SOURCE_DIR) / "meshes" / "bearing_6208_outer_ring.msh", dir);
  write_text(dir / "g.prm", config("  set Source = gmsh\n  set Mesh file = " + relative.string() + "\n"));
  const auto result = run_program("mesh " + (dir / "g.prm").string() + " -o " + (dir / "out").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("cells:    1920 hexahedra"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("DoFs:     56448 (FE_Q2"), std::string::npos) << result.output;
  EXPECT_EQ(ids_in(dir / "out" / "mesh_boundary.vtu"), (std::set<int>{1, 2, 3, 6}));
}

TEST(MeshCommand, BadInputGivesOneLineExitTwoAndWritesNothing)
{
  const auto dir = scratch_directory("mesh-bad");
  const auto out = dir / "out";
  struct Case
  {
    std::string name, text, expected;
  };
  write_text(dir / "missing_ids.msh", one_hex_msh({1, 6, 6, 6, 6, 6}, "1 2 3 4 5 6 7 8"));
  write_text(dir / "twisted.msh", one_hex_msh({1, 3, 6, 6, 6, 6}, "1 2 4 3 5 6 7 8"));
  write_text(dir / "untagged.msh", one_hex_msh({1, 3, 0, 6, 6, 6}, "1 2 3 4 5 6 7 8"));
  const std::vector<Case> cases{
    {"missing_ids.prm", config("  set Source = gmsh\n  set Mesh file = missing_ids.msh\n"),
     "the required boundaries are missing: ring_outer (3)"},
    {"twisted.prm", config("  set Source = gmsh\n  set Mesh file = twisted.msh\n"), "inverted or degenerate"},
    {"untagged.prm", config("  set Source = gmsh\n  set Mesh file = untagged.msh\n"),
     "boundary faces carry no physical surface tag"},
    {"absent.prm", config("  set Source = gmsh\n  set Mesh file = absent.msh\n"), "no such mesh file"},
    {"empty.prm", config("  set Source = gmsh\n"), "parameter 'Mesh/Mesh file'"},
    {"groove.prm", config("", "subsection Ring\n  set Groove radius = 0.02\nend\n"),
     "parameter 'Ring/Groove radius'"},
    {"housing.prm", config("  set Bodies = housing\n", "subsection Housing\n  set Outer radius = 0.03\nend\n"),
     "parameter 'Housing/Outer radius'"},
    {"degree.prm", config("  set Element degree = 3\n"), "parameter 'Mesh/Element degree'"},
  };
  for (const Case &c : cases)
    {
      write_text(dir / c.name, c.text);
      const auto result = run_program("mesh " + (dir / c.name).string() + " -o " + out.string());
      EXPECT_EQ(result.exit_code, 2) << c.name << ": " << result.output;
      EXPECT_NE(result.output.find(c.expected), std::string::npos) << c.name << ": " << result.output;
      EXPECT_NE(result.output.find(c.name), std::string::npos) << "names the configuration: " << result.output;
      EXPECT_EQ(count_lines(result.output), 1) << c.name << ": " << result.output;
      EXPECT_FALSE(std::filesystem::exists(out)) << c.name;
    }
}

TEST(MeshCommand, ParametersAreListedAndTheSceneIsChecked)
{
  const auto params = run_program("params ring_housing");
  EXPECT_EQ(params.exit_code, 0);
  EXPECT_NE(params.output.find("set Groove bottom radius = 0.03635"), std::string::npos) << params.output;
  EXPECT_NE(params.output.find("[m]"), std::string::npos);

  const auto dir = scratch_directory("mesh-scene");
  write_text(dir / "c.prm", "set Scene = concentrated\n");
  const auto wrong = run_program("mesh " + (dir / "c.prm").string() + " -o " + (dir / "out").string());
  EXPECT_EQ(wrong.exit_code, 2) << wrong.output;
  EXPECT_NE(wrong.output.find("ring_housing"), std::string::npos) << wrong.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}
