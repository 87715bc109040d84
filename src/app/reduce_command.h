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

  /// `fretsim reduce CONFIG --study`: error against run time. Reduces the
  /// model once for every (m, n_cc) of Reduction/Study ... lists and measures
  /// each against the full FE model (lowest 10 frequencies with the boundary
  /// free and clamped, a static squeeze of the outer surface); writes
  /// reduction_study.csv and a PNG into the output directory.
  /// The input hash `reduce` writes into the model file of this ring_housing
  /// configuration (with these overrides), computed without building anything;
  /// a model file is current when its hash matches. Throws InputError.
  std::string reduce_input_hash(const std::string &config_file,
                                const std::vector<std::pair<std::string, std::string>> &overrides = {});

  /// The zero-displacement supports the configuration holds its body by
  /// (Reduction/Clamped surfaces: a housing at its outside). Throws InputError.
  std::vector<fem::Support> reduction_supports(const std::string &config_file);

  /// A housing alone around a ring: the body of a flexible housing's
  /// reduction, or the housing `fretsim compare` meshes beside the ring.
  struct HousingAround
  {
    RingHousingRequest        request;
    std::vector<fem::Support> supports; ///< Reduction/Clamped surfaces
  };

  /// Reads `config_file` and checks it meshes the housing alone (Mesh/Bodies
  /// = housing) with its bore at `ring`'s outer radius and width (the fit is
  /// the interface layer's) and holds it somewhere. Throws InputError naming
  /// `source` and `parameter` (the parameter that named the file).
  HousingAround read_housing_around(const std::string &config_file, const fem::RingGeometry &ring,
                                    const std::string &source, const std::string &parameter);

  std::vector<std::string> run_reduction_study(const RingHousingCommandOptions &options, std::ostream &out);
} // namespace fretsim::app
