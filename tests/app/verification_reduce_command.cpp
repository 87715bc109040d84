// `fretsim reduce`: a small grooved ring reduced from the command line; the
// model file holds the matrices and operators of the stated sizes, and the
// reduced model meets the required 0.5 % on the lowest 10 free frequencies
// against the full FE solve the command runs itself; `--study` writes a table
// whose frequency error falls as n_cc grows (nested bases, Rayleigh–Ritz:
// min-max principle); the raceway ball operator is stored for the default
// 720 ball positions, and the full FE raceway approach under a ball exceeds
// the reduced one (the reduced model leaves out the footprint's local
// compliance: it is the Rayleigh–Ritz (stiffer) solution); bad input gives
// exit code 2, one line naming the parameter, and no file.
#include "app/test_files.h"

#include <fretsim/output/results_file.h>

#include <gtest/gtest.h>

#include <sstream>

using fretsim::output::ResultsFile;
using fretsim::test_files::read_text;
using fretsim::test_files::run_program;
using fretsim::test_files::scratch_directory;
using fretsim::test_files::write_text;

namespace
{
  std::string small_ring(const std::string &reduction)
  {
    return "set Scene = ring_housing\n"
           "subsection Divisions\n  set Circumferential = 24\n  set Radial ring = 1\n  set Axial = 2\n"
           "  set Axial land = 1\nend\n"
           "subsection Reduction\n  set Interface grid circumferential cells = 72\n"
           "  set Interface grid axial cells = 6\n  set Sample points per line = 12\n" +
           reduction + "end\n";
  }

  double number_after(const std::string &text, const std::string &label)
  {
    const auto at = text.find(label);
    return at == std::string::npos ? -1.0 : std::stod(text.substr(at + label.size()));
  }
} // namespace

