#include "app/cli.h"

#include "app/build_info.h"
#include "app/compare_command.h"
#include "app/compare_traction.h"
#include "app/fe_command.h"
#include "app/mesh_command.h"
#include "app/reduce_command.h"
#include "app/parameters.h"
#include "app/run_control.h"
#include "app/stress_benchmark.h"
#include "scenes/scene.h"

#include <fretsim/fem/library_info.h>
#include <fretsim/reduction/library_info.h>

#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>

namespace fretsim::app
{
  namespace
  {
    constexpr int exit_ok           = 0;
    constexpr int exit_failure      = 1;
    constexpr int exit_bad_input    = 2;

    std::string version_text()
    {
      return std::string("fretsim ") + FRETSIM_VERSION + " (" + fem::library_versions() + ", " +
             reduction::library_versions() + ")";
    }

    /// "Section/Name=value" from --set, as (path, value).
    std::vector<std::pair<std::string, std::string>> parse_overrides(const std::vector<std::string> &settings)
    {
      std::vector<std::pair<std::string, std::string>> overrides;
      for (const auto &setting : settings)
        {
          const auto equals = setting.find('=');
          if (equals == std::string::npos || equals == 0)
            throw InputError("(command line)", "--set", "expected Section/Name=value, got '" + setting + "'");
          overrides.emplace_back(setting.substr(0, equals), setting.substr(equals + 1));
        }
      return overrides;
    }

    int run_scene(const std::string &config_file, std::string output_directory, bool plots, bool quiet,
                  const std::vector<std::string> &settings)
    {
      // Everything is read and checked before anything is written.
      const auto scene = scenes::load_scene(config_file, parse_overrides(settings));
      if (output_directory.empty())
        output_directory = (std::filesystem::path("results") / std::filesystem::path(config_file).stem()).string();
      install_interrupt_handlers();
      const scenes::RunReport report = scene->run({output_directory, plots, !quiet});
      std::cout << "results:  " << std::filesystem::absolute(report.results_file).string() << "\n"
                << "summary:  " << std::filesystem::absolute(report.summary_file).string() << "\n"
                << "paraview: " << std::filesystem::absolute(std::filesystem::path(output_directory) / "results.xdmf").string() << "\n";
      for (const auto &figure : report.figures)
        std::cout << "figure:   " << std::filesystem::absolute(figure).string() << "\n";
      if (!report.completed)
        {
          std::cerr << "fretsim: interrupted; results hold the steps done so far\n";
          return 128 + interrupt_signal();
        }
      return exit_ok;
    }

    int print_parameters(const std::string &scene)
    {
      auto known_names = scenes::scene_names();
      known_names.push_back(ring_housing_scene);
      const auto names = scene.empty() ? known_names : std::vector<std::string>{scene};
      for (const auto &name : names)
        {
          if (name == ring_housing_scene)
            {
              SceneParameters(name, ring_housing_parameter_specs()).print_reference(std::cout);
              continue;
            }
          bool known = false;
          for (const auto &candidate : scenes::scene_names())
            known = known || candidate == name;
          if (!known)
            throw InputError("(command line)", "SCENE", "unknown scene '" + name + "'");
          scenes::declare_parameters(name).print_reference(std::cout);
        }
      return exit_ok;
    }
  } // namespace

