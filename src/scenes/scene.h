#pragma once
// A scene builds only the stages it needs and runs them (DESIGN.md §5).
#include "app/parameters.h"

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
  };

  class Scene
  {
  public:
    virtual ~Scene() = default;
    virtual RunReport run(const RunOptions &options) = 0;
  };

  std::vector<std::string> scene_names();
  /// The declared parameters of a scene; throws std::invalid_argument for an unknown name.
  app::SceneParameters declare_parameters(const std::string &scene);
  /// Reads the file, validates every parameter and builds the scene. Throws
  /// app::InputError; touches nothing on disk.
  /// `overrides` ("Section/Name", value) replace the file's values.
  std::unique_ptr<Scene> load_scene(const std::string &config_file,
                                    const std::vector<std::pair<std::string, std::string>> &overrides = {});
} // namespace fretsim::scenes
