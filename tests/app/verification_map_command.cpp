// `fretsim map` end to end on a small concentrated scene: records against
// single runs, identical records from one thread, two threads and two MPI
// ranks, a map stopped (by a point limit or SIGKILL) and continued against an
// uninterrupted one, the bisected D = 1 boundary against the grid's, and bad
// axes refused with exit code 2 before anything is written.
#include "app/map_command.h"
#include <fretsim/support/parameters.h>
#include "app/test_files.h"

#include <fretsim/output/map_file.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <thread>

using namespace fretsim;
using test_files::run_program;

namespace
{
  /// The small paper scene (32² cells, 3 cycles × 40 steps).
  std::filesystem::path small_scene_file(const std::filesystem::path &directory)
  {
    const auto scene = directory / "small.prm";
    test_files::write_text(scene, test_files::small_scene());
    return scene;
  }

  const std::string two_axes =
    " --axis 'Loading/Sliding amplitude=1e-6:4e-6:3' --axis 'Loading/Normal load=600:1800:2' -q --no-plots";

  /// Records by index, without the run times (the only part that may differ).
  std::map<long, output::MapRecord> records_of(const std::filesystem::path &folder)
  {
    std::map<long, output::MapRecord> records;
    for (auto record : output::MapFile::read((folder / "map.h5").string()))
      {
        record.numbers.erase("wall_time_s");
        records[record.index] = record;
      }
    return records;
  }

  void expect_identical(const std::map<long, output::MapRecord> &a, const std::map<long, output::MapRecord> &b,
                        const std::string &what)
  {
    ASSERT_EQ(a.size(), b.size()) << what;
    for (const auto &[index, record] : a)
      {
        const auto &other = b.at(index);
        EXPECT_EQ(record.axis_values, other.axis_values) << what << ", point " << index;
        EXPECT_EQ(record.status, other.status) << what << ", point " << index;
        EXPECT_EQ(record.regime, other.regime) << what << ", point " << index;
        EXPECT_EQ(record.parameters, other.parameters) << what << ", point " << index;
        ASSERT_EQ(record.numbers.size(), other.numbers.size()) << what << ", point " << index;
        for (const auto &[name, value] : record.numbers)
          EXPECT_EQ(value, other.numbers.at(name)) << what << ", point " << index << ", " << name;
      }
  }

  bool mpiexec_available() { return std::system("command -v mpiexec > /dev/null 2>&1") == 0; }
} // namespace

TEST(MapAxis, ParsesEvenAndGeometricAxesAndRefusesBadOnes)
{
  const auto even = app::MapAxis::parse("Loading/Normal load=100:3000:30");
  EXPECT_EQ(even.path, "Loading/Normal load");
  const auto values = even.values();
  ASSERT_EQ(values.size(), 30u);
  EXPECT_EQ(values.front(), 100.0);
  EXPECT_EQ(values.back(), 3000.0);
  EXPECT_NEAR(values[1], 200.0, 1e-12);
  const auto log = app::MapAxis::parse("Loading/Sliding amplitude=0.2e-6:10e-6:3:log");
  EXPECT_TRUE(log.logarithmic);
  EXPECT_NEAR(log.values()[1], std::sqrt(0.2e-6 * 10e-6), 1e-18);
  EXPECT_EQ(app::MapAxis::parse(log.text()).values(), log.values());
  for (const std::string bad : {"Loading/Normal load", "=1:2:3", "Loading/Normal load=1:2", "Loading/Normal load=1:2:0",
                                "Loading/Normal load=1:2:2.5", "Loading/Normal load=a:2:3",
                                "Loading/Normal load=-1:2:3:log", "Loading/Normal load=1:1:3",
                                "Loading/Normal load=1:2:3:cubic"})
    EXPECT_THROW(app::MapAxis::parse(bad), app::InputError) << bad;
}

