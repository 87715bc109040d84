#pragma once
// `fretsim fe CONFIG -o DIR`: full-FE reference solutions of a ring_housing
// configuration (static load cases, eigenmodes, transients), written as
// stress snapshots to HDF5 (DESIGN.md §3).
#include "app/ring_housing.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace fretsim::app
{
  /// The parameters of the `fe` command's sections.
  std::vector<ParameterSpec> fe_parameter_specs();

  /// Reads and validates the configuration (InputError before anything is
  /// written), runs the FE analysis, writes the results and returns the files
  /// written. Collective over the MPI ranks.
  std::vector<std::string> run_fe_command(const RingHousingCommandOptions &options, std::ostream &out);
} // namespace fretsim::app
