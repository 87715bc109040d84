#pragma once
// A scene builds only the stages it needs and runs them (docs/theory.md §5).
#include <fretsim/support/parameters.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace fretsim::scenes
{
  struct RunOptions
  {
    std::string output_directory;
    bool        plots    = true; ///< write PNG figures (needs python3 + matplotlib + h5py)
    bool        progress = true; ///< progress line on a terminal
    /// false: nothing is written (no results, summary or figures), the report's
    /// numbers are the run's result (a map's point).
    bool files = true;
  };

  /// What a run tells the command line.
  struct RunReport
  {
    bool        completed = true; ///< false if interrupted
    std::string results_file;
    std::string summary_file;
    std::vector<std::string> figures;
    /// Key results by their summary.json names, for tools that compare runs
    /// (e.g. "risk_max", "wall_time_s", "dissipated_energy_per_cycle_J").
    std::map<std::string, double> numbers;
    std::map<std::string, std::string> labels; ///< e.g. "regime": "partial slip"
  };

  /// What a run needs, estimated from its parameters before anything is
  /// built, so that a run that cannot fit is refused at once rather than
  /// failing after hours (or thrashing the machine). Upper estimates of the
  /// largest terms; each names the parameters that set it.
  struct ResourceEstimate
  {
    double      memory_bytes = 0.0; ///< peak resident memory
    double      disk_bytes   = 0.0; ///< written into the output folder
    std::string memory_basis;       ///< e.g. "Grid/Cells x × Grid/Cells y = 4096 × 4096, 5 depth layers"
    std::string disk_basis;         ///< e.g. "2e7 field snapshots of 5.2 MB"
  };

  class Scene
  {
  public:
    virtual ~Scene() = default;
    virtual RunReport run(const RunOptions &options) = 0;
    /// Builds what runs of these parameters share and would otherwise build on
    /// first use (the bearing scene's reduced models), collectively on every
    /// MPI rank when MPI runs: a map calls it once before its points.
    virtual void prepare() {}
  };

  /// Settings every point of a map runs with, on top of the user's: results
  /// identical in every process (FFTW plans without timing), and nothing built
  /// on the way (prepare() built it).
  std::vector<std::pair<std::string, std::string>> map_point_settings(const std::string &scene);
  /// The "FFT plans" parameter (measure | estimate) of a scene's FFTs, at `path`.
  app::ParameterSpec fft_plans_parameter(const std::string &path);

  /// Whether runs of the scene may share a process in parallel threads (runs
  /// that write no files and plan FFTs under one lock); otherwise one at a time.
  bool runs_in_threads(const std::string &scene);

  std::vector<std::string> scene_names();
  /// The declared parameters of a scene; throws std::invalid_argument for an unknown name.
  app::SceneParameters declare_parameters(const std::string &scene);
  /// Reads the file and validates every parameter on its own, building
  /// nothing. Throws app::InputError; touches nothing on disk.
  /// `overrides` ("Section/Name", value) replace the file's values.
  app::SceneParameters load_parameters(const std::string &config_file,
                                       const std::vector<std::pair<std::string, std::string>> &overrides = {});
  /// The run's memory and disk, from the parameters alone (fast: builds nothing).
  ResourceEstimate estimate_resources(const app::SceneParameters &parameters);
  /// Builds the scene, with its cross-parameter checks. Throws app::InputError;
  /// touches nothing on disk.
  std::unique_ptr<Scene> make_scene(app::SceneParameters parameters);
  /// load_parameters, then make_scene.
  std::unique_ptr<Scene> load_scene(const std::string &config_file,
                                    const std::vector<std::pair<std::string, std::string>> &overrides = {});
} // namespace fretsim::scenes
