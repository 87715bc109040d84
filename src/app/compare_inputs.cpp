// `fretsim compare`'s inputs: the scene file read into CompareInputs, then
// every input checked and read into the Plan the other stages work on.
#include "app/compare_stages.h"

#include <fretsim/output/results_file.h>
#include <fretsim/scenes/scene.h>

#include <fretsim/models/model_source.h>
#include <fretsim/models/reduced_statics.h>
#include <fretsim/models/reduction.h>
#include <fretsim/reduction/craig_bampton.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>

namespace fretsim::app
{
  namespace
  {
    const std::string bearing_scene = "bearing_housing";

    std::vector<unsigned int> counts(const SceneParameters &p, const std::string &path)
    {
      std::vector<unsigned int> result;
      for (const double value : p.get_double_list(path))
        {
          if (value != std::floor(value) || value < 0.0)
            p.reject(path, "expected non-negative whole numbers, got " + std::to_string(value));
          result.push_back(static_cast<unsigned int>(value));
        }
      if (result.empty())
        p.reject(path, "is empty; give at least one count");
      return result;
    }
  } // namespace

  CompareInputs read_compare_inputs(const std::string &config_file,
                                    const std::vector<std::pair<std::string, std::string>> &overrides)
  {
    // The bearing_housing scene declares Model/... and Compare/... (bearing_scene.cpp).
    SceneParameters::scene_of_file(config_file, {bearing_scene}); // rejects a file of another scene
    SceneParameters p = scenes::declare_parameters(bearing_scene);
    p.parse_file(config_file);
    for (const auto &[path, value] : overrides)
      p.set(path, value);

    CompareInputs in;
    in.source                    = config_file;
    const std::string reduction  = p.get("Model/Reduction configuration");
    if (reduction.empty())
      p.reject("Model/Reduction configuration", "is empty; name the ring_housing configuration of the reduced model");
    // The reduction configurations and model files as the scene resolves
    // them (with the ring's basis sizes the scene may set over its own).
    const models::ModelSource ring = models::ring_model_source(p);
    in.reduction_config            = ring.config;
    in.model_file                  = ring.file;
    in.model_overrides             = ring.overrides;
    in.results_file = p.get("Compare/Results file");
    if (in.results_file.empty())
      in.results_file =
        (std::filesystem::path("results") / std::filesystem::path(config_file).stem() / "results.h5").string();
    in.instants              = static_cast<unsigned int>(p.get_integer("Compare/Instants"));
    in.full_transient_steps  = static_cast<unsigned int>(p.get_integer("Compare/Full transient steps"));
    in.fixed_interface_modes = counts(p, "Compare/Fixed-interface modes");
    in.constraint_modes      = counts(p, "Compare/Characteristic constraint modes");
    for (const unsigned int c : in.constraint_modes)
      if (c == 0)
        p.reject("Compare/Characteristic constraint modes", "expected counts >= 1, got 0");
    if (const std::string housing = p.get("Compare/Full transient housing"); !housing.empty())
      {
        in.full_transient_housing_config =
          (std::filesystem::path(config_file).parent_path() / housing).lexically_normal().string();
        if (!std::filesystem::is_regular_file(in.full_transient_housing_config))
          p.reject("Compare/Full transient housing", "no file '" + in.full_transient_housing_config + "'");
      }
    in.normal_stiffness    = p.get_double("Interface/Normal stiffness");
    in.radial_interference = p.get_double("Interface/Radial interference");
    if (!p.get("Model/Housing reduction configuration").empty())
      {
        const models::ModelSource housing = models::housing_model_source(p);
        in.housing_reduction_config       = housing.config;
        in.housing_model_file             = housing.file;
      }
    return in;
  }

  namespace compare
  {
    namespace
    {
      using models::RingHousingRequest;

      /// Throws the InputError of `parameter` in the scene file.
      [[noreturn]] void reject(const CompareInputs &in, const std::string &parameter, const std::string &problem)
      {
        throw InputError(in.source, parameter, problem);
      }

      void check_parameters(const CompareInputs &in)
      {
        if (in.instants == 0)
          reject(in, "Compare/Instants", "must be at least 1");
        if (!(in.normal_stiffness > 0.0) || !std::isfinite(in.normal_stiffness))
          reject(in, "Interface/Normal stiffness",
                 "must be a finite k_n > 0 Pa/m (the Winkler layer the pressure is compared on), got " +
                   std::to_string(in.normal_stiffness));
        if (!std::isfinite(in.radial_interference))
          reject(in, "Interface/Radial interference", "must be finite");
      }

