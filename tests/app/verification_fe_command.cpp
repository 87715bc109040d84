// `fretsim fe`: the shrink-fit interface pressure through the command against
// Lamé, the layout of what it writes (results.h5, XDMF, VTU, summary.json)
// for static, modal and transient runs, bad input (exit code 2, one line
// naming file and parameter, nothing written), and the same numbers under
// `mpiexec -np 2`.
#include "app/test_files.h"

#include <fretsim/output/results_file.h>

#include <gtest/gtest.h>

#include <regex>

#include <algorithm>
#include <cmath>
#include <cstdlib>

using fretsim::output::ResultsFile;
using fretsim::test_files::read_text;
using fretsim::test_files::run_program;
using fretsim::test_files::scratch_directory;
using fretsim::test_files::summary_number;
using fretsim::test_files::write_text;

namespace
{
  /// A plain ring (a = 34.1 mm, R = 40 mm) in a housing (c = 60 mm), both
  /// steel (the defaults), as a plane-strain quarter model.
  std::string shrink_fit_config(const std::string &extra_fe = "")
  {
    return "set Scene = ring_housing\n"
           "subsection Mesh\n  set Bodies = ring_in_housing\n  set Element degree = 2\nend\n"
           "subsection Ring\n  set Groove radius = 0\nend\n"
           "subsection Divisions\n  set Circumferential = 8\n  set Radial ring = 6\n  set Radial housing = 6\n"
           "  set Axial = 1\n  set Sector angle = 1.5707963267948966\nend\n"
           "subsection FE run\n  set Analysis = static\n"
           "  subsection Supports\n    set Clamped = none\n    set Axial faces = fixed\n"
           "    set Symmetry planes = true\n  end\n"
           "  subsection Loads\n    set Interference = 10e-6\n    set Ball load = 0\n  end\n"
           "  subsection Sampling\n    set Points per line = 9\n    set Grid circumferential = 3\n"
           "    set Grid axial = 2\n  end\n" +
           extra_fe + "end\n";
  }

  /// `text` with its one `set NAME = ...` line given `value` (a file may set
  /// a parameter only once).
  std::string with_value(const std::string &text, const std::string &name, const std::string &value)
  {
    return std::regex_replace(text, std::regex("set " + name + " *=[^\n]*"), "set " + name + " = " + value);
  }

  /// A small full ring with its groove, for the modal and transient runs.
  std::string small_ring_config(const std::string &fe)
  {
    return "set Scene = ring_housing\n"
           "subsection Mesh\n  set Bodies = ring\n  set Element degree = 1\nend\n"
           "subsection Divisions\n  set Circumferential = 24\n  set Radial ring = 1\n  set Axial = 2\n"
           "  set Axial land = 1\nend\n"
           "subsection FE run\n  subsection Supports\n    set Clamped = ring_outer\n  end\n" + fe + "end\n";
  }
} // namespace

