#include "app/reduce_command.h"

#include <fretsim/scenes/figures.h>

#include <fretsim/models/reduction.h>

namespace fretsim::app
{
  std::vector<std::string> run_reduce_command(const RingHousingCommandOptions &options, std::ostream &out)
  {
    return models::write_reduced_model(options, out);
  }

  std::vector<std::string> run_reduction_study(const RingHousingCommandOptions &options, std::ostream &out)
  {
    std::vector<std::string> files = models::run_reduction_study(options, out);
    if (options.plots && !files.empty())
      for (const auto &figure : scenes::run_plot_script("plot_reduction_study.py", {files.front()}))
        files.push_back(figure);
    return files;
  }
} // namespace fretsim::app