  int run_command_line(int argc, char **argv)
  {
    CLI::App app{"FretSim: fretting-fatigue simulation of machine contacts (SI units throughout)", "fretsim"};
    app.set_version_flag("--version", version_text());
    app.require_subcommand(1);

    std::string config_file, output_directory, scene;
    bool        no_plots = false, quiet = false;
    auto *run = app.add_subcommand("run", "Run the scene described by a configuration file");
    run->add_option("CONFIG", config_file, "Scene file (.prm or .json)")->required();
    run->add_option("-o,--output", output_directory, "Output directory (default: results/<config name>)");
    run->add_flag("--no-plots", no_plots, "Do not write PNG figures");
    run->add_flag("-q,--quiet", quiet, "No progress line");
    std::vector<std::string> settings;
    run->add_option("--set", settings, "Override a parameter, e.g. --set 'Grid/Cells x=256' (repeatable)");
    auto *params = app.add_subcommand("params", "Print every parameter of a scene: default, allowed values, unit");
    params->add_option("SCENE", scene, "Scene name (default: all scenes)");
    CompareTractionOptions compare;
    auto *compare_traction = app.add_subcommand(
      "compare-traction", "Run a scene with each traction model (bristle, elastoplastic bristle, exact) and "
                          "report run time, loop, energy and D_max differences against the exact model");
    compare_traction->add_option("CONFIG", compare.config_file, "Scene file (.prm or .json)")->required();
    compare_traction->add_option("-o,--output", compare.output_directory,
                                 "Output directory (default: results/<config name>-traction)");
    compare_traction->add_flag("--no-plots", no_plots, "Do not write the PNG figure");
    compare_traction->add_flag("-q,--quiet", quiet, "No progress line");
    compare_traction->add_option("--set", settings, "Override a parameter, e.g. --set 'Loading/Sliding amplitude=1.12e-6'");
    // The commands on a ring_housing configuration share their options.
    RingHousingCommandOptions fe_options;
    auto add_ring_housing_command = [&](const std::string &name, const std::string &description,
                                        const std::string &output_help) {
      auto *command = app.add_subcommand(name, description);
      command->add_option("CONFIG", fe_options.config_file,
                          "Configuration file (.prm or .json, Scene = ring_housing)")
        ->required();
      command->add_option("-o,--output", fe_options.output, output_help);
      command->add_option("--set", settings, "Override a parameter, e.g. --set 'Mesh/Element degree=1'");
      return command;
    };
    auto *mesh = add_ring_housing_command(
      "mesh",
      "Build or read the ring/housing FE mesh of a ring_housing configuration, check it, write it with its "
      "boundary ids for ParaView (VTU) and print cells, DoFs and the ids found",
      "Output directory (default: results/<config name>-mesh)");
    auto *fe = add_ring_housing_command(
      "fe", "Full-FE reference solutions of a ring_housing configuration: static load cases, eigenmodes or a "
            "transient, with stress snapshots in HDF5",
      "Output directory (default: results/<config name>-fe)");
    fe->add_flag("--no-plots", no_plots, "Do not write PNG figures");
    fe->add_flag("-q,--quiet", quiet, "No progress display");
    auto *reduce = add_ring_housing_command(
      "reduce", "Craig-Bampton reduced model of the ring (constraint modes, characteristic constraint modes, "
                "fixed-interface modes) written to an HDF5 model file",
      "Model file (default: results/<config name>-model.h5)");
    reduce->add_flag("--no-plots", no_plots, "Do not write PNG figures");
    bool reduction_study = false;
    reduce->add_flag("--study", reduction_study,
                     "Error against run time instead: reduce for every (m, n_cc) of the Reduction/Study lists and "
                     "compare with the full FE model (table, CSV, PNG; -o is then a directory)");
    reduce->add_flag("-q,--quiet", quiet, "No progress display");
    CompareOptions full_fe_check;
    auto *compare_full = app.add_subcommand(
      "compare", "Check a bearing_housing run's reduced ring against the full FE model: the same ball loads and "
                 "interface tractions at N instants, errors of the recovered displacements and stresses, run times, "
                 "and the error against the reduced model's size (table, CSV, PNG)");
    compare_full->add_option("CONFIG", full_fe_check.config_file, "Scene file (.prm or .json, Scene = bearing_housing)")
      ->required();
    compare_full->add_option("-o,--output", full_fe_check.output_directory,
                             "Output directory (default: results/<config name>-compare)");
    compare_full->add_flag("--no-plots", no_plots, "Do not write the PNG figure");
    compare_full->add_flag("-q,--quiet", quiet, "No progress display");
    compare_full->add_option("--set", settings, "Override a parameter, e.g. --set 'Compare/Instants=8'");
    auto *bench = app.add_subcommand("bench", "Error against run time of the numerical approximations");
    bench->require_subcommand(1);
    StressBenchmarkOptions stress_bench;
    auto *bench_stresses = bench->add_subcommand(
      "stresses", "Subsurface-stress evaluators (direct, MLMI, DC-FFT): run time and error against direct "
                  "summation over grid sizes, depth layers and threads; table, CSV and PNG");
    bench_stresses->add_option("--sizes", stress_bench.sizes, "Cells per side")->delimiter(',')->capture_default_str();
    bench_stresses->add_option("--layers", stress_bench.layers, "Depth-layer counts")->delimiter(',')->capture_default_str();
    bench_stresses->add_option("--threads", stress_bench.threads, "Thread counts")->delimiter(',')->capture_default_str();
    bench_stresses->add_option("--direct-limit", stress_bench.direct_time_limit,
                               "Run direct summation only where its predicted time is below this [s]")
      ->capture_default_str();
    bench_stresses->add_option("-o,--output", stress_bench.output_directory, "Output directory")->capture_default_str();
    bench_stresses->add_flag("--no-plots", no_plots, "Do not write the PNG figure");

    try
      {
        app.parse(argc, argv);
      }
    catch (const CLI::ParseError &error)
      {
        const int code = app.exit(error);
        return code == 0 ? exit_ok : exit_bad_input;
      }

    try
      {
        if (*run)
          return run_scene(config_file, output_directory, !no_plots, quiet, settings);
        if (*compare_traction)
          {
            compare.plots    = !no_plots;
            compare.progress = !quiet;
            compare.overrides = parse_overrides(settings);
            install_interrupt_handlers();
            for (const auto &file : run_traction_comparison(compare))
              std::cout << (file.size() > 4 && file.substr(file.size() - 4) == ".png" ? "figure:   " : "table:    ")
                        << std::filesystem::absolute(file).string() << "\n";
            return exit_ok;
          }
        if (*mesh || *fe || *reduce)
          {
            fe_options.overrides = parse_overrides(settings);
            fe_options.progress  = !quiet;
            fe_options.plots     = !no_plots;
            if (*mesh)
              run_mesh_command(fe_options, std::cout);
            else
              {
                // `fe` stops a transient between steps and keeps what it wrote; a
                // reduction has no steps to keep (its file appears complete or
                // not at all), so Ctrl-C simply ends it.
                if (*fe)
                  install_interrupt_handlers();
                const auto files = *fe              ? run_fe_command(fe_options, std::cout) :
                                   reduction_study ? run_reduction_study(fe_options, std::cout) :
                                                     run_reduce_command(fe_options, std::cout);
                for (const auto &file : files)
                  std::cout << (file.size() > 4 && file.substr(file.size() - 4) == ".png" ? "figure:   " : "written:  ")
                            << std::filesystem::absolute(file).string() << "\n";
              }
            return exit_ok;
          }
        if (*compare_full)
          {
            full_fe_check.overrides = parse_overrides(settings);
            full_fe_check.plots     = !no_plots;
            full_fe_check.progress  = !quiet;
            for (const auto &file : run_compare_command(full_fe_check, std::cout))
              std::cout << (file.size() > 4 && file.substr(file.size() - 4) == ".png" ? "figure:   " : "table:    ")
                        << std::filesystem::absolute(file).string() << "\n";
            return exit_ok;
          }
        if (*bench_stresses)
          {
            stress_bench.plots = !no_plots;
            for (const auto &file : run_stress_benchmark(stress_bench))
              std::cout << (file.size() > 4 && file.substr(file.size() - 4) == ".png" ? "figure:   " : "table:    ")
                        << std::filesystem::absolute(file).string() << "\n";
            return exit_ok;
          }
        return print_parameters(scene);
      }
    catch (const InputError &error)
      {
        std::cerr << "fretsim: error: " << error.what() << "\n";
        return exit_bad_input;
      }
    catch (const std::exception &error)
      {
        std::cerr << "fretsim: internal error: " << error.what() << "\n";
        return exit_failure;
      }
  }
} // namespace fretsim::app