      /// The reduction configuration's body: the ring alone, meshed parametrically.
      RingHousingRequest read_ring(const CompareInputs &in)
      {
        const SceneParameters    ring_parameters = models::read_ring_housing_parameters(in.reduction_config, {});
        const RingHousingRequest body            = models::read_ring_housing_request(ring_parameters);
        if (body.bodies != "ring")
          reject(in, "Model/Reduction configuration",
                 "names '" + in.reduction_config + "' with Mesh/Bodies = " + body.bodies +
                   "; the reduced model is of the ring alone (Mesh/Bodies = ring)");
        if (!body.gmsh_file.empty())
          reject(in, "Model/Reduction configuration",
                 "names '" + in.reduction_config +
                   "', a Gmsh mesh; the balls are placed on the Ring section's raceway, "
                   "which needs Mesh/Source = parametric");
        return body;
      }

      /// The reduced model, made from the configuration's inputs, with the
      /// operators the comparison samples.
      reduction::ReducedModel read_model(const CompareInputs &in)
      {
        reduction::ReducedModel model;
        try
          {
            // The hash `fretsim reduce` writes for this configuration: a model made
            // from other inputs (geometry, mesh, material, mode counts) is refused.
            model = reduction::read_model_file(in.model_file,
                                               models::reduce_input_hash(in.reduction_config, in.model_overrides));
          }
        catch (const reduction::ModelFileError &error)
          {
            reject(in, "Model/Model file",
                   std::string(error.what()) + " (reduction configuration '" + in.reduction_config + "')");
          }
        if (model.interface_grid.grid.nx == 0)
          reject(in, "Model/Model file", "'" + in.model_file + "' has no interface grid operators: reduce with "
                                                             "Reduction/Interface grid circumferential cells > 0");
        if (model.raceway.angles.empty())
          reject(in, "Model/Model file", "'" + in.model_file + "' has no raceway ball operator: reduce with "
                                                             "Reduction/Raceway ball positions > 0");
        // Inertia relief needs the rigid-body motions among the coordinates: the
        // first six characteristic constraint modes of a free ring (Guyan
        // eigenvalue 0; below the 1 Hz rigid-body cutoff of fem::ModalSettings).
        if (!models::starts_with_rigid_motions(model.matrices))
          reject(in, "Model/Model file",
                 "'" + in.model_file + "' does not start with the six rigid-body motions of the free "
                                       "ring among its characteristic constraint modes (a free ring "
                                       "reduced with Reduction/Characteristic constraint modes > 6 "
                                       "does)");
        return model;
      }

      /// Reads the results file's datasets into `r` and checks their shapes
      /// against the model's interface grid and coordinates.
      void read_run_fields(const CompareInputs &in, const reduction::ReducedModel &model, RunFields &r)
      {
        const auto reject_file = [&](const std::string &problem) {
          reject(in, "Compare/Results file", "'" + in.results_file + "' " + problem);
        };
        using output::ResultsFile;
        const auto              &grid = model.interface_grid.grid;
        std::vector<std::size_t> dims;
        r.time        = ResultsFile::read_dataset(in.results_file, "/time", &dims);
        r.n_snapshots = r.time.size();
        if (r.n_snapshots == 0)
          reject_file("holds no snapshot");
        for (const auto &[name, field] : {std::pair<const char *, std::vector<double> *>{"pressure", &r.pressure},
                                          {"shear_x", &r.shear_x},
                                          {"shear_y", &r.shear_y}})
          {
            *field = ResultsFile::read_dataset(in.results_file, std::string("/fields/") + name, &dims);
            if (dims != std::vector<std::size_t>{r.n_snapshots, static_cast<std::size_t>(grid.ny),
                                                 static_cast<std::size_t>(grid.nx)})
              reject_file(std::string("has /fields/") + name + " of another shape than [" +
                          std::to_string(r.n_snapshots) + ", " + std::to_string(grid.ny) + ", " +
                          std::to_string(grid.nx) + "] (snapshots, the model's interface grid): the run used another model");
          }
        r.n_cells    = grid.size();
        r.ball_angle = ResultsFile::read_dataset(in.results_file, "/fields/ball_angle", &dims);
        if (dims.size() != 2 || dims[0] != r.n_snapshots || dims[1] == 0)
          reject_file("has /fields/ball_angle of a shape other than [snapshots, balls]");
        r.n_balls   = dims[1];
        r.ball_load = ResultsFile::read_dataset(in.results_file, "/fields/ball_load", &dims);
        if (dims != std::vector<std::size_t>{r.n_snapshots, r.n_balls})
          reject_file("has /fields/ball_load of another shape than /fields/ball_angle");
        r.modal_coordinates = ResultsFile::read_dataset(in.results_file, "/fields/modal_coordinates", &dims);
        if (dims.size() != 2 || dims[0] != r.n_snapshots || dims[1] == 0)
          reject_file("has /fields/modal_coordinates of a shape other than [snapshots, coordinates]");
        r.n_coordinates = dims[1];
      }

