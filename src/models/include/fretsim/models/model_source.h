#pragma once
// Where a bearing_housing scene's reduced models come from, and reading them
// or building them with the reduction when their file is missing or was made
// from other inputs.
#include <fretsim/support/parameters.h>

#include <fretsim/models/interface_influence.h>
#include <fretsim/models/ring_stress.h>
#include <fretsim/reduction/reduced_model.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace fretsim::fem
{
  class ParallelEnvironment;
} // namespace fretsim::fem

namespace fretsim::models
{
  /// A reduced model as `run` and `compare` resolve it: the reduction
  /// configuration (relative to the scene's file), the model file (empty
  /// parameter: results/<configuration name>-model.h5, where `fretsim reduce`
  /// writes it; with basis sizes the scene sets they go into its name,
  /// results/<name>-m<m>-ncc<n_cc>-model.h5 or <file>-m<m>-ncc<n_cc>.h5, so
  /// that each model keeps its file), and the reduction parameters the scene
  /// sets over the configuration's (the ring's Model/Fixed-interface modes,
  /// Model/Characteristic constraint modes and the raceway footprints of
  /// Model/Ball footprint = load following, which add -hertz to the name;
  /// the housing's Model/Housing fixed-interface modes and Model/Housing
  /// characteristic constraint modes).
  struct ModelSource
  {
    std::string config, file;
    std::string file_parameter; ///< the scene parameter that names the file
    std::vector<std::pair<std::string, std::string>> overrides; ///< Reduction/... = value
    /// The raceway footprints among them (Reduction/Ball footprint ...), and
    /// the tag they add to file names ("-hertz"); empty: the configuration's.
    std::vector<std::pair<std::string, std::string>> footprint_overrides;
    std::string                                      footprint_tag;
    std::string expected_hash; ///< the model file's input hash (reduce_input_hash of config and overrides)
  };

  /// The ring's and the housing's model of a bearing_housing scene (Model/...).
  /// Throws app::InputError if the configuration is missing or cannot be read.
  ModelSource ring_model_source(const app::SceneParameters &scene);
  ModelSource housing_model_source(const app::SceneParameters &scene);
  /// The ring's full-FE stress tables of a bearing_housing scene (Stresses/Ring
  /// mesh, Stresses/Ring mesh radial grading, its depth layers), kept beside
  /// the ring's model file as <reduction configuration name><footprint
  /// tag>-stress-tables.h5.
  /// Throws app::InputError for a malformed mesh.
  RingStressSource ring_stress_source(const app::SceneParameters &scene, const ModelSource &ring,
                                      const std::vector<double> &depths);

  /// Reads model files, building a missing or stale one first when allowed.
  /// MPI starts on the first build and runs until finish() (it starts only
  /// once per process); a scene whose models are there never starts it.
  class ModelLoader
  {
  public:
    ModelLoader(bool build_if_missing, bool progress);
    ~ModelLoader();

    /// The model of `source`; a file that cannot be used and may not be
    /// built is an app::InputError of `scene`'s source.file_parameter.
    reduction::ReducedModel load(const ModelSource &source, const app::SceneParameters &scene);
    /// The ring's stress tables of `source` on `ring`'s grid and raceway
    /// footprint, read or built (collectively under MPI; the file written
    /// by rank 0). Not allowed to build: an app::InputError of Stresses/Ring mesh.
    InterfaceInfluence load_ring_stress(const RingStressSource &source, const reduction::ReducedModel &ring,
                                        const app::SceneParameters &scene);
    /// Whether load() built a model file.
    bool built() const { return built_any; }
    /// Stops MPI if a build started it: the run after the models needs none.
    void finish();

  private:
    bool                                      build_if_missing;
    bool                                      progress;
    bool                                      built_any = false;
    std::unique_ptr<fem::ParallelEnvironment> mpi;
  };
} // namespace fretsim::models
