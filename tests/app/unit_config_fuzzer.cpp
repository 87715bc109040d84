// The config fuzzer (scripts/fuzz_configs.py) on a small fixed batch: mutated
// shipped configurations give exit code 0 or 2, never a crash, and a refusal
// is one line. The same executable is the fuzzer's in-process driver: with
// FRETSIM_FUZZ_LIST set it runs `fretsim run --dry-run` on each listed file
// through the command-line entry point and reports the outcomes.
#include "app/test_files.h"

#include "app/cli.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>

using namespace fretsim;

namespace
{
  /// Exit code and standard error of one command line, run in this process.
  std::pair<int, std::string> run_in_process(std::vector<std::string> arguments)
  {
    std::vector<char *> argv;
    for (auto &argument : arguments)
      argv.push_back(argument.data());
    std::ostringstream errors, output;
    auto *const        error_buffer  = std::cerr.rdbuf(errors.rdbuf());
    auto *const        output_buffer = std::cout.rdbuf(output.rdbuf());
    const int          code = app::run_command_line(static_cast<int>(argv.size()), argv.data());
    std::cerr.rdbuf(error_buffer);
    std::cout.rdbuf(output_buffer);
    return {code, errors.str()};
  }

  std::size_t line_count(const std::string &text)
  {
    std::size_t       lines = 0;
    std::string       line;
    for (std::istringstream in(text); std::getline(in, line);)
      ++lines;
    return lines;
  }
} // namespace

TEST(ConfigFuzzer, DriverOrSmallBatchGivesOnlyExitCodesZeroAndTwo)
{
  if (const char *listing = std::getenv("FRETSIM_FUZZ_LIST"))
    {
      // Driver mode: the fuzzer judges the report.
      std::ifstream in(listing);
      std::ofstream report(std::getenv("FRETSIM_FUZZ_REPORT"));
      const std::string scratch = std::getenv("FRETSIM_FUZZ_OUTPUT");
      for (std::string path; std::getline(in, path);)
        {
          if (path.empty())
            continue;
          const std::string output = scratch + "/out-" + std::filesystem::path(path).filename().string();
          const auto [code, errors] = run_in_process({"fretsim", "run", "--dry-run", path, "-o", output});
          report << code << '\t' << line_count(errors) << '\t' << path << '\n' << std::flush;
        }
      return;
    }
  const std::string python = FRETSIM_PYTHON;
  // python3 is one of the packages scripts/setup.sh installs: its absence is a
  // broken set-up, not a reason to skip.
  ASSERT_FALSE(python.empty()) << "CMake found no python3 (FRETSIM_PYTHON)";
  const auto log = test_files::scratch_directory("fuzz") / "fuzz.log";
  const std::string command = python + " " + FRETSIM_SOURCE_DIR + "/scripts/fuzz_configs.py --count 200 --seed 1 --batch 100" +
                              " --program " + FRETSIM_BINARY_DIR + "/fretsim --driver /proc/" +
                              std::to_string(::getpid()) + "/exe > " + log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << test_files::read_text(log);
  EXPECT_NE(test_files::read_text(log).find("200 inputs, 0 problems"), std::string::npos) << test_files::read_text(log);
}
