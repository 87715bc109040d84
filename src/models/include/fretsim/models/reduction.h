#pragma once
// The Craig–Bampton reduced model of a ring_housing configuration, with its
// provenance and input hash (docs/theory.md §3): what `fretsim reduce` writes and
// what a scene builds when its model file is missing or stale.
#include <fretsim/models/ring_housing.h>

#include <iosfwd>
#include <string>
#include <vector>

namespace fretsim::models
{
  /// The parameters of the `reduce` command's section.
  std::vector<ParameterSpec> reduce_parameter_specs();

  /// Reads and validates the configuration, builds the FE model, reduces it
  /// and writes the model file (via a temporary file: never half-written);
  /// with Reduction/Compare with full FE, measures it against the full model
  /// first. Returns the files written. Collective over the MPI ranks.
  std::vector<std::string> write_reduced_model(const RingHousingCommandOptions &options, std::ostream &out);

  /// Error against run time: reduces the model once for every (m, n_cc) of
  /// Reduction/Study ... lists and measures each against the full FE model
  /// (lowest 10 frequencies with the boundary free and clamped, a static
  /// squeeze of the outer surface); writes reduction_study.csv into the output
  /// directory and returns its path (on rank 0).
  std::vector<std::string> run_reduction_study(const RingHousingCommandOptions &options, std::ostream &out);

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
} // namespace fretsim::models
