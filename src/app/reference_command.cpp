#include "app/reference_command.h"

#include "app/compare_command.h"

#include <fretsim/output/results_file.h>
#include <fretsim/output/summary.h>
#include <fretsim/scenes/bearing_scene.h>
#include <fretsim/scenes/figures.h>
#include <fretsim/scenes/scene.h>

#include <fretsim/contact/dang_van.h>
#include <fretsim/contact/subsurface_stress.h>
#include <fretsim/fem/elastic_model.h>
#include <fretsim/fem/parallel_environment.h>
#include <fretsim/models/fe_reference.h>
#include <fretsim/models/interface_influence.h>
#include <fretsim/models/reduction.h>
#include <fretsim/models/ring_stress.h>
#include <fretsim/models/ring_housing.h>
#include <fretsim/reduction/reduced_model.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <memory>
#include <numeric>
#include <omp.h>
#include <optional>
#include <ostream>
#include <sstream>

namespace fretsim::app
{
  namespace
  {
    using Clock = std::chrono::steady_clock;
    double seconds_since(Clock::time_point start)
    {
      return std::chrono::duration<double>(Clock::now() - start).count();
    }
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();

    /// Everything the reference needs, read and checked before anything is built.
    struct Inputs
    {
      CompareInputs                              paths;
      scenes::BearingHousingScene::ReferenceView view;
      models::RingHousingRequest                 ring;
      std::optional<models::HousingAround>       housing;
      std::vector<fem::MeshDivisions>            meshes;
      int                                        substeps = 4, snapshots = 0, points_per_side = 3;
    };

    std::vector<fem::MeshDivisions> parse_meshes(const SceneParameters &p, double grading)
    {
      std::vector<fem::MeshDivisions> meshes;
      std::stringstream               list(p.get("Reference/Meshes"));
      std::string                     item;
      while (std::getline(list, item, ';'))
        {
          if (item.find_first_not_of(" \t") == std::string::npos)
            continue;
          const std::vector<long> c = parse_cell_counts(item, 5);
          if (c.empty() || c[0] < 3)
            p.reject("Reference/Meshes", "expected 'around x radial ring x radial housing x axial x axial land' "
                                         "cells (whole numbers >= 1, at least 3 around) per mesh, got '" +
                                           item + "'");
          fem::MeshDivisions d;
          d.circumferential = static_cast<unsigned int>(c[0]);
          d.radial_ring     = static_cast<unsigned int>(c[1]);
          d.radial_housing  = static_cast<unsigned int>(c[2]);
          d.axial           = static_cast<unsigned int>(c[3]);
          d.axial_land      = static_cast<unsigned int>(c[4]);
          d.radial_grading  = grading;
          meshes.push_back(d);
        }
      if (meshes.empty())
        p.reject("Reference/Meshes", "is empty; give at least one mesh");
      return meshes;
    }

    Inputs read_inputs(const ReferenceOptions &options)
    {
      Inputs in;
      in.paths = read_compare_inputs(options.config_file, options.overrides);
      SceneParameters p = scenes::declare_parameters("bearing_housing");
      p.parse_file(options.config_file);
      for (const auto &[path, value] : options.overrides)
        p.set(path, value);
      const double grading = p.get_double("Reference/Radial grading");
      in.substeps        = static_cast<int>(p.get_integer("Reference/Substeps"));
      in.snapshots       = static_cast<int>(p.get_integer("Reference/Snapshots"));
      in.points_per_side = static_cast<int>(p.get_integer("Reference/Points per cell side"));
      const std::string housing = p.get("Reference/Housing");
      in.meshes = parse_meshes(p, grading);
      in.view = scenes::BearingHousingScene(std::move(p)).reference_view();
      if (in.view.flexible_housing)
        throw InputError(options.config_file, "Model/Housing reduction configuration",
                 "names a flexible housing; `fretsim reference` checks the rigid housing's run (with or without "
                 "its half-space), whose full-FE housing is Reference/Housing");
      in.ring = models::read_ring_housing_request(models::read_ring_housing_parameters(in.view.reduction_config, {}));
      if (!housing.empty())
        {
          const auto file = (std::filesystem::path(options.config_file).parent_path() / housing).lexically_normal();
          if (!std::filesystem::is_regular_file(file))
            throw InputError(options.config_file, "Reference/Housing", "no file '" + file.string() + "'");
          in.housing = models::read_housing_around(file.string(), in.ring.ring, options.config_file, "Reference/Housing");
        }
      return in;
    }

