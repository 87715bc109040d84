#pragma once
// `fretsim reduce CONFIG -o model.h5`: the Craig–Bampton reduced model of a
// ring_housing configuration, with its provenance (DESIGN.md §3).
#include "app/ring_housing.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace fretsim::app
{
  /// The parameters of the `reduce` command's section.
  std::vector<ParameterSpec> reduce_parameter_specs();

  /// Reads and validates the configuration, builds the FE model, reduces it
  /// and writes the model file (via a temporary file: never half-written).
  /// Returns the files written. Collective over the MPI ranks.
  std::vector<std::string> run_reduce_command(const RingHousingCommandOptions &options, std::ostream &out);
} // namespace fretsim::app
