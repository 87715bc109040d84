// The paper's §4 case end to end through the Dang Van stage (paper Fig. 11:
// "maximum risk around 0.8", at the contact edge on the surface).
//
// With the paper's bristle traction and the pressure solved on the grid
// (docs/concentrated.md, "D_max against the numerics"): on 128 x 128 cells,
// 200 steps per cycle, D_max = 0.635. It rises
// with the grid because the maximum sits exactly on the contact edge, where
// pressure and traction have square-root profiles that cell-centred sampling
// resolves as h^0.7: 0.568 / 0.629 / 0.687 / 0.722 at 64 / 128 / 256 / 512
// cells (100 steps), extrapolated 0.78 +- 0.03 at zero cell size, plus
// +0.006 for the time step at 200 steps per cycle. The tests below hold the
// shipped discretisation to its own value (a drift detector: the numbers are
// deterministic to ~1e-10) and to the bounds the study gives.
#include "app/test_files.h"

#include <fretsim/output/results_file.h>

#include <gtest/gtest.h>

#include <cmath>
#include <map>

using namespace fretsim;
using test_files::run_program;
using test_files::summary_number;

namespace
{
  /// summary.json of the shipped paper scene with `edits`.
  std::string run_paper_scene(const std::string &name, const std::vector<std::pair<std::string, std::string>> &edits)
  {
    const auto directory = test_files::scratch_directory(name);
    test_files::write_text(directory / "scene.prm", test_files::edited_paper_scene(edits));
    const auto result = run_program("run " + (directory / "scene.prm").string() + " -o " +
                                    (directory / "out").string() + " --no-plots -q");
    EXPECT_EQ(result.exit_code, 0) << result.output;
    return test_files::read_text(directory / "out" / "summary.json");
  }

  std::vector<double> summary_vector(const std::string &json, const std::string &key)
  {
    std::vector<double> values;
    auto                at = json.find("\"" + key + "\"");
    if (at == std::string::npos)
      return values;
    at = json.find('[', at);
    const auto end = json.find(']', at);
    const char *cursor = json.c_str() + at + 1;
    while (cursor < json.c_str() + end)
      {
        char *next = nullptr;
        values.push_back(std::strtod(cursor, &next));
        cursor = next + 1;
      }
    return values;
  }
} // namespace

TEST(SceneRisk, PaperCaseMaximumRiskAtTheContactEdge)
{
  // The running mean reaches D_max in the first cycle (t = 0.675 s), so two
  // cycles give the 8-cycle value exactly; the loop metrics are not tested here.
  // The pressure solved on the grid, as in the study.
  const std::string summary = run_paper_scene("risk-paper", {{"Cycles", "2"}, {"Traction model", "bristle"},
                                                             {"Risk error estimate", "false"},
                                                             {"Pressure model", "numerical"}});
  const double      risk_max = summary_number(summary, "risk_max");
  // Drift detector: the shipped discretisation's value, 0.63526, to 0.5 %.
  EXPECT_NEAR(risk_max, 0.63526, 0.005 * 0.63526);
  // Physical bounds from the convergence study: below the converged 0.78 +- 0.03
  // (the grid only underestimates the edge peak) and above 0.55 (64 x 64).
  EXPECT_LT(risk_max, 0.81);
  EXPECT_GT(risk_max, 0.55);
  EXPECT_NEAR(summary_number(summary, "risk_max_time_s"), 0.675, 0.0051); // one step = 0.005 s
  EXPECT_EQ(summary_number(summary, "risk_infinite_points"), 0);

  // On the surface, at the contact edge in the sliding direction: |x| within
  // two cells (2 x 3a/128 = 35 um) of the numerical contact radius, |y| < 0.15a.
  const double              contact_radius = summary_number(summary, "contact_radius_m");
  const std::vector<double> location       = summary_vector(summary, "risk_max_location_m");
  ASSERT_EQ(location.size(), 3u);
  EXPECT_NEAR(std::abs(location[0]), contact_radius, 35e-6);
  EXPECT_LT(std::abs(location[1]), 0.15 * contact_radius);
  EXPECT_EQ(location[2], 0.0);
  EXPECT_EQ(summary_number(summary, "risk_max_depth_m"), 0.0);
}

