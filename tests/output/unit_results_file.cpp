// results.h5 writer: layout, units and attributes read back through HDF5, a
// run killed after a flush, and the XDMF sidecar.
#include <fretsim/output/results_file.h>

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

using fretsim::output::ResultsFile;

namespace
{
  std::filesystem::path scratch_directory(const std::string &name)
  {
    const auto directory = std::filesystem::path(FRETSIM_BINARY_DIR) / "test_output" / name;
    std::filesystem::remove_all(directory);
    std::filesystem::create_directories(directory);
    return directory;
  }

  std::string file_text(const std::filesystem::path &path)
  {
    std::ifstream      in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

  std::size_t occurrences(const std::string &text, const std::string &pattern)
  {
    std::size_t count = 0;
    for (std::size_t at = text.find(pattern); at != std::string::npos; at = text.find(pattern, at + 1))
      ++count;
    return count;
  }

  using Dims = std::vector<std::size_t>;

  // A 4 x 3 grid with 2 depth layers: cell centres 0.5 … 3.5 mm and 0.5 … 2.5 mm.
  const std::vector<double> grid_x{0.5e-3, 1.5e-3, 2.5e-3, 3.5e-3};
  const std::vector<double> grid_y{0.5e-3, 1.5e-3, 2.5e-3};
  const std::vector<double> grid_z{0.0, 1e-4};
  const std::size_t         nx = 4, ny = 3, nz = 2;

  /// Value of snapshot s at flat index i, distinct per field.
  double pressure_value(std::size_t s, std::size_t i) { return 1e6 * (s + 1) + i; }
  double risk_value(std::size_t s, std::size_t i) { return 0.01 * i + s; }

  /// Writes grid, two series (5 rows), a [ny, nx] and an [nz, ny, nx] field
  /// (3 snapshots) and the fixed /fields/risk_max.
  void write_example(const std::string &path)
  {
    ResultsFile results(path, "concentrated", "set Normal load = 10\n# comment with \"quotes\" and µm");
    results.write_grid(grid_x, grid_y, grid_z);
    results.set_root_attribute("contact_radius_m", 1.25e-4);
    results.declare_series("time", "s");
    results.declare_series("tangential_force_x", "N");
    for (int row = 0; row < 5; ++row)
      results.append_series_row({0.1 * row, -2.0 * row});
    results.declare_field("pressure", "Pa", {ny, nx});
    results.declare_field("risk", "1", {nz, ny, nx});
    for (std::size_t s = 0; s < 3; ++s)
      {
        std::vector<double> pressure(ny * nx), risk(nz * ny * nx);
        for (std::size_t i = 0; i < pressure.size(); ++i)
          pressure[i] = pressure_value(s, i);
        for (std::size_t i = 0; i < risk.size(); ++i)
          risk[i] = risk_value(s, i);
        results.append_snapshot(0.5 * s, {&pressure, &risk});
        results.flush();
      }
    std::vector<double> risk_max(nz * ny * nx);
    for (std::size_t i = 0; i < risk_max.size(); ++i)
      risk_max[i] = 0.5 + i;
    results.write_dataset("/fields/risk_max", "1", {nz, ny, nx}, risk_max);
    results.set_root_attribute("status", "complete");
    EXPECT_EQ(results.n_series_rows(), 5u);
    EXPECT_EQ(results.n_snapshots(), 3u);
  }
} // namespace

TEST(ResultsFile, LayoutValuesUnitsAndAttributes)
{
  const std::string path = (scratch_directory("layout") / "results.h5").string();
  write_example(path);

  Dims dims;
  EXPECT_EQ(ResultsFile::read_dataset(path, "/grid/x", &dims), grid_x);
  EXPECT_EQ(dims, Dims{nx});
  EXPECT_EQ(ResultsFile::read_dataset(path, "/grid/y", &dims), grid_y);
  EXPECT_EQ(ResultsFile::read_dataset(path, "/grid/z", &dims), grid_z);
  EXPECT_EQ(ResultsFile::read_string_attribute(path, "/grid/z", "unit"), "m");

  const auto force = ResultsFile::read_dataset(path, "/series/tangential_force_x", &dims);
  EXPECT_EQ(dims, Dims{5});
  EXPECT_EQ(force, (std::vector<double>{0.0, -2.0, -4.0, -6.0, -8.0}));
  EXPECT_EQ(ResultsFile::read_dataset(path, "/series/time", &dims)[3], 0.1 * 3);
  EXPECT_EQ(ResultsFile::read_string_attribute(path, "/series/time", "unit"), "s");
  EXPECT_EQ(ResultsFile::read_string_attribute(path, "/series/tangential_force_x", "unit"), "N");

  EXPECT_EQ(ResultsFile::read_dataset(path, "/time", &dims), (std::vector<double>{0.0, 0.5, 1.0}));
  EXPECT_EQ(ResultsFile::read_string_attribute(path, "/time", "unit"), "s");

  const auto pressure = ResultsFile::read_dataset(path, "/fields/pressure", &dims);
  ASSERT_EQ(dims, (Dims{3, ny, nx}));
  for (std::size_t s = 0; s < 3; ++s)
    for (std::size_t i = 0; i < ny * nx; ++i)
      ASSERT_EQ(pressure[s * ny * nx + i], pressure_value(s, i)) << "snapshot " << s << " cell " << i;
  EXPECT_EQ(ResultsFile::read_string_attribute(path, "/fields/pressure", "unit"), "Pa");

  const auto risk = ResultsFile::read_dataset(path, "/fields/risk", &dims);
  ASSERT_EQ(dims, (Dims{3, nz, ny, nx}));
  for (std::size_t s = 0; s < 3; ++s)
    for (std::size_t i = 0; i < nz * ny * nx; ++i)
      ASSERT_EQ(risk[s * nz * ny * nx + i], risk_value(s, i)) << "snapshot " << s << " index " << i;
  EXPECT_EQ(ResultsFile::read_string_attribute(path, "/fields/risk", "unit"), "1");

  const auto risk_max = ResultsFile::read_dataset(path, "fields/risk_max", &dims);
  EXPECT_EQ(dims, (Dims{nz, ny, nx}));
  EXPECT_EQ(risk_max.front(), 0.5);
  EXPECT_EQ(risk_max.back(), 0.5 + nz * ny * nx - 1);
  EXPECT_EQ(ResultsFile::read_string_attribute(path, "/fields/risk_max", "unit"), "1");

  EXPECT_EQ(ResultsFile::read_string_attribute(path, "/", "scene"), "concentrated");
  EXPECT_EQ(ResultsFile::read_string_attribute(path, "/", "parameters"),
            "set Normal load = 10\n# comment with \"quotes\" and µm");
  EXPECT_EQ(ResultsFile::read_string_attribute(path, "/", "status"), "complete");
  EXPECT_EQ(ResultsFile::read_double_attribute(path, "/", "contact_radius_m"), 1.25e-4);
}

TEST(ResultsFile, SeriesDeclaredLateStartsWithNaN)
{
  const std::string path = (scratch_directory("late_series") / "results.h5").string();
  {
    ResultsFile results(path, "test", "");
    results.declare_series("a", "1");
    results.append_series_row({1.0});
    results.append_series_row({2.0});
    results.declare_series("b", "1");
    results.append_series_row({3.0, 30.0});
    EXPECT_EQ(results.n_series_rows(), 3u);
  }
  const auto b = ResultsFile::read_dataset(path, "/series/b");
  ASSERT_EQ(b.size(), 3u);
  EXPECT_TRUE(std::isnan(b[0]) && std::isnan(b[1]));
  EXPECT_EQ(b[2], 30.0);
  EXPECT_EQ(ResultsFile::read_dataset(path, "/series/a"), (std::vector<double>{1.0, 2.0, 3.0}));
}

TEST(ResultsFile, MisuseAndFailuresThrowWithNames)
{
  const auto        directory = scratch_directory("errors");
  const std::string path      = (directory / "results.h5").string();
  {
    ResultsFile results(path, "test", "");
    results.declare_series("a", "1");
    EXPECT_THROW(results.append_series_row({1.0, 2.0}), std::invalid_argument);
    EXPECT_THROW(results.declare_series("a", "1"), std::invalid_argument);
    EXPECT_THROW(results.declare_series("bad/name", "1"), std::invalid_argument);
    std::vector<double> wrong(5);
    EXPECT_THROW(results.append_snapshot(0.0, {}), std::logic_error);
    results.declare_field("p", "Pa", {2, 3});
    EXPECT_THROW(results.append_snapshot(0.0, {&wrong}), std::invalid_argument);
    EXPECT_THROW(results.write_dataset("/fields/q", "1", {2, 2}, wrong), std::invalid_argument);
    EXPECT_THROW(results.write_xdmf((directory / "no_grid.xdmf").string()), std::runtime_error);
    EXPECT_EQ(results.n_snapshots(), 0u);
  }
  const std::string missing = (directory / "no_such_folder" / "results.h5").string();
  try
    {
      ResultsFile results(missing, "test", "");
      FAIL() << "creating a file in a missing folder must throw";
    }
  catch (const std::runtime_error &error)
    {
      EXPECT_NE(std::string(error.what()).find(missing), std::string::npos) << error.what();
    }
  try
    {
      ResultsFile::read_dataset(path, "/series/missing");
      FAIL() << "reading a missing dataset must throw";
    }
  catch (const std::runtime_error &error)
    {
      EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find("/series/missing"), std::string::npos) << error.what();
    }
}

