#include "app/parameters.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/patterns.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <regex>
#include <sstream>

namespace fretsim::app
{
  namespace
  {
    std::vector<std::string> split_path(const std::string &path)
    {
      std::vector<std::string> parts;
      std::stringstream        stream(path);
      for (std::string part; std::getline(stream, part, '/');)
        parts.push_back(part);
      return parts;
    }

    std::string format_number(double value)
    {
      std::ostringstream out;
      out << std::setprecision(10) << value;
      return out.str();
    }

    std::string one_line(const std::string &text)
    {
      std::string result;
      bool        space = false;
      for (const char c : text)
        {
          if (std::isspace(static_cast<unsigned char>(c)))
            space = !result.empty();
          else
            {
              if (space)
                result += ' ';
              result += c;
              space = false;
            }
        }
      return result;
    }

    std::size_t edit_distance(const std::string &a, const std::string &b)
    {
      std::vector<std::size_t> row(b.size() + 1);
      for (std::size_t j = 0; j <= b.size(); ++j)
        row[j] = j;
      for (std::size_t i = 1; i <= a.size(); ++i)
        {
          std::size_t diagonal = row[0];
          row[0]               = i;
          for (std::size_t j = 1; j <= b.size(); ++j)
            {
              const std::size_t above = row[j];
              row[j] = std::min({row[j] + 1, row[j - 1] + 1,
                                 diagonal + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1)});
              diagonal = above;
            }
        }
      return row[b.size()];
    }

    std::string extension_of(const std::string &path)
    {
      const auto dot = path.find_last_of('.');
      return dot == std::string::npos ? "" : path.substr(dot);
    }

    void require_readable(const std::string &path)
    {
      std::ifstream in(path);
      if (!in)
        throw InputError(path, "", "cannot open the configuration file (expected a readable .prm or .json file)");
      const std::string extension = extension_of(path);
      if (extension != ".prm" && extension != ".json")
        throw InputError(path, "", "unknown file type '" + extension + "' (expected a .prm or .json file)");
    }

