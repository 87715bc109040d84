#include <fretsim/scenes/scene.h>

#include <fretsim/scenes/bearing_scene.h>
#include "concentrated_scene.h"

#include <fretsim/support/run_control.h>

#include <stdexcept>
#include <string>

namespace fretsim::scenes
{
  std::vector<std::string> scene_names() { return {"concentrated", "bearing_housing"}; }

  namespace
  {
    /// A scene file may carry the map `fretsim map` draws over it; `run` ignores it.
    std::vector<app::ParameterSpec> map_parameter_specs()
    {
      app::ParameterSpec axes;
      axes.path          = "Map/Axes";
      axes.kind          = app::ParameterSpec::Kind::text;
      axes.default_value = "none";
      axes.doc = "The axes `fretsim map` uses when none is given on its command line, separated by ';', each "
                 "'Section/Name=FROM:TO:N' or 'Section/Name=FROM:TO:N:log' as for --axis; none: no map of its "
                 "own (`fretsim run` ignores them) [-].";
      return {axes, app::ParameterSpec::selection("Map/Boundary", "false",
                                                  "true: `fretsim map` also bisects for D = 1, as --boundary.",
                                                  "true|false")};
    }

    std::vector<app::ParameterSpec> with_map(std::vector<app::ParameterSpec> specs)
    {
      for (auto &spec : map_parameter_specs())
        specs.push_back(std::move(spec));
      return specs;
    }
  } // namespace

  app::SceneParameters declare_parameters(const std::string &scene)
  {
    if (scene == "concentrated")
      return app::SceneParameters(scene, with_map(ConcentratedContactScene::parameter_specs()));
    if (scene == "bearing_housing")
      return app::SceneParameters(scene, with_map(BearingHousingScene::parameter_specs()));
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
    return ConcentratedContactScene::estimate_resources(parameters);
  }

  std::unique_ptr<Scene> make_scene(app::SceneParameters parameters)
  {
    if (parameters.scene() == "bearing_housing")
      return std::make_unique<BearingHousingScene>(std::move(parameters));
    return std::make_unique<ConcentratedContactScene>(std::move(parameters));
  }

  std::vector<std::pair<std::string, std::string>> map_point_settings(const std::string &scene)
  {
    if (scene == "bearing_housing")
      return {{"Model/Build if missing", "false"}, {"Stresses/FFT plans", "estimate"}};
    return {{"Grid/FFT plans", "estimate"}};
  }

  app::ParameterSpec fft_plans_parameter(const std::string &path)
  {
    return app::ParameterSpec::selection(path, "measure",
                                         "measure: FFTW times candidate transforms once and keeps the fastest "
                                         "(faster runs; results can differ from another process's in the last "
                                         "digits); estimate: plans chosen without timing, so every process gives "
                                         "identical results (fretsim map uses it).",
                                         "measure|estimate");
  }

  bool runs_in_threads(const std::string &scene) { return scene == "concentrated"; }

  std::unique_ptr<Scene> load_scene(const std::string &config_file,
                                    const std::vector<std::pair<std::string, std::string>> &overrides)
  {
    return make_scene(load_parameters(config_file, overrides));
  }
} // namespace fretsim::scenes
