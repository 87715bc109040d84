#include "scenes/scene.h"

#include "scenes/bearing_scene.h"
#include "scenes/concentrated_scene.h"

#include "app/run_control.h"

#include <stdexcept>
#include <string>

namespace fretsim::scenes
{
  namespace
  {
    /// The concentrated scene's run: its largest arrays grow with the grid
    /// (N = Cells x × Cells y) times the depth layers (L), its results with
    /// the field snapshots.
    ResourceEstimate concentrated_resources(const app::SceneParameters &p)
    {
      const double cells  = double(p.get_integer("Grid/Cells x")) * double(p.get_integer("Grid/Cells y"));
      const double layers = double(p.get_double_list("Stresses/Depth layers").size());
      const double steps_per_cycle = double(p.get_integer("Loading/Steps per cycle"));
      const double steps           = double(p.get_integer("Loading/Cycles")) * steps_per_cycle;
      const double snapshots =
        double(p.get_integer("Output/Field snapshots per cycle")) * double(p.get_integer("Output/Field output cycles"));
      // Per grid cell and depth layer: the stress evaluator's kernel spectra
      // (3 loads × 6 components on the 2nx × 2ny padded grid, ~580 B), the
      // stress fields (3 × 6 doubles), the Dang Van state (13 doubles) and a
      // snapshot's staging (6 doubles): ~900 B. Per cell: the normal and
      // traction solvers' fields and kernels, ~600 B. The process itself
      // (libraries) ~150 MB. Measured at 128² and 512²: within 1.5x above.
      ResourceEstimate estimate;
      double           per_point = 900.0;
      std::string      path_note;
      if (p.get("Dang Van/Residual stress") == "hypersphere")
        {
          // The hypersphere keeps the deviatoric path of the last cycle.
          per_point += 40.0 * steps_per_cycle;
          path_note = ", the hypersphere's path of " + std::to_string(long(steps_per_cycle)) +
                      " steps per cycle (Dang Van/Residual stress)";
        }
      estimate.memory_bytes = 150e6 + cells * (600.0 + per_point * layers);
      estimate.memory_basis = "Grid/Cells x × Grid/Cells y = " + std::to_string(p.get_integer("Grid/Cells x")) +
                              " × " + std::to_string(p.get_integer("Grid/Cells y")) + " cells on " +
                              std::to_string(long(layers)) + " Stresses/Depth layers" + path_note;
      // results.h5: one row of 9 series per step, and per snapshot 5 surface
      // fields, the stress tensor and the risk on every layer; figures ~5 MB.
      const double snapshot_bytes = 8.0 * cells * (5.0 + 7.0 * layers);
      estimate.disk_bytes         = 5e6 + 80.0 * (steps + 1.0) + snapshots * snapshot_bytes + 8.0 * cells * layers;
      estimate.disk_basis = std::to_string(long(snapshots)) +
                            " field snapshots (Output/Field snapshots per cycle × Output/Field output cycles) of " +
                            app::format_bytes(snapshot_bytes) + " each, and " + std::to_string(long(steps)) +
                            " steps (Loading/Cycles × Loading/Steps per cycle)";
      return estimate;
    }
  } // namespace

  std::vector<std::string> scene_names() { return {"concentrated", "bearing_housing"}; }

  app::SceneParameters declare_parameters(const std::string &scene)
  {
    if (scene == "concentrated")
      return app::SceneParameters(scene, ConcentratedContactScene::parameter_specs());
    if (scene == "bearing_housing")
      return app::SceneParameters(scene, BearingHousingScene::parameter_specs());
    throw std::invalid_argument("unknown scene '" + scene + "'");
  }

  app::SceneParameters load_parameters(const std::string &config_file,
                                       const std::vector<std::pair<std::string, std::string>> &overrides)
  {
    app::SceneParameters parameters =
      declare_parameters(app::SceneParameters::scene_of_file(config_file, scene_names()));
    parameters.parse_file(config_file);
    for (const auto &[path, value] : overrides)
      parameters.set(path, value);
    return parameters;
  }

  ResourceEstimate estimate_resources(const app::SceneParameters &parameters)
  {
    if (parameters.scene() == "bearing_housing")
      return BearingHousingScene::estimate_resources(parameters);
    return concentrated_resources(parameters);
  }

  std::unique_ptr<Scene> make_scene(app::SceneParameters parameters)
  {
    if (parameters.scene() == "bearing_housing")
      return std::make_unique<BearingHousingScene>(std::move(parameters));
    return std::make_unique<ConcentratedContactScene>(std::move(parameters));
  }

  std::unique_ptr<Scene> load_scene(const std::string &config_file,
                                    const std::vector<std::pair<std::string, std::string>> &overrides)
  {
    return make_scene(load_parameters(config_file, overrides));
  }
} // namespace fretsim::scenes
