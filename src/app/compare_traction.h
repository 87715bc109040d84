#pragma once
// `fretsim compare-traction CONFIG`: the same scene with each tangential
// traction model (bristle, elastoplastic bristle, exact), side by side: run
// time and its ratio, loop error, dissipated energy error, D_max difference and
// the distance between the D_max locations, all against the exact model (the
// paper's Fig. 4 and 12 and its central speed claim, measured).
#include <string>
#include <utility>
#include <vector>

namespace fretsim::app
{
  struct CompareTractionOptions
  {
    std::string config_file;
    std::string output_directory; ///< default: results/<config name>-traction
    bool        plots    = true;
    bool        progress = true;
    /// ("Section/Name", value) pairs that replace the file's values.
    std::vector<std::pair<std::string, std::string>> overrides;
  };

  /// Runs the comparison, prints the table and returns the files written
  /// (CSV and PNG; each model's own results under <output>/<model>/). Throws
  /// InputError for a bad scene before anything is written.
  std::vector<std::string> run_traction_comparison(const CompareTractionOptions &options);
} // namespace fretsim::app