TEST(ResultsFile, RunKilledAfterFlushLeavesReadableFile)
{
  const std::string path    = (scratch_directory("killed") / "results.h5").string();
  const int         flushed = 37;
  const pid_t       child   = fork();
  ASSERT_GE(child, 0) << "fork failed";
  if (child == 0)
    {
      // The "run": writes and flushes row by row, one snapshot, then dies
      // without closing the file (no destructor, no atexit handlers).
      int status = 1;
      try
        {
          auto *results = new ResultsFile(path, "test", "p");
          results->write_grid({0.0, 1.0}, {0.0}, {0.0});
          results->declare_series("time", "s");
          results->declare_series("force", "N");
          results->declare_field("pressure", "Pa", {1, 2});
          for (int row = 0; row < flushed; ++row)
            {
              results->append_series_row({0.5 * row, 3.0 * row});
              if (row == 10)
                {
                  const std::vector<double> pressure{7.0, 8.0};
                  results->append_snapshot(0.5 * row, {&pressure});
                }
              results->flush();
            }
          status = 0;
        }
      catch (...)
        {
        }
      _exit(status);
    }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "child run failed";

  Dims       dims;
  const auto force = ResultsFile::read_dataset(path, "/series/force", &dims);
  ASSERT_EQ(dims, Dims{flushed});
  for (int row = 0; row < flushed; ++row)
    EXPECT_EQ(force[row], 3.0 * row);
  EXPECT_EQ(ResultsFile::read_dataset(path, "/series/time").back(), 0.5 * (flushed - 1));
  EXPECT_EQ(ResultsFile::read_dataset(path, "/fields/pressure", &dims), (std::vector<double>{7.0, 8.0}));
  EXPECT_EQ(dims, (Dims{1, 1, 2}));
  EXPECT_EQ(ResultsFile::read_string_attribute(path, "/", "scene"), "test");

  // The sidecar can still be written for what the file holds.
  const std::string xdmf = (std::filesystem::path(path).parent_path() / "results.xdmf").string();
  ResultsFile::write_xdmf(path, xdmf);
  EXPECT_EQ(occurrences(file_text(xdmf), "results.h5:/fields/pressure"), 1u);
}

