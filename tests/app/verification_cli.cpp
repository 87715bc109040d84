// The `fretsim` program end to end: exit codes, nothing written on bad input,
// a small concentrated run with its summary, and interrupted runs that leave a
// readable results file.
#include "app/test_files.h"

#include <fretsim/output/results_file.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

using namespace fretsim;

const std::string program = std::string(FRETSIM_BINARY_DIR) + "/fretsim";
using test_files::run_program;
using test_files::small_scene;
using test_files::summary_number;

TEST(Cli, VersionHelpAndParams)
{
  const auto version = run_program("--version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_NE(version.output.find("deal.II"), std::string::npos) << version.output;
  EXPECT_EQ(run_program("--help").exit_code, 0);
  const auto params = run_program("params concentrated");
  EXPECT_EQ(params.exit_code, 0);
  EXPECT_NE(params.output.find("set Friction coefficient = 0.53"), std::string::npos);
  EXPECT_EQ(run_program("params nonsense").exit_code, 2);
  EXPECT_EQ(run_program("frobnicate").exit_code, 2);
  EXPECT_EQ(run_program("run").exit_code, 2);
}

TEST(Cli, BadInputExitsWithTwoAndWritesNothing)
{
  const auto directory = test_files::scratch_directory("cli-bad");
  const auto scene     = directory / "bad.prm";
  test_files::write_text(scene, small_scene({{"Normal load", "-5"}}));
  const auto output = directory / "out";
  const auto result = run_program("run " + scene.string() + " -o " + output.string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("bad.prm"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("Loading/Normal load"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(output));
  // One line of error, nothing else.
  EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;

  const auto missing = run_program("run " + (directory / "missing.prm").string() + " -o " + output.string());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_FALSE(std::filesystem::exists(output));
}

TEST(Cli, SmallConcentratedRunWritesResultsAndSummary)
{
  const auto directory = test_files::scratch_directory("cli-run");
  const auto scene     = directory / "small.prm";
  test_files::write_text(scene, small_scene());
  const auto output = directory / "out";
  const auto result = run_program("run " + scene.string() + " -o " + output.string() + " --no-plots");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("results.h5"), std::string::npos);
  const std::string summary = test_files::read_text(output / "summary.json");
  for (const std::string key : {"scene", "wall_time_s", "contact_radius_m", "peak_pressure_Pa",
                                "tangential_force_amplitude_N", "dissipated_energy_per_cycle_J",
                                "loop_error_vs_mindlin"})
    EXPECT_NE(summary.find("\"" + key + "\""), std::string::npos) << key;
  // Hertz on a 32^2 grid: contact radius 752.8 um within 5 % (docs/references.md §1.2).
  EXPECT_NEAR(summary_number(summary, "contact_radius_m") / 752.77e-6, 1.0, 0.05);
  EXPECT_EQ(summary_number(summary, "cycles"), 3);
  const auto time = output::ResultsFile::read_dataset((output / "results.h5").string(), "/series/time");
  EXPECT_EQ(time.size(), 3u * 40u + 1u);
  EXPECT_TRUE(std::filesystem::exists(output / "results.xdmf"));
}

namespace
{
  /// Starts a long run, sends `signal_number` once some rows are on disk, and
  /// returns the exit status and the output directory.
  std::pair<int, std::filesystem::path> interrupted_run(int signal_number, const std::string &name)
  {
    const auto directory = test_files::scratch_directory(name);
    const auto scene     = directory / "long.prm";
    test_files::write_text(scene, small_scene({{"Cycles", "100000"}, {"Steps per cycle", "200"},
                                            {"Field snapshots per cycle", "1"}, {"Field output cycles", "100000"},
                                               {"Depth layers", "0"}}));
    const auto output = directory / "out";
    const pid_t child = fork();
    if (child == 0)
      {
        const std::string out = output.string(), cfg = scene.string();
        execl(program.c_str(), program.c_str(), "run", cfg.c_str(), "-o", out.c_str(), "--no-plots", "-q",
              static_cast<char *>(nullptr));
        _exit(127);
      }
    // Signal once the run is well under way: the results file exists (set-up
    // done) and a second of steps has followed, however loaded the machine.
    const auto started = std::chrono::steady_clock::now();
    while (!std::filesystem::exists(output / "results.h5") &&
           std::chrono::steady_clock::now() - started < std::chrono::seconds(60))
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    kill(child, signal_number);
    int status = 0;
    waitpid(child, &status, 0);
    return {status, output};
  }
} // namespace

TEST(Cli, InterruptedRunClosesResultsWithStepsDone)
{
  const auto [status, output] = interrupted_run(SIGTERM, "cli-term");
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
  const auto time = output::ResultsFile::read_dataset((output / "results.h5").string(), "/series/time");
  EXPECT_GT(time.size(), 10u);
  EXPECT_NE(test_files::read_text(output / "summary.json").find("\"interrupted\""), std::string::npos);
}

TEST(Cli, KilledRunLeavesReadableResults)
{
  // SIGKILL cannot be caught: the file must be readable from the flushes alone.
  const auto [status, output] = interrupted_run(SIGKILL, "cli-kill");
  ASSERT_TRUE(WIFSIGNALED(status));
  const auto time  = output::ResultsFile::read_dataset((output / "results.h5").string(), "/series/time");
  const auto force = output::ResultsFile::read_dataset((output / "results.h5").string(), "/series/tangential_force_x");
  EXPECT_GT(time.size(), 10u);
  // Series are separate datasets; a kill between two of them can leave one
  // row of difference.
  EXPECT_LE(std::max(force.size(), time.size()) - std::min(force.size(), time.size()), 1u);
}
