#pragma once
// Scratch files and directories for the application tests.
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
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
} // namespace fretsim::test_files
