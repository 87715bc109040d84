#pragma once
// The paper's §5 case (DESIGN.md §5 `paper_dgbb_housing`, issue 8): a deep
// groove ball bearing whose flexible outer ring (the Craig–Bampton model of
// `fretsim reduce`) sits in a rigid ring-shaped housing; the inner ring is
// displaced and rotates, the cage-guided balls load the raceway, and the
// interface pressure, bristle traction, subsurface stresses and Dang Van risk
// are followed in time. Builds no mesh unless the model file must be made.
#include "scenes/scene.h"

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace fretsim::scenes
{
  /// Where a bearing_housing scene's reduced model comes from, as `run` and
  /// `compare` resolve it: the reduction configuration (relative to the
  /// scene's file), the model file (empty parameter: results/<configuration
  /// name>-model.h5, where `fretsim reduce` writes it; the ring's with basis
  /// sizes the scene sets gets them in its name, results/<name>-m<m>-ncc<n_cc>
  /// -model.h5 or <file>-m<m>-ncc<n_cc>.h5, so that each model keeps its file), and
  /// the reduction parameters the scene sets over the configuration's
  /// (Model/Fixed-interface modes, Model/Characteristic constraint modes: the
  /// ring's only). Throws app::InputError if the configuration is missing or
  /// cannot be read.
  struct ModelSource
  {
    std::string config, file;
    std::string file_parameter; ///< the scene parameter that names the file
    std::vector<std::pair<std::string, std::string>> overrides; ///< Reduction/... = value
    std::string expected_hash; ///< the model file's input hash (app::reduce_input_hash of config and overrides)
  };
  ModelSource ring_model_source(const app::SceneParameters &scene);
  ModelSource housing_model_source(const app::SceneParameters &scene);

  class BearingHousingScene : public Scene
  {
  public:
    static std::vector<app::ParameterSpec> parameter_specs();
    /// Memory and disk of a run, from the parameters and the interface grid
    /// of the reduction configurations they name (no model is read or built).
    static ResourceEstimate estimate_resources(const app::SceneParameters &parameters);

    /// Reads and cross-checks the parameters (and the reduction configuration
    /// they name); throws app::InputError and touches nothing on disk.
    explicit BearingHousingScene(app::SceneParameters parameters);
    ~BearingHousingScene() override;

    /// Loads (or builds) the reduced model, integrates, evaluates stresses and
    /// the Dang Van risk at every output time; results.h5 grows as it goes,
    /// summary.json and figures at the end.
    RunReport run(const RunOptions &options) override;

  private:
    struct Settings;
    app::SceneParameters      parameters;
    std::unique_ptr<Settings> settings;
  };
} // namespace fretsim::scenes