    /// deal.II reports parse errors as multi-line exception text; keep the
    /// message, drop the layout, and name the parameter the way users write it.
    std::string describe_parse_error(const dealii::ExceptionBase &error,
                                     const std::vector<ParameterSpec> &specs)
    {
      std::ostringstream info;
      error.print_info(info);
      std::string message = one_line(info.str());
      std::smatch match;
      if (std::regex_search(message, match, std::regex("No entry with name <([^>]*)>")))
        {
          const std::string unknown = match[1];
          std::string       best;
          std::size_t       best_distance = 4; // suggest only near-misses
          for (const auto &spec : specs)
            {
              const std::string name     = split_path(spec.path).back();
              const std::size_t distance = edit_distance(unknown, name);
              if (distance < best_distance)
                {
                  best_distance = distance;
                  best          = spec.path;
                }
            }
          message = "unknown parameter '" + unknown + "' (" + message + ")";
          if (!best.empty())
            message += "; did you mean '" + best + "'?";
        }
      return message;
    }
  } // namespace

  InputError::InputError(const std::string &file, const std::string &parameter,
                         const std::string &problem)
    : std::runtime_error(file + ": " + (parameter.empty() ? "" : "parameter '" + parameter + "': ") + problem)
  {}

  std::string ParameterSpec::expected() const
  {
    switch (kind)
      {
        case Kind::boolean:
          return "true or false";
        case Kind::selection:
          return "one of: " + options;
        case Kind::text:
          return "any text";
        case Kind::real:
        case Kind::integer:
        case Kind::real_list:
          break;
      }
    const std::string noun = kind == Kind::integer ? "an integer" : kind == Kind::real ? "a number" : "a comma-separated list of numbers, each";
    const bool has_min = min > -1e299;
    const bool has_max = max < 1e299;
    std::string text = noun;
    if (has_min)
      text += std::string(min_exclusive ? " > " : " >= ") + format_number(min);
    if (has_min && has_max)
      text += " and";
    if (has_max)
      text += std::string(max_exclusive ? " < " : " <= ") + format_number(max);
    return text;
  }

  ParameterSpec ParameterSpec::real_range(const std::string &path, const std::string &value,
                                          const std::string &doc, double min, double max, bool min_exclusive,
                                          bool max_exclusive)
  {
    ParameterSpec spec;
    spec.path          = path;
    spec.kind          = Kind::real;
    spec.default_value = value;
    spec.doc           = doc;
    spec.min           = min;
    spec.max           = max;
    spec.min_exclusive = min_exclusive;
    spec.max_exclusive = max_exclusive;
    return spec;
  }

  ParameterSpec ParameterSpec::positive(const std::string &path, const std::string &value, const std::string &doc)
  {
    return real_range(path, value, doc, 0.0, 1e300, true);
  }

  ParameterSpec ParameterSpec::non_negative(const std::string &path, const std::string &value,
                                            const std::string &doc)
  {
    return real_range(path, value, doc, 0.0, 1e300);
  }

  ParameterSpec ParameterSpec::integer_range(const std::string &path, const std::string &value,
                                             const std::string &doc, long min, long max)
  {
    ParameterSpec spec = real_range(path, value, doc, static_cast<double>(min), static_cast<double>(max));
    spec.kind          = Kind::integer;
    return spec;
  }

  ParameterSpec ParameterSpec::selection(const std::string &path, const std::string &value,
                                         const std::string &doc, const std::string &options)
  {
    ParameterSpec spec = real_range(path, value, doc, 0.0, 0.0);
    spec.kind          = Kind::selection;
    spec.options       = options;
    return spec;
  }

  struct SceneParameters::Impl
  {
    mutable dealii::ParameterHandler handler;
    /// Each parameter's pattern, by path. The handler itself accepts any text
    /// so that a mismatch is reported here with the full path and the range in
    /// words (deal.II's own message names neither the subsection nor the range).
    std::map<std::string, std::unique_ptr<dealii::Patterns::PatternBase>> patterns;

    template <typename F>
    auto at(const std::string &path, F &&read) const
    {
      const auto parts = split_path(path);
      for (std::size_t i = 0; i + 1 < parts.size(); ++i)
        handler.enter_subsection(parts[i]);
      auto value = read(parts.back());
      for (std::size_t i = 0; i + 1 < parts.size(); ++i)
        handler.leave_subsection();
      return value;
    }
  };

  SceneParameters::SceneParameters(const std::string &scene, std::vector<ParameterSpec> specs)
    : scene_name(scene)
    , spec_table(std::move(specs))
    , impl(std::make_unique<Impl>())
  {
    using dealii::Patterns::Bool;
    using dealii::Patterns::Double;
    using dealii::Patterns::Integer;
    auto &handler = impl->handler;
    handler.declare_entry("Scene", scene, dealii::Patterns::Selection(scene),
                          "Which scene this file describes.");
    for (const auto &spec : spec_table)
      {
        const auto parts = split_path(spec.path);
        for (std::size_t i = 0; i + 1 < parts.size(); ++i)
          handler.enter_subsection(parts[i]);
        // deal.II's numeric patterns are inclusive; the exclusive ends are
        // checked after parsing with a message of our own.
        const double lower = std::max(spec.min, Double::min_double_value);
        const double upper = std::min(spec.max, Double::max_double_value);
        std::unique_ptr<dealii::Patterns::PatternBase> pattern;
        switch (spec.kind)
          {
            case ParameterSpec::Kind::real:
              pattern = std::make_unique<Double>(lower, upper);
              break;
            case ParameterSpec::Kind::integer:
              pattern = std::make_unique<Integer>(static_cast<int>(std::max(spec.min, -2e9)),
                                                  static_cast<int>(std::min(spec.max, 2e9)));
              break;
            case ParameterSpec::Kind::boolean:
              pattern = std::make_unique<Bool>();
              break;
            case ParameterSpec::Kind::selection:
              pattern = std::make_unique<dealii::Patterns::Selection>(spec.options);
              break;
            case ParameterSpec::Kind::text:
              pattern = std::make_unique<dealii::Patterns::Anything>();
              break;
            case ParameterSpec::Kind::real_list:
              pattern = std::make_unique<dealii::Patterns::List>(Double(lower, upper), 0, 1000);
              break;
          }
        handler.declare_entry(parts.back(), spec.default_value, dealii::Patterns::Anything(),
                              spec.doc + " Allowed: " + spec.expected() + ".");
        impl->patterns[spec.path] = std::move(pattern);
        for (std::size_t i = 0; i + 1 < parts.size(); ++i)
          handler.leave_subsection();
      }
  }

  SceneParameters::~SceneParameters() = default;
  SceneParameters::SceneParameters(SceneParameters &&) noexcept = default;

  void SceneParameters::parse_file(const std::string &path)
  {
    require_readable(path);
    file_name = path;
    try
      {
        if (extension_of(path) == ".json")
          {
            std::ifstream in(path);
            impl->handler.parse_input_from_json(in);
          }
        else
          impl->handler.parse_input(path);
      }
    catch (const dealii::ExceptionBase &error)
      {
        throw InputError(path, "", describe_parse_error(error, spec_table));
      }
    catch (const std::exception &error)
      {
        // e.g. boost's JSON parser on malformed input
        throw InputError(path, "", one_line(error.what()));
      }

    validate();
  }

  void SceneParameters::set(const std::string &path, const std::string &value)
  {
    if (!impl->patterns.count(path))
      throw InputError(file_name.empty() ? "(defaults)" : file_name, path, "no such parameter");
    impl->at(path, [&](const std::string &name) {
      impl->handler.set(name, value);
      return 0;
    });
    validate();
  }

  void SceneParameters::validate() const
  {
    for (const auto &spec : spec_table)
      {
        const std::string value = get(spec.path);
        if (!impl->patterns.at(spec.path)->match(value))
          reject(spec.path, "expected " + spec.expected() + ", got '" + value + "'");
      }
    // Exclusive bounds and the plain-number checks deal.II's patterns cannot say.
    for (const auto &spec : spec_table)
      {
        if (spec.kind != ParameterSpec::Kind::real && spec.kind != ParameterSpec::Kind::real_list)
          continue;
        const std::vector<double> values = spec.kind == ParameterSpec::Kind::real ?
                                             std::vector<double>{get_double(spec.path)} :
                                             get_double_list(spec.path);
        for (const double value : values)
          if (!std::isfinite(value) || (spec.min_exclusive && !(value > spec.min)) ||
              (spec.max_exclusive && !(value < spec.max)))
            reject(spec.path, "expected " + spec.expected() + ", got " + format_number(value));
      }
  }

  void SceneParameters::reject(const std::string &path, const std::string &problem) const
  {
    throw InputError(file_name.empty() ? "(defaults)" : file_name, path, problem);
  }

  double SceneParameters::get_double(const std::string &path) const
  {
    return impl->at(path, [this](const std::string &name) { return impl->handler.get_double(name); });
  }

  long SceneParameters::get_integer(const std::string &path) const
  {
    return impl->at(path, [this](const std::string &name) { return impl->handler.get_integer(name); });
  }

  bool SceneParameters::get_bool(const std::string &path) const
  {
    return impl->at(path, [this](const std::string &name) { return impl->handler.get_bool(name); });
  }

  std::string SceneParameters::get(const std::string &path) const
  {
    return impl->at(path, [this](const std::string &name) { return impl->handler.get(name); });
  }

  std::vector<double> SceneParameters::get_double_list(const std::string &path) const
  {
    const std::string text = get(path);
    std::vector<double> values;
    std::stringstream   stream(text);
    for (std::string item; std::getline(stream, item, ',');)
      if (item.find_first_not_of(" \t") != std::string::npos)
        values.push_back(std::stod(item));
    return values;
  }

  std::string SceneParameters::to_prm() const
  {
    std::ostringstream out;
    impl->handler.print_parameters(out, dealii::ParameterHandler::ShortPRM);
    return out.str();
  }

  void SceneParameters::print_reference(std::ostream &out) const
  {
    out << "# Scene '" << scene_name << "': every parameter, its default, allowed values and unit.\n"
        << "# All quantities are SI (m, N, Pa, s).\n"
        << "set Scene = " << scene_name << "\n";
    std::vector<std::string> open_sections;
    for (const auto &spec : spec_table)
      {
        auto parts = split_path(spec.path);
        const std::string name = parts.back();
        parts.pop_back();
        std::size_t common = 0;
        while (common < parts.size() && common < open_sections.size() && parts[common] == open_sections[common])
          ++common;
        while (open_sections.size() > common)
          {
            open_sections.pop_back();
            out << std::string(2 * open_sections.size(), ' ') << "end\n";
          }
        for (std::size_t i = common; i < parts.size(); ++i)
          {
            out << std::string(2 * open_sections.size(), ' ') << "subsection " << parts[i] << "\n";
            open_sections.push_back(parts[i]);
          }
        const std::string indent(2 * open_sections.size(), ' ');
        out << indent << "# " << spec.doc << "\n"
            << indent << "# Allowed: " << spec.expected() << "\n"
            << indent << "set " << name << " = " << spec.default_value << "\n";
      }
    while (!open_sections.empty())
      {
        open_sections.pop_back();
        out << std::string(2 * open_sections.size(), ' ') << "end\n";
      }
  }

  std::string SceneParameters::scene_of_file(const std::string &path,
                                             const std::vector<std::string> &known_scenes)
  {
    require_readable(path);
    dealii::ParameterHandler handler;
    handler.declare_entry("Scene", "", dealii::Patterns::Anything(), "scene name");
    try
      {
        if (extension_of(path) == ".json")
          {
            std::ifstream in(path);
            handler.parse_input_from_json(in, /*skip_undefined=*/true);
          }
        else
          handler.parse_input(path, "", /*skip_undefined=*/true);
      }
    catch (const dealii::ExceptionBase &error)
      {
        std::ostringstream info;
        error.print_info(info);
        throw InputError(path, "", one_line(info.str()));
      }
    catch (const std::exception &error)
      {
        throw InputError(path, "", one_line(error.what()));
      }
    const std::string scene = handler.get("Scene");
    std::string       names;
    for (const auto &known : known_scenes)
      {
        if (known == scene)
          return scene;
        names += (names.empty() ? "" : "|") + known;
      }
    throw InputError(path, "Scene",
                     scene.empty() ? "missing; expected 'set Scene = " + names + "'" :
                                     "unknown scene '" + scene + "', expected one of: " + names);
  }
} // namespace fretsim::app
