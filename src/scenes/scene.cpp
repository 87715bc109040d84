#include "scenes/scene.h"

#include "scenes/bearing_scene.h"
#include "scenes/concentrated_scene.h"

#include <stdexcept>

namespace fretsim::scenes
{
  std::vector<std::string> scene_names() { return {"concentrated", "bearing_housing"}; }

  app::SceneParameters declare_parameters(const std::string &scene)
  {
    if (scene == "concentrated")
      return app::SceneParameters(scene, ConcentratedContactScene::parameter_specs());
    if (scene == "bearing_housing")
      return app::SceneParameters(scene, BearingHousingScene::parameter_specs());
    throw std::invalid_argument("unknown scene '" + scene + "'");
  }

  std::unique_ptr<Scene> load_scene(const std::string &config_file,
                                    const std::vector<std::pair<std::string, std::string>> &overrides)
  {
    const std::string scene      = app::SceneParameters::scene_of_file(config_file, scene_names());
    app::SceneParameters parameters = declare_parameters(scene);
    parameters.parse_file(config_file);
    for (const auto &[path, value] : overrides)
      parameters.set(path, value);
    if (scene == "bearing_housing")
      return std::make_unique<BearingHousingScene>(std::move(parameters));
    return std::make_unique<ConcentratedContactScene>(std::move(parameters));
  }
} // namespace fretsim::scenes
