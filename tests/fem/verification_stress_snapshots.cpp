// Stress recovery at points against Lamé (thick cylinder under internal
// pressure, plane strain; the model of verification_lame_cylinder.cpp), in
// both frames and on a surface grid, and the snapshot file
// [n_snapshots, n_points, 6] with its XDMF sidecar. Runs on one rank and
// again under mpiexec -np 2 (points owned by either rank).
//
//   σ_rr = A - B/r²,  σ_θθ = A + B/r²,  σ_zz = ν (σ_rr + σ_θθ),
//   A = p a²/(b² - a²),  B = p a² b²/(b² - a²)
#include "fem_test_environment.h"

#include <fretsim/fem/elastic_model.h>
#include <fretsim/fem/stress_sampler.h>

#include <fretsim/output/stress_snapshots.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <unistd.h>

using namespace fretsim::fem;

namespace
{
  constexpr double a = 0.1, b = 0.2, width = 0.02; // [m]
  constexpr double E = 200e9, nu = 0.3, rho = 7800.0, p = 100e6;
  constexpr double A = p * a * a / (b * b - a * a), B = p * a * a * b * b / (b * b - a * a);

  std::array<double, 3> lame(double r) { return {A - B / (r * r), A + B / (r * r), nu * 2 * A}; }

  struct Model
  {
    std::shared_ptr<const Mesh> mesh;
    ElasticModel                model;
    DisplacementField           u;
  };

  Model solve()
  {
    RingGeometry g;
    g.bore_radius  = a;
    g.outer_radius = b;
    g.width        = width;
    MeshDivisions d;
    d.radial_ring     = 16;
    d.circumferential = 32;
    d.axial           = 1;
    d.sector_angle    = 0.5 * M_PI;
    auto         mesh = std::make_shared<const Mesh>(Mesh::ring(g, d));
    ElasticModel model(mesh, {{MaterialId::ring, {E, nu, rho}}}, 2,
                       {{BoundaryId::side_faces, false, false, true},
                        {BoundaryId::sector_start, false, true, false},
                        {BoundaryId::sector_end, true, false, false}});
    StaticLoad load;
    load.pressures.push_back({BoundaryId::raceway, p});
    DisplacementField u = model.solve_static(load);
    return {mesh, std::move(model), std::move(u)};
  }

  // One solve for all tests, released before MPI finalises (p4est checks
  // that no mesh is left).
  std::unique_ptr<Model> shared_model;

  Model &solution()
  {
    if (!shared_model)
      shared_model = std::make_unique<Model>(solve());
    return *shared_model;
  }
} // namespace

class StressSnapshots : public ::testing::Test
{
public:
  static void TearDownTestSuite() { shared_model.reset(); }
};

// Gradients at a point are O(h^p) accurate: σ_rr at the bore is off by 1.5 %
// of p with Q2 on 8 x 16 cells, 0.50 % on 16 x 32 (the mesh here), less inside. Points on cell faces (r = a, b and the θ of
// cell edges) take either neighbour's gradient, both within that error.
TEST_F(StressSnapshots, PointStressesAgainstLame)
{
  auto               &m = solution();
  std::vector<Point3> points;
  std::vector<double> radii;
  for (const double r : {a, 0.125, 0.15, 0.175, b})
    for (const double theta : {0.1, 0.4, 0.7854, 1.3})
      {
        points.push_back({r * std::cos(theta), r * std::sin(theta), 0.3 * width});
        radii.push_back(r);
      }
  const std::vector<double> cyl  = StressSampler(m.model, points, StressFrame::cylindrical).evaluate(m.u);
  const std::vector<double> cart = StressSampler(m.model, points, StressFrame::cartesian).evaluate(m.u);
  double worst = 0.0;
  for (std::size_t k = 0; k < points.size(); ++k)
    {
      const auto   exact = lame(radii[k]);
      const double c = points[k][0] / radii[k], s = points[k][1] / radii[k];
      // Cartesian from the exact cylindrical state, to check the other frame.
      const double xx = exact[0] * c * c + exact[1] * s * s, yy = exact[0] * s * s + exact[1] * c * c,
                   xy = (exact[0] - exact[1]) * c * s;
      const double expected_cyl[6]  = {exact[0], exact[1], exact[2], 0, 0, 0};
      const double expected_cart[6] = {xx, yy, exact[2], 0, 0, xy};
      for (unsigned int i = 0; i < 6; ++i)
        {
          worst = std::max({worst, std::abs(cyl[6 * k + i] - expected_cyl[i]) / p,
                            std::abs(cart[6 * k + i] - expected_cart[i]) / p});
          EXPECT_NEAR(cyl[6 * k + i], expected_cyl[i], 0.01 * p) << "point " << k << " component " << i;
          EXPECT_NEAR(cart[6 * k + i], expected_cart[i], 0.01 * p) << "point " << k << " component " << i;
        }
    }
  std::printf("%zu points, %lu DoFs: largest stress error %.3f %% of p\n", points.size(), m.model.n_dofs(),
              100 * worst);
}

