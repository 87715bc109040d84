#pragma once
// The paper's §5 case (docs/theory.md §5 `paper_dgbb_housing`): a deep
// groove ball bearing whose flexible outer ring (the Craig–Bampton model of
// `fretsim reduce`) sits in a rigid ring-shaped housing; the inner ring is
// displaced and rotates, the cage-guided balls load the raceway, and the
// interface pressure, bristle traction, subsurface stresses and Dang Van risk
// are followed in time. Builds no mesh unless the model file must be made.
#include <fretsim/scenes/scene.h>

#include <fretsim/contact/dang_van.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace fretsim::scenes
{
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
    /// Loads or builds the reduced models (collectively on every MPI rank).
    void prepare() override;

    /// What a full-FE reference of the run takes from the scene: the
    /// interface law, the ball footprint, the stress layers and the risk's
    /// criterion, as the run has them.
    struct ReferenceView
    {
      std::string                reduction_config;  ///< the ring's ring_housing configuration (resolved)
      double                     friction_coefficient = 0.0, normal_stiffness = 0.0, tangential_stiffness = 0.0;
      double                     radial_interference  = 0.0; ///< [m]
      std::vector<double>        depth_layers;                ///< [m]
      contact::DangVanConstants  dang_van_constants;
      contact::DangVanSettings   dang_van;
      std::string                local_compliance; ///< what the run had in series with the layer
      bool                       flexible_housing = false;
    };
    ReferenceView reference_view() const;

    /// The validated parameters, as the run uses them.
    struct Settings;

  private:
    app::SceneParameters      parameters;
    std::unique_ptr<Settings> settings;
  };
} // namespace fretsim::scenes
