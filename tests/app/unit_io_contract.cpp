// The program's input/output contract: bad input is refused with one line
// naming the file or option, the parameter and what was expected, exit code
// 2, before anything is computed; nothing of the user's is overwritten.
#include "app/test_files.h"

#include <fretsim/support/parameters.h>
#include <fretsim/support/run_control.h>
#include <fretsim/scenes/scene.h>

#include <gtest/gtest.h>

#include <chrono>

using namespace fretsim;
using test_files::run_program;

namespace
{
  std::filesystem::path small_scene_file(const std::filesystem::path &dir)
  {
    test_files::write_text(dir / "scene.prm", test_files::small_scene({{"Cycles", "2"}, {"Steps per cycle", "8"},
                                                                      {"Field snapshots per cycle", "2"}}));
    return dir / "scene.prm";
  }

  /// The InputError message of loading a configuration text, "" if it loads.
  std::string load_error(const std::string &text, const std::string &extension = ".prm",
                         const std::vector<std::pair<std::string, std::string>> &overrides = {})
  {
    const auto path = test_files::scratch_directory("contract") / ("scene" + extension);
    test_files::write_text(path, text);
    try
      {
        scenes::load_parameters(path.string(), overrides);
      }
    catch (const app::InputError &error)
      {
        return error.what();
      }
    return "";
  }

  bool one_line(const std::string &text) { return text.find('\n') == text.size() - 1; }
} // namespace

TEST(OutputFolder, PreviousResultIsRefusedWithoutForceAndOnlyOwnFilesAreReplacedWithIt)
{
  const auto dir = test_files::scratch_directory("folder-policy");
  const auto scene = small_scene_file(dir);
  const std::string run = "run " + scene.string() + " -q --no-plots -o " + (dir / "out").string();
  ASSERT_EQ(run_program(run).exit_code, 0);
  test_files::write_text(dir / "out" / "notes.txt", "the user's");
  test_files::write_text(dir / "out" / "loop.png", "a previous run's figure");

  const auto again = run_program(run);
  EXPECT_EQ(again.exit_code, 2) << again.output;
  EXPECT_NE(again.output.find("'-o'"), std::string::npos) << again.output;
  EXPECT_NE(again.output.find("--force"), std::string::npos) << again.output;
  EXPECT_TRUE(one_line(again.output)) << again.output;

  const auto forced = run_program(run + " --force");
  EXPECT_EQ(forced.exit_code, 0) << forced.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "loop.png")) << "a stale figure of the previous run";
  EXPECT_EQ(test_files::read_text(dir / "out" / "notes.txt"), "the user's");
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "results.h5"));
}

TEST(OutputFolder, SecondCommandIntoALockedFolderIsRefused)
{
  const auto dir = test_files::scratch_directory("folder-lock");
  const auto scene = small_scene_file(dir);
  app::OutputPolicy policy;
  policy.own_files = app::scene_output_files();
  {
    const app::OutputFolder held((dir / "out").string(), policy);
    const auto second = run_program("run " + scene.string() + " -q --no-plots --force -o " + (dir / "out").string());
    EXPECT_EQ(second.exit_code, 2) << second.output;
    EXPECT_NE(second.output.find("another fretsim command"), std::string::npos) << second.output;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "out")) << "an unused new folder is removed again";
}

TEST(OutputFolder, EveryOutputPathProblemNamesTheOptionBeforeComputing)
{
  const auto dir = test_files::scratch_directory("output-paths");
  const auto scene = small_scene_file(dir);
  test_files::write_text(dir / "a_file", "x");
  // Every path problem with `run`, and one with every other command (they share the check).
  std::vector<std::pair<std::string, std::string>> cases;
  for (const std::string &output : {(dir / "a_file" / "below").string(), std::string("''"),
                                   std::string("/mnt/fretsim-no-such-drive/out")})
    cases.emplace_back("run " + scene.string(), output);
  for (const std::string command : {"run", "compare-traction", "fe", "mesh", "compare"})
    cases.emplace_back(command + " " + scene.string(), (dir / "a_file").string());
  cases.emplace_back("bench stresses", (dir / "a_file").string());
  for (const auto &[command, output] : cases)
      {
        const auto result = run_program(command + " -o " + output);
        EXPECT_EQ(result.exit_code, 2) << command << " -o " << output << ": " << result.output;
        EXPECT_NE(result.output.find("'-o'"), std::string::npos) << command << ": " << result.output;
        EXPECT_EQ(result.output.find("internal error"), std::string::npos) << result.output;
        EXPECT_TRUE(one_line(result.output)) << result.output;
      }
  const auto model = run_program("reduce " + scene.string() + " -o " + dir.string());
  EXPECT_EQ(model.exit_code, 2) << model.output;
  EXPECT_NE(model.output.find("is a folder"), std::string::npos) << model.output;
}

