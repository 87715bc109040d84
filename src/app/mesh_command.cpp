#include "app/mesh_command.h"

#include <fretsim/fem/mesh.h>
#include <fretsim/fem/parallel_environment.h>

#include <filesystem>
#include <iomanip>
#include <ostream>

namespace fretsim::app
{
  using models::RingHousingRequest;
  using models::build_ring_housing_mesh;
  using models::read_ring_housing_parameters;
  using models::read_ring_housing_request;

  namespace
  {
    using fem::BoundaryId;

    void print_report(std::ostream &out, const fem::MeshSummary &s, const unsigned long n_dofs,
                      const unsigned int degree, const std::string &directory)
    {
      out << "mesh:     " << s.description << "\n"
          << "cells:    " << s.n_cells << " hexahedra on " << s.n_ranks << (s.n_ranks == 1 ? " rank" : " ranks")
          << "\n"
          << "DoFs:     " << n_dofs << " (FE_Q" << degree << ", 3 displacement components)\n"
          << std::setprecision(6) << "volume:   " << s.volume << " m^3\n"
          << "boundary ids found:\n";
      for (const auto &[id, faces] : s.boundary_faces)
        out << "  " << std::setw(2) << id << "  " << std::left << std::setw(14)
            << fem::to_string(static_cast<BoundaryId>(id)) << std::right << std::setw(7) << faces
            << " faces  area " << s.boundary_area.at(id) << " m^2\n";
      out << "materials:\n";
      for (const auto &[id, cells] : s.material_cells)
        out << "  " << std::setw(2) << id << "  " << std::left << std::setw(14)
            << fem::to_string(static_cast<fem::MaterialId>(id)) << std::right << std::setw(7) << cells
            << " cells  volume " << s.material_volume.at(id) << " m^3\n";
      const auto dir = std::filesystem::absolute(directory);
      out << "paraview: " << (dir / "mesh.vtu").string() << "\n"
          << "paraview: " << (dir / "mesh_boundary.vtu").string() << "  (colour by boundary_id)\n";
    }
  } // namespace

  std::vector<std::string> run_mesh_command(const RingHousingCommandOptions &options, std::ostream &out)
  {
    // Everything that can be checked without MPI is checked before MPI starts.
    const SceneParameters    parameters = read_ring_housing_parameters(options.config_file, options.overrides);
    const RingHousingRequest request    = read_ring_housing_request(parameters);
    const std::string directory =
      options.output.empty() ?
        (std::filesystem::path("results") / (std::filesystem::path(options.config_file).stem().string() + "-mesh"))
          .string() :
        options.output;

    const fem::ParallelEnvironment mpi;
    fem::Mesh                      mesh = build_ring_housing_mesh(request, options.config_file);
    const fem::MeshSummary summary = mesh.summary(3);
    const unsigned long    n_dofs  = mesh.n_dofs(request.degree);
    mesh.write_vtu(directory, "mesh");
    if (mesh.rank() == 0)
      print_report(out, summary, n_dofs, request.degree, directory);
    return {(std::filesystem::path(directory) / "mesh.vtu").string(),
            (std::filesystem::path(directory) / "mesh_boundary.vtu").string()};
  }
} // namespace fretsim::app