TEST(FeCommand, ShrinkFitPressureMatchesLame)
{
  // Lamé, plane strain (E' = E/(1 - ν²), ν' = ν/(1 - ν); Timoshenko & Goodier §28):
  //   p = δ / ( R/E'_h ((c² + R²)/(c² - R²) + ν'_h) + R/E'_r ((R² + a²)/(R² - a²) - ν'_r) ).
  const double a = 0.0341, R = 0.040, c = 0.060, delta = 10e-6, E = 2.08e11, nu = 0.3;
  const double Ep = E / (1 - nu * nu), nup = nu / (1 - nu);
  const double p  = delta / (R / Ep * ((c * c + R * R) / (c * c - R * R) + nup) +
                            R / Ep * ((R * R + a * a) / (R * R - a * a) - nup));
  const auto dir = scratch_directory("fe-shrink-fit");
  write_text(dir / "fit.prm", shrink_fit_config());
  const auto result = run_program("fe " + (dir / "fit.prm").string() + " -o " + (dir / "out").string() + " --no-plots");
  ASSERT_EQ(result.exit_code, 0) << result.output;

  const std::string summary = read_text(dir / "out" / "summary.json");
  const double      p_fe    = summary_number(summary, "interface_pressure_Pa");
  std::printf("interface pressure %.6e Pa, Lamé %.6e Pa, error %.2e\n", p_fe, p, std::abs(p_fe / p - 1));
  EXPECT_NEAR(p_fe, p, 0.01 * p); // 1 % required

  // Layout: 9 + 9 line points and a 3 × 2 grid, one static snapshot. (The
  // grid's centres avoid the cell faces, where the stress jumps and the
  // sampled cell may differ between rank counts.)
  const std::string h5 = (dir / "out" / "results.h5").string();
  std::vector<std::size_t> dims;
  const auto stress = ResultsFile::read_dataset(h5, "/fields/stress", &dims);
  EXPECT_EQ(dims, (std::vector<std::size_t>{1, 24, 6}));
  ResultsFile::read_dataset(h5, "/points", &dims);
  EXPECT_EQ(dims, (std::vector<std::size_t>{24, 3}));
  EXPECT_EQ(ResultsFile::read_dataset(h5, "/time").size(), 1u);
  EXPECT_EQ(ResultsFile::read_string_attribute(h5, "/", "stress_frame"), "cylindrical");
  EXPECT_EQ(ResultsFile::read_string_attribute(h5, "/", "scene"), "ring_housing");

  // The ring outer line samples the ring at the interface: σ_rr = -p and
  // σ_θθ = -p (R² + a²)/(R² - a²) (Lamé), within the point stresses'
  // accuracy (gradients of Q2, O(h²); 2 %).
  const double hoop = -p * (R * R + a * a) / (R * R - a * a);
  for (std::size_t k = 0; k < 9; ++k)
    {
      EXPECT_NEAR(stress[6 * k + 0], -p, 0.02 * p) << "point " << k;
      EXPECT_NEAR(stress[6 * k + 1], hoop, 0.02 * std::abs(hoop)) << "point " << k;
    }
  EXPECT_NE(read_text(dir / "out" / "results.xdmf").find("results.h5:/fields/stress"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "displacement.pvtu") ||
              std::filesystem::exists(dir / "out" / "displacement_0.pvtu"));
  for (const std::string key : {"dofs", "wall_time_s", "max_von_mises_Pa"})
    EXPECT_FALSE(std::isnan(summary_number(summary, key))) << key;
  EXPECT_NE(summary.find("\"stage_times_s\""), std::string::npos);
}

TEST(FeCommand, ModesAndTransientLayout)
{
  const auto dir   = scratch_directory("fe-layout");
  write_text(dir / "modes.prm",
             with_value(small_ring_config("  set Analysis = modes\n  set Modes = 4\n"
                                          "  subsection Sampling\n    set Points per line = 12\n  end\n"),
                        "Clamped", "none"));
  auto result = run_program("fe " + (dir / "modes.prm").string() + " -o " + (dir / "modes").string() + " --no-plots");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string modes_h5 = (dir / "modes" / "results.h5").string();
  const auto        frequencies = ResultsFile::read_dataset(modes_h5, "/frequencies");
  ASSERT_EQ(frequencies.size(), 4u);
  EXPECT_GT(frequencies[0], 100.0); // elastic modes: the six rigid-body modes are excluded
  std::vector<std::size_t> dims;
  ResultsFile::read_dataset(modes_h5, "/fields/stress", &dims);
  EXPECT_EQ(dims, (std::vector<std::size_t>{4, 24, 6}));

  write_text(dir / "transient.prm",
             small_ring_config("  set Analysis = transient\n"
                               "  subsection Loads\n    set Ball load = 1000\n  end\n"
                               "  subsection Transient\n    set Time step = 2e-4\n    set Steps = 3\n  end\n"
                               "  subsection Sampling\n    set Points per line = 12\n  end\n"));
  result = run_program("fe " + (dir / "transient.prm").string() + " -o " + (dir / "transient").string() +
                       " --no-plots");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto time = ResultsFile::read_dataset((dir / "transient" / "results.h5").string(), "/time");
  ASSERT_EQ(time.size(), 4u); // t = 0 and three steps
  EXPECT_NEAR(time[3], 6e-4, 1e-15);
  EXPECT_EQ(summary_number(read_text(dir / "transient" / "summary.json"), "steps_done"), 3.0);
}

