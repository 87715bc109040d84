// Traction models in the scene and `fretsim compare-traction`: the exact model
// reproduces Mindlin–Deresiewicz through the whole scene pipeline, and the
// comparison reports every model against it.
#include "app/test_files.h"

#include <gtest/gtest.h>

#include <sstream>

using namespace fretsim;
using test_files::run_program;
using test_files::summary_number;

namespace
{
  /// 64 x 64 cells, 40 steps per cycle, 2 cycles, one depth layer.
  std::string scene_text(const std::string &model)
  {
    return test_files::edited_paper_scene({{"Cells x", "64"}, {"Cells y", "64"}, {"Cycles", "2"},
                                           {"Steps per cycle", "40"}, {"Field snapshots per cycle", "4"},
                                           {"Depth layers", "0"},
                                           {"Friction coefficient", "0.53\n  set Traction model = " + model}});
  }
} // namespace

TEST(TractionModels, ExactModelFollowsMindlinInTheScene)
{
  const auto directory = test_files::scratch_directory("traction-exact");
  test_files::write_text(directory / "scene.prm", scene_text("exact"));
  const auto result = run_program("run " + (directory / "scene.prm").string() + " -o " +
                                  (directory / "out").string() + " --no-plots -q");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string summary = test_files::read_text(directory / "out" / "summary.json");
  // Issue 5: the exact loop within 1 % of mu P of Mindlin–Deresiewicz at every
  // point of the cycle (measured 3e-4 on 64^2 with 40 steps), energy within 2 %.
  EXPECT_LT(summary_number(summary, "loop_error_vs_mindlin"), 0.01);
  EXPECT_NEAR(summary_number(summary, "dissipated_energy_per_cycle_J") /
                summary_number(summary, "mindlin_dissipated_energy_per_cycle_J"),
              1.0, 0.02);
  EXPECT_GT(summary_number(summary, "traction_iterations_per_step"), 0.0);
}

TEST(TractionModels, CompareTractionReportsEveryModelAgainstExact)
{
  const auto directory = test_files::scratch_directory("compare-traction");
  test_files::write_text(directory / "scene.prm", scene_text("bristle"));
  const auto output = directory / "out";
  const auto result =
    run_program("compare-traction " + (directory / "scene.prm").string() + " -o " + output.string() + " --no-plots -q");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::istringstream lines(test_files::read_text(output / "compare_traction.csv"));
  std::string        line;
  std::getline(lines, line);
  std::map<std::string, std::vector<double>> rows;
  while (std::getline(lines, line))
    {
      std::istringstream fields(line);
      std::string        model, value;
      std::getline(fields, model, ',');
      while (std::getline(fields, value, ','))
        rows[model].push_back(std::stod(value));
    }
  ASSERT_EQ(rows.size(), 3u);
  // Columns after the model: wall, speed-up, traction time, traction speed-up,
  // loop error, energy, energy error, D_max, dD_max, distance, x, y, depth.
  EXPECT_EQ(rows["exact"][4], 0.0);
  EXPECT_EQ(rows["exact"][8], 0.0);
  // The paper's claim, for the traction stage: the local bristle models are
  // orders of magnitude faster than the exact solver (measured ~400-900x).
  EXPECT_GT(rows["bristle"][3], 30.0);
  EXPECT_GT(rows["elastoplastic bristle"][3], 30.0);
  // The exponential bristle's loop is the farther from exact (8.5 % vs 2.3 %
  // of mu P on the paper case) and dissipates several times more (README).
  EXPECT_GT(rows["bristle"][4], rows["elastoplastic bristle"][4]);
  EXPECT_GT(rows["bristle"][6], 1.0);
  for (const auto &model : {"bristle", "elastoplastic bristle", "exact"})
    EXPECT_TRUE(std::filesystem::exists(output / std::string(model == std::string("elastoplastic bristle") ?
                                                                "elastoplastic_bristle" : model) /
                                        "results.h5"));
}
