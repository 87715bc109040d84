// Model file round trip and refusals: a file read back equals what was
// written (bit for bit: doubles stored as IEEE-754 64-bit); a file made from
// other inputs (hash), a truncated file and a file that is not a model are
// refused with a ModelFileError naming the file; a write never leaves the
// temporary file behind. A file written before the raceway operator existed
// (no /operators/raceway) reads with an empty one.
#include <fretsim/reduction/reduced_model.h>

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace fretsim::reduction;

namespace
{
  std::filesystem::path scratch(const std::string &name)
  {
    const auto dir = std::filesystem::temp_directory_path() /
                     ("fretsim-test-model-file-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    return dir / name;
  }

  ReducedModel example()
  {
    ReducedModel model;
    auto        &m = model.matrices;
    m.n_constraint = 2;
    m.n_modal      = 1;
    m.mass         = {2, 0.1, 0, 0.1, 3, 0.2, 0, 0.2, 1};
    m.stiffness    = {5, -1, 0, -1, 6, 0, 0, 0, 7};
    m.fixed_interface_frequencies_hz = {1234.5};
    m.interface_frequencies_hz       = {0.0, 99.0};
    m.n_boundary_dofs                = 30;
    m.n_interior_dofs                = 70;
    model.free_frequencies_hz        = {0.0, 10.0, 20.0};
    model.interface_grid.grid        = {0.04, 2, 1, 0.1, 0.018, 0.0, -0.009};
    model.interface_grid.displacement.assign(2 * 3 * 3, 0.25);
    model.interface_grid.stress.assign(2 * 6 * 3, -1e6);
    model.sample_points.points = {{0.04, 0.0, 0.0}};
    model.sample_points.stress.assign(6 * 3, 3.5);
    // Values whose decimal forms do not round-trip, to see bits kept; two
    // footprints that follow the load (Hertz ellipses of 1 and 8 kN).
    model.raceway.angles   = {0.0, M_PI};
    model.raceway.approach = {1.0 / 3.0, -2.0 / 7.0, 1e-9 / 3.0, std::nextafter(0.1, 1.0), -M_PI, 5e-324,
                              2.0 / 3.0, -4.0 / 7.0, 2e-9 / 3.0, std::nextafter(0.2, 1.0), -2 * M_PI, 1e-323};
    model.raceway.footprints    = {{0.3e-3 / 2.0, 1.3e-3 / 6.0, 1000.0}, {0.3e-3, 1.3e-3 / 3.0, 8000.0}};
    model.raceway.contact_angle = 0.0;
    model.timings.total        = 1.5;
    model.provenance["mesh"]   = "parametric";
    model.input_hash           = fingerprint("inputs");
    return model;
  }
} // namespace

TEST(ModelFile, RoundTrip)
{
  const auto path = scratch("model.h5");
  write_model_file(path.string(), example());
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
  const ReducedModel back = read_model_file(path.string(), fingerprint("inputs"));
  const ReducedModel original = example();
  EXPECT_EQ(back.matrices.mass, original.matrices.mass);
  EXPECT_EQ(back.matrices.stiffness, original.matrices.stiffness);
  EXPECT_EQ(back.matrices.size(), 3u);
  EXPECT_EQ(back.matrices.fixed_interface_frequencies_hz, original.matrices.fixed_interface_frequencies_hz);
  EXPECT_EQ(back.free_frequencies_hz, original.free_frequencies_hz);
  EXPECT_EQ(back.interface_grid.displacement, original.interface_grid.displacement);
  EXPECT_EQ(back.interface_grid.grid.nx, 2);
  EXPECT_DOUBLE_EQ(back.interface_grid.grid.y_min, -0.009);
  EXPECT_EQ(back.sample_points.points.size(), 1u);
  EXPECT_EQ(back.sample_points.stress, original.sample_points.stress);
  EXPECT_EQ(back.provenance.at("mesh"), "parametric");
  EXPECT_EQ(back.timings.total, 1.5);
  EXPECT_EQ(back.raceway.angles, original.raceway.angles);
  EXPECT_EQ(back.raceway.approach, original.raceway.approach);
  ASSERT_EQ(back.raceway.footprints.size(), 2u);
  for (std::size_t f = 0; f < 2; ++f)
    {
      EXPECT_EQ(back.raceway.footprints[f].semi_axis_circumferential,
                original.raceway.footprints[f].semi_axis_circumferential);
      EXPECT_EQ(back.raceway.footprints[f].semi_axis_transverse, original.raceway.footprints[f].semi_axis_transverse);
      EXPECT_EQ(back.raceway.footprints[f].load, original.raceway.footprints[f].load);
    }
  EXPECT_EQ(back.raceway.footprint_loads(), (std::vector<double>{1000.0, 8000.0}));
  // A ball between them gets its own load's ellipse, semi-axes as Q^(1/3).
  EXPECT_NEAR(back.raceway.footprint_at(4000.0).semi_axis_transverse, 1.3e-3 / 3.0 * std::cbrt(0.5), 1e-18);
  EXPECT_EQ(back.raceway.contact_angle, original.raceway.contact_angle);
  EXPECT_TRUE(back.residual.empty());
}

TEST(ModelFile, ResidualFlexibilityRoundTripsWithAndWithoutItsBallTable)
{
  // A ring's residual flexibility has a ball table; a housing's (no
  // raceway) has the pressure's alone, and must read back as present.
  for (const bool with_ball : {true, false})
    {
      ReducedModel model = example();
      auto        &residual = model.residual;
      residual.column_angle = 0.5 / 0.04;
      residual.traction[0]  = {1e-12 / 3.0, 5e-324}; // [1 row][2 cells]
      if (with_ball) // [footprint][cell]
        residual.ball = {1e-10, -1e-10 / 3.0, 2e-10, -2e-10 / 3.0};
      const auto path = scratch(with_ball ? "ring_residual.h5" : "housing_residual.h5");
      write_model_file(path.string(), model);
      const ReducedModel back = read_model_file(path.string(), fingerprint("inputs"));
      EXPECT_FALSE(back.residual.empty()) << with_ball;
      EXPECT_EQ(back.residual.traction[0], residual.traction[0]);
      EXPECT_TRUE(back.residual.traction[1].empty());
      EXPECT_EQ(back.residual.ball, residual.ball);
      EXPECT_EQ(back.residual.column_angle, residual.column_angle);
    }
}

TEST(ModelFile, OlderFileWithoutRacewayOperatorReadsAsEmpty)
{
  const auto path = scratch("model-old.h5");
  write_model_file(path.string(), example());
  {
    const hid_t file = H5Fopen(path.string().c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    ASSERT_GE(H5Ldelete(file, "/operators/raceway", H5P_DEFAULT), 0);
    H5Fclose(file);
  }
  const ReducedModel back = read_model_file(path.string());
  EXPECT_TRUE(back.raceway.angles.empty());
  EXPECT_TRUE(back.raceway.approach.empty());
  EXPECT_EQ(back.interface_grid.displacement, example().interface_grid.displacement);

  // No operator at all is written as an empty one, and reads back so.
  ReducedModel none = example();
  none.raceway      = {};
  write_model_file(path.string(), none);
  EXPECT_TRUE(read_model_file(path.string()).raceway.angles.empty());
}

TEST(ModelFile, RefusesOtherInputsTruncationAndForeignFiles)
{
  const auto path = scratch("model-refusals.h5");
  write_model_file(path.string(), example());
  try
    {
      read_model_file(path.string(), fingerprint("other inputs"));
      FAIL() << "a model made from other inputs was accepted";
    }
  catch (const ModelFileError &error)
    {
      EXPECT_NE(std::string(error.what()).find("other inputs"), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find(path.string()), std::string::npos) << error.what();
    }

  const auto truncated = scratch("truncated.h5");
  std::filesystem::copy_file(path, truncated, std::filesystem::copy_options::overwrite_existing);
  std::filesystem::resize_file(truncated, std::filesystem::file_size(path) / 2);
  EXPECT_THROW(read_model_file(truncated.string()), ModelFileError);

  const auto foreign = scratch("foreign.h5");
  std::ofstream(foreign) << "not HDF5\n";
  EXPECT_THROW(read_model_file(foreign.string()), ModelFileError);
  EXPECT_THROW(read_model_file(scratch("missing.h5").string()), ModelFileError);

  // A file of the format before load-following footprints (version 3) is
  // refused in one line that says so (the scene then rebuilds it).
  const auto older = scratch("version3.h5");
  std::filesystem::copy_file(path, older, std::filesystem::copy_options::overwrite_existing);
  {
    const hid_t file = H5Fopen(older.string().c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    const hid_t  attribute = H5Aopen(file, "format_version", H5P_DEFAULT);
    const double version   = 3.0;
    ASSERT_GE(H5Awrite(attribute, H5T_NATIVE_DOUBLE, &version), 0);
    H5Aclose(attribute);
    H5Fclose(file);
  }
  try
    {
      read_model_file(older.string());
      FAIL() << "a version 3 model file was accepted";
    }
  catch (const ModelFileError &error)
    {
      const std::string message = error.what();
      EXPECT_NE(message.find("format version 3"), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }

  // Footprints that are not one load's Hertz ellipses scaled are refused.
  ReducedModel wrong = example();
  wrong.raceway.footprints[0].semi_axis_transverse *= 1.01;
  write_model_file(path.string(), wrong);
  EXPECT_THROW(read_model_file(path.string()), ModelFileError);
}