TEST(MapCommand, BadAxisOrFolderExitsWithTwoAndWritesNothing)
{
  const auto directory = test_files::scratch_directory("map-bad");
  const auto scene     = small_scene_file(directory);
  const auto output    = directory / "out";
  for (const std::string axis : {"'Loading/No such=1:2:3'", "'Loading/Normal load=-5:10:3'",
                                 "'Loading/Normal load=1:2:two'"})
    {
      const auto result = run_program("map " + scene.string() + " -o " + output.string() + " --axis " + axis);
      EXPECT_EQ(result.exit_code, 2) << axis << ": " << result.output;
      EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
      EXPECT_FALSE(std::filesystem::exists(output)) << axis;
    }
  const auto four = run_program("map " + scene.string() + " -o " + output.string() +
                                " --axis 'Loading/Cycles=2:3:2' --axis 'Loading/Period=1:2:2' --axis "
                                "'Loading/Normal load=1:2:2' --axis 'Friction/Friction coefficient=0.1:0.2:2'");
  EXPECT_EQ(four.exit_code, 2) << four.output;
  EXPECT_NE(four.output.find("one to three axes"), std::string::npos) << four.output;
}

// Each point's record holds what a single run of its parameters reports; a
// single run's loops use two threads, a map point's one, so the sums round
// differently: 1e-8 relative.
TEST(MapCommand, RecordsMatchSingleRunsAndThreadsAndRanksGiveIdenticalRecords)
{
  const auto directory = test_files::scratch_directory("map-records");
  const auto scene     = small_scene_file(directory);
  const auto one       = run_program("map " + scene.string() + " -o " + (directory / "one").string() + " --jobs 1" +
                                     two_axes);
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const auto two = run_program("map " + scene.string() + " -o " + (directory / "two").string() + " --jobs 2" +
                               two_axes);
  ASSERT_EQ(two.exit_code, 0) << two.output;
  const auto records = records_of(directory / "one");
  ASSERT_EQ(records.size(), 6u);
  for (const auto &[index, record] : records)
    {
      EXPECT_EQ(record.status, "ok") << record.message;
      EXPECT_FALSE(record.regime.empty());
      for (const char *name : {"risk_max", "risk_max_converged", "risk_max_error_estimate", "peak_pressure_Pa",
                               "tangential_force_amplitude_N", "von_mises_max_Pa"})
        EXPECT_TRUE(record.numbers.count(name) && std::isfinite(record.numbers.at(name))) << name;
    }
  expect_identical(records, records_of(directory / "two"), "two threads against one");
  const auto table = test_files::read_csv(directory / "one" / "map.csv");
  ASSERT_EQ(table.size(), 6u);
  EXPECT_NEAR(table[4].at("risk_max"), records.at(4).numbers.at("risk_max"), 1e-9); // 10 digits

  // Point 4: amplitude 2.5 µm (second value), load 1800 N (second value).
  const auto &point = records.at(4);
  ASSERT_EQ(point.axis_values.size(), 2u);
  EXPECT_NEAR(point.axis_values[0], 2.5e-6, 1e-20);
  EXPECT_EQ(point.axis_values[1], 1800.0);
  char amplitude[40];
  std::snprintf(amplitude, sizeof amplitude, "%.17g", point.axis_values[0]);
  const auto single = run_program("run " + scene.string() + " -o " + (directory / "single").string() +
                                  " -q --no-plots --set 'Loading/Sliding amplitude=" + amplitude +
                                  "' --set 'Loading/Normal load=1800' --set 'Grid/FFT plans=estimate'");
  ASSERT_EQ(single.exit_code, 0) << single.output;
  const auto summary = test_files::read_text(directory / "single" / "summary.json");
  for (const char *name : {"risk_max", "risk_max_converged", "peak_pressure_Pa", "von_mises_max_Pa"})
    EXPECT_NEAR(point.numbers.at(name), test_files::summary_number(summary, name),
                1e-8 * std::abs(test_files::summary_number(summary, name)))
      << name;

  ASSERT_TRUE(mpiexec_available()) << "mpiexec not found (scripts/setup.sh installs Open MPI)";
  const std::string mpi = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpiexec -np 2 --oversubscribe " +
                          std::string(FRETSIM_BINARY_DIR) + "/fretsim map " + scene.string() + " -o " +
                          (directory / "ranks").string() + two_axes + " > " + (directory / "ranks.log").string() +
                          " 2>&1";
  ASSERT_EQ(std::system(mpi.c_str()), 0) << test_files::read_text(directory / "ranks.log");
  expect_identical(records, records_of(directory / "ranks"), "two MPI ranks against one process");
}