TEST(ReduceCommand, WritesAModelThatMeetsTheFrequencyTarget)
{
  const auto dir = scratch_directory("reduce");
  write_text(dir / "ring.prm", small_ring("  set Fixed-interface modes = 16\n  set Characteristic constraint modes = 40\n"));
  const auto result = run_program("reduce " + (dir / "ring.prm").string() + " -q -o " + (dir / "model.h5").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::printf("%s", result.output.c_str());

  const double error = number_after(result.output, "max frequency error: ");
  EXPECT_GE(error, 0.0);
  EXPECT_LT(error, 5e-3); // required: < 0.5 % on the lowest 10

  std::vector<std::size_t> dims;
  const auto               k = ResultsFile::read_dataset((dir / "model.h5").string(), "/matrices/stiffness", &dims);
  ASSERT_EQ(dims, (std::vector<std::size_t>{56, 56}));
  const auto g = ResultsFile::read_dataset((dir / "model.h5").string(), "/operators/interface_grid/displacement", &dims);
  EXPECT_EQ(dims, (std::vector<std::size_t>{72 * 6, 3, 56}));
  ResultsFile::read_dataset((dir / "model.h5").string(), "/operators/sample_points/stress", &dims);
  EXPECT_EQ(dims, (std::vector<std::size_t>{24, 6, 56}));
  const auto angles = ResultsFile::read_dataset((dir / "model.h5").string(), "/operators/raceway/angles", &dims);
  EXPECT_EQ(dims, (std::vector<std::size_t>{720}));
  ASSERT_EQ(angles.size(), 720u);
  EXPECT_DOUBLE_EQ(angles[180], 0.5 * M_PI);
  ResultsFile::read_dataset((dir / "model.h5").string(), "/operators/raceway/approach", &dims);
  EXPECT_EQ(dims, (std::vector<std::size_t>{1, 720, 56})); // one fixed footprint
  const auto footprints = ResultsFile::read_dataset((dir / "model.h5").string(), "/operators/raceway/footprints", &dims);
  EXPECT_EQ(dims, (std::vector<std::size_t>{1, 3}));
  EXPECT_EQ(footprints[2], 0.0); // no load: fixed
  EXPECT_NE(result.output.find("raceway:      720 ball positions"), std::string::npos) << result.output;
  const double full    = number_after(result.output, "raceway approach under a 2 kN ball at 90 deg (the opposite one "
                                                     "at 270 deg): full ");
  const double reduced = number_after(result.output, " m, reduced ");
  std::printf("raceway approach: full %.4e m, reduced %.4e m\n", full, reduced);
  EXPECT_GT(reduced, 0.0);
  // Both solve the same load by energy minimisation, the reduced one in a
  // subspace: its energy, i.e. this pair's work, can only be lower.
  EXPECT_GT(full, reduced);
  EXPECT_EQ(ResultsFile::read_string_attribute((dir / "model.h5").string(), "/", "input_hash").size(), 16u);
  EXPECT_FALSE(std::filesystem::exists(dir / "model.h5.tmp"));
}

TEST(ReduceCommand, AHousingHeldAtItsOutsideIsReducedOnItsBore)
{
  // The flexible housing of the co-simulation: Mesh/Bodies = housing, the
  // bore the coupling surface, the outside clamped. With every constraint
  // mode kept (n_cc = 0) Craig–Bampton reproduces any static load on the bore
  // exactly, so the squeeze error is round-off only if the clamp is the same
  // support in the full and the reduced model; the lowest 10 frequencies of
  // the clamped housing meet the required 0.5 %.
  const auto dir     = scratch_directory("reduce-housing");
  // `reduction`'s lines join the Reduction section; one naming a parameter
  // the section already sets replaces that line (a file sets each once).
  const auto housing = [](const std::string &reduction) {
    std::string section = "  set Coupling surfaces = housing_bore\n  set Clamped surfaces = housing_outer\n"
                          "  set Interface grid circumferential cells = 72\n  set Interface grid axial cells = 6\n"
                          "  set Sample points per line = 12\n  set Fixed-interface modes = 16\n";
    std::istringstream lines(reduction);
    for (std::string line; std::getline(lines, line);)
      {
        const std::string name = line.substr(0, line.find('=') + 1);
        const auto        at   = section.find(name);
        if (at == std::string::npos)
          section += line + "\n";
        else
          section.replace(at, section.find('\n', at) - at, line);
      }
    return "set Scene = ring_housing\nsubsection Mesh\n  set Bodies = housing\nend\n"
           "subsection Divisions\n  set Circumferential = 24\n  set Radial housing = 1\n  set Axial = 2\n"
           "  set Axial land = 1\nend\n"
           "subsection Reduction\n" +
           section + "end\n";
  };
  write_text(dir / "housing.prm", housing("  set Characteristic constraint modes = 0\n  set Raceway ball positions = 0\n"));
  const auto result = run_program("reduce " + (dir / "housing.prm").string() + " -q -o " + (dir / "model.h5").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::printf("%s", result.output.c_str());
  EXPECT_NE(result.output.find("lowest 10 modes (clamped supports)"), std::string::npos) << result.output;
  const double frequency_error = number_after(result.output, "max frequency error: ");
  EXPECT_GE(frequency_error, 0.0);
  EXPECT_LT(frequency_error, 5e-3); // measured 9.9e-4
  const double squeeze = number_after(result.output, "static squeeze of the interface surface (2 x 5 kN Hertz "
                                                     "patches): u_r error ");
  EXPECT_GE(squeeze, 0.0);
  EXPECT_LT(squeeze, 1e-10); // measured 8e-16
  std::vector<std::size_t> dims;
  ResultsFile::read_dataset((dir / "model.h5").string(), "/operators/interface_grid/displacement", &dims);
  EXPECT_EQ(dims, (std::vector<std::size_t>{72 * 6, 3, 720 + 16})); // 24 x 5 x 2 bore nodes x 3 (Q2) + m
  ResultsFile::read_dataset((dir / "model.h5").string(), "/operators/raceway/angles", &dims);
  EXPECT_EQ(dims, (std::vector<std::size_t>{0}));

  // A housing has no raceway; a surface cannot be both clamped and coupled.
  for (const auto &[reduction, parameter] : std::vector<std::pair<std::string, std::string>>{
         {"", "Reduction/Raceway ball positions"},
         {"  set Raceway ball positions = 0\n  set Clamped surfaces = housing_bore\n", "Reduction/Clamped surfaces"},
         {"  set Raceway ball positions = 0\n  set Coupling surfaces = ring_outer\n",
          "Reduction/Interface grid circumferential cells"}})
    {
      std::filesystem::remove(dir / "bad.h5");
      write_text(dir / "housing.prm", housing(reduction));
      const auto bad = run_program("reduce " + (dir / "housing.prm").string() + " -q -o " + (dir / "bad.h5").string());
      EXPECT_EQ(bad.exit_code, 2) << bad.output;
      EXPECT_NE(bad.output.find(parameter), std::string::npos) << bad.output;
      EXPECT_FALSE(std::filesystem::exists(dir / "bad.h5"));
    }
}

TEST(ReduceCommand, StudyErrorFallsWithInterfaceModes)
{
  const auto dir = scratch_directory("reduce-study");
  write_text(dir / "ring.prm", small_ring("  set Study fixed-interface modes = 16\n"
                                          "  set Study characteristic constraint modes = 12, 20, 40\n"));
  const auto result = run_program("reduce " + (dir / "ring.prm").string() + " --study --no-plots -q -o " +
                                  (dir / "study").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::printf("%s", result.output.c_str());
  std::istringstream csv(read_text(dir / "study" / "reduction_study.csv"));
  std::string        line;
  std::getline(csv, line); // header
  std::vector<double> errors;
  while (std::getline(csv, line))
    {
      std::vector<std::string> cells;
      std::stringstream        row(line);
      for (std::string cell; std::getline(row, cell, ',');)
        cells.push_back(cell);
      ASSERT_EQ(cells.size(), 12u) << line;
      errors.push_back(std::stod(cells[4]));
      EXPECT_LT(std::stod(cells[5]), 1e-7) << "clamped boundary: the fixed-interface modes are exact";
    }
  ASSERT_EQ(errors.size(), 3u);
  for (std::size_t k = 1; k < errors.size(); ++k)
    EXPECT_LE(errors[k], errors[k - 1] * (1 + 1e-9));
  EXPECT_LT(errors.back(), 5e-3);
}

TEST(ReduceCommand, BadInputNamesTheParameterAndWritesNothing)
{
  const auto dir = scratch_directory("reduce-bad");
  for (const auto &[reduction, parameter] :
       std::vector<std::pair<std::string, std::string>>{
         {"  set Coupling surfaces = ring_outer, nowhere\n", "Reduction/Coupling surfaces"},
         {"  set Characteristic constraint modes = -3\n", "Reduction/Characteristic constraint modes"},
         {"  set Coupling surfaces = raceway\n", "Reduction/Interface grid circumferential cells"},
         {"  set Characteristic constraint modes = 100000\n", "Reduction/Characteristic constraint modes"},
         {"  set Ball footprint transverse semi-axis = 6e-3\n", "Reduction/Ball footprint transverse semi-axis"},
         {"  set Raceway ball positions = -1\n", "Reduction/Raceway ball positions"}})
    {
      write_text(dir / "ring.prm", small_ring(reduction));
      const auto result = run_program("reduce " + (dir / "ring.prm").string() + " -q -o " + (dir / "model.h5").string());
      EXPECT_EQ(result.exit_code, 2) << result.output;
      EXPECT_NE(result.output.find(parameter), std::string::npos) << result.output;
      EXPECT_NE(result.output.find("ring.prm"), std::string::npos) << result.output;
      EXPECT_FALSE(std::filesystem::exists(dir / "model.h5"));
    }
  // A sector cannot hold balls all round.
  write_text(dir / "ring.prm", small_ring(""));
  const auto result = run_program("reduce " + (dir / "ring.prm").string() + " --set 'Divisions/Sector angle=3' -q -o " +
                                  (dir / "model.h5").string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("Reduction/Raceway ball positions"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "model.h5"));
}