    /// The run's output times as its results file holds them.
    struct Run
    {
      std::vector<double> time, ball_angle, ball_load, pressure, shear_x, shear_y, stress, risk_max;
      std::size_t         snapshots = 0, balls = 0;
      double              seconds   = nan;
      std::string         ring_stresses = "half-space"; ///< the run's stress model (a run without the attribute had only this)
    };

    Run read_run(const Inputs &in, const fem::CylinderGrid &grid)
    {
      using output::ResultsFile;
      const std::string &file   = in.paths.results_file;
      const auto         reject = [&](const std::string &problem) {
        throw InputError(in.paths.source, "Compare/Results file", "'" + file + "' " + problem);
      };
      if (!std::filesystem::exists(file))
        reject("does not exist; run the scene first (`fretsim run " + in.paths.source + "`)");
      Run r;
      try
        {
          std::vector<std::size_t> dims;
          r.time      = ResultsFile::read_dataset(file, "/time", &dims);
          r.snapshots = r.time.size();
          r.ball_angle = ResultsFile::read_dataset(file, "/fields/ball_angle", &dims);
          r.balls      = dims.size() == 2 ? dims[1] : 0;
          r.ball_load  = ResultsFile::read_dataset(file, "/fields/ball_load", &dims);
          r.pressure   = ResultsFile::read_dataset(file, "/fields/pressure", &dims);
          if (dims != std::vector<std::size_t>{r.snapshots, std::size_t(grid.ny), std::size_t(grid.nx)})
            reject("has /fields/pressure on another grid than the model's");
          r.shear_x = ResultsFile::read_dataset(file, "/fields/shear_x", &dims);
          r.shear_y = ResultsFile::read_dataset(file, "/fields/shear_y", &dims);
          r.risk_max = ResultsFile::read_dataset(file, "/fields/risk_max", &dims);
          if (dims != std::vector<std::size_t>{in.view.depth_layers.size(), std::size_t(grid.ny), std::size_t(grid.nx)})
            reject("has no /fields/risk_max on the scene's depth layers (a run that did not finish?)");
          try
            {
              r.stress = ResultsFile::read_dataset(file, "/fields/stress", &dims);
            }
          catch (const std::exception &)
            {
              r.stress.clear(); // a run from before stresses were written: no stress comparison
            }
          try
            {
              r.seconds = ResultsFile::read_double_attribute(file, "/", "run_seconds");
              r.ring_stresses = ResultsFile::read_string_attribute(file, "/", "ring_stresses");
            }
          catch (const std::exception &)
            {
            }
        }
      catch (const InputError &)
        {
          throw;
        }
      catch (const std::exception &error)
        {
          reject(std::string("cannot be read as a bearing_housing results file: ") + error.what());
        }
      if (r.snapshots == 0 || r.balls == 0)
        reject("holds no snapshot with balls");
      return r;
    }

    /// What one mesh gives.
    struct MeshResult
    {
      fem::MeshDivisions  divisions;
      unsigned long       ring_dofs = 0, housing_dofs = 0;
      int                 period = 1;
      double              table_seconds = 0.0, march_seconds = 0.0;
      double              risk_max = 0.0, peak_pressure = 0.0;
      /// D_max of the full-FE ring's stresses under the run's own tractions
      /// and balls: the run's stress model's share of its error.
      double              risk_max_of_run_tractions = 0.0;
      std::size_t         risk_point = 0, peak_snapshot = 0;
      double              stress_difference = 0.0, stress_scale = 0.0; ///< max |σ_run − σ_FE|, max |σ_FE| [Pa]
      long                iterations = 0, linear_iterations = 0;
      std::vector<double> peak_pressure_field;                        ///< at peak_snapshot [cell]
      std::vector<double> risk_max_field;                             ///< [layer][cell]
    };

