// summary.json: ordered keys, each stored as its JSON text; written through a
// temporary file and a rename so a reader never sees half a file.
#include <fretsim/output/summary.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include <unistd.h>

namespace fretsim::output
{
  namespace
  {
    std::string json_string(const std::string &text)
    {
      std::string out = "\"";
      for (const char c : text)
        switch (c)
          {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\b': out += "\\b"; break;
            case '\f': out += "\\f"; break;
            case '\n': out += "\\n"; break;
            case '\r': out += "\\r"; break;
            case '\t': out += "\\t"; break;
            default:
              if (static_cast<unsigned char>(c) < 0x20)
                {
                  char escaped[8];
                  std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned>(c));
                  out += escaped;
                }
              else
                out += c; // UTF-8 bytes pass through: JSON text is UTF-8
          }
      return out + "\"";
    }

    /// The shortest "%.Ng" (N ≤ 17) that reads back as the same double, so
    /// 0.1 stays "0.1" and every value round-trips; JSON has no NaN or
    /// infinity, so those become null.
    std::string json_number(double value)
    {
      if (!std::isfinite(value))
        return "null";
      char buffer[32];
      for (int digits = 15; digits <= 17; ++digits)
        {
          std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
          if (std::strtod(buffer, nullptr) == value)
            break;
        }
      return buffer;
    }

    /// Re-indents the compact JSON text this class writes: objects get one
    /// member per line, arrays stay on one line.
    std::string indented(const std::string &compact, int indent)
    {
      std::string out;
      std::string stack; // '{' or '[' per open container
      bool        in_string = false, escaped = false;
      auto        newline   = [&] { out += "\n" + std::string(stack.size() * indent, ' '); };
      for (std::size_t i = 0; i < compact.size(); ++i)
        {
          const char c = compact[i];
          if (in_string)
            {
              out += c;
              if (escaped)
                escaped = false;
              else if (c == '\\')
                escaped = true;
              else if (c == '"')
                in_string = false;
              continue;
            }
          switch (c)
            {
              case '"':
                in_string = true;
                out += c;
                break;
              case '{':
                out += c;
                stack += c;
                if (i + 1 < compact.size() && compact[i + 1] != '}')
                  newline();
                break;
              case '[':
                out += c;
                stack += c;
                break;
              case '}':
                stack.pop_back();
                if (i > 0 && compact[i - 1] != '{')
                  newline();
                out += c;
                break;
              case ']':
                stack.pop_back();
                out += c;
                break;
              case ',':
                out += c;
                if (!stack.empty() && stack.back() == '{')
                  {
                    newline();
                    if (i + 1 < compact.size() && compact[i + 1] == ' ')
                      ++i;
                  }
                break;
              default: out += c;
            }
        }
      return out;
    }

    /// Sets `key`; a key set again keeps its place.
    void put(std::vector<std::pair<std::string, std::string>> &entries, const std::string &key, std::string json)
    {
      for (auto &entry : entries)
        if (entry.first == key)
          {
            entry.second = std::move(json);
            return;
          }
      entries.emplace_back(key, std::move(json));
    }
  } // namespace

  void Summary::set(const std::string &key, double value) { put(entries, key, json_number(value)); }

  void Summary::set(const std::string &key, long long value) { put(entries, key, std::to_string(value)); }

  void Summary::set(const std::string &key, const std::string &value) { put(entries, key, json_string(value)); }

  void Summary::set(const std::string &key, bool value) { put(entries, key, value ? "true" : "false"); }

  void Summary::set(const std::string &key, const std::vector<double> &values)
  {
    std::string json = "[";
    for (std::size_t i = 0; i < values.size(); ++i)
      json += (i ? ", " : "") + json_number(values[i]);
    put(entries, key, json + "]");
  }

  void Summary::set_object(const std::string &key, const Summary &object) { put(entries, key, object.to_json(0)); }

  std::string Summary::to_json(int indent) const
  {
    std::string compact = "{";
    for (std::size_t i = 0; i < entries.size(); ++i)
      compact += (i ? ", " : "") + json_string(entries[i].first) + ": " + entries[i].second;
    compact += "}";
    return indent > 0 ? indented(compact, indent) : compact;
  }

  void Summary::write(const std::string &path) const
  {
    const std::string text      = to_json(2) + "\n";
    const std::string temporary = path + ".tmp";
    auto              failure   = [&](const std::string &what) {
      const std::string reason = std::strerror(errno);
      std::remove(temporary.c_str());
      return std::runtime_error("summary file '" + path + "': " + what + " (" + reason + ")");
    };
    std::FILE *file = std::fopen(temporary.c_str(), "wb");
    if (!file)
      throw failure("cannot create '" + temporary + "'");
    const bool written = std::fwrite(text.data(), 1, text.size(), file) == text.size() && std::fflush(file) == 0 &&
                         fsync(fileno(file)) == 0;
    const int saved_errno = errno;
    if (std::fclose(file) != 0 || !written)
      {
        if (!written)
          errno = saved_errno;
        throw failure("cannot write '" + temporary + "'");
      }
    if (std::rename(temporary.c_str(), path.c_str()) != 0)
      throw failure("cannot rename '" + temporary + "'");
  }
} // namespace fretsim::output
