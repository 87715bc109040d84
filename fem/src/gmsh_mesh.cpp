// Gmsh meshes: read with deal.II's GridIn, then checked before use, because a
// mesh with an untagged or inverted cell gives wrong answers, not an error.
#include "mesh_impl.h"

#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/manifold_lib.h>
#include <deal.II/grid/tria.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace fretsim::fem
{
  namespace
  {
    std::string first_line(const std::string &text)
    {
      // deal.II messages start with a banner; keep the informative lines.
      std::istringstream in(text);
      std::string        line, kept;
      while (std::getline(in, line))
        if (line.find("-------") == std::string::npos && line.find_first_not_of(" \t") != std::string::npos &&
            line.find("An error occurred in") == std::string::npos && line.find("Additional information") == std::string::npos &&
            line.find("The violated condition") == std::string::npos)
          kept += (kept.empty() ? "" : " ") + line.substr(line.find_first_not_of(" \t"));
      return kept.substr(0, 400);
    }

    std::string where(const dealii::Point<3> &p)
    {
      std::ostringstream s;
      s << "(" << p[0] << ", " << p[1] << ", " << p[2] << ") m";
      return s.str();
    }

    /// Smallest Jacobian determinant of the trilinear map at the 8 corners,
    /// relative to the cell's size: ≤ 0 means inverted or degenerate.
    double min_corner_jacobian(const dealii::Triangulation<3>::cell_iterator &cell)
    {
      double worst = std::numeric_limits<double>::max();
      for (unsigned int v = 0; v < 8; ++v)
        {
          const unsigned int a = v & 1, b = (v >> 1) & 1, c = (v >> 2) & 1;
          const dealii::Tensor<1, 3> e0 = (cell->vertex(v ^ 1) - cell->vertex(v)) * (a ? -1.0 : 1.0);
          const dealii::Tensor<1, 3> e1 = (cell->vertex(v ^ 2) - cell->vertex(v)) * (b ? -1.0 : 1.0);
          const dealii::Tensor<1, 3> e2 = (cell->vertex(v ^ 4) - cell->vertex(v)) * (c ? -1.0 : 1.0);
          const double scale = e0.norm() * e1.norm() * e2.norm();
          worst = std::min(worst, scale > 0.0 ? dealii::cross_product_3d(e0, e1) * e2 / scale : -1.0);
        }
      return worst;
    }
  } // namespace

  Mesh Mesh::from_gmsh(const std::string &path, const std::vector<BoundaryId> &required, const Ranks ranks)
  {
    if (!std::filesystem::is_regular_file(path))
      throw MeshError(path, "no such mesh file");

    // Read into a serial triangulation first, so that the checks below see
    // every cell on every rank and a bad file fails the same way everywhere.
    dealii::Triangulation<3> serial;
    try
      {
        dealii::GridIn<3> grid_in;
        grid_in.attach_triangulation(serial);
        std::ifstream in(path);
        grid_in.read_msh(in);
      }
    catch (const dealii::ExceptionBase &e)
      {
        throw MeshError(path, "cannot be read as an ASCII Gmsh mesh of hexahedra: " + first_line(e.what()));
      }
    catch (const std::exception &e)
      {
        throw MeshError(path, std::string("cannot be read as an ASCII Gmsh mesh of hexahedra: ") + e.what());
      }
    if (serial.n_active_cells() == 0)
      throw MeshError(path, "holds no hexahedral cells");

    std::set<unsigned int> found;
    unsigned long          untagged = 0, unknown = 0;
    std::set<unsigned int> unknown_ids;
    for (const auto &cell : serial.active_cell_iterators())
      {
        if (cell->reference_cell() != dealii::ReferenceCells::Hexahedron)
          throw MeshError(path, "cell at " + where(cell->center()) + " is not a hexahedron; FretSim meshes are all-hex");
        if (min_corner_jacobian(cell) <= 1e-12)
          throw MeshError(path, "cell at " + where(cell->center()) +
                                  " is inverted or degenerate (non-positive Jacobian at a corner); check the "
                                  "node order of the volume elements");
        const unsigned int material = cell->material_id();
        if (material != static_cast<unsigned int>(MaterialId::ring) &&
            material != static_cast<unsigned int>(MaterialId::housing))
          throw MeshError(path, "cell at " + where(cell->center()) + " has physical volume tag " +
                                  std::to_string(material) + "; expected 1 (ring) or 2 (housing)");
        for (unsigned int f = 0; f < cell->n_faces(); ++f)
          if (cell->face(f)->at_boundary())
            {
              const unsigned int id = cell->face(f)->boundary_id();
              if (id == 0)
                ++untagged;
              else if (id > max_boundary_id)
                {
                  ++unknown;
                  unknown_ids.insert(id);
                }
              else
                found.insert(id);
            }
      }
    if (untagged > 0)
      throw MeshError(path, std::to_string(untagged) +
                              " boundary faces carry no physical surface tag; tag every boundary surface with "
                              "one of the ids 1..8 (raceway, ring_lands, ring_outer, housing_bore, housing_outer, "
                              "side_faces, sector_start, sector_end)");
    if (unknown > 0)
      throw MeshError(path, std::to_string(unknown) + " boundary faces carry unknown physical surface tag " +
                              std::to_string(*unknown_ids.begin()) + "; the known ids are 1..8");
    std::string missing;
    for (const BoundaryId id : required)
      if (found.count(static_cast<unsigned int>(id)) == 0)
        missing += (missing.empty() ? "" : ", ") + to_string(id) + " (" +
                   std::to_string(static_cast<unsigned int>(id)) + ")";
    if (!missing.empty())
      throw MeshError(path, "the required boundaries are missing: " + missing);

    auto impl = std::make_unique<Impl>(communicator_of(ranks));
    impl->triangulation.copy_triangulation(serial);
    // Gmsh gives straight-edged hexahedra; new points on refinement and the
    // higher-order mapping follow cylinders about the z axis (exact for bores
    // and outer surfaces, a chord-wise approximation of a groove arc).
    impl->triangulation.set_all_manifold_ids(0);
    impl->triangulation.set_manifold(0, dealii::CylindricalManifold<3>(2));
    impl->description = "Gmsh mesh " + path;
    return Mesh(std::move(impl));
  }
} // namespace fretsim::fem
