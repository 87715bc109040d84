#pragma once
// `fretsim fe CONFIG -o DIR`: full-FE reference solutions of a ring_housing
// configuration (static load cases, eigenmodes, transients), written as
// stress snapshots to HDF5 (docs/theory.md §3).
#include "app/ring_housing_command.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace fretsim::app
{
  /// Reads and validates the configuration (InputError before anything is
  /// written), runs the FE analysis, writes the results and returns the files
  /// written. Collective over the MPI ranks.
  std::vector<std::string> run_fe_command(const RingHousingCommandOptions &options, std::ostream &out);
} // namespace fretsim::app