    std::string describe(const fem::MeshDivisions &d)
    {
      return std::to_string(d.circumferential) + "x" + std::to_string(d.radial_ring) + "x" +
             std::to_string(d.radial_housing) + "x" + std::to_string(d.axial) + "x" + std::to_string(d.axial_land);
    }

    /// The housing's tables on the same divisions, held as its configuration holds it.
    models::InterfaceInfluence housing_influence(const Inputs &in, const fem::CylinderGrid &grid,
                                                 const fem::MeshDivisions &divisions)
    {
      models::RingHousingRequest housing = in.housing->request;
      housing.divisions                  = divisions;
      housing.refinements                = 0;
      auto mesh = std::make_shared<const fem::Mesh>(models::build_ring_housing_mesh(housing, ""));
      fem::ElasticModel        fe(mesh, housing.materials, housing.degree, in.housing->supports);
      models::InfluenceRequest request;
      request.support               = models::InfluenceSupport::housing_bore;
      request.circumferential_cells = divisions.circumferential;
      request.points_per_side       = in.points_per_side;
      return models::interface_influence(fe, grid, request);
    }

    MeshResult solve_on_mesh(const Inputs &in, const reduction::ReducedModel &model, const Run &run,
                             const fem::MeshDivisions &divisions, std::size_t snapshots, std::ostream &out,
                             bool root)
    {
      MeshResult               r;
      const fem::CylinderGrid &grid = model.interface_grid.grid;
      r.divisions                   = divisions;
      const auto table_start        = Clock::now();
      const models::InterfaceInfluence ring_tables =
        models::ring_influence(in.ring, in.view.reduction_config, model, divisions, in.view.depth_layers,
                               in.points_per_side);
      r.ring_dofs                                  = ring_tables.dofs;
      r.period                                     = ring_tables.period;
      std::optional<models::InterfaceInfluence> housing_tables;
      if (in.housing)
        {
          housing_tables = housing_influence(in, grid, divisions);
          r.housing_dofs = housing_tables->dofs;
        }
      r.table_seconds = seconds_since(table_start);

      // The march's convolutions are small (48 rows per column): on one
      // thread they run faster than two threads' synchronisation allows.
      const int  threads     = omp_get_max_threads();
      omp_set_num_threads(1);
      const auto march_start = Clock::now();
      models::ReferenceSettings   settings;
      settings.substeps = in.substeps;
      const models::ReferenceInterface law{in.view.friction_coefficient, in.view.normal_stiffness,
                                           in.view.tangential_stiffness, in.view.radial_interference};
      models::FeReference reference(ring_tables, housing_tables ? &*housing_tables : nullptr, law, settings);
      const std::size_t   cells = grid.size(), layers = in.view.depth_layers.size();
      contact::DangVanField risk(layers * cells, in.view.dang_van_constants, in.view.dang_van);
      contact::DangVanField run_traction_risk(layers * cells, in.view.dang_van_constants, in.view.dang_van);
      contact::StressField  field;
      field.resize(static_cast<int>(layers), grid.ny, grid.nx);
      const std::size_t per_snapshot = layers * 6 * cells;
      for (std::size_t k = 0; k < snapshots; ++k)
        {
          models::ReferenceLoads loads;
          loads.time = run.time[k];
          loads.ball_angles.assign(run.ball_angle.begin() + k * run.balls, run.ball_angle.begin() + (k + 1) * run.balls);
          loads.ball_loads.assign(run.ball_load.begin() + k * run.balls, run.ball_load.begin() + (k + 1) * run.balls);
          const models::ReferenceState state = reference.advance(loads);
          r.iterations += state.iterations;
          r.linear_iterations += state.linear_iterations;
          field.values = state.stress;
          risk.add_step(field);
          const auto run_field = [&](const std::vector<double> &all) {
            return std::vector<double>(all.begin() + k * cells, all.begin() + (k + 1) * cells);
          };
          field.values =
            reference.ring_stress(loads, run_field(run.pressure), run_field(run.shear_x), run_field(run.shear_y));
          run_traction_risk.add_step(field);
          const double peak = *std::max_element(state.pressure.begin(), state.pressure.end());
          if (peak > r.peak_pressure)
            {
              r.peak_pressure       = peak;
              r.peak_snapshot       = k;
              r.peak_pressure_field = state.pressure;
            }
          if (run.stress.size() >= (k + 1) * per_snapshot)
            for (std::size_t q = 0; q < per_snapshot; ++q)
              {
                r.stress_difference = std::max(r.stress_difference, std::abs(run.stress[k * per_snapshot + q] - state.stress[q]));
                r.stress_scale      = std::max(r.stress_scale, std::abs(state.stress[q]));
              }
          if (root && (k + 1) % 20 == 0)
            out << "  " << describe(divisions) << ": " << k + 1 << " of " << snapshots << " output times\n"
                << std::flush;
        }
      r.march_seconds  = seconds_since(march_start);
      omp_set_num_threads(threads);
      r.risk_max_field = risk.risk_max();
      r.risk_point     = static_cast<std::size_t>(
        std::max_element(r.risk_max_field.begin(), r.risk_max_field.end()) - r.risk_max_field.begin());
      r.risk_max = r.risk_max_field[r.risk_point];
      r.risk_max_of_run_tractions =
        *std::max_element(run_traction_risk.risk_max().begin(), run_traction_risk.risk_max().end());
      return r;
    }

