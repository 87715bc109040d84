// Mesh output for ParaView: cells with material and owner, boundary faces with
// their ids. Hand-written VTU (ASCII) so that the boundary faces come out as a
// surface of their own, which DataOut does not give without a DoFHandler.
#include "mesh_impl.h"

#include <deal.II/base/mpi.h>

#include <filesystem>
#include <fstream>

namespace fretsim::fem
{
  namespace
  {
    /// Polygons flattened as [v0x v0y v0z v1x ... id] per item.
    void write_unstructured(const std::string &file, const std::vector<double> &items, const unsigned int n_vertices,
                            const unsigned int vtk_type, const std::vector<std::string> &data_names)
    {
      const unsigned int stride  = 3 * n_vertices + data_names.size();
      const std::size_t  n_items = items.size() / stride;
      std::ofstream      out(file);
      out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
          << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << n_items * n_vertices << "\" NumberOfCells=\"" << n_items
          << "\">\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
      out.precision(12);
      for (std::size_t c = 0; c < n_items; ++c)
        for (unsigned int k = 0; k < 3 * n_vertices; ++k)
          out << items[c * stride + k] << (k % 3 == 2 ? '\n' : ' ');
      out << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
      for (std::size_t i = 0; i < n_items * n_vertices; ++i)
        out << i << ((i + 1) % n_vertices == 0 ? '\n' : ' ');
      out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
      for (std::size_t c = 1; c <= n_items; ++c)
        out << c * n_vertices << '\n';
      out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
      for (std::size_t c = 0; c < n_items; ++c)
        out << vtk_type << '\n';
      out << "</DataArray>\n</Cells>\n<CellData>\n";
      for (unsigned int d = 0; d < data_names.size(); ++d)
        {
          out << "<DataArray type=\"Int32\" Name=\"" << data_names[d] << "\" format=\"ascii\">\n";
          for (std::size_t c = 0; c < n_items; ++c)
            out << static_cast<long>(items[c * stride + 3 * n_vertices + d]) << '\n';
          out << "</DataArray>\n";
        }
      out << "</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
      if (!out)
        throw std::runtime_error("cannot write " + file);
    }
  } // namespace

  void Mesh::write_vtu(const std::string &directory, const std::string &name) const
  {
    const auto    &tria = pimpl->triangulation;
    const MPI_Comm comm = pimpl->communicator();
    const double   me   = rank();

    std::vector<double> cells, faces;
    // deal.II's lexicographic hexahedron vertex order → VTK's counter-clockwise order.
    constexpr unsigned int hex_to_vtk[8] = {0, 1, 3, 2, 4, 5, 7, 6};
    constexpr unsigned int quad_to_vtk[4] = {0, 1, 3, 2};
    for (const auto &cell : tria.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        for (const unsigned int v : hex_to_vtk)
          for (unsigned int d = 0; d < 3; ++d)
            cells.push_back(cell->vertex(v)[d]);
        cells.push_back(cell->material_id());
        cells.push_back(me);
        for (unsigned int f = 0; f < cell->n_faces(); ++f)
          if (cell->face(f)->at_boundary())
            {
              for (const unsigned int v : quad_to_vtk)
                for (unsigned int d = 0; d < 3; ++d)
                  faces.push_back(cell->face(f)->vertex(v)[d]);
              faces.push_back(cell->face(f)->boundary_id());
            }
      }
    const auto all_cells = dealii::Utilities::MPI::gather(comm, cells, 0);
    const auto all_faces = dealii::Utilities::MPI::gather(comm, faces, 0);
    if (rank() != 0)
      return;
    std::filesystem::create_directories(directory);
    std::vector<double> c, f;
    for (const auto &part : all_cells)
      c.insert(c.end(), part.begin(), part.end());
    for (const auto &part : all_faces)
      f.insert(f.end(), part.begin(), part.end());
    const std::filesystem::path dir(directory);
    write_unstructured((dir / (name + ".vtu")).string(), c, 8, 12, {"material_id", "rank"});
    write_unstructured((dir / (name + "_boundary.vtu")).string(), f, 4, 9, {"boundary_id"});
  }
} // namespace fretsim::fem