TEST_F(StressSnapshots, SurfaceGridOnTheBoreAndSnapshotFile)
{
  auto        &m = solution();
  CylinderGrid grid;
  grid.radius = a;
  grid.nx = 12, grid.ny = 3;
  grid.hx = 0.5 * M_PI * a / grid.nx, grid.hy = width / grid.ny;
  grid.x_min = 0.0, grid.y_min = -0.5 * width;
  const StressSampler sampler = StressSampler::on_grid(m.model, grid);
  ASSERT_EQ(sampler.n_points(), grid.size());
  const std::vector<double> sigma = sampler.evaluate(m.u);
  for (std::size_t k = 0; k < grid.size(); ++k)
    {
      EXPECT_NEAR(sigma[6 * k + 0], -p, 0.01 * p) << k; // the traction: σ_rr = -p on the bore
      EXPECT_NEAR(sigma[6 * k + 1], lame(a)[1], 0.01 * p) << k;
    }

  if (ParallelEnvironment::rank() != 0)
    return;
  // Linearity: the load scaled by 0.5 and 1 as two snapshots of one "run".
  const auto dir = std::filesystem::temp_directory_path() / ("fretsim-fem-snapshots-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string h5 = (dir / "stress.h5").string();
  {
    fretsim::output::StressSnapshotFile file(h5, sampler.points(), "cylindrical");
    std::vector<double> half = sigma;
    for (double &v : half)
      v *= 0.5;
    file.append(0.0, half);
    file.append(1.0, sigma);
    file.write_xdmf((dir / "stress.xdmf").string());
  }
  std::vector<std::size_t> dims;
  const auto stored = fretsim::output::ResultsFile::read_dataset(h5, "/fields/stress", &dims);
  EXPECT_EQ(dims, (std::vector<std::size_t>{2, grid.size(), 6}));
  for (std::size_t i = 0; i < sigma.size(); ++i)
    {
      EXPECT_DOUBLE_EQ(stored[i], 0.5 * sigma[i]);
      EXPECT_DOUBLE_EQ(stored[sigma.size() + i], sigma[i]);
    }
  EXPECT_EQ(fretsim::output::ResultsFile::read_dataset(h5, "/points").size(), 3 * grid.size());
  EXPECT_EQ(fretsim::output::ResultsFile::read_string_attribute(h5, "/", "stress_components"), "rr tt zz tz rz rt");
  std::ifstream xdmf(dir / "stress.xdmf");
  const std::string text{std::istreambuf_iterator<char>(xdmf), std::istreambuf_iterator<char>()};
  EXPECT_NE(text.find("Polyvertex"), std::string::npos);
  EXPECT_NE(text.find("stress.h5:/fields/stress"), std::string::npos);
  EXPECT_NE(text.find("snapshot_1"), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST_F(StressSnapshots, PointsOffTheMeshAreRejected)
{
  EXPECT_THROW(StressSampler(solution().model, {{0.0, 0.0, 0.0}}), std::invalid_argument);
  EXPECT_THROW(StressSampler(solution().model, {{-0.15, 0.01, 0.0}}), std::invalid_argument); // outside the quarter
}
