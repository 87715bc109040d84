// `fretsim compare`: its stages in order (compare_stages.h).
#include "app/compare_command.h"

#include "app/compare_stages.h"

#include <fretsim/fem/parallel_environment.h>

#include <filesystem>
#include <memory>

namespace fretsim::app
{
  std::vector<std::string> run_comparison(const CompareInputs &in, const std::string &output_directory, bool plots,
                                          std::ostream &out)
  {
    // Everything is read and checked before MPI starts and before any file is written.
    const compare::Plan plan = compare::read_plan(in);

    std::unique_ptr<fem::ParallelEnvironment> mpi;
    if (!fem::ParallelEnvironment::active())
      mpi = std::make_unique<fem::ParallelEnvironment>();
    const bool root = fem::ParallelEnvironment::rank() == 0;

    // The ring's FE objects go before the housing's are built, and both
    // before MPI stops.
    const compare::RingResults ring = compare::compare_ring(in, plan, root ? &out : nullptr);
    const std::vector<HousingComparison::Result> housing = compare::compare_housing(plan);

    if (!root)
      return {};
    compare::print_summary(out, in, plan, ring, housing);
    return compare::write_files(output_directory, plots, plan, ring, housing);
  }

  std::vector<std::string> run_compare_command(const CompareOptions &options, std::ostream &out)
  {
    const CompareInputs inputs = read_compare_inputs(options.config_file, options.overrides);
    const std::string   directory =
      options.output_directory.empty() ?
          (std::filesystem::path("results") / (std::filesystem::path(options.config_file).stem().string() + "-compare"))
          .string() :
          options.output_directory;
    return run_comparison(inputs, directory, options.plots, out);
  }
} // namespace fretsim::app