TEST(SceneRisk, ResidualStressOptionsOnThePaperCase)
{
  // The per-cycle centres skip the running mean's first-cycle transient: they
  // give a lower D_max (0.613 last-cycle mean, 0.609 hypersphere on the shipped
  // grid), and they agree with each other within 1 % because the stress cycle
  // at the hot spot is nearly symmetric about its mean.
  const std::vector<std::pair<std::string, std::string>> bristle{
    {"Cycles", "2"}, {"Traction model", "bristle"}, {"Risk error estimate", "false"}, {"Pressure model", "numerical"}};
  auto with = [&](const std::string &centre) {
    auto edits = bristle;
    edits.emplace_back("Residual stress", centre);
    return edits;
  };
  const std::string mean   = run_paper_scene("risk-mean", with("last_cycle_mean"));
  const std::string sphere = run_paper_scene("risk-sphere", with("hypersphere"));
  const double risk_mean = summary_number(mean, "risk_max"), risk_sphere = summary_number(sphere, "risk_max");
  EXPECT_NEAR(risk_mean, 0.6128, 0.005 * 0.6128);
  EXPECT_NEAR(risk_sphere, 0.6091, 0.005 * 0.6091);
  EXPECT_LT(risk_mean, 0.63526);
}

TEST(SceneRisk, TheConvergedRiskOfACoarseRunHoldsTheFineOne)
{
  // The shipped model (exact masing) on N^2 cells and on 4 times finer, each
  // with its estimate over h, 2h, 4h (2 cycles of 100 steps: the running-mean
  // risk peaks in the first). From 64^2 on the converged value is the contact
  // fronts' D_max; at 32^2 the coarsest rerun (8^2) cannot place the edge and
  // the grid's Richardson limit is taken. Measured: 32^2 0.859 +- 0.457 (grid),
  // 128^2 1.0048 +- 0.0144; 64^2 1.0032 +- 0.0468, 256^2 1.0009 +- 0.0067 (surface).
  // The study on 128^2 against 512^2 (scripts/study_risk_error.py) is the real test.
  const std::vector<std::pair<std::string, std::string>> history{
    {"Cycles", "2"}, {"Steps per cycle", "100"}, {"Field snapshots per cycle", "0"}};
  auto on = [&](const std::string &cells) {
    auto edits = history;
    edits.emplace_back("Cells x", cells);
    edits.emplace_back("Cells y", cells);
    return edits;
  };
  const auto hot_spot = [](const std::string &summary) {
    const auto key   = summary.find("\"hot_spot\"");
    const auto open  = summary.find('"', summary.find(':', key) + 1);
    const auto close = summary.find('"', open + 1);
    return key == std::string::npos ? std::string() : summary.substr(open + 1, close - open - 1);
  };
  std::map<std::string, std::string> runs;
  for (const char *cells : {"32", "64", "128", "256"})
    runs[cells] = run_paper_scene(std::string("risk-") + cells, on(cells));
  for (const auto &[coarse_cells, fine_cells] : {std::pair{"32", "128"}, std::pair{"64", "256"}})
    {
      SCOPED_TRACE(std::string(coarse_cells) + " against " + fine_cells);
      const std::string &coarse = runs[coarse_cells], &fine = runs[fine_cells];
      const double       converged      = summary_number(coarse, "risk_max_converged");
      const double       bar            = summary_number(coarse, "risk_max_error_estimate");
      const double       fine_converged = summary_number(fine, "risk_max_converged");
      EXPECT_LE(std::abs(converged - fine_converged), bar);
      // The fine run's own bar is narrower, and each run's grid D_max lies
      // below its converged value (the grid only underestimates the edge peak).
      EXPECT_LT(summary_number(fine, "risk_max_error_estimate"), 0.5 * bar);
      EXPECT_LT(summary_number(coarse, "risk_max"), converged);
      EXPECT_LT(summary_number(fine, "risk_max"), fine_converged);
      EXPECT_EQ(hot_spot(fine), "surface");
      // The traction model against the incremental exact solver on the coarsest
      // grid: measured 5.2e-5 (8 cells) and 7.1e-4 (32 cells).
      EXPECT_LT(summary_number(coarse, "traction_model_error_estimate"), 0.01);
      EXPECT_LT(summary_number(fine, "traction_model_error_estimate"), 0.01);
    }
  EXPECT_EQ(hot_spot(runs["32"]), "grid");
  // On 256^2 cells the bar is within 1 % (measured 0.67 %), taken on
  // the edge point in the sliding direction.
  EXPECT_LT(summary_number(runs["256"], "risk_max_error_estimate"), 0.01);
  const std::vector<double> where = summary_vector(runs["256"], "risk_max_converged_location_m");
  ASSERT_EQ(where.size(), 3u);
  EXPECT_NEAR(where[0], summary_number(runs["256"], "hertz_contact_radius_m"), 1e-12);
  EXPECT_EQ(where[1], 0.0);
  EXPECT_EQ(where[2], 0.0);
}