TEST(ResultsFile, XdmfDescribesEverySnapshotAndLayer)
{
  const auto        directory = scratch_directory("xdmf");
  const std::string path      = (directory / "results.h5").string();
  const std::string xdmf      = (directory / "results.xdmf").string();
  {
    ResultsFile results(path, "concentrated", "");
    results.write_grid(grid_x, grid_y, grid_z);
    results.declare_field("pressure", "Pa", {ny, nx});
    results.declare_field("risk", "1", {nz, ny, nx});
    std::vector<double> pressure(ny * nx, 1.0), risk(nz * ny * nx, 2.0);
    for (int s = 0; s < 3; ++s)
      results.append_snapshot(0.25 * s, {&pressure, &risk});
    results.write_dataset("/fields/risk_max", "1", {nz, ny, nx}, risk);
    results.write_xdmf(xdmf);
  }
  const std::string text = file_text(xdmf);

  // Well-formed: every element opened is closed, in order.
  {
    std::vector<std::string> open;
    const std::regex         tag("<(/?)([A-Za-z]+)[^>]*?(/?)>");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), tag); it != std::sregex_iterator(); ++it)
      {
        const auto &m = *it;
        if (m[3] == "/")
          continue; // <Time .../>
        if (m[1] == "/")
          {
            ASSERT_FALSE(open.empty()) << "closing </" << m[2] << "> without an opening tag";
            ASSERT_EQ(open.back(), m[2].str());
            open.pop_back();
          }
        else
          open.push_back(m[2]);
      }
    EXPECT_TRUE(open.empty());
  }
  // One temporal collection of three uniform grids.
  EXPECT_EQ(occurrences(text, "<Grid "), 4u);
  EXPECT_EQ(occurrences(text, "CollectionType=\"Temporal\""), 1u);
  EXPECT_EQ(occurrences(text, "<Time Value=\"0.25\"/>"), 1u);
  // Nodes: (ny + 1) x (nx + 1), edges half a cell outside the centres.
  EXPECT_EQ(occurrences(text, "TopologyType=\"2DRectMesh\" Dimensions=\"4 5\""), 3u);
  {
    const std::string item = "<DataItem Dimensions=\"5\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">";
    const auto        at   = text.find(item);
    ASSERT_NE(at, std::string::npos);
    std::istringstream nodes(text.substr(at + item.size(), text.find('<', at + item.size()) - at - item.size()));
    std::vector<double> x_nodes;
    for (double v; nodes >> v;)
      x_nodes.push_back(v);
    ASSERT_EQ(x_nodes.size(), nx + 1);
    for (std::size_t i = 0; i <= nx; ++i)
      EXPECT_NEAR(x_nodes[i], 1e-3 * i, 1e-15) << "x node " << i;
    EXPECT_EQ(occurrences(text, item), 3u);
    EXPECT_EQ(occurrences(text, "<DataItem Dimensions=\"4\" NumberType=\"Float\""), 3u); // y nodes
  }
  // Per snapshot: pressure, risk_z0, risk_z1, risk_max_z0, risk_max_z1.
  EXPECT_EQ(occurrences(text, "<Attribute "), 3u * 5u);
  EXPECT_EQ(occurrences(text, "results.h5:/fields/pressure<"), 3u);
  EXPECT_EQ(occurrences(text, "results.h5:/fields/risk<"), 6u);
  EXPECT_EQ(occurrences(text, "results.h5:/fields/risk_max<"), 6u);
  EXPECT_EQ(occurrences(text, "Name=\"risk_z1\""), 3u);
  EXPECT_EQ(occurrences(text, "Name=\"risk_max_z0\""), 3u);
  EXPECT_EQ(occurrences(text, "ItemType=\"HyperSlab\" Type=\"HyperSlab\" Dimensions=\"3 4\""), 15u);
  // The last snapshot's second layer: start, stride, count over [3, nz, ny, nx].
  EXPECT_NE(text.find(">2 1 0 0  1 1 1 1  1 1 3 4<"), std::string::npos);
  EXPECT_NE(text.find("Dimensions=\"3 2 3 4\""), std::string::npos);
  EXPECT_EQ(text.find(directory.string()), std::string::npos) << "the .h5 must be named relative to the XDMF";

  // The same from the closed file, and from another folder.
  const std::string again = (directory / "again.xdmf").string();
  ResultsFile::write_xdmf(path, again);
  EXPECT_EQ(file_text(again), text);
  std::filesystem::create_directories(directory / "view");
  const std::string elsewhere = (directory / "view" / "results.xdmf").string();
  ResultsFile::write_xdmf(path, elsewhere);
  EXPECT_EQ(occurrences(file_text(elsewhere), "../results.h5:/fields/pressure<"), 3u);
  EXPECT_FALSE(std::filesystem::exists(xdmf + ".tmp"));
}
