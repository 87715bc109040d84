#pragma once
// `fretsim reference CONFIG`: a bearing_housing run set against the full FE
// of the same scene (docs/fe_reference.md). Ring and housing are meshed on
// a sequence of meshes (Reference/Meshes), condensed exactly onto the
// interface grid, and driven quasi-statically through the run's output times
// by the run's ball loads, with the run's layer, bristle law and friction, the
// slip history carried from increment to increment (models/fe_reference.h).
// The full FE's stresses on the run's depth layers go through the same Dang
// Van criterion; the finest mesh is the reference and the spread over the
// meshes its error bar. Writes compare_summary.json (the verdict),
// reference.csv (one row per mesh), reference_profile.csv and
// reference.png (pressure and D_max around the ring, both models).
#include <fretsim/support/parameters.h> // InputError

#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace fretsim::app
{
  struct ReferenceOptions
  {
    std::string config_file;      ///< bearing_housing scene file
    std::string output_directory; ///< default: results/<config name>-reference
    std::vector<std::pair<std::string, std::string>> overrides; ///< --set Section/Name=value
    bool        plots    = true;
    bool        progress = true;
  };

  /// Checks every input (InputError naming the file and parameter, nothing
  /// written), then builds, marches and reports; returns the files written
  /// (rank 0). Starts MPI unless it runs already; each FE model is
  /// distributed over the ranks.
  std::vector<std::string> run_reference_command(const ReferenceOptions &options, std::ostream &out);
} // namespace fretsim::app