TEST(SceneRisk, ASmallAmplitudesRiskPeaksInTheSlipAnnulusAndItsBarHoldsTheFinerRun)
{
  // mu 0.1 and 0.07 um (5 % of the gross-slip shift): the stick zone's front
  // lies at 0.975 a, the risk peaks in the thin slip annulus, which 64^2
  // cells do not resolve (0.55 of a cell): the grid's own D_max is then the
  // bar's lower end. Measured: 64^2 0.0668 +- 0.0089, 256^2 0.0703 +- 0.0025
  // (the annulus 2.2 cells wide), the grid's D_max on 256^2 0.0659 at 0.978 a.
  const std::vector<std::pair<std::string, std::string>> history{
    {"Cycles", "2"}, {"Steps per cycle", "100"}, {"Field snapshots per cycle", "0"},
    {"Friction coefficient", "0.1"}, {"Sliding amplitude", "0.07e-6"}};
  auto on = [&](const std::string &cells) {
    auto edits = history;
    edits.emplace_back("Cells x", cells);
    edits.emplace_back("Cells y", cells);
    return edits;
  };
  const std::string coarse = run_paper_scene("risk-annulus-64", on("64"));
  const std::string fine   = run_paper_scene("risk-annulus-256", on("256"));
  EXPECT_LE(std::abs(summary_number(coarse, "risk_max_converged") - summary_number(fine, "risk_max_converged")),
            summary_number(coarse, "risk_max_error_estimate"));
  EXPECT_LT(summary_number(fine, "risk_max_error_estimate"), 0.5 * summary_number(coarse, "risk_max_error_estimate"));
  // The fronts' maximum lies in the slip annulus, above the grid's samples.
  const double              a     = summary_number(fine, "hertz_contact_radius_m");
  const std::vector<double> where = summary_vector(fine, "risk_max_edge_location_m");
  ASSERT_EQ(where.size(), 3u);
  const double r = std::hypot(where[0], where[1]);
  EXPECT_GT(r, 0.97 * a);
  EXPECT_LT(r, 0.999 * a);
  EXPECT_GT(summary_number(fine, "risk_max_edge"), summary_number(fine, "risk_max"));
}

TEST(SceneRisk, TheTractionCheckReadsTheModelsRiskFromTheCoarsestRun)
{
  // The traction check's model side is the coarsest rerun (8^2 cells here)
  // read after the check's 2 cycles, not a run of its own: it must equal a
  // separate 8^2 run of 2 cycles, and differ from the finer reruns' D_max.
  // Each run solves the normal problem afresh (parallel reductions); the
  // traction solves, to 1e-10 here, keep them within 1e-9 relative whatever
  // FFT plans each run takes.
  const std::vector<std::pair<std::string, std::string>> history{
    {"Cells x", "32"}, {"Cells y", "32"}, {"Cycles", "3"}, {"Steps per cycle", "40"},
    {"Field snapshots per cycle", "0"}, {"Exact solver tolerance", "1e-10"}};
  const std::string with_check = run_paper_scene("risk-check", history);
  auto edits = history;
  edits.insert(edits.end(), {{"Cells x", "8"}, {"Cells y", "8"}, {"Risk error estimate", "false"}, {"Cycles", "2"}});
  const double alone = summary_number(run_paper_scene("risk-check-alone", edits), "risk_max");
  const double model = summary_number(with_check, "risk_max_model");
  EXPECT_NEAR(model, alone, 1e-9 * alone);
  const std::vector<double> grids = // 8^2, 16^2, 32^2
    summary_vector(with_check.substr(with_check.find("\"risk_convergence\"")), "risk_max");
  ASSERT_EQ(grids.size(), 3u);
  EXPECT_GT(std::abs(grids[1] - alone), 1e-3 * alone);
  EXPECT_EQ(summary_number(with_check, "cycles_compared"), 2);
}

