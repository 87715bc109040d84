#include "app/cli.h"

#include "app/compare_command.h"
#include "app/compare_traction.h"
#include "app/map_command.h"
#include "app/fe_command.h"
#include "app/mesh_command.h"
#include "app/reduce_command.h"
#include "app/reference_command.h"
#include "app/stress_benchmark.h"

#include <fretsim/output/results_file.h>
#include <fretsim/scenes/scene.h>
#include <fretsim/support/build_info.h>
#include <fretsim/support/parameters.h>
#include <fretsim/support/run_control.h>

#include <fretsim/fem/library_info.h>
#include <fretsim/fem/parallel_environment.h>
#include <fretsim/reduction/library_info.h>

#include <CLI/CLI.hpp>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>

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

    /// "Section/Name=value" from --set, as (path, value). The same path twice
    /// is refused: which one should win is the user's to say.
    std::vector<std::pair<std::string, std::string>> parse_overrides(const std::vector<std::string> &settings)
    {
      std::vector<std::pair<std::string, std::string>> overrides;
      for (const auto &setting : settings)
        {
          const auto equals = setting.find('=');
          if (equals == std::string::npos || equals == 0)
            throw InputError("(command line)", "--set", "expected Section/Name=value, got '" + setting + "'");
          const std::string path = setting.substr(0, equals);
          for (const auto &[earlier, value] : overrides)
            if (earlier == path)
              throw InputError("--set '" + setting + "'", path,
                               "set twice (also --set '" + earlier + "=" + value + "'); expected it once");
          overrides.emplace_back(path, setting.substr(equals + 1));
        }
      return overrides;
    }

    std::string default_output(const std::string &config_file, const std::string &suffix)
    {
      return (std::filesystem::path("results") / (std::filesystem::path(config_file).stem().string() + suffix))
        .string();
    }

    /// Claims a command's output folder: every rank checks it, rank 0 takes it
    /// (before MPI starts).
    std::unique_ptr<OutputFolder> claim_output(const std::string &folder, std::vector<std::string> own_files,
                                               bool force)
    {
      OutputPolicy policy;
      policy.own_files = std::move(own_files);
      policy.force     = force;
      if (launcher_rank() != 0)
        {
          OutputFolder::check(folder, policy);
          return nullptr;
        }
      return std::make_unique<OutputFolder>(folder, policy);
    }

    /// The same for a command's default folder, results/<config name><suffix>, when -o is not given.
    std::unique_ptr<OutputFolder> claim_output(std::string &folder, const std::string &config_file,
                                               const std::string &suffix, std::vector<std::string> own_files,
                                               bool force)
    {
      if (folder.empty())
        folder = default_output(config_file, suffix);
      return claim_output(folder, std::move(own_files), force);
    }

    std::string resources_text(const scenes::ResourceEstimate &estimate, double memory, double disk,
                               const std::string &output_directory)
    {
      return "memory: about " + format_bytes(estimate.memory_bytes) + " for " + estimate.memory_basis + "; " +
             format_bytes(memory) + " available (MemAvailable)\n" + "disk:   about " +
             format_bytes(estimate.disk_bytes) + " for " + estimate.disk_basis + "; " + format_bytes(disk) +
             " free at '" + output_directory + "'\n";
    }

    /// Refuses a run that cannot fit the machine, naming what sets the size.
    void check_resources(const scenes::ResourceEstimate &estimate, const std::string &config_file,
                         const std::string &output_directory)
    {
      const double memory = available_memory_bytes(), disk = free_disk_bytes(output_directory);
      if (estimate.memory_bytes > memory)
        throw InputError(config_file, "", "the run needs about " + format_bytes(estimate.memory_bytes) +
                                            " of memory for " + estimate.memory_basis + ", but " +
                                            format_bytes(memory) +
                                            " is available (MemAvailable); expected a smaller problem");
      if (estimate.disk_bytes > disk)
        throw InputError(config_file, "", "the run writes about " + format_bytes(estimate.disk_bytes) + " for " +
                                            estimate.disk_basis + ", but " + format_bytes(disk) + " is free at '" +
                                            output_directory + "' (-o); expected fewer outputs");
    }

    struct SceneRunOptions
    {
      std::string              config_file, output_directory;
      bool                     plots = true, quiet = false, force = false, dry_run = false;
      std::vector<std::string> settings;
    };

    int run_scene(const SceneRunOptions &options)
    {
      // Everything is read and checked before anything is written: the
      // parameters, the machine's room for the run, the output folder, then
      // the scene's own cross-checks.
      const auto &config_file = options.config_file;
      auto parameters = scenes::load_parameters(config_file, parse_overrides(options.settings));
      const std::string output_directory =
        options.output_directory.empty() ? default_output(config_file, "") : options.output_directory;
      OutputPolicy policy;
      policy.own_files = scene_output_files();
      policy.force     = options.force;
      OutputFolder::check(output_directory, policy);
      const auto estimate = scenes::estimate_resources(parameters);
      if (options.dry_run)
        {
          std::cout << "config: " << config_file << " (scene " << parameters.scene() << "): every parameter valid\n"
                    << resources_text(estimate, available_memory_bytes(), free_disk_bytes(output_directory),
                                      output_directory);
          check_resources(estimate, config_file, output_directory);
          std::cout << "dry run: nothing computed or written\n";
          return exit_ok;
        }
      check_resources(estimate, config_file, output_directory);
      const auto scene = scenes::make_scene(std::move(parameters));
      if (started_by_mpi_launcher())
        { // the ranks build the scene's models together; the run itself is rank 0's
          {
            const fem::ParallelEnvironment mpi;
            scene->prepare();
          }
          if (launcher_rank() != 0)
            return exit_ok;
        }
      const OutputFolder folder(output_directory, policy);
      install_interrupt_handlers();
      const scenes::RunReport report = scene->run({output_directory, options.plots, !options.quiet});
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

    /// `fretsim map`: its options, into `options`.
    CLI::App *add_map_command(CLI::App &app, MapOptions &options)
    {
      auto *map = app.add_subcommand(
        "map", "Run a scene at every point of a grid over one to three of its parameters, in parallel (threads, "
               "and MPI ranks under mpirun), resumably: D_max (converged, with its error bar where the scene "
               "estimates it), where it sits, regime, force amplitude, peak pressure and yield margin per point in "
               "map.h5 and map.csv, and map.png with the D = 1 boundary");
      map->add_option("CONFIG", options.config_file, "Scene file (.prm or .json)")->required();
      map->add_option("--axis", options.axes,
                      "An axis 'Section/Name=FROM:TO:N' (evenly spaced) or 'Section/Name=FROM:TO:N:log' "
                      "(geometric), e.g. --axis 'Loading/Normal load=100:3000:20'; one to three, the first "
                      "varying fastest (default: the scene file's Map/Axes)");
      map->add_flag("--boundary", options.boundary,
                    "Also locate D = 1 along each line of the first axis by bisection between the grid points "
                    "that bracket it (boundary.csv; also with the scene file's Map/Boundary = true)");
      map->add_option("--boundary-tolerance", options.boundary_tolerance,
                      "Bisection stops when the bracket is below this fraction of the first axis's range (of its "
                      "logarithm's on a log axis)")
        ->capture_default_str()
        ->check(CLI::Range(1e-9, 0.5));
      map->add_option("-j,--jobs", options.jobs,
                      "Points run at a time by each process (0: the machine's cores shared by the ranks on it; "
                      "scenes that write files run one at a time)")
        ->capture_default_str()
        ->check(CLI::Range(0, 4096));
      map->add_option("--max-points", options.max_points,
                      "Run at most this many points not yet in map.h5, then stop (a batch job's share; the same "
                      "command continues the map)")
        ->check(CLI::Range(1L, 100000000L));
      return map;
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

    /// What the command line sets: the options every command shares, each
    /// command's own, and the subcommands, to tell which one was given.
    /// CLI11 writes into these members, so the object stays where it was made.
    struct CommandLine
    {
      std::string              scene;
      bool                     no_plots = false, quiet = false, force = false;
      std::vector<std::string> settings;
      // Every command that writes a folder: a new one, or --force to replace
      // the previous result of the same command (its own files only).
      std::vector<std::pair<CLI::Option *, const std::string *>> outputs;

      SceneRunOptions           scene_run;
      CompareTractionOptions    compare;
      RingHousingCommandOptions fe_options; // the commands on a ring_housing configuration share them
      bool                      reduction_study = false;
      CompareOptions            full_fe_check;
      ReferenceOptions          reference;
      MapOptions                map_options;
      StressBenchmarkOptions    stress_bench;

      CLI::App *run = nullptr, *compare_traction = nullptr, *mesh = nullptr, *fe = nullptr, *reduce = nullptr,
               *compare_full = nullptr, *reference_command = nullptr, *map = nullptr, *bench_stresses = nullptr;

      void add_output(CLI::App *command, std::string &output, const std::string &help)
      {
        outputs.emplace_back(command->add_option("-o,--output", output,
                                                 help + "; a new folder, or one holding a previous result with --force"),
                             &output);
        command->add_flag("--force", force,
                          "Replace the previous result in the output folder (only the files this command writes)");
      }
    };

    /// `fretsim run`, `params` and `compare-traction`.
    void add_scene_commands(CLI::App &app, CommandLine &line)
    {
      auto &scene_run = line.scene_run;
      line.run        = app.add_subcommand("run", "Run the scene described by a configuration file");
      line.run->add_option("CONFIG", scene_run.config_file, "Scene file (.prm or .json)")->required();
      line.add_output(line.run, scene_run.output_directory, "Output directory (default: results/<config name>)");
      line.run->add_flag("--no-plots", line.no_plots, "Do not write PNG figures");
      line.run->add_flag("-q,--quiet", line.quiet, "No progress line");
      line.run->add_flag("--dry-run", scene_run.dry_run,
                         "Check the configuration and the output folder and print the run's memory and disk "
                         "estimate; compute and write nothing");
      line.run->add_option("--set", line.settings,
                           "Override a parameter, e.g. --set 'Grid/Cells x=256' (repeatable)");
      auto *params = app.add_subcommand("params", "Print every parameter of a scene: default, allowed values, unit");
      params->add_option("SCENE", line.scene, "Scene name (default: all scenes)");
      auto &compare         = line.compare;
      line.compare_traction = app.add_subcommand(
        "compare-traction", "Run a scene with each traction model (bristle, elastoplastic bristle, exact) and "
                            "report run time, loop, energy and D_max differences against the exact model");
      line.compare_traction->add_option("CONFIG", compare.config_file, "Scene file (.prm or .json)")->required();
      line.add_output(line.compare_traction, compare.output_directory,
                      "Output directory (default: results/<config name>-traction)");
      line.compare_traction->add_flag("--no-plots", line.no_plots, "Do not write the PNG figure");
      line.compare_traction->add_flag("-q,--quiet", line.quiet, "No progress line");
      line.compare_traction->add_option("--set", line.settings,
                                        "Override a parameter, e.g. --set 'Loading/Sliding amplitude=1.12e-6'");
    }

    /// `fretsim mesh`, `fe` and `reduce`, on a ring_housing configuration.
    void add_ring_housing_commands(CLI::App &app, CommandLine &line)
    {
      const auto add_command = [&](const std::string &name, const std::string &description,
                                   const std::string &output_help) {
        auto *command = app.add_subcommand(name, description);
        command->add_option("CONFIG", line.fe_options.config_file,
                            "Configuration file (.prm or .json, Scene = ring_housing)")
          ->required();
        line.add_output(command, line.fe_options.output, output_help);
        command->add_option("--set", line.settings, "Override a parameter, e.g. --set 'Mesh/Element degree=1'");
        return command;
      };
      line.mesh = add_command(
        "mesh",
        "Build or read the ring/housing FE mesh of a ring_housing configuration, check it, write it with its "
        "boundary ids for ParaView (VTU) and print cells, DoFs and the ids found",
        "Output directory (default: results/<config name>-mesh)");
      line.fe = add_command(
        "fe", "Full-FE reference solutions of a ring_housing configuration: static load cases, eigenmodes or a "
              "transient, with stress snapshots in HDF5",
        "Output directory (default: results/<config name>-fe)");
      line.fe->add_flag("--no-plots", line.no_plots, "Do not write PNG figures");
      line.fe->add_flag("-q,--quiet", line.quiet, "No progress display");
      line.reduce = add_command(
        "reduce", "Craig-Bampton reduced model of the ring (constraint modes, characteristic constraint modes, "
                  "fixed-interface modes) written to an HDF5 model file",
        "Model file (default: results/<config name>-model.h5)");
      line.reduce->add_flag("--no-plots", line.no_plots, "Do not write PNG figures");
      line.reduce->add_flag("--study", line.reduction_study,
                            "Error against run time instead: reduce for every (m, n_cc) of the Reduction/Study lists "
                            "and compare with the full FE model (table, CSV, PNG; -o is then a directory)");
      line.reduce->add_flag("-q,--quiet", line.quiet, "No progress display");
    }

    /// A command on a bearing_housing scene file and its run: CONFIG, -o,
    /// --no-plots, -q, --set.
    CLI::App *add_bearing_run_command(CLI::App &app, CommandLine &line, const std::string &name,
                                      const std::string &description, std::string &config_file,
                                      std::string &output_directory, const std::string &set_example)
    {
      CLI::App *command = app.add_subcommand(name, description);
      command->add_option("CONFIG", config_file, "Scene file (.prm or .json, Scene = bearing_housing)")->required();
      line.add_output(command, output_directory, "Output directory (default: results/<config name>-" + name + ")");
      command->add_flag("--no-plots", line.no_plots, "Do not write the PNG figure");
      command->add_flag("-q,--quiet", line.quiet, "No progress display");
      command->add_option("--set", line.settings, "Override a parameter, e.g. --set '" + set_example + "'");
      return command;
    }

    /// `fretsim compare`, `reference` and `map`.
    void add_compare_and_map_commands(CLI::App &app, CommandLine &line)
    {
      line.compare_full = add_bearing_run_command(
        app, line, "compare",
        "Check a bearing_housing run's reduced ring against the full FE model: the same ball loads and interface "
        "tractions at N instants, errors of the recovered displacements and stresses, run times, and the error "
        "against the reduced model's size (table, CSV, PNG)",
        line.full_fe_check.config_file, line.full_fe_check.output_directory, "Compare/Instants=8");
      line.reference_command = add_bearing_run_command(
        app, line, "reference",
        "Set a bearing_housing run against the full FE of the same scene: ring and housing meshed on "
        "Reference/Meshes, driven by the run's ball loads with its layer and friction, the same Dang Van (D_max and "
        "peak pressure of both, the reference's error bar; table, CSV, PNG)",
        line.reference.config_file, line.reference.output_directory, "Reference/Substeps=8");
      line.map = add_map_command(app, line.map_options);
      line.add_output(line.map, line.map_options.output_directory,
                      "Output directory (default: results/<config name>-map); the same command with the same "
                      "folder continues a map that stopped");
      line.map->add_flag("--no-plots", line.no_plots, "Do not write the PNG figure");
      line.map->add_flag("-q,--quiet", line.quiet, "No progress line");
      line.map->add_option("--set", line.settings,
                           "Override a parameter at every point, e.g. --set 'Grid/Cells x=64'");
    }

    /// `fretsim bench stresses`.
    void add_bench_commands(CLI::App &app, CommandLine &line)
    {
      auto *bench = app.add_subcommand("bench", "Error against run time of the numerical approximations");
      bench->require_subcommand(1);
      auto &stress_bench  = line.stress_bench;
      line.bench_stresses = bench->add_subcommand(
        "stresses", "Subsurface-stress evaluators (direct, MLMI, DC-FFT): run time and error against direct "
                    "summation over grid sizes, depth layers and threads; table, CSV and PNG");
      auto *stresses = line.bench_stresses;
      stresses->add_option("--sizes", stress_bench.sizes, "Cells per side")->delimiter(',')->capture_default_str();
      stresses->add_option("--layers", stress_bench.layers, "Depth-layer counts")->delimiter(',')->capture_default_str();
      stresses->add_option("--threads", stress_bench.threads, "Thread counts")->delimiter(',')->capture_default_str();
      stresses->add_option("--direct-limit", stress_bench.direct_time_limit,
                           "Run direct summation only where its predicted time is below this [s]")
        ->capture_default_str();
      line.add_output(stresses, stress_bench.output_directory,
                      "Output directory (default: " + stress_bench.output_directory + ")");
      stresses->add_flag("--no-plots", line.no_plots, "Do not write the PNG figure");
    }

    /// A command's files, absolute, one a line: figures as such, the others under `label`.
    void print_files(const std::vector<std::string> &files, const char *label)
    {
      for (const auto &file : files)
        std::cout << (file.size() > 4 && file.substr(file.size() - 4) == ".png" ? "figure:   " : label)
                  << std::filesystem::absolute(file).string() << "\n";
    }

    int run_traction_comparison_command(CommandLine &line)
    {
      auto &compare     = line.compare;
      compare.plots     = !line.no_plots;
      compare.progress  = !line.quiet;
      compare.overrides = parse_overrides(line.settings);
      const auto folder = claim_output(compare.output_directory, compare.config_file, "-traction",
                                       {"compare_traction.csv", "compare_traction.png", "bristle/",
                                        "elastoplastic_bristle/", "exact_masing/", "exact/"},
                                       line.force);
      install_interrupt_handlers();
      print_files(run_traction_comparison(compare), "table:    ");
      return exit_ok;
    }

    /// `mesh`, `fe` or `reduce`: the output (a folder, or a model file) claimed, then the command.
    int run_ring_housing_command(CommandLine &line)
    {
      auto      &fe_options = line.fe_options;
      const bool mesh(*line.mesh), fe(*line.fe), reduce(*line.reduce);
      fe_options.overrides = parse_overrides(line.settings);
      fe_options.progress  = !line.quiet;
      fe_options.plots     = !line.no_plots;
      std::unique_ptr<OutputFolder> folder;
      if (reduce && !line.reduction_study)
        {
          if (fe_options.output.empty())
            fe_options.output = default_output(fe_options.config_file, "-model.h5");
          prepare_output_file(fe_options.output, "-o", line.force);
        }
      else if (reduce)
        folder = claim_output(fe_options.output, fe_options.config_file, "-reduction-study",
                              {"reduction_study.csv", "reduction_study.png"}, line.force);
      else if (mesh)
        folder = claim_output(fe_options.output, fe_options.config_file, "-mesh", {"mesh*.vtu", "mesh*.pvtu"},
                              line.force);
      else
        folder = claim_output(fe_options.output, fe_options.config_file, "-fe",
                              {"results.h5", "results.xdmf", "results.xdmf.tmp", "summary.json", "summary.json.tmp",
                               "fe_stress.png", "fe_modes.png", "displacement*.vtu", "displacement*.pvtu",
                               "fit_displacement*.vtu", "fit_displacement*.pvtu", "mode_*.vtu", "mode_*.pvtu"},
                              line.force);
      if (mesh)
        {
          run_mesh_command(fe_options, std::cout);
          return exit_ok;
        }
      // `fe` stops a transient between steps and keeps what it wrote; a
      // reduction has no steps to keep (its file appears complete or not at
      // all), so Ctrl-C simply ends it.
      if (fe)
        install_interrupt_handlers();
      print_files(fe                   ? run_fe_command(fe_options, std::cout) :
                  line.reduction_study ? run_reduction_study(fe_options, std::cout) :
                                         run_reduce_command(fe_options, std::cout),
                  "written:  ");
      return exit_ok;
    }

    /// `compare` and `reference`: options from the command line, the output
    /// folder claimed for the command's own files, the command run.
    template <typename Options, typename Command>
    int run_bearing_check(CommandLine &line, Options &options, const std::string &suffix,
                          std::vector<std::string> own_files, Command command)
    {
      options.overrides = parse_overrides(line.settings);
      options.plots     = !line.no_plots;
      options.progress  = !line.quiet;
      const auto folder =
        claim_output(options.output_directory, options.config_file, suffix, std::move(own_files), line.force);
      print_files(command(options, std::cout), "table:    ");
      return exit_ok;
    }

    int run_full_fe_comparison_command(CommandLine &line)
    {
      return run_bearing_check(line, line.full_fe_check, "-compare",
                               {"compare.csv", "compare_housing.csv", "compare_transient.csv", "compare_pressure.csv",
                                "compare.png"},
                               run_compare_command);
    }

    int run_reference(CommandLine &line)
    {
      return run_bearing_check(line, line.reference, "-reference",
                               {"compare_summary.json", "reference.csv", "reference_profile.csv", "reference.png"},
                               run_reference_command);
    }

    int run_map(CommandLine &line)
    {
      auto &map_options = line.map_options;
      if (map_options.output_directory.empty())
        map_options.output_directory = default_output(map_options.config_file, "-map");
      map_options.overrides = parse_overrides(line.settings);
      map_options.plots     = !line.no_plots;
      map_options.progress  = !line.quiet;
      map_options.force     = line.force;
      print_files(run_map_command(map_options), "written:  ");
      return interrupt_requested() ? 128 + interrupt_signal() : exit_ok;
    }

    int run_stress_benchmark_command(CommandLine &line)
    {
      line.stress_bench.plots = !line.no_plots;
      const auto folder       = claim_output(line.stress_bench.output_directory,
                                             {"stress_benchmark.csv", "stress_benchmark.png"}, line.force);
      print_files(run_stress_benchmark(line.stress_bench), "table:    ");
      return exit_ok;
    }

    /// Runs the command that was given; its exit code.
    int run_given_command(CommandLine &line)
    {
      // An empty -o is a mistake (an unset shell variable), not the default.
      for (const auto &[option, value] : line.outputs)
        if (option->count() > 0 && value->empty())
          throw InputError("(command line)", "-o", "expected a folder, got ''");
      if (*line.run)
        {
          line.scene_run.plots    = !line.no_plots;
          line.scene_run.quiet    = line.quiet;
          line.scene_run.force    = line.force;
          line.scene_run.settings = line.settings;
          return run_scene(line.scene_run);
        }
      if (*line.compare_traction)
        return run_traction_comparison_command(line);
      if (*line.mesh || *line.fe || *line.reduce)
        return run_ring_housing_command(line);
      if (*line.compare_full)
        return run_full_fe_comparison_command(line);
      if (*line.reference_command)
        return run_reference(line);
      if (*line.map)
        return run_map(line);
      if (*line.bench_stresses)
        return run_stress_benchmark_command(line);
      return print_parameters(line.scene);
    }
  } // namespace

  int run_command_line(int argc, char **argv)
  {
    CLI::App app{"FretSim: fretting-fatigue simulation of machine contacts (SI units throughout)", "fretsim"};
    app.set_version_flag("--version", version_text());
    app.require_subcommand(1);
    CommandLine line;
    add_scene_commands(app, line);
    add_ring_housing_commands(app, line);
    add_compare_and_map_commands(app, line);
    add_bench_commands(app, line);

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
        return run_given_command(line);
      }
    catch (const InputError &error)
      {
        std::cerr << "fretsim: error: " << error.what() << "\n";
        return exit_bad_input;
      }
    catch (const std::exception &error)
      {
        std::cerr << "fretsim: internal error: " << error.what() << "\n";
        if (output::ResultsFile::file_left_open())
          {
            // HDF5 would retry closing the file at exit and crash; what it
            // holds was flushed step by step.
            std::cout.flush();
            std::cerr.flush();
            std::_Exit(exit_failure);
          }
        return exit_failure;
      }
  }
} // namespace fretsim::app