TEST(FeCommand, BadInputExitsWithTwoAndWritesNothing)
{
  const auto dir = scratch_directory("fe-bad");
  struct BadCase
  {
    std::string name, value, named;
  };
  const std::vector<BadCase> cases{
    {"Clamped", "housing_outer, shaft", "FE run/Supports/Clamped"},
    {"Symmetry planes", "false", "FE run/Supports/Clamped"},
    {"Interference", "-1e-6", "FE run/Loads/Interference"},
    {"Analysis", "transient", "FE run/Loads/Ball load"},
    {"Analysis", "sideways", "FE run/Analysis"},
  };
  for (std::size_t k = 0; k < cases.size(); ++k)
    {
      const auto config = dir / ("bad" + std::to_string(k) + ".prm");
      write_text(config, with_value(shrink_fit_config(), cases[k].name, cases[k].value));
      const auto out    = dir / ("out" + std::to_string(k));
      const auto result = run_program("fe " + config.string() + " -o " + out.string());
      EXPECT_EQ(result.exit_code, 2) << result.output;
      EXPECT_NE(result.output.find(cases[k].named), std::string::npos) << result.output;
      EXPECT_NE(result.output.find(config.string()), std::string::npos) << result.output;
      EXPECT_FALSE(std::filesystem::exists(out)) << "case " << k;
    }
  // Interference needs the housing; ball loads need the full ring.
  write_text(dir / "ring.prm", small_ring_config("  subsection Loads\n    set Interference = 1e-5\n  end\n"));
  auto result = run_program("fe " + (dir / "ring.prm").string() + " -o " + (dir / "ring-out").string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("FE run/Loads/Interference"), std::string::npos) << result.output;
  write_text(dir / "sector.prm", with_value(shrink_fit_config(), "Ball load", "1000"));
  result = run_program("fe " + (dir / "sector.prm").string() + " -o " + (dir / "sector-out").string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("FE run/Loads/Balls"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "ring-out"));
  EXPECT_FALSE(std::filesystem::exists(dir / "sector-out"));
}

TEST(FeCommand, SameNumbersOnTwoRanks)
{
  // `mpiexec -np 2 fretsim fe` distributes the mesh over two ranks; with the
  // direct solver both runs agree to MUMPS's round-off (1e-10 relative).
  const auto dir = scratch_directory("fe-np2");
  write_text(dir / "fit.prm", shrink_fit_config());
  const auto one = run_program("fe " + (dir / "fit.prm").string() + " -o " + (dir / "np1").string() + " --no-plots");
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const std::string mpiexec = "env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
                              "OMPI_MCA_rmaps_base_oversubscribe=1 mpiexec -np 2 " +
                              std::string(FRETSIM_BINARY_DIR) + "/fretsim";
  const std::string log    = (dir / "np2.txt").string();
  const int status = std::system((mpiexec + " fe " + (dir / "fit.prm").string() + " -o " + (dir / "np2").string() +
                                  " --no-plots > " + log + " 2>&1")
                                   .c_str());
  ASSERT_EQ(status, 0) << read_text(log);
  const std::string s1 = read_text(dir / "np1" / "summary.json"), s2 = read_text(dir / "np2" / "summary.json");
  EXPECT_EQ(summary_number(s2, "ranks"), 2.0);
  for (const std::string key : {"interface_pressure_Pa", "strain_energy_J", "max_von_mises_Pa"})
    EXPECT_NEAR(summary_number(s2, key), summary_number(s1, key), 1e-10 * std::abs(summary_number(s1, key))) << key;
  const auto a = ResultsFile::read_dataset((dir / "np1" / "results.h5").string(), "/fields/stress");
  const auto b = ResultsFile::read_dataset((dir / "np2" / "results.h5").string(), "/fields/stress");
  ASSERT_EQ(a.size(), b.size());
  double worst = 0.0, scale = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
    worst = std::max(worst, std::abs(a[k] - b[k])), scale = std::max(scale, std::abs(a[k]));
  EXPECT_LT(worst, 1e-10 * scale);
}
