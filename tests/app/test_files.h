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

  /// A small grooved ring of the bearing tests (a coarse Craig–Bampton model
  /// built on first use in seconds).
  inline const std::string small_ring = "set Scene = ring_housing\n"
                                 "subsection Mesh\n  set Element degree = 1\nend\n"
                                 "subsection Divisions\n  set Circumferential = 48\n  set Radial ring = 1\n"
                                 "  set Axial = 2\n  set Axial land = 1\nend\n"
                                 "subsection Reduction\n  set Fixed-interface modes = 10\n"
                                 "  set Characteristic constraint modes = 30\n  set Compare with full FE = false\n"
                                 "  set Interface grid circumferential cells = 72\n  set Interface grid axial cells = 4\n"
                                 "  set Sample points per line = 8\n  set Raceway ball positions = 360\nend\n";

  /// The housing of the small ring, held at its outside, reduced on its bore.
  /// As many divisions around as the grid has columns: then every column
  /// sits on the mesh as the first does, as the circulant residual
  /// flexibility takes it (with 48 divisions its u_r error at the run's
  /// tractions went only from 0.070 to 0.045 with R_h, against 0.18-0.20 to
  /// 0.017-0.026 with 72).
  inline const std::string small_housing =
    "set Scene = ring_housing\n"
    "subsection Mesh\n  set Bodies = housing\n  set Element degree = 1\nend\n"
    "subsection Divisions\n  set Circumferential = 72\n  set Radial housing = 2\n"
    "  set Axial = 2\n  set Axial land = 1\nend\n"
    "subsection Reduction\n  set Coupling surfaces = housing_bore\n"
    "  set Clamped surfaces = housing_outer\n  set Fixed-interface modes = 10\n"
    "  set Characteristic constraint modes = 30\n  set Compare with full FE = false\n"
    "  set Interface grid circumferential cells = 72\n  set Interface grid axial cells = 4\n"
    "  set Sample points per line = 8\n  set Raceway ball positions = 0\nend\n";

  /// A bearing_housing scene on small_ring (ring.prm in `dir`), its model
  /// and its ring stress tables (a mesh as many cells around as the grid has
  /// columns, built on first use in seconds) in `dir`.
  inline std::string small_bearing_scene(const std::filesystem::path &dir, const std::string &extra = "")
  {
    return "set Scene = bearing_housing\n"
           "subsection Model\n  set Reduction configuration = ring.prm\n  set Model file = " +
           (dir / "model.h5").string() +
           "\nend\n"
           "subsection Loading\n  set Ball pass periods = 3.5\n  set Ramp time = 0.5e-3\nend\n"
           "subsection Output\n  set Samples per ball pass = 24\nend\n"
           "subsection Stresses\n  set Depth layers = 0, 2e-4\n  set Ring mesh = 72x2x3x1\nend\n" +
           extra;
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
