#include "app/compare_traction.h"

#include <fretsim/support/parameters.h>
#include <fretsim/support/run_control.h>
#include <fretsim/output/results_file.h>
#include <fretsim/scenes/figures.h>
#include <fretsim/scenes/scene.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

namespace fretsim::app
{
  namespace
  {
    struct ModelRun
    {
      std::string         model, directory;
      scenes::RunReport   report;
      std::vector<double> force_x, force_y, cycle, slip_fraction; // /series of results.h5
    };

    double number(const ModelRun &run, const std::string &key)
    {
      const auto at = run.report.numbers.find(key);
      return at == run.report.numbers.end() ? std::nan("") : at->second;
    }

    /// Largest of `difference(run, reference, row)` over the reference's last
    /// complete cycle (the rows are the same time steps in every run).
    template <typename Difference>
    double largest_over_last_cycle(const ModelRun &run, const ModelRun &reference, Difference difference)
    {
      const std::size_t rows = std::min(run.force_x.size(), reference.force_x.size());
      if (rows < 2)
        return std::nan("");
      const double last_cycle = reference.cycle[rows - 1];
      double       largest    = 0.0;
      for (std::size_t r = 0; r < rows; ++r)
        if (reference.cycle[r] == last_cycle)
          largest = std::max(largest, difference(r));
      return largest;
    }

    /// Largest |Q - Q_reference| over the last cycle [N].
    double loop_difference(const ModelRun &run, const ModelRun &reference)
    {
      return largest_over_last_cycle(run, reference, [&](std::size_t r) {
        return std::hypot(run.force_x[r] - reference.force_x[r], run.force_y[r] - reference.force_y[r]);
      });
    }

    /// Largest |slip area fraction - the reference's| over the last cycle [-].
    double slip_zone_difference(const ModelRun &run, const ModelRun &reference)
    {
      return largest_over_last_cycle(run, reference, [&](std::size_t r) {
        return std::abs(run.slip_fraction[r] - reference.slip_fraction[r]);
      });
    }

    std::string slug(const std::string &model)
    {
      std::string text = model;
      std::replace(text.begin(), text.end(), ' ', '_');
      return text;
    }
  } // namespace