    /// The reference's discretisation error from the last three meshes (or
    /// two): Richardson's estimate where the differences shrink, else the
    /// larger difference itself.
    double error_estimate(const std::vector<double> &values)
    {
      const std::size_t n = values.size();
      if (n < 2)
        return nan;
      const double last = std::abs(values[n - 1] - values[n - 2]);
      if (n < 3)
        return last;
      const double before = std::abs(values[n - 2] - values[n - 3]);
      if (last < before && last > 0.0)
        {
          const double ratio = last / before; // geometric convergence: the rest of the series
          return std::max(last * ratio / (1.0 - ratio), last);
        }
      return std::max(last, before);
    }

    double relative(double value, double reference) { return (value - reference) / reference; }

    /// Per column: the largest over rows (and layers) of a field [layer][ny][nx].
    std::vector<double> column_maxima(const std::vector<double> &field, const fem::CylinderGrid &grid)
    {
      std::vector<double> columns(static_cast<std::size_t>(grid.nx), 0.0);
      for (std::size_t k = 0; k < field.size(); ++k)
        {
          double &c = columns[k % static_cast<std::size_t>(grid.nx)];
          c         = std::max(c, field[k]);
        }
      return columns;
    }
  } // namespace

  namespace
  {
    std::vector<double> per_mesh(const std::vector<MeshResult> &results, double MeshResult::*value)
    {
      std::vector<double> values;
      for (const auto &r : results)
        values.push_back(r.*value);
      return values;
    }

    /// The finest mesh against the run, with the meshes' spread.
    struct Verdict
    {
      double run_risk = 0.0, run_peak = 0.0, risk_error = nan, peak_error = nan, risk_rel = nan, peak_rel = nan;
      double stress_rel = nan, fe_seconds = 0.0;
    };

    Verdict judge(const std::vector<MeshResult> &results, const Run &run, std::size_t snapshots, std::size_t cells)
    {
      const MeshResult &fine = results.back();
      Verdict           v;
      for (std::size_t q = 0; q < snapshots * cells; ++q)
        v.run_peak = std::max(v.run_peak, run.pressure[q]);
      v.run_risk   = *std::max_element(run.risk_max.begin(), run.risk_max.end());
      v.risk_error = error_estimate(per_mesh(results, &MeshResult::risk_max));
      v.peak_error = error_estimate(per_mesh(results, &MeshResult::peak_pressure));
      v.risk_rel   = relative(v.run_risk, fine.risk_max);
      v.peak_rel   = relative(v.run_peak, fine.peak_pressure);
      v.stress_rel = fine.stress_scale > 0.0 ? fine.stress_difference / fine.stress_scale : nan;
      v.fe_seconds = fine.table_seconds + fine.march_seconds;
      return v;
    }