      /// The results file's attribute `name`, or `fallback` if it has none.
      template <typename Read, typename Value>
      Value attribute_or(Read read, const Value &fallback)
      {
        try
          {
            return read();
          }
        catch (const std::exception &)
          {
            return fallback;
          }
      }

      RunFields read_run(const CompareInputs &in, const reduction::ReducedModel &model)
      {
        const auto reject_file = [&](const std::string &problem) {
          reject(in, "Compare/Results file", "'" + in.results_file + "' " + problem);
        };
        if (!std::filesystem::exists(in.results_file))
          reject_file("does not exist; run the scene first (`fretsim run " + in.source + "`)");
        using output::ResultsFile;
        const std::string &file = in.results_file;
        RunFields          r;
        try
          {
            read_run_fields(in, model, r);
            // A run from before these were recorded (each came at its own
            // time) had the ring alone on the layer: the defaults stay.
            r.housing_coordinates = attribute_or(
              [&] { return static_cast<std::size_t>(ResultsFile::read_double_attribute(file, "/", "housing_coordinates")); },
              r.housing_coordinates);
            r.local_compliance = attribute_or(
              [&] { return ResultsFile::read_string_attribute(file, "/", "local_compliance"); }, r.local_compliance);
            if (r.housing_coordinates >= r.n_coordinates)
              reject_file("records " + std::to_string(r.housing_coordinates) + " housing coordinates of " +
                          std::to_string(r.n_coordinates) + " in /fields/modal_coordinates: none left for the ring");
            // A run with another model of the same ring (e.g. a larger n_cc)
            // still gives loads and pressures to compare; only its q is not.
            r.other_model = r.n_coordinates - r.housing_coordinates != model.matrices.size();
          }
        catch (const InputError &)
          {
            throw;
          }
        catch (const std::exception &error)
          {
            reject_file(std::string("cannot be read as a bearing_housing results file: ") + error.what());
          }
        // Without it the instants spread over the whole run instead.
        r.ball_pass_frequency_hz =
          attribute_or([&] { return ResultsFile::read_double_attribute(file, "/", "ball_pass_frequency_hz"); }, 0.0);
        try
          {
            r.integrator_steps        = ResultsFile::read_double_attribute(file, "/", "integrator_steps");
            r.run_seconds             = ResultsFile::read_double_attribute(file, "/", "run_seconds");
            r.inner_ring_frequency_hz = ResultsFile::read_double_attribute(file, "/", "inner_ring_frequency_hz");
          }
        catch (const std::exception &)
          {
            r.integrator_steps = r.run_seconds = r.inner_ring_frequency_hz = 0.0; // no timing to set the full one against
          }
        for (const double v : r.ball_load)
          if (!std::isfinite(v))
            reject_file("holds ball loads that are not finite");
        return r;
      }

      /// A flexible housing's own model, when the run had one and the scene
      /// names it; its size must be the run's housing coordinates.
      std::unique_ptr<HousingComparison> read_housing(const CompareInputs &in, const RingHousingRequest &body,
                                                      const reduction::ReducedModel &model, const RunFields &run)
      {
        if (run.housing_coordinates == 0 || in.housing_reduction_config.empty())
          return nullptr;
        auto housing = std::make_unique<HousingComparison>(in.source, in.housing_reduction_config,
                                                           in.housing_model_file, body.ring,
                                                           model.interface_grid.grid.size());
        if (housing->coordinates() != run.housing_coordinates)
          reject(in, "Model/Housing model file",
                 "'" + in.housing_model_file + "' has " + std::to_string(housing->coordinates()) +
                   " coordinates; the run (" + in.results_file + ") had " + std::to_string(run.housing_coordinates));
        return housing;
      }

      /// The asked-for counts the model has, every pair of them, and the model itself.
      Study choose_study(const CompareInputs &in, const reduction::ReducedMatrices &matrices)
      {
        Study study;
        study.reduced_interface = !matrices.interface_frequencies_hz.empty();
        std::vector<unsigned int> fixed_list, constraint_list;
        for (const unsigned int m : in.fixed_interface_modes)
          (m <= matrices.n_modal ? fixed_list : study.dropped_fixed).push_back(m);
        for (const unsigned int c : in.constraint_modes)
          (study.reduced_interface && c <= matrices.n_constraint && c >= models::rigid_modes ? constraint_list
                                                                                              : study.dropped_constraint)
            .push_back(c);
        auto &truncations = study.truncations;
        for (const unsigned int m : fixed_list)
          for (const unsigned int c : constraint_list)
            truncations.emplace_back(m, c);
        if (std::find(truncations.begin(), truncations.end(),
                      std::make_pair(matrices.n_modal, matrices.n_constraint)) == truncations.end())
          truncations.emplace_back(matrices.n_modal, matrices.n_constraint);
        std::sort(truncations.begin(), truncations.end());
        truncations.erase(std::unique(truncations.begin(), truncations.end()), truncations.end());
        return study;
      }

