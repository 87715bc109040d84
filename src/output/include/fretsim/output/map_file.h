#pragma once
// map.h5 of `fretsim map` (docs/results.md): one record per point of the map,
// saved as each point finishes (the whole file written beside it and renamed
// over it), so that a map stopped at any moment, even killed, leaves a
// readable file and a restarted map continues from it. HDF5 types stay
// inside map_file.cpp.
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace fretsim::output
{
  /// One point of a map.
  struct MapRecord
  {
    long                          index = -1;   ///< position in the map, first axis fastest
    std::vector<double>           axis_values;  ///< one per axis, in the axes' units
    std::string                   status;       ///< "ok" or "failed"
    std::string                   message;      ///< why a point failed ("" if ok)
    std::string                   regime;       ///< stick | partial slip | gross slip | ""
    std::string                   parameters;   ///< the point's full parameter set (.prm text)
    std::map<std::string, double> numbers;      ///< by the map file's number names; absent: NaN
  };

  class MapFile
  {
  public:
    /// Opens `path` to continue the map it holds, or creates it. `definition`
    /// identifies the map (scene, base parameters, axes): a file holding
    /// another definition throws MapFileMismatch and is left untouched.
    MapFile(const std::string &path, const std::string &scene, const std::string &definition,
            const std::vector<std::string> &axis_names, const std::vector<std::string> &number_names);
    ~MapFile();
    MapFile(const MapFile &)            = delete;
    MapFile &operator=(const MapFile &) = delete;

    /// Appends one record and saves the file.
    void append(const MapRecord &record);
    /// The records written so far, in the order they were written.
    const std::vector<MapRecord> &records() const { return written; }
    /// /boundary: per line of the first axis, the other axes' values and the
    /// first axis's value where D_max = 1 (NaN where none is bracketed) and its
    /// bracket. Replaces an earlier /boundary.
    void write_boundary(const std::vector<std::vector<double>> &line_values, const std::vector<double> &boundary,
                        const std::vector<double> &bracket_low, const std::vector<double> &bracket_high);

    /// Reads every record of a map file (for tools and tests).
    static std::vector<MapRecord> read(const std::string &path);

  private:
    struct Impl;
    std::unique_ptr<Impl>  impl;
    std::vector<MapRecord> written;
  };

  /// A map file whose definition differs from the map being run.
  struct MapFileMismatch : std::runtime_error
  {
    using std::runtime_error::runtime_error;
  };
} // namespace fretsim::output
