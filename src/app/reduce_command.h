#pragma once
// `fretsim reduce CONFIG -o model.h5`: the Craig–Bampton reduced model of a
// ring_housing configuration (models/reduction.h builds it), and `--study`,
// its error against run time.
#include "app/ring_housing_command.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace fretsim::app
{
  /// Builds and writes the model file; returns the files written.
  /// Collective over the MPI ranks.
  std::vector<std::string> run_reduce_command(const RingHousingCommandOptions &options, std::ostream &out);

  /// `fretsim reduce CONFIG --study`: reduction_study.csv and its PNG in the
  /// output directory; returns the files written.
  std::vector<std::string> run_reduction_study(const RingHousingCommandOptions &options, std::ostream &out);
} // namespace fretsim::app