  std::vector<std::string> run_traction_comparison(const CompareTractionOptions &options)
  {
    // The exact model last: it is the reference.
    const std::vector<std::string> models{"bristle", "elastoplastic bristle", "exact masing", "exact"};
    // Every model's scene is built (and so checked) before anything is run.
    // The models are compared on one grid: the runs' own error estimates on
    // coarser grids are left out unless asked for.
    std::vector<std::unique_ptr<scenes::Scene>> scenes_to_run;
    const bool estimate_asked =
      std::any_of(options.overrides.begin(), options.overrides.end(),
                  [](const auto &override) { return override.first == "Convergence/Risk error estimate"; });
    for (const auto &model : models)
      {
        auto overrides = options.overrides;
        if (!estimate_asked)
          overrides.insert(overrides.begin(), {"Convergence/Risk error estimate", "false"});
        overrides.emplace_back("Friction/Traction model", model);
        scenes_to_run.push_back(scenes::load_scene(options.config_file, overrides));
      }

    const std::string output =
      options.output_directory.empty() ?
        (std::filesystem::path("results") / (std::filesystem::path(options.config_file).stem().string() + "-traction"))
          .string() :
        options.output_directory;
    std::vector<ModelRun> runs;
    for (std::size_t m = 0; m < models.size(); ++m)
      {
        ModelRun run;
        run.model     = models[m];
        run.directory = (std::filesystem::path(output) / slug(models[m])).string();
        std::cout << "compare-traction: running the " << models[m] << " model into " << run.directory << std::endl;
        run.report = scenes_to_run[m]->run({run.directory, false, options.progress});
        if (!run.report.completed)
          throw std::runtime_error("interrupted during the " + models[m] + " run");
        run.force_x = output::ResultsFile::read_dataset(run.report.results_file, "/series/tangential_force_x");
        run.force_y = output::ResultsFile::read_dataset(run.report.results_file, "/series/tangential_force_y");
        run.cycle   = output::ResultsFile::read_dataset(run.report.results_file, "/series/cycle");
        run.slip_fraction =
          output::ResultsFile::read_dataset(run.report.results_file, "/series/slip_area_fraction");
        runs.push_back(std::move(run));
      }

    const ModelRun &exact        = runs.back();
    const double    friction_limit = number(exact, "friction_force_limit_N");
    std::cout << "\nTraction models against the exact elastic solution (same grid, steps and stages):\n"
              << "  run time: whole run; traction: the traction stage alone; loop error: max |Q - Q_exact| / (mu P)\n"
              << "  over the last cycle; slip: max |slip area fraction - exact's| over the last cycle; energy:\n"
              << "  dissipated per cycle; D_max: maximum Dang Van risk, dD_max its difference from the exact one's.\n\n"
              << std::left << std::setw(24) << "model" << std::right << std::setw(11) << "run [s]" << std::setw(10)
              << "speed-up" << std::setw(14) << "traction [s]" << std::setw(10) << "speed-up" << std::setw(12)
              << "loop error" << std::setw(8) << "slip" << std::setw(13) << "energy [J]" << std::setw(11) << "error" << std::setw(9)
              << "D_max" << std::setw(10) << "dD_max" << std::setw(14) << "distance [um]" << "\n";
    const std::string csv = (std::filesystem::path(output) / "compare_traction.csv").string();
    std::ofstream     table(csv);
    table << "model,wall_time_s,speed_up_vs_exact,traction_time_s,traction_speed_up_vs_exact,loop_error_mu_P,"
             "slip_fraction_error,dissipated_energy_J,energy_error,risk_max,risk_max_difference,"
             "risk_max_relative_error,risk_max_distance_m,risk_max_x_m,risk_max_y_m,risk_max_depth_m\n"
          << std::setprecision(8);
    for (const auto &run : runs)
      {
        const double wall = number(run, "wall_time_s"), traction = number(run, "traction_seconds");
        const double loop_error = loop_difference(run, exact) / friction_limit;
        const double slip_error = slip_zone_difference(run, exact);
        const double energy = number(run, "dissipated_energy_per_cycle_J");
        const double energy_error = energy / number(exact, "dissipated_energy_per_cycle_J") - 1.0;
        const double risk = number(run, "risk_max"), risk_difference = risk - number(exact, "risk_max");
        const double risk_relative = risk_difference / number(exact, "risk_max");
        const double distance = std::sqrt(std::pow(number(run, "risk_max_x_m") - number(exact, "risk_max_x_m"), 2) +
                                          std::pow(number(run, "risk_max_y_m") - number(exact, "risk_max_y_m"), 2) +
                                          std::pow(number(run, "risk_max_depth_m") - number(exact, "risk_max_depth_m"), 2));
        std::ostringstream row;
        row << std::left << std::setw(24) << run.model << std::right << std::fixed << std::setprecision(2)
            << std::setw(11) << wall << std::setw(9) << number(exact, "wall_time_s") / wall << "x" << std::setw(14)
            << std::setprecision(4) << traction << std::setw(9) << std::setprecision(0)
            << number(exact, "traction_seconds") / traction << "x" << std::setw(12) << std::setprecision(4)
            << loop_error << std::setw(8) << std::setprecision(3) << slip_error << std::setw(13) << std::scientific << std::setprecision(3) << energy << std::fixed
            << std::setw(10) << std::setprecision(1) << 100 * energy_error << "%" << std::setw(9)
            << std::setprecision(3) << risk << std::setw(10) << std::showpos << risk_difference << std::setw(8)
            << std::setprecision(1) << 100 * risk_relative << "%" << std::noshowpos << std::setw(14)
            << std::setprecision(1) << distance * 1e6;
        std::cout << row.str() << "\n";
        table << run.model << "," << wall << "," << number(exact, "wall_time_s") / wall << "," << traction << ","
              << number(exact, "traction_seconds") / traction << "," << loop_error << "," << slip_error << ","
              << energy << "," << energy_error << "," << risk << "," << risk_difference << "," << risk_relative
              << "," << distance << ","
              << number(run, "risk_max_x_m") << "," << number(run, "risk_max_y_m") << ","
              << number(run, "risk_max_depth_m") << "\n";
      }
    std::cout << "\nThe stress and Dang Van stages are the same for every model, so the whole-run speed-up is\n"
                 "far below the traction stage's.\n";
    table.close();

    std::vector<std::string> files{csv};
    if (options.plots)
      {
        std::vector<std::string> arguments{output};
        for (const auto &run : runs)
          arguments.push_back(run.directory);
        for (const auto &figure : scenes::run_plot_script("plot_compare_traction.py", arguments))
          files.push_back(figure);
      }
    return files;
  }
} // namespace fretsim::app