    void print_verdict(std::ostream &out, const Verdict &v, const MeshResult &fine, const Run &run)
    {
      const auto percent = [](double value) {
        std::ostringstream s;
        s << std::showpos << std::fixed << std::setprecision(1) << 100.0 * value << " %";
        return s.str();
      };
      out << "\nverdict:      D_max co-simulation " << std::setprecision(4) << v.run_risk << ", full FE "
          << fine.risk_max << " +- " << v.risk_error << " (" << percent(v.risk_rel) << ")\n"
          << "              peak pressure co-simulation " << std::setprecision(4) << v.run_peak / 1e6
          << " MPa, full FE " << fine.peak_pressure / 1e6 << " +- " << v.peak_error / 1e6 << " MPa ("
          << percent(v.peak_rel) << ")\n"
          << "              interface stresses: largest difference " << std::setprecision(3) << 100.0 * v.stress_rel
          << " % of the full FE's largest; the full FE's stresses of the co-simulation's own tractions give D_max "
          << std::setprecision(4) << fine.risk_max_of_run_tractions << "\n"
          << "              time: co-simulation " << run.seconds << " s, full FE (finest mesh) " << v.fe_seconds
          << " s\n";
    }

    std::vector<std::string> write_files(const std::string &directory, const Inputs &in, const Run &run,
                                         const std::vector<MeshResult> &results, const Verdict &v,
                                         const fem::CylinderGrid &grid, std::size_t snapshots, bool plots)
    {
      const MeshResult        &fine = results.back();
      std::vector<std::string> files;
      std::filesystem::create_directories(directory);
      output::Summary summary;
      summary.set("full_fe_risk_max", fine.risk_max);
      summary.set("full_fe_risk_max_error_estimate", v.risk_error);
      summary.set("cosim_risk_max", v.run_risk);
      summary.set("cosim_ring_stresses", run.ring_stresses);
      summary.set("full_fe_stress_risk_max_of_cosim_tractions", fine.risk_max_of_run_tractions);
      summary.set("risk_max_relative_error", v.risk_rel);
      summary.set("full_fe_peak_pressure_Pa", fine.peak_pressure);
      summary.set("full_fe_peak_pressure_error_estimate_Pa", v.peak_error);
      summary.set("cosim_peak_pressure_Pa", v.run_peak);
      summary.set("peak_pressure_relative_error", v.peak_rel);
      summary.set("interface_stress_relative_error", v.stress_rel);
      summary.set("full_fe_wall_time_s", v.fe_seconds);
      summary.set("cosim_wall_time_s", run.seconds);
      summary.set("speed_ratio", v.fe_seconds / run.seconds);
      summary.set("snapshots", static_cast<long long>(snapshots));
      summary.set("substeps", static_cast<long long>(in.substeps));
      summary.set("full_fe_risk_max_per_mesh", per_mesh(results, &MeshResult::risk_max));
      summary.set("full_fe_peak_pressure_per_mesh_Pa", per_mesh(results, &MeshResult::peak_pressure));
      summary.set("full_fe_stress_risk_max_of_cosim_tractions_per_mesh",
                  per_mesh(results, &MeshResult::risk_max_of_run_tractions));
      summary.set("friction_coefficient", in.view.friction_coefficient);
      summary.set("housing", std::string(in.housing ? "meshed" : "rigid"));
      summary.set("run_local_compliance", in.view.local_compliance);
      summary.write((std::filesystem::path(directory) / "compare_summary.json").string());
      files.push_back((std::filesystem::path(directory) / "compare_summary.json").string());

      const std::string table = (std::filesystem::path(directory) / "reference.csv").string();
      {
        std::ofstream csv(table);
        csv << "mesh,ring_dofs,housing_dofs,period_columns,risk_max,risk_max_theta_deg,risk_max_depth_m,"
               "risk_max_of_run_tractions,peak_pressure_Pa,stress_difference_Pa,stress_scale_Pa,table_seconds,march_seconds,iterations,linear_iterations\n"
            << std::setprecision(10);
        for (const auto &r : results)
          {
            const std::size_t cell = r.risk_point % grid.size(), layer = r.risk_point / grid.size();
            csv << describe(r.divisions) << ',' << r.ring_dofs << ',' << r.housing_dofs << ',' << r.period << ','
                << r.risk_max << ',' << grid.x(static_cast<int>(cell % grid.nx)) / grid.radius * 180.0 / M_PI << ','
                << in.view.depth_layers[layer] << ',' << r.risk_max_of_run_tractions << ',' << r.peak_pressure << ','
                << r.stress_difference << ','
                << r.stress_scale << ',' << r.table_seconds << ',' << r.march_seconds << ',' << r.iterations << ','
                << r.linear_iterations << '\n';
          }
      }
      files.push_back(table);

      const std::string profile = (std::filesystem::path(directory) / "reference_profile.csv").string();
      {
        const std::vector<double> fe_p = column_maxima(fine.peak_pressure_field, grid),
                                  run_p = column_maxima(std::vector<double>(run.pressure.begin() + fine.peak_snapshot * grid.size(),
                                                                            run.pressure.begin() + (fine.peak_snapshot + 1) * grid.size()),
                                                        grid),
                                  fe_d = column_maxima(fine.risk_max_field, grid), run_d = column_maxima(run.risk_max, grid);
        std::ofstream csv(profile);
        csv << "theta_deg,cosim_pressure_Pa,full_fe_pressure_Pa,cosim_risk_max,full_fe_risk_max\n" << std::setprecision(10);
        for (int i = 0; i < grid.nx; ++i)
          csv << grid.x(i) / grid.radius * 180.0 / M_PI << ',' << run_p[i] << ',' << fe_p[i] << ',' << run_d[i] << ','
              << fe_d[i] << '\n';
      }
      files.push_back(profile);
      if (plots)
        for (const auto &png : scenes::run_plot_script("plot_reference.py", {directory}))
          files.push_back(png);
      return files;
    }

