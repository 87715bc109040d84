#pragma once
#include <string>
#include <vector>

namespace fretsim::scenes
{
  /// Runs scripts/<script> (Python with matplotlib and h5py) with `arguments`
  /// and returns the PNG files it wrote; the script prints the path of each,
  /// one per line. A missing Python or a plotting failure is reported on
  /// stderr and gives no figures; it does not fail the run.
  std::vector<std::string> run_plot_script(const std::string &script, const std::vector<std::string> &arguments);

  /// scripts/plot_results.py on a results directory.
  std::vector<std::string> make_figures(const std::string &output_directory);
} // namespace fretsim::scenes
