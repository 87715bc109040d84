// Scene configuration: defaults, .prm and .json, and one-line errors that name
// the file, the parameter and what was expected.
#include "app/test_files.h"

#include <fretsim/support/parameters.h>
#include <fretsim/scenes/scene.h>

#include <gtest/gtest.h>

#include <sstream>

using namespace fretsim;

namespace
{
  /// The InputError message for a scene file, or "" if it loads.
  std::string load_error(const std::string &text, const std::string &extension = ".prm")
  {
    const auto path = test_files::scratch_directory("parameters") / ("scene" + extension);
    test_files::write_text(path, text);
    try
      {
        scenes::load_scene(path.string());
      }
    catch (const app::InputError &error)
      {
        return error.what();
      }
    return "";
  }
} // namespace

TEST(Parameters, ShippedPaperSceneLoads)
{
  EXPECT_EQ(load_error(test_files::edited_paper_scene({})), "");
}

TEST(Parameters, EveryParameterHasDefaultRangeAndUnit)
{
  const auto parameters = scenes::declare_parameters("concentrated");
  for (const auto &spec : parameters.specs())
    {
      EXPECT_FALSE(spec.default_value.empty()) << spec.path;
      // Doc strings end with the unit in brackets, [-] when dimensionless
      // (selections describe their options instead).
      if (spec.kind != app::ParameterSpec::Kind::selection)
        {
          EXPECT_NE(spec.doc.find('['), std::string::npos) << spec.path;
        }
      EXPECT_FALSE(spec.expected().empty()) << spec.path;
    }
  std::ostringstream reference;
  parameters.print_reference(reference);
  EXPECT_NE(reference.str().find("set Normal load = 1250"), std::string::npos);
  EXPECT_NE(reference.str().find("Allowed: a number > 0"), std::string::npos);
}

TEST(Parameters, DefaultsAloneMakeAValidScene)
{
  EXPECT_EQ(load_error("set Scene = concentrated\n"), "");
}

TEST(Parameters, MisspeltParameterIsNamedWithSuggestion)
{
  const std::string message = load_error("set Scene = concentrated\nsubsection Loading\n  set Normal lod = 5\nend\n");
  EXPECT_NE(message.find("scene.prm"), std::string::npos) << message;
  EXPECT_NE(message.find("Normal lod"), std::string::npos) << message;
  EXPECT_NE(message.find("did you mean 'Loading/Normal load'"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
}

TEST(Parameters, OutOfRangeValuesNameParameterAndExpectation)
{
  struct Case
  {
    std::string name, value, parameter, expectation;
  };
  for (const auto &c : std::vector<Case>{
         {"Radius x", "-0.05", "Radius x", "> 0"},
         {"Radius x", "0", "Radius x", "> 0"},
         {"Poisson ratio  ", "0.5", "Poisson ratio", "< 0.5"},
         {"Friction coefficient    ", "-0.1", "Friction coefficient", ">= 0"},
         {"Cells x          ", "0", "Cells x", ">= 8"},
         {"Normal load      ", "abc", "Normal load", "a number > 0, got 'abc'"},
         {"Pressure model", "fem", "Pressure model", "hertz|numerical"},
         {"Field snapshots per cycle", "7", "Field snapshots per cycle", "divisor"},
         {"Depth layers", "0, -1e-5", "Stresses/Depth layers", ">= 0, increasing, got '0, -1e-5'"},
         // Torsion limit above the bending limit: almost surely swapped.
         {"Torsion fatigue limit", "700e6", "Dang Van/Torsion fatigue limit", "swapped"},
         {"Warm-up cycles", "8", "Dang Van/Warm-up cycles", "fewer than"},
         {"Depth layers", "", "Stresses/Depth layers", "at least one depth"},
         {"Evaluator", "fast", "Stresses/Evaluator", "fft|mlmi|direct"},
         {"Evaluator", "mlmi\n  set MLMI order = 5", "Stresses/MLMI order", "even"},
         // 128 cells cannot be coarsened 9 times.
         {"Evaluator", "mlmi\n  set MLMI levels = 9", "Stresses/MLMI levels", "levels"},
       })
    {
      // Poisson ratio appears twice in the file; the first (lower body) is edited.
      const std::string message = load_error(test_files::edited_paper_scene({{c.name, c.value}}));
      EXPECT_NE(message.find("scene.prm"), std::string::npos) << message;
      EXPECT_NE(message.find(c.parameter), std::string::npos) << message;
      EXPECT_NE(message.find(c.expectation), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
    }
}

TEST(Parameters, PerCycleResidualStressNeedsTwoCycles)
{
  // The first cycle only defines the centre of the per-cycle options.
  const std::string message =
    load_error(test_files::edited_paper_scene({{"Residual stress", "hypersphere"}, {"Cycles", "1"}}));
  EXPECT_NE(message.find("Loading/Cycles"), std::string::npos) << message;
  EXPECT_NE(message.find("at least 2"), std::string::npos) << message;
  EXPECT_EQ(load_error(test_files::edited_paper_scene({{"Residual stress", "hypersphere"}, {"Cycles", "2"}})), "");
}

TEST(Parameters, MissingFileAndUnknownSceneAreInputErrors)
{
  try
    {
      scenes::load_scene("/nonexistent/dir/scene.prm");
      ADD_FAILURE() << "no error for a missing file";
    }
  catch (const app::InputError &error)
    {
      EXPECT_NE(std::string(error.what()).find("/nonexistent/dir/scene.prm"), std::string::npos);
    }
  const std::string message = load_error("set Scene = bearing_of_doom\n");
  EXPECT_NE(message.find("Scene"), std::string::npos) << message;
  EXPECT_NE(message.find("concentrated"), std::string::npos) << message;
  EXPECT_NE(load_error("subsection Loading\nset Normal load = 5\nend\n").find("missing"), std::string::npos);
}

TEST(Parameters, JsonIsAccepted)
{
  EXPECT_EQ(load_error(R"({"Scene": "concentrated", "Loading": {"Normal load": "1000", "Cycles": "2"}})", ".json"),
            "");
  const std::string message =
    load_error(R"({"Scene": "concentrated", "Loading": {"Normal load": "-1000"}})", ".json");
  EXPECT_NE(message.find("Normal load"), std::string::npos) << message;
  EXPECT_NE(message.find("> 0"), std::string::npos) << message;
}
