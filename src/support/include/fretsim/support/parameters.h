#pragma once
// Scene configuration: a declarative table of parameters, each with a default,
// an allowed range and a doc string with its unit, parsed by deal.II's
// ParameterHandler from .prm or .json. deal.II types stay in parameters.cpp.
#include <iosfwd>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace fretsim::app
{
  /// Bad user input: names the file, the parameter and what was expected.
  /// The program reports what() on one line and exits with code 2.
  class InputError : public std::runtime_error
  {
  public:
    InputError(const std::string &file, const std::string &parameter, const std::string &problem);
  };

  /// One parameter: "Section/Subsection/Name" path, its default, range and doc.
  struct ParameterSpec
  {
    enum class Kind { real, integer, boolean, selection, text, real_list };
    std::string path;
    Kind        kind = Kind::real;
    std::string default_value;
    std::string doc;         ///< meaning and unit, e.g. "Normal load P [N]"
    double      min = -1e300;
    double      max = 1e300;
    bool        min_exclusive = false;
    bool        max_exclusive = false;
    std::string options;     ///< for selection: "a|b|c"
    bool        increasing = false; ///< for real_list: strictly increasing (no repeats)

    /// Human-readable allowed range, e.g. "a number > 0", "one of: hertz|numerical".
    std::string expected() const;

    // Builders that keep scene tables readable. Bounds are inclusive unless
    // the name says otherwise.
    static ParameterSpec positive(const std::string &path, const std::string &value, const std::string &doc);
    static ParameterSpec non_negative(const std::string &path, const std::string &value, const std::string &doc);
    static ParameterSpec real_range(const std::string &path, const std::string &value, const std::string &doc,
                                    double min, double max, bool min_exclusive = false, bool max_exclusive = false);
    static ParameterSpec integer_range(const std::string &path, const std::string &value, const std::string &doc,
                                       long min, long max);
    static ParameterSpec selection(const std::string &path, const std::string &value, const std::string &doc,
                                   const std::string &options);
  };

  /// `count` whole numbers >= 1 joined by 'x' ("360x3x6x2", blanks around
  /// the text allowed), as a mesh's cell counts are given; empty if the text
  /// is anything else.
  std::vector<long> parse_cell_counts(const std::string &text, std::size_t count);

  /// The parameters of one scene, declared from its table and read from a file.
  class SceneParameters
  {
  public:
    SceneParameters(const std::string &scene, std::vector<ParameterSpec> specs);
    ~SceneParameters();
    SceneParameters(SceneParameters &&) noexcept;

    /// Reads and validates a .prm or .json file; throws InputError.
    void parse_file(const std::string &path);
    /// Overrides one parameter and validates again; throws InputError naming
    /// `source` (default: the command line's --set 'path=value') and the
    /// parameter, with a suggestion for a misspelt path.
    void set(const std::string &path, const std::string &value, const std::string &source = "");

    double              get_double(const std::string &path) const;
    long                get_integer(const std::string &path) const;
    bool                get_bool(const std::string &path) const;
    std::string         get(const std::string &path) const;
    std::vector<double> get_double_list(const std::string &path) const;

    /// Throws InputError for `path` with `problem` (for cross-parameter checks),
    /// naming where the value came from (file and line, or --set).
    [[noreturn]] void reject(const std::string &path, const std::string &problem) const;

    const std::string &scene() const { return scene_name; }
    const std::string &file() const { return file_name; }
    const std::vector<ParameterSpec> &specs() const { return spec_table; }

    /// The full parameter set in .prm syntax (stored with the results).
    std::string to_prm() const;
    /// Every parameter with default, allowed range and doc string.
    void print_reference(std::ostream &out) const;

    /// Finds the scene named by the top-level "Scene" entry of a file;
    /// throws InputError if the file is missing or names no known scene.
    static std::string scene_of_file(const std::string &path,
                                     const std::vector<std::string> &known_scenes);

  private:
    void validate() const;
    /// Unknown sections and parameters, and a parameter set twice, in the
    /// text of a .prm or .json file; records where each value was set.
    void check_prm_text(const std::string &text);
    void check_json_text(const std::string &text);
    /// Where `path`'s value was set: "file:line", "file" or "--set '...'".
    std::string origin_of(const std::string &path) const;

    struct Impl;
    std::string                scene_name;
    std::string                file_name;
    std::vector<ParameterSpec> spec_table;
    std::unique_ptr<Impl>      impl;
  };
} // namespace fretsim::app
