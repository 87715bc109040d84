#pragma once
// `fretsim bench stresses`: error against run time of the subsurface-stress
// evaluators (direct, MLMI, DC-FFT) over grid sizes, depth-layer counts and
// thread counts, as a table, a CSV file and a PNG of error against time.
#include <string>
#include <vector>

namespace fretsim::app
{
  struct StressBenchmarkOptions
  {
    std::vector<int> sizes{32, 64, 128, 256, 512}; ///< cells per side
    std::vector<int> layers{1, 4, 8};              ///< depth-layer counts
    std::vector<int> threads{1, 2};                ///< OpenMP thread counts
    /// Direct summation runs only where its predicted time stays below this [s].
    double      direct_time_limit = 60.0;
    std::string output_directory  = "results/bench_stresses";
    bool        plots             = true;
  };

  /// Runs the study, prints the table and returns the files written (CSV,
  /// PNG). Throws InputError for bad options before anything is written.
  std::vector<std::string> run_stress_benchmark(const StressBenchmarkOptions &options);
} // namespace fretsim::app
