#include <fretsim/support/parameters.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/patterns.h>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <map>
#include <regex>
#include <set>
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

    /// The closest of `candidates` to `unknown`, if near enough to be a
    /// misspelling; "" otherwise.
    std::string closest(const std::string &unknown, const std::vector<std::string> &candidates,
                        bool by_last_part = false)
    {
      std::string best;
      // Near-misses only: a few edits, more for long names.
      std::size_t best_distance = std::max<std::size_t>(4, unknown.size() / 4);
      for (const auto &candidate : candidates)
        {
          const std::string name     = by_last_part ? split_path(candidate).back() : candidate;
          const std::size_t distance = edit_distance(unknown, name);
          if (distance < best_distance)
            {
              best_distance = distance;
              best          = candidate;
            }
        }
      return best;
    }

    std::string did_you_mean(const std::string &unknown, const std::vector<std::string> &candidates,
                             bool by_last_part = false)
    {
      const std::string best = closest(unknown, candidates, by_last_part);
      return best.empty() ? "" : "; did you mean '" + best + "'?";
    }

    std::string joined(const std::vector<std::string> &items, const std::string &separator = ", ")
    {
      std::string text;
      for (const auto &item : items)
        text += (text.empty() ? "" : separator) + item;
      return text;
    }

    /// The text of a configuration file, checked to be one and without a
    /// UTF-8 byte order mark (editors on Windows add one; deal.II would read
    /// it as part of the first name).
    std::string read_config_text(const std::string &path)
    {
      std::error_code error;
      if (std::filesystem::is_directory(path, error))
        throw InputError(path, "", "is a directory; expected a .prm or .json file");
      std::ifstream in(path, std::ios::binary);
      if (!in)
        throw InputError(path, "", "cannot open the configuration file (expected a readable .prm or .json file)");
      const std::string extension = extension_of(path);
      if (extension != ".prm" && extension != ".json")
        throw InputError(path, "", "unknown file type '" + extension + "' (expected a .prm or .json file)");
      std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
      if (in.bad())
        throw InputError(path, "", "cannot read the configuration file");
      if (text.compare(0, 3, "\xEF\xBB\xBF") == 0)
        text.erase(0, 3);
      if (text.find('\0') != std::string::npos)
        throw InputError(path, "", "holds a NUL byte; expected a text file");
      return text;
    }

    std::string trimmed(const std::string &text)
    {
      const auto first = text.find_first_not_of(" \t\r");
      if (first == std::string::npos)
        return "";
      return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
    }

    /// A name as deal.II compares it: trimmed, inner runs of blanks as one.
    std::string normalised_name(const std::string &text)
    {
      std::string result;
      for (const char c : trimmed(text))
        if (!(c == ' ' || c == '\t') || (!result.empty() && result.back() != ' '))
          result += (c == '\t' ? ' ' : c);
      return result;
    }

    /// One `subsection NAME` or `set NAME = value` of a .prm file.
    struct PrmStatement
    {
      std::size_t line;
      std::string section; ///< the enclosing sections, "A/B"; "" at the top
      std::string name;
      std::string value;
      bool        is_section;
    };

    /// Walks a .prm text as deal.II reads it (comments from '#', a trailing
    /// backslash continues a line) and reports each statement; throws
    /// InputError with the line for an unmatched 'end', an unclosed section
    /// or a 'set' without '='.
    void scan_prm(const std::string &text, const std::string &file,
                  const std::function<void(const PrmStatement &)> &visit)
    {
      std::vector<std::string> open;       // the section path, one name per level
      std::vector<std::size_t> open_lines; // where each level was opened
      std::istringstream       lines(text);
      std::string              line;
      for (std::size_t next = 1; std::getline(lines, line);)
        {
          const std::size_t number = next++;
          std::string       continued;
          while (!trimmed(line).empty() && trimmed(line).back() == '\\' && std::getline(lines, continued))
            {
              line = trimmed(line);
              line.pop_back();
              line += " " + continued;
              ++next;
            }
          const std::string statement = trimmed(line.substr(0, line.find('#')));
          const std::string where     = file + ":" + std::to_string(number);
          std::string       keyword, rest;
          std::istringstream words(statement);
          words >> keyword;
          std::getline(words, rest);
          if (keyword == "subsection")
            {
              visit({number, joined(open, "/"), normalised_name(rest), "", true});
              open.push_back(normalised_name(rest));
              open_lines.push_back(number);
            }
          else if (keyword == "end")
            {
              if (open.empty())
                throw InputError(where, "", "'end' without a 'subsection' to close");
              open.pop_back();
              open_lines.pop_back();
            }
          else if (keyword == "set")
            {
              const auto equals = rest.find('=');
              if (equals == std::string::npos)
                throw InputError(where, "", "expected 'set Name = value', got '" + statement + "'");
              visit({number, joined(open, "/"), normalised_name(rest.substr(0, equals)),
                     trimmed(rest.substr(equals + 1)), false});
            }
        }
      if (!open.empty())
        throw InputError(file + ":" + std::to_string(open_lines.back()), "",
                         "section '" + open.back() + "' is not closed; expected an 'end' for it");
    }

    boost::property_tree::ptree read_json_tree(const std::string &text, const std::string &file)
    {
      boost::property_tree::ptree tree;
      try
        {
          std::istringstream in(text);
          boost::property_tree::read_json(in, tree);
        }
      catch (const boost::property_tree::json_parser_error &error)
        {
          throw InputError(file + ":" + std::to_string(error.line()), "", "not valid JSON: " + error.message());
        }
      return tree;
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
          std::vector<std::string> paths;
          for (const auto &spec : specs)
            paths.push_back(spec.path);
          message = "unknown parameter '" + unknown + "' (" + message + ")" + did_you_mean(unknown, paths, true);
        }
      // deal.II quotes names in <...>; a section's name may lose its closing
      // bracket in the one-line form, so no brackets are left in the message.
      std::replace(message.begin(), message.end(), '<', '\'');
      std::replace(message.begin(), message.end(), '>', '\'');
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
    if (increasing)
      text += ", increasing";
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
    /// The declared tree: each section's ("" is the top) parameters and subsections.
    std::map<std::string, std::vector<std::string>> entries, subsections;
    /// Where each value that is not a default was set, by path.
    std::map<std::string, std::string> origins;

    void declare_layout(const std::string &path)
    {
      const auto  parts = split_path(path);
      std::string section;
      for (std::size_t i = 0; i + 1 < parts.size(); ++i)
        {
          const std::string child = section.empty() ? parts[i] : section + "/" + parts[i];
          auto &children = subsections[section];
          if (std::find(children.begin(), children.end(), parts[i]) == children.end())
            children.push_back(parts[i]);
          section = child;
        }
      entries[section].push_back(parts.back());
    }

    /// What may appear in `section`, for messages.
    std::string allowed_in(const std::string &section) const
    {
      std::vector<std::string> names;
      if (entries.count(section))
        names = entries.at(section);
      if (subsections.count(section))
        for (const auto &child : subsections.at(section))
          names.push_back("subsection " + child);
      return names.empty() ? "nothing" : joined(names);
    }

    [[noreturn]] void unknown_name(const std::string &where, const std::string &section, const std::string &name,
                                   bool is_section) const
    {
      std::vector<std::string> candidates;
      const auto &own = is_section ? subsections : entries;
      if (own.count(section))
        for (const auto &candidate : own.at(section))
          candidates.push_back(section.empty() ? candidate : section + "/" + candidate);
      std::string suggestion = did_you_mean(name, candidates, true);
      if (suggestion.empty() && !is_section)
        {
          // A parameter in the wrong section: suggest it where it is declared.
          std::vector<std::string> everywhere;
          for (const auto &[owner, names] : entries)
            for (const auto &candidate : names)
              everywhere.push_back(owner.empty() ? candidate : owner + "/" + candidate);
          suggestion = did_you_mean(name, everywhere, true);
        }
      throw InputError(where, "",
                       std::string("unknown ") + (is_section ? "section '" : "parameter '") + name + "' in " +
                         (section.empty() ? "the top level" : "section '" + section + "'") + " (allowed there: " +
                         allowed_in(section) + ")" + suggestion);
    }

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
    impl->declare_layout("Scene");
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
        impl->declare_layout(spec.path);
        for (std::size_t i = 0; i + 1 < parts.size(); ++i)
          handler.leave_subsection();
      }
  }

  SceneParameters::~SceneParameters() = default;
  SceneParameters::SceneParameters(SceneParameters &&) noexcept = default;

  void SceneParameters::parse_file(const std::string &path)
  {
    const std::string text = read_config_text(path);
    file_name              = path;
    const bool json        = extension_of(path) == ".json";
    if (json)
      check_json_text(text);
    else
      check_prm_text(text);
    try
      {
        std::istringstream in(text);
        if (json)
          impl->handler.parse_input_from_json(in);
        else
          impl->handler.parse_input(in, path);
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

  void SceneParameters::check_prm_text(const std::string &text)
  {
    std::map<std::string, std::size_t> seen; // path -> line
    scan_prm(text, file_name, [&](const PrmStatement &statement) {
      const std::string where = file_name + ":" + std::to_string(statement.line);
      const auto &declared = statement.is_section ? impl->subsections[statement.section] : impl->entries[statement.section];
      if (std::find(declared.begin(), declared.end(), statement.name) == declared.end())
        impl->unknown_name(where, statement.section, statement.name, statement.is_section);
      if (statement.is_section)
        return;
      const std::string path = statement.section.empty() ? statement.name : statement.section + "/" + statement.name;
      if (const auto previous = seen.find(path); previous != seen.end())
        throw InputError(where, path, "set twice, on lines " + std::to_string(previous->second) + " and " +
                                        std::to_string(statement.line) + "; expected it once");
      seen[path]          = statement.line;
      impl->origins[path] = where;
    });
  }

  void SceneParameters::check_json_text(const std::string &text)
  {
    namespace pt = boost::property_tree;
    // A JSON object may repeat a key; the parser keeps both, deal.II would use one.
    std::function<void(const pt::ptree &, const std::string &)> walk = [&](const pt::ptree &node,
                                                                         const std::string &section) {
      std::set<std::string> keys;
      for (const auto &[key, child] : node)
        {
          if (key.empty())
            throw InputError(file_name, section, "holds a list; expected an object of parameters and sections");
          const std::string path = section.empty() ? key : section + "/" + key;
          if (!keys.insert(key).second)
            throw InputError(file_name, path, "set twice in " +
                                                (section.empty() ? "the top level" : "section '" + section + "'") +
                                                "; expected it once");
          const bool  is_section = !child.empty();
          const auto &declared   = is_section ? impl->subsections[section] : impl->entries[section];
          if (std::find(declared.begin(), declared.end(), key) == declared.end())
            impl->unknown_name(file_name, section, key, is_section);
          if (is_section)
            walk(child, path);
          else
            impl->origins[path] = file_name;
        }
    };
    walk(read_json_tree(text, file_name), "");
  }

  std::string SceneParameters::origin_of(const std::string &path) const
  {
    if (const auto origin = impl->origins.find(path); origin != impl->origins.end())
      return origin->second;
    return file_name.empty() ? "(defaults)" : file_name;
  }

  void SceneParameters::set(const std::string &path, const std::string &value, const std::string &source)
  {
    const std::string origin = source.empty() ? "--set '" + path + "=" + value + "'" : source;
    if (!impl->patterns.count(path))
      {
        std::vector<std::string> paths;
        for (const auto &spec : spec_table)
          paths.push_back(spec.path);
        throw InputError(origin, "", "no parameter '" + path + "' in scene '" + scene_name + "'" +
                                       did_you_mean(path, paths));
      }
    impl->at(path, [&](const std::string &name) {
      impl->handler.set(name, value);
      return 0;
    });
    impl->origins[path] = origin;
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
        if (spec.increasing)
          for (std::size_t k = 1; k < values.size(); ++k)
            if (!(values[k] > values[k - 1]))
              reject(spec.path, "expected increasing values, each once, got " + format_number(values[k]) +
                                  " after " + format_number(values[k - 1]) + " in '" + get(spec.path) + "'");
      }
  }

  void SceneParameters::reject(const std::string &path, const std::string &problem) const
  {
    throw InputError(origin_of(path), path, problem);
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
    const std::string text = read_config_text(path);
    std::string       scene;
    if (extension_of(path) == ".json")
      scene = read_json_tree(text, path).get<std::string>("Scene", "");
    else
      scan_prm(text, path, [&](const PrmStatement &statement) {
        if (!statement.is_section && statement.section.empty() && statement.name == "Scene")
          scene = statement.value;
      });
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
  std::vector<long> parse_cell_counts(const std::string &text, std::size_t count)
  {
    std::string spaced = text;
    std::replace(spaced.begin(), spaced.end(), 'x', ' ');
    std::istringstream in(spaced);
    std::vector<long>  counts;
    std::string        word;
    while (in >> word)
      {
        std::size_t used = 0;
        long        value = 0;
        try
          {
            value = std::stol(word, &used);
          }
        catch (const std::exception &)
          {
            return {};
          }
        if (used != word.size() || value < 1)
          return {};
        counts.push_back(value);
      }
    if (counts.size() != count || static_cast<std::size_t>(std::count(text.begin(), text.end(), 'x')) + 1 != count)
      return {};
    return counts;
  }
} // namespace fretsim::app