TEST(SceneRisk, TheErrorEstimateNeedsGridsItCanHalveTwice)
{
  const auto directory = test_files::scratch_directory("risk-cells");
  test_files::write_text(directory / "scene.prm", test_files::edited_paper_scene({{"Cells x", "30"}}));
  const auto result = run_program("run " + (directory / "scene.prm").string() + " -o " +
                                  (directory / "out").string() + " --no-plots -q");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("Cells x"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("multiple of 4"), std::string::npos) << result.output;
}

TEST(SceneRisk, AZeroAmplitudeSticksAndRisksOnlyThePressure)
{
  // No sliding: the regime is stick, no tangential force, and D_max is the
  // frictionless Hertz contact's (finite, below the sliding case's).
  const std::string summary = run_paper_scene(
    "risk-still", {{"Cells x", "32"}, {"Cells y", "32"}, {"Cycles", "2"}, {"Steps per cycle", "20"},
                   {"Field snapshots per cycle", "0"}, {"Sliding amplitude", "0"}});
  EXPECT_NE(summary.find("\"regime\": \"stick\""), std::string::npos) << summary;
  EXPECT_EQ(summary_number(summary, "tangential_force_amplitude_N"), 0.0);
  EXPECT_TRUE(std::isfinite(summary_number(summary, "risk_max")));
  EXPECT_TRUE(std::isfinite(summary_number(summary, "risk_max_converged")));
}

// The Bulk stress section reaches Dang Van component by component: fully
// reversed tension along x or y of amplitude f-1, or shear of amplitude t-1,
// under a ball too lightly loaded to matter (1e-30 N), gives D = 1 (the
// fatigue limits' definition) to 1e-9, on every grid of the error estimate.
TEST(SceneRisk, FullyReversedBulkStressAtTheFatigueLimitsGivesRiskOne)
{
  const auto directory = test_files::scratch_directory("risk-bulk");
  test_files::write_text(directory / "scene.prm",
                         test_files::edited_paper_scene({{"Cells x", "32"}, {"Cells y", "32"}, {"Cycles", "3"},
                                                         {"Steps per cycle", "40"}, {"Field snapshots per cycle", "0"},
                                                         {"Sliding amplitude", "0"}, {"Normal load", "1e-30"},
                                                         {"Friction coefficient", "0"}, {"Traction model", "bristle"},
                                                         {"Residual stress", "last_cycle_mean"},
                                                         {"Warm-up cycles", "1"}}));
  for (const auto &[component, limit] : std::vector<std::pair<std::string, std::string>>{
         {"Amplitude xx", "690e6"}, {"Amplitude yy", "690e6"}, {"Amplitude xy", "428e6"}})
    {
      const auto out    = directory / ("out-" + component.substr(component.size() - 2));
      const auto result = run_program("run " + (directory / "scene.prm").string() + " -o " + out.string() +
                                      " --no-plots -q --set 'Bulk stress/" + component + "=" + limit + "'");
      ASSERT_EQ(result.exit_code, 0) << result.output;
      const auto summary = test_files::read_text(out / "summary.json");
      EXPECT_NEAR(summary_number(summary, "risk_max"), 1.0, 1e-9) << component;
      EXPECT_NEAR(summary_number(summary, "risk_max_converged"), 1.0, 1e-9) << component;
    }
  const auto params = run_program("params concentrated");
  EXPECT_NE(params.output.find("Bulk stress"), std::string::npos);
  EXPECT_NE(params.output.find("Static gradient xx"), std::string::npos);
}