TEST(MapCommand, StoppedMapsContinueToTheRecordsOfAnUninterruptedOne)
{
  const auto directory = test_files::scratch_directory("map-resume");
  const auto scene     = small_scene_file(directory);
  const auto command   = "map " + scene.string() + two_axes + " --jobs 1 -o ";
  ASSERT_EQ(run_program(command + (directory / "whole").string()).exit_code, 0);
  const auto whole = records_of(directory / "whole");

  // A batch job's share: two points, then the same command without the limit.
  const auto part = run_program(command + (directory / "limited").string() + " --max-points 2");
  ASSERT_EQ(part.exit_code, 0) << part.output;
  EXPECT_EQ(records_of(directory / "limited").size(), 2u);
  EXPECT_NE(part.output.find("the same command continues"), std::string::npos) << part.output;
  const auto rest = run_program(command + (directory / "limited").string());
  ASSERT_EQ(rest.exit_code, 0) << rest.output;
  EXPECT_NE(rest.output.find("2 already in map.h5"), std::string::npos) << rest.output;
  expect_identical(whole, records_of(directory / "limited"), "continued after --max-points");

  // Killed without warning while points run.
  const auto killed = directory / "killed";
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0)
    {
      const std::string line = std::string(FRETSIM_BINARY_DIR) + "/fretsim " + command + killed.string() +
                               " > /dev/null 2>&1";
      execl("/bin/sh", "sh", "-c", ("exec " + line).c_str(), static_cast<char *>(nullptr));
      _exit(127);
    }
  // Killed as soon as map.h5 grows past its empty layout: the first record
  // is being written or on disk.
  const auto map_file = killed / "map.h5";
  std::uintmax_t empty_size = 0;
  for (int wait = 0; wait < 6000; ++wait)
    {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      std::error_code error;
      const auto      size = std::filesystem::file_size(map_file, error);
      if (error)
        continue;
      if (empty_size == 0)
        empty_size = size;
      else if (size > empty_size)
        break;
    }
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  const auto after_kill = records_of(killed).size();
  EXPECT_LT(after_kill, whole.size()) << "the map finished before it was killed: the test proves nothing";
  // A save cut short leaves its half-written map.h5.part beside map.h5 (the
  // file is renamed over map.h5 only once whole): made here by hand, it is
  // dropped and map.h5 continued.
  test_files::write_text(killed / "map.h5.part", "not an HDF5 file");
  const auto resumed = run_program(command + killed.string());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  expect_identical(whole, records_of(killed), "continued after SIGKILL");
  EXPECT_FALSE(std::filesystem::exists(killed / "map.h5.part"));

  // Another map in the same folder is refused; --force starts it over.
  const auto other = run_program("map " + scene.string() + " -o " + killed.string() +
                                 " --axis 'Loading/Normal load=600:1800:2' -q --no-plots");
  EXPECT_EQ(other.exit_code, 2) << other.output;
  EXPECT_NE(other.output.find("holds another map"), std::string::npos) << other.output;
  EXPECT_EQ(run_program("map " + scene.string() + " -o " + killed.string() +
                        " --axis 'Loading/Normal load=600:1800:2' -q --no-plots --force")
              .exit_code,
            0);
  EXPECT_EQ(records_of(killed).size(), 2u);
}

