#pragma once
// Scratch files and directories for the application tests.
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <cmath>
#include <cstdlib>
#include <regex>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <utility>
#include <vector>

namespace fretsim::test_files
{
  /// A fresh directory of this test process: ctest runs tests in parallel,
  /// each in its own process, so the name carries the process id.
  inline std::filesystem::path scratch_directory(const std::string &name)
  {
    const auto path = std::filesystem::temp_directory_path() /
                      ("fretsim-test-" + name + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
    return path;
  }

  inline std::string read_text(const std::filesystem::path &path)
  {
    std::ifstream in(path);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }

  /// A CSV table with a header line, as numbers by column name ("nan" reads
  /// as NaN, text as 0).
  using Row = std::map<std::string, double>;

  inline std::vector<Row> read_csv(const std::filesystem::path &path)
  {
    std::istringstream       text(read_text(path));
    std::string              line;
    std::vector<std::string> header;
    std::getline(text, line);
    for (std::stringstream cells(line); std::getline(cells, line, ',');)
      header.push_back(line);
    std::vector<Row> rows;
    while (std::getline(text, line))
      {
        Row               row;
        std::stringstream cells(line);
        std::string       cell;
        for (std::size_t k = 0; std::getline(cells, cell, ','); ++k)
          row[header.at(k)] = std::strtod(cell.c_str(), nullptr);
        rows.push_back(row);
      }
    return rows;
  }

  inline void write_text(const std::filesystem::path &path, const std::string &text)
  {
    std::ofstream(path) << text;
  }

  /// The shipped paper scene with `set NAME = ...` lines replaced, e.g.
  /// edited_paper_scene({{"Normal load", "-5"}}).
  inline std::string edited_paper_scene(const std::vector<std::pair<std::string, std::string>> &edits)
  {
    std::string text = read_text(std::string(FRETSIM_SOURCE_DIR) + "/configs/paper_concentrated.prm");
    for (const auto &[raw_name, value] : edits)
      {
        const std::string name = raw_name.substr(0, raw_name.find_last_not_of(' ') + 1);
        text = std::regex_replace(text, std::regex("set " + name + " *= *[^\n]*"), "set " + name + " = " + value);
      }
    return text;
  }

  /// A small, fast variant of the paper scene, with further edits.
  inline std::string small_scene(const std::vector<std::pair<std::string, std::string>> &extra = {})
  {
    std::vector<std::pair<std::string, std::string>> edits{
      {"Cells x", "32"}, {"Cells y", "32"}, {"Cycles", "3"}, {"Steps per cycle", "40"},
      {"Field snapshots per cycle", "4"}};
    edits.insert(edits.end(), extra.begin(), extra.end());
    return edited_paper_scene(edits);
  }

  struct Outcome
  {
    int         exit_code;
    std::string output; // stdout and stderr
  };

  /// Runs build/fretsim with `arguments` and captures its output.
  inline Outcome run_program(const std::string &arguments)
  {
    static int  calls   = 0;
    const auto  log     = scratch_directory("log-" + std::to_string(calls++)) / "output.txt";
    const auto  program = std::string(FRETSIM_BINARY_DIR) + "/fretsim";
    const int   status  = std::system((program + " " + arguments + " > " + log.string() + " 2>&1").c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_text(log)};
  }

  /// A number from summary.json, NaN if the key is missing.
  inline double summary_number(const std::string &json, const std::string &key)
  {
    const auto at = json.find("\"" + key + "\"");
    if (at == std::string::npos)
      return std::nan("");
    return std::strtod(json.c_str() + json.find(':', at) + 1, nullptr);
  }
} // namespace fretsim::test_files
