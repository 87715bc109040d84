#pragma once
#include <string>
#include <vector>

namespace fretsim::scenes
{
  /// Runs scripts/plot_results.py on a results directory and returns the PNG
  /// files it wrote. A missing Python or plotting failure is reported on
  /// stderr and gives no figures; it does not fail the run.
  std::vector<std::string> make_figures(const std::string &output_directory);
} // namespace fretsim::scenes