// Along the amplitude, D crosses 1 between two grid points; the bisection's
// boundary lies in that interval, and within it at most the interval from
// the grid's own linear interpolation (both bracket the same crossing).
TEST(MapCommand, BisectedBoundaryLiesWithinTheGridSpacingOfTheGridCrossing)
{
  const auto directory = test_files::scratch_directory("map-boundary");
  const auto scene     = small_scene_file(directory);
  const auto folder    = directory / "out";
  const auto result    = run_program("map " + scene.string() + " -o " + folder.string() +
                                     " --axis 'Loading/Sliding amplitude=1e-6:6e-6:6' --boundary "
                                     "--boundary-tolerance 1e-3 -q");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto records = records_of(folder);
  std::vector<double> amplitude, risk;
  for (const auto &[index, record] : records)
    {
      amplitude.push_back(record.axis_values[0]);
      risk.push_back(record.numbers.at("risk_max_converged"));
    }
  double grid_crossing = std::nan(""), low = 0, high = 0;
  for (std::size_t i = 0; i + 1 < risk.size() && std::isnan(grid_crossing); ++i)
    if ((risk[i] - 1.0) * (risk[i + 1] - 1.0) <= 0.0)
      {
        low = amplitude[i], high = amplitude[i + 1];
        grid_crossing = low + (high - low) * (1.0 - risk[i]) / (risk[i + 1] - risk[i]);
      }
  ASSERT_FALSE(std::isnan(grid_crossing)) << "D does not cross 1 on this axis: the test proves nothing";
  const auto boundary = test_files::read_csv(folder / "boundary.csv");
  ASSERT_EQ(boundary.size(), 1u);
  const double bisected = boundary[0].at("Loading/Sliding amplitude at D=1");
  EXPECT_GE(bisected, low);
  EXPECT_LE(bisected, high);
  EXPECT_NEAR(bisected, grid_crossing, high - low);
  EXPECT_LE(boundary[0].at("bracket high") - boundary[0].at("bracket low"), 1e-3 * 5e-6 * (1 + 1e-9));
  EXPECT_TRUE(std::filesystem::exists(folder / "map.png"));
}

// The bearing scene over two inner-ring displacements: the small ring's model
// is built once before the points, every point keeps its run folder and its
// record holds the run's D_max and peak pressure, those of a single run of the
// same parameters on one core with the same FFT plans (on two cores the sums
// round differently and the adaptive steps follow: 1.2e-3 in D_max, 5e-5 in
// the peak pressure), and two MPI ranks give the same records.
TEST(MapCommand, BearingSceneMapBuildsTheModelOnceAndRecordsEachRun)
{
  const auto        directory = test_files::scratch_directory("map-bearing");
  const std::string one_pass  = " --set 'Loading/Ball pass periods=1.5'";
  test_files::write_text(directory / "ring.prm", test_files::small_ring);
  test_files::write_text(directory / "scene.prm", test_files::small_bearing_scene(directory));
  const auto folder = directory / "map";
  const auto result = run_program("map " + (directory / "scene.prm").string() + " -o " + folder.string() +
                                  " --axis 'Loading/Inner ring displacement y=40e-6:60e-6:2'" + one_pass);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::size_t builds = 0;
  for (auto at = result.output.find("building it"); at != std::string::npos; at = result.output.find("building it", at + 1))
    ++builds;
  EXPECT_EQ(builds, 1u) << result.output;
  for (const char *file : {"map.h5", "map.csv", "map.png", "points/point_000000/results.h5",
                           "points/point_000001/summary.json"})
    EXPECT_TRUE(std::filesystem::exists(folder / file)) << file;
  const auto records = records_of(folder);
  ASSERT_EQ(records.size(), 2u);
  for (const auto &[index, record] : records)
    {
      EXPECT_EQ(record.status, "ok") << record.message;
      EXPECT_GT(record.numbers.at("risk_max"), 0.0);
      EXPECT_GT(record.numbers.at("peak_pressure_Pa"), 0.0);
    }
  // The larger displacement loads the ring more.
  EXPECT_GT(records.at(1).numbers.at("peak_pressure_Pa"), records.at(0).numbers.at("peak_pressure_Pa"));
  setenv("OMP_NUM_THREADS", "1", 1);
  const auto single = run_program("run " + (directory / "scene.prm").string() + " -q --no-plots -o " +
                                  (directory / "single").string() +
                                  " --set 'Loading/Inner ring displacement y=60e-6' --set 'Stresses/FFT plans=estimate'" +
                                  one_pass);
  unsetenv("OMP_NUM_THREADS");
  ASSERT_EQ(single.exit_code, 0) << single.output;
  const auto summary = test_files::read_text(directory / "single" / "summary.json");
  for (const char *name : {"risk_max", "peak_pressure_Pa"})
    EXPECT_NEAR(records.at(1).numbers.at(name), test_files::summary_number(summary, name),
                1e-12 * test_files::summary_number(summary, name))
      << name;

  // Two ranks on the same model file: the same records.
  ASSERT_TRUE(mpiexec_available()) << "mpiexec not found (scripts/setup.sh installs Open MPI)";
  const std::string mpi = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpiexec -np 2 --oversubscribe " +
                          std::string(FRETSIM_BINARY_DIR) + "/fretsim map " + (directory / "scene.prm").string() +
                          " -o " + (directory / "ranks").string() +
                          " --axis 'Loading/Inner ring displacement y=40e-6:60e-6:2' -q --no-plots" + one_pass +
                          " > " + (directory / "ranks.log").string() + " 2>&1";
  ASSERT_EQ(std::system(mpi.c_str()), 0) << test_files::read_text(directory / "ranks.log");
  expect_identical(records, records_of(directory / "ranks"), "two MPI ranks against one process");
}