    reduction::ReducedModel read_model(const Inputs &in)
    {
      try
        {
          return reduction::read_model_file(in.paths.model_file);
        }
      catch (const reduction::ModelFileError &error)
        {
          throw InputError(in.paths.source, "Model/Model file", error.what());
        }
    }
  } // namespace

  std::vector<std::string> run_reference_command(const ReferenceOptions &options, std::ostream &out)
  {
    const Inputs                  in    = read_inputs(options);
    const reduction::ReducedModel model = read_model(in);
    const fem::CylinderGrid      &grid  = model.interface_grid.grid;
    const Run                     run   = read_run(in, grid);
    const std::size_t snapshots =
      in.snapshots > 0 ? std::min<std::size_t>(run.snapshots, static_cast<std::size_t>(in.snapshots)) : run.snapshots;
    const std::string directory = options.output_directory.empty()
                                    ? (std::filesystem::path("results") /
                                       (std::filesystem::path(options.config_file).stem().string() + "-reference"))
                                        .string()
                                    : options.output_directory;

    std::unique_ptr<fem::ParallelEnvironment> mpi;
    if (!fem::ParallelEnvironment::active())
      mpi = std::make_unique<fem::ParallelEnvironment>();
    const bool root = fem::ParallelEnvironment::rank() == 0;
    if (root)
      out << "reference:    " << in.meshes.size() << " full-FE meshes of the ring"
          << (in.housing ? " and the housing" : " on a rigid housing") << ", " << snapshots << " output times of "
          << in.paths.results_file << ", " << in.substeps << " quasi-static increments each, mu = "
          << in.view.friction_coefficient << "\n"
          << std::flush;

    std::vector<MeshResult> results;
    for (const auto &divisions : in.meshes)
      {
        results.push_back(solve_on_mesh(in, model, run, divisions, snapshots, out, root));
        const MeshResult &r = results.back();
        if (root)
          out << "  mesh " << describe(divisions) << ": ring " << r.ring_dofs << " + housing " << r.housing_dofs
              << " DoFs, tables " << std::fixed << std::setprecision(1) << r.table_seconds << " s, march "
              << r.march_seconds << " s; D_max " << std::setprecision(5) << r.risk_max << ", peak pressure "
              << std::setprecision(2) << r.peak_pressure / 1e6 << " MPa\n"
              << std::defaultfloat << std::flush;
      }
    if (!root)
      return {};
    const Verdict verdict = judge(results, run, snapshots, grid.size());
    print_verdict(out, verdict, results.back(), run);
    return write_files(directory, in, run, results, verdict, grid, snapshots, options.plots);
  }
} // namespace fretsim::app