TEST(ResourceEstimate, DryRunPrintsTheEstimateAndWritesNothing)
{
  const auto dir = test_files::scratch_directory("dry-run");
  const auto result = run_program("run --dry-run " + small_scene_file(dir).string() + " -o " + (dir / "out").string());
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("memory: about"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("MemAvailable"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("disk:   about"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

TEST(ResourceEstimate, GridThatCannotFitInMemoryIsRefusedAtOnce)
{
  const auto dir   = test_files::scratch_directory("huge-grid");
  const auto start = std::chrono::steady_clock::now();
  const auto result = run_program("run " + small_scene_file(dir).string() + " --set 'Grid/Cells x=4096' --set "
                                  "'Grid/Cells y=4096' -o " + (dir / "out").string());
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("Grid/Cells x"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("MemAvailable"), std::string::npos) << result.output;
  EXPECT_TRUE(one_line(result.output)) << result.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

TEST(ResourceEstimate, TerabytesOfFieldSnapshotsAreRefused)
{
  // A snapshot every step over 1e7 steps: ~50 TB at 128 x 128 cells.
  const auto dir    = test_files::scratch_directory("huge-output");
  const auto result = run_program(
    "run --dry-run " + small_scene_file(dir).string() + " --set 'Grid/Cells x=128' --set 'Grid/Cells y=128'" +
    " --set 'Loading/Cycles=100' --set 'Loading/Steps per cycle=100000' --set 'Output/Field snapshots per "
    "cycle=100000' --set 'Output/Field output cycles=100'");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("Output/Field snapshots per cycle"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("TB"), std::string::npos) << result.output;
}

TEST(ResourceEstimate, GrowsWithTheGridAndTheSnapshots)
{
  const auto estimate = [](const std::vector<std::pair<std::string, std::string>> &edits) {
    const auto path = test_files::scratch_directory("estimate") / "scene.prm";
    test_files::write_text(path, test_files::small_scene(edits));
    return scenes::estimate_resources(scenes::load_parameters(path.string()));
  };
  // Above what every run needs (the process, the figures), the estimate
  // follows the cells and the snapshots.
  const auto small = estimate({}), fine = estimate({{"Cells x", "256"}, {"Cells y", "256"}});
  EXPECT_GT(fine.memory_bytes - 150e6, 32.0 * (small.memory_bytes - 150e6)); // 64x the cells
  const auto often = estimate({{"Field snapshots per cycle", "40"}});         // 10x the snapshots
  EXPECT_GT(often.disk_bytes - 5e6, 5.0 * (small.disk_bytes - 5e6));
}

TEST(Messages, MisspeltJsonSectionAndParameterAreNamedWithWhatIsAllowed)
{
  const std::string entry = load_error(R"({"Scene": "concentrated", "Loading": {"Normal lod": "5"}})", ".json");
  EXPECT_NE(entry.find("scene.json"), std::string::npos) << entry;
  EXPECT_NE(entry.find("'Normal lod'"), std::string::npos) << entry;
  EXPECT_NE(entry.find("allowed there: Normal load"), std::string::npos) << entry;
  EXPECT_NE(entry.find("did you mean 'Loading/Normal load'"), std::string::npos) << entry;
  const std::string section = load_error(R"({"Scene": "concentrated", "Loadng": {"Normal load": "5"}})", ".json");
  EXPECT_NE(section.find("unknown section 'Loadng'"), std::string::npos) << section;
  EXPECT_NE(section.find("did you mean 'Loading'"), std::string::npos) << section;
}

TEST(Messages, SetErrorsNameSetWithSuggestion)
{
  const std::string misspelt = load_error("set Scene = concentrated\n", ".prm", {{"Loading/Normal lod", "5"}});
  EXPECT_NE(misspelt.find("--set 'Loading/Normal lod=5'"), std::string::npos) << misspelt;
  EXPECT_NE(misspelt.find("did you mean 'Loading/Normal load'"), std::string::npos) << misspelt;
  EXPECT_EQ(misspelt.find("scene.prm"), std::string::npos) << misspelt;
  const std::string range = load_error("set Scene = concentrated\n", ".prm", {{"Loading/Normal load", "-5"}});
  EXPECT_EQ(range.rfind("--set 'Loading/Normal load=-5'", 0), 0u) << range;

  const auto twice = run_program("run --dry-run " + small_scene_file(test_files::scratch_directory("set-twice")).string() +
                                 " --set 'Grid/Cells x=32' --set 'Grid/Cells x=64'");
  EXPECT_EQ(twice.exit_code, 2) << twice.output;
  EXPECT_NE(twice.output.find("--set 'Grid/Cells x=32'"), std::string::npos) << twice.output;
  EXPECT_NE(twice.output.find("--set 'Grid/Cells x=64'"), std::string::npos) << twice.output;
}

TEST(Messages, ParameterSetTwiceInAFileNamesBothLines)
{
  const std::string prm = load_error("set Scene = concentrated\nsubsection Loading\n  set Cycles = 2\n  set Cycles = 3\nend\n");
  EXPECT_NE(prm.find("scene.prm:4"), std::string::npos) << prm;
  EXPECT_NE(prm.find("lines 3 and 4"), std::string::npos) << prm;
  const std::string json =
    load_error(R"({"Scene": "concentrated", "Loading": {"Cycles": "2", "Cycles": "3"}})", ".json");
  EXPECT_NE(json.find("'Loading/Cycles': set twice"), std::string::npos) << json;
}

TEST(Messages, SectionErrorsInPrmFilesAreOneLineWithoutAngleBrackets)
{
  for (const std::string text : {"set Scene = concentrated\nsubsection Loadng\nend\n",
                                 "set Scene = concentrated\nend\n",
                                 "set Scene = concentrated\nsubsection Loading\n  set Cycles = 2\n"})
    {
      const std::string message = load_error(text);
      EXPECT_NE(message, "") << text;
      EXPECT_EQ(message.find('<'), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      EXPECT_NE(message.find("scene.prm:"), std::string::npos) << message;
    }
}

TEST(Messages, ByteOrderMarkIsAcceptedAndADirectoryIsNamedAsOne)
{
  EXPECT_EQ(load_error("\xEF\xBB\xBFset Scene = concentrated\n"), "");
  EXPECT_EQ(load_error("\xEF\xBB\xBF{\"Scene\": \"concentrated\"}", ".json"), "");
  const auto dir = test_files::scratch_directory("config-dir") / "scene.prm";
  std::filesystem::create_directories(dir);
  const auto result = run_program("run --dry-run " + dir.string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("is a directory"), std::string::npos) << result.output;
}

TEST(Messages, FullDiskIsOneLineAndNoCrash)
{
  // A file size limit stands in for a full disk (the write fails with EFBIG).
  const auto dir   = test_files::scratch_directory("full-disk");
  const auto log   = dir / "log.txt";
  const auto scene = small_scene_file(dir);
  const std::string command = "ulimit -f 100; trap '' XFSZ; " + std::string(FRETSIM_BINARY_DIR) + "/fretsim run " +
                              scene.string() + " -q --no-plots --set 'Grid/Cells x=64' --set 'Grid/Cells y=64' -o " +
                              (dir / "out").string() + " > " + log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1) << test_files::read_text(log);
  EXPECT_TRUE(one_line(test_files::read_text(log))) << test_files::read_text(log);
  EXPECT_NE(test_files::read_text(log).find("File too large"), std::string::npos) << test_files::read_text(log);
}

TEST(DepthLayers, UnsortedOrRepeatedListIsRefusedWhereTheSpecAsksForIncreasing)
{
  auto depths       = app::ParameterSpec::non_negative("Stresses/Depth layers", "0, 1e-4", "Depths [m].");
  depths.kind       = app::ParameterSpec::Kind::real_list;
  depths.increasing = true;
  app::SceneParameters parameters("test", {depths});
  EXPECT_NO_THROW(parameters.set("Stresses/Depth layers", "0, 1e-5, 2e-5"));
  for (const std::string bad : {"0, 2e-5, 1e-5", "0, 1e-5, 1e-5"})
    try
      {
        parameters.set("Stresses/Depth layers", bad);
        ADD_FAILURE() << bad;
      }
    catch (const app::InputError &error)
      {
        EXPECT_NE(std::string(error.what()).find("expected increasing"), std::string::npos) << error.what();
        EXPECT_NE(std::string(error.what()).find("Stresses/Depth layers"), std::string::npos) << error.what();
      }
  bool       bearing_flagged = false;
  const auto bearing         = scenes::declare_parameters("bearing_housing");
  for (const auto &spec : bearing.specs())
    bearing_flagged = bearing_flagged || (spec.path == "Stresses/Depth layers" && spec.increasing);
  EXPECT_TRUE(bearing_flagged);
}
