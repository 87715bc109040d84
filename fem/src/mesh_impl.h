#pragma once
// The deal.II side of fem::Mesh, shared by the fem sources (never installed).
#include <fretsim/fem/mesh.h>

#include <deal.II/distributed/tria.h>

#include <mpi.h>

namespace fretsim::fem
{
  struct Mesh::Impl
  {
    explicit Impl(MPI_Comm communicator)
      : triangulation(communicator)
    {}

    MPI_Comm communicator() const { return triangulation.get_communicator(); }

    dealii::parallel::distributed::Triangulation<3> triangulation;
    std::string                                      description;
  };

  MPI_Comm communicator_of(Ranks ranks);
} // namespace fretsim::fem