      /// N snapshots spread evenly over the last ball-pass period (the load
      /// pattern repeats with it), or over the whole run if it is shorter; the
      /// last snapshot is always among them.
      std::vector<std::size_t> choose_snapshots(const std::vector<double> &time, unsigned int wanted, double bpf_hz)
      {
        std::vector<std::size_t> chosen;
        if (wanted >= time.size())
          {
            for (std::size_t k = 0; k < time.size(); ++k)
              chosen.push_back(k);
            return chosen;
          }
        const double t0 = time.front(), t1 = time.back();
        const double period = bpf_hz > 0.0 ? 1.0 / bpf_hz : 0.0;
        const double span   = period > 0.0 && period * (wanted - 1.0) / wanted <= t1 - t0 ? period : t1 - t0;
        for (unsigned int i = 0; i < wanted; ++i)
          {
            const double target = t1 - span * (wanted - 1.0 - i) / wanted;
            std::size_t  best   = 0;
            for (std::size_t k = 1; k < time.size(); ++k)
              if (std::abs(time[k] - target) < std::abs(time[best] - target))
                best = k;
            if (chosen.empty() || chosen.back() != best)
              chosen.push_back(best);
          }
        return chosen;
      }

      /// The loads of snapshot `k`: its loaded balls, its tractions and,
      /// from a run of this model, the ring's coordinates.
      Instant instant_at(const RunFields &run, std::size_t k, std::size_t ring_coordinates)
      {
        Instant instant;
        instant.snapshot = k;
        instant.time     = run.time[k];
        for (std::size_t j = 0; j < run.n_balls; ++j)
          if (run.ball_load[k * run.n_balls + j] > 0.0)
            {
              instant.ball_angles.push_back(run.ball_angle[k * run.n_balls + j]);
              instant.ball_loads.push_back(run.ball_load[k * run.n_balls + j]);
            }
        const auto cells = [&](const std::vector<double> &field) {
          return std::vector<double>(field.begin() + k * run.n_cells, field.begin() + (k + 1) * run.n_cells);
        };
        instant.tractions.pressure = cells(run.pressure);
        instant.tractions.shear_x  = cells(run.shear_x);
        instant.tractions.shear_y  = cells(run.shear_y);
        if (!run.other_model) // the ring's coordinates, the first of the row
          instant.run_q.assign(run.modal_coordinates.begin() + k * run.n_coordinates,
                               run.modal_coordinates.begin() + k * run.n_coordinates + ring_coordinates);
        return instant;
      }

      /// The raceway sample points: the line of the model's points inside the outer surface.
      void choose_raceway_points(Plan &plan)
      {
        const auto &points = plan.model.sample_points.points;
        for (std::size_t p = 0; p < points.size(); ++p)
          if (std::hypot(points[p][0], points[p][1]) < plan.body.ring.outer_radius * (1.0 - 1e-6))
            {
              plan.raceway_points.push_back(p);
              plan.raceway_xyz.push_back(points[p]);
            }
      }
    } // namespace

    Plan read_plan(const CompareInputs &in)
    {
      check_parameters(in);
      Plan plan;
      plan.body = read_ring(in);
      if (!in.full_transient_housing_config.empty())
        plan.transient_housing = models::read_housing_around(in.full_transient_housing_config, plan.body.ring,
                                                             in.source, "Compare/Full transient housing");
      plan.model = read_model(in);
      plan.run   = read_run(in, plan.model);
      // Checked now, compared after the ring; a scene that names no housing
      // model gets its ring compared and a note.
      plan.housing = read_housing(in, plan.body, plan.model, plan.run);
      // With a half-space or a flexible housing the run's pressure is not the
      // layer-alone problem the Winkler check solves: the two are not set
      // against each other.
      plan.run_on_layer = plan.run.other_problem().empty();
      plan.study        = choose_study(in, plan.model.matrices);
      for (const std::size_t k : choose_snapshots(plan.run.time, in.instants, plan.run.ball_pass_frequency_hz))
        plan.instants.push_back(instant_at(plan.run, k, plan.model.matrices.size()));
      choose_raceway_points(plan);
      return plan;
    }
  } // namespace compare
} // namespace fretsim::app