// A point whose values the scene refuses (warm-up cycles reaching the cycles:
// a cross-check no single parameter's range can make) is recorded as failed
// with the scene's message, and the map goes on to its other points.
TEST(MapCommand, AFailingPointIsRecordedWithItsMessageAndTheMapGoesOn)
{
  const auto directory = test_files::scratch_directory("map-failing");
  const auto scene     = small_scene_file(directory);
  const auto result    = run_program("map " + scene.string() + " -o " + (directory / "out").string() +
                                     " --axis 'Dang Van/Warm-up cycles=0:3:2' -q --no-plots");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("1 of 2 points failed"), std::string::npos) << result.output;
  const auto records = records_of(directory / "out");
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records.at(0).status, "ok") << records.at(0).message;
  EXPECT_EQ(records.at(1).status, "failed");
  EXPECT_NE(records.at(1).message.find("Warm-up cycles"), std::string::npos) << records.at(1).message;
  EXPECT_TRUE(std::isnan(test_files::read_csv(directory / "out" / "map.csv")[1].at("risk_max")));
}

// Without --axis the map is the scene file's Map section; `run` ignores it.
TEST(MapCommand, TheSceneFileCarriesItsMap)
{
  const auto directory = test_files::scratch_directory("map-file");
  const auto scene     = small_scene_file(directory);
  const std::string map_section =
    " --set 'Map/Axes=Loading/Normal load=600:1800:2 ; Loading/Sliding amplitude=1e-6:4e-6:2' --set 'Map/Boundary=true'";
  const auto result = run_program("map " + scene.string() + " -o " + (directory / "out").string() + " -q --no-plots" +
                                  map_section);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto records = records_of(directory / "out");
  ASSERT_EQ(records.size(), 4u);
  EXPECT_EQ(records.at(3).axis_values, (std::vector<double>{1800.0, 4e-6}));
  EXPECT_TRUE(std::filesystem::exists(directory / "out" / "boundary.csv"));
  EXPECT_EQ(run_program("run " + scene.string() + " -o " + (directory / "run").string() + " -q --no-plots" +
                        map_section)
              .exit_code,
            0);
  const auto none = run_program("map " + scene.string() + " -o " + (directory / "none").string());
  EXPECT_EQ(none.exit_code, 2) << none.output;
  EXPECT_NE(none.output.find("Map/Axes"), std::string::npos) << none.output;
}
