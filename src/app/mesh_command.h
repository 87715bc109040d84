#pragma once
// `fretsim mesh CONFIG -o DIR`: builds (or reads) the ring/housing mesh that a
// "ring_housing" configuration describes, checks it, writes it with its
// boundary ids for ParaView and reports cells, DoFs and the ids found.
#include "app/ring_housing_command.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace fretsim::app
{

  /// Reads and validates the configuration (InputError before anything else
  /// happens), then starts MPI/PETSc for the FE work, builds the mesh (a Gmsh
  /// file with inverted cells or missing boundary ids is an InputError too,
  /// raised before anything is written), writes `<DIR>/mesh.vtu` and
  /// `<DIR>/mesh_boundary.vtu` and prints the report on rank 0. Returns the
  /// files written. MPI lives only inside this call: the contact scenes never
  /// start it.
  std::vector<std::string> run_mesh_command(const RingHousingCommandOptions &options, std::ostream &out);
} // namespace fretsim::app
