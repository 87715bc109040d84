#pragma once
// `fretsim map CONFIG --axis 'Section/Name=FROM:TO:N[:log]' ...`: a scene run
// at every point of a grid over one to three of its parameters, the points
// spread over threads and MPI ranks, each point's record written to map.h5 as
// it finishes (a restarted map continues from it), then map.csv and map.png;
// with --boundary the D = 1 boundary located along the first axis by bisection.
#include <string>
#include <utility>
#include <vector>

namespace fretsim::app
{
  /// One axis of a map: `count` values from `from` to `to`, evenly spaced, or
  /// geometrically with `logarithmic`.
  struct MapAxis
  {
    std::string path;
    double      from = 0.0, to = 0.0;
    int         count       = 0;
    bool        logarithmic = false;

    /// 'Section/Name=FROM:TO:N[:log]'; throws InputError naming --axis.
    static MapAxis parse(const std::string &text);
    std::vector<double> values() const;
    /// The canonical form parse() reads back.
    std::string text() const;
  };

  struct MapOptions
  {
    std::string              config_file;
    std::string              output_directory; ///< default: results/<config name>-map
    std::vector<std::string> axes;             ///< as given to --axis; none: the scene file's Map/Axes
    /// ("Section/Name", value) pairs that replace the file's values at every point.
    std::vector<std::pair<std::string, std::string>> overrides;
    bool   boundary           = false;
    double boundary_tolerance = 1e-3; ///< of the first axis's range (of its logarithm for a log axis)
    int    jobs               = 0;    ///< points at a time per process; 0: the cores shared by the ranks on a node
    long   max_points         = 0;    ///< > 0: run at most this many new points, then stop (the same command continues)
    bool   plots = true, progress = true, force = false;
  };

  /// Runs the map (under mpirun: every rank calls it). Returns the files
  /// written (on rank 0; empty on the others). Throws InputError for a bad
  /// axis, configuration or output folder before any point runs.
  std::vector<std::string> run_map_command(const MapOptions &options);
} // namespace fretsim::app
