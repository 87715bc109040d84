#pragma once
// summary.json: a flat record of the run's key numbers (docs/theory.md §6),
// written atomically (temporary file + rename) so it is never half-written.
#include <string>
#include <utility>
#include <vector>

namespace fretsim::output
{
  class Summary
  {
  public:
    void set(const std::string &key, double value);
    void set(const std::string &key, long long value);
    void set(const std::string &key, const std::string &value);
    void set(const std::string &key, bool value);
    void set(const std::string &key, const std::vector<double> &values);
    /// Stored as a nested JSON object, e.g. "stage_times_s": {...}.
    void set_object(const std::string &key, const Summary &object);

    std::string to_json(int indent = 0) const;
    void        write(const std::string &path) const;

  private:
    std::vector<std::pair<std::string, std::string>> entries; // key, JSON text
  };
} // namespace fretsim::output
