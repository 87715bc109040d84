// The paper's §4 case end to end through the Dang Van stage (paper Fig. 11:
// "maximum risk around 0.8", at the contact edge on the surface).
//
// Convergence study (docs/concentrated.md, "D_max against the numerics"): on the shipped
// discretisation (128 x 128 cells, 200 steps per cycle) D_max = 0.635. It rises
// with the grid because the maximum sits exactly on the contact edge, where
// pressure and traction have square-root profiles that cell-centred sampling
// resolves as h^0.7: 0.568 / 0.629 / 0.687 / 0.722 at 64 / 128 / 256 / 512
// cells (100 steps), extrapolated 0.78 +- 0.03 at zero cell size, plus
// +0.006 for the time step at 200 steps per cycle. The tests below hold the
// shipped discretisation to its own value (a drift detector: the numbers are
// deterministic to ~1e-10) and to the bounds the study gives.
#include "app/test_files.h"

#include "output/results_file.h"

#include <gtest/gtest.h>

#include <cmath>

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
  const std::string summary = run_paper_scene("risk-paper", {{"Cycles", "2"}});
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
  const std::string mean =
    run_paper_scene("risk-mean", {{"Cycles", "2"}, {"Residual stress", "last_cycle_mean"}});
  const std::string sphere =
    run_paper_scene("risk-sphere", {{"Cycles", "2"}, {"Residual stress", "hypersphere"}});
  const double risk_mean = summary_number(mean, "risk_max"), risk_sphere = summary_number(sphere, "risk_max");
  EXPECT_NEAR(risk_mean, 0.6128, 0.005 * 0.6128);
  EXPECT_NEAR(risk_sphere, 0.6091, 0.005 * 0.6091);
  EXPECT_LT(risk_mean, 0.63526);
}
