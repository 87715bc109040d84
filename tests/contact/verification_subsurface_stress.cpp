// Subsurface stresses of the grid evaluators against closed forms:
// frictionless Hertz on the axis (docs/references.md §1.1) and anywhere (Hamilton 1983,
// docs/references.md §3.1), full-sliding Hertz (docs/references.md §3.2 surface forms and the
// §3.3 table), and DC-FFT against direct summation.
#include <fretsim/contact/subsurface_stress.h>

#include "reference/hamilton.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

using namespace fretsim::contact;
using fretsim::reference::Stress;

namespace
{
  // Paper case (docs/references.md §1.2): R = 50 mm, P = 1250 N, E = 200 GPa, nu = 0.3, both bodies steel.
  const double nu = 0.3, load = 1250.0, radius = 0.05, youngs = 200e9;
  const double contact_modulus = youngs / (2 * (1 - nu * nu));
  const double a  = std::cbrt(3 * load * radius / (4 * contact_modulus));
  const double p0 = 3 * load / (2 * M_PI * a * a);

  /// n x n cells of size h whose cell (n/2, n/2) is centred on the contact
  /// axis: the grid is [-(n/2 + 1/2) h, (n/2 - 1/2) h] in x and y.
  SurfaceGrid axis_centred_grid(int n, double h)
  {
    SurfaceGrid g;
    g.nx = g.ny = n;
    g.hx = g.hy = h;
    g.x_min = g.y_min = -(n / 2 + 0.5) * h;
    return g;
  }

  Field hertz_pressure(const SurfaceGrid &g)
  {
    Field p = g.zeros();
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i)
        {
          const double rr = (g.x(i) * g.x(i) + g.y(j) * g.y(j)) / (a * a);
          p[g.index(i, j)] = rr < 1 ? p0 * std::sqrt(1 - rr) : 0.0;
        }
    return p;
  }

  Field scaled(const Field &f, double factor)
  {
    Field out(f);
    for (double &v : out)
      v *= factor;
    return out;
  }

  Stress tensor_at(const StressField &s, int layer, int j, int i)
  {
    Stress t;
    for (int c = 0; c < 6; ++c)
      t[c] = s.at(layer, c, j, i);
    return t;
  }

  double tresca(const Stress &s)
  {
    const auto e = fretsim::reference::principal_stresses(s);
    return 0.5 * (e[2] - e[0]);
  }

  StressEvaluatorSettings method(const std::string &name)
  {
    StressEvaluatorSettings settings;
    settings.method = name;
    return settings;
  }

  double seconds_since(std::chrono::steady_clock::time_point start)
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
} // namespace

// ---- frictionless Hertz -----------------------------------------------------------------

TEST(SubsurfaceStressHertz, AxisStressesAndMaximumShear)
{
  // Paper case on a 128 x 128 grid over +-1.5a, shifted half a cell so that a
  // cell centre lies on the axis; pressure sampled at cell centres.
  const int         n = 128;
  const SurfaceGrid grid = axis_centred_grid(n, 3 * a / n);
  const int         axis = n / 2;
  std::vector<double> depths;
  const std::vector<double> check_depths = {0.0, 0.1, 0.25, 0.5, 1.0, 2.0};
  for (const double z : check_depths)
    depths.push_back(z * a);
  // Fine scan through the maximum of (sigma1 - sigma3)/2 at z = 0.4809a.
  const int    scan_first = static_cast<int>(depths.size());
  const double scan_step  = 0.004;
  for (double z = 0.40; z <= 0.56 + 1e-9; z += scan_step)
    depths.push_back(z * a);

  const auto  evaluator = make_subsurface_stress(grid, depths, nu, method("fft"));
  const Field p = hertz_pressure(grid), zero = grid.zeros();
  StressField stress;
  evaluator->evaluate(p, zero, zero, stress);

  double worst_z = 0, worst_r = 0;
  for (std::size_t k = 0; k < check_depths.size(); ++k)
    {
      const double z = depths[k];
      const Stress s = tensor_at(stress, static_cast<int>(k), axis, axis);
      // Piecewise-constant sampling of the Hertz pressure: O(h^2) discretisation
      // error (docs/references.md §6.3: 7e-5 of u_z(0) at the centre for 128 cells);
      // measured below 2e-4 p0 here, asserted at 1e-3 p0.
      worst_z = std::max(worst_z, std::abs(s[zz] - fretsim::reference::hertz_axis_sigma_z(z, a, p0)) / p0);
      worst_r = std::max(worst_r, std::abs(s[xx] - fretsim::reference::hertz_axis_sigma_r(z, a, p0, nu)) / p0);
      EXPECT_NEAR(s[zz] / p0, fretsim::reference::hertz_axis_sigma_z(z, a, p0) / p0, 1e-3) << "z/a = " << z / a;
      EXPECT_NEAR(s[xx] / p0, fretsim::reference::hertz_axis_sigma_r(z, a, p0, nu) / p0, 1e-3) << "z/a = " << z / a;
      EXPECT_NEAR(s[yy] / p0, s[xx] / p0, 1e-12) << "axisymmetry, z/a = " << z / a;
    }

  // Maximum of the Tresca shear on the axis column: the scan maximum refined
  // by a parabola through it and its neighbours.
  std::vector<double> shear;
  for (std::size_t k = scan_first; k < depths.size(); ++k)
    shear.push_back(tresca(tensor_at(stress, static_cast<int>(k), axis, axis)) / p0);
  const auto   peak = std::max_element(shear.begin() + 1, shear.end() - 1);
  const double f0 = peak[-1], f1 = peak[0], f2 = peak[1];
  const double offset = 0.5 * (f0 - f2) / (f0 - 2 * f1 + f2);
  const double tau_max = f1 - 0.25 * (f0 - f2) * offset;
  const double z_max   = depths[scan_first + (peak - shear.begin())] / a + offset * scan_step;
  std::printf("axis: max |sigma_z error| %.2e p0, |sigma_r error| %.2e p0; tau_max = %.5f p0 at z = %.4f a\n",
              worst_z, worst_r, tau_max, z_max);
  // docs/references.md §1.1 table, nu = 0.3: 0.31002 p0 at z = 0.4809a; 1 % required.
  EXPECT_NEAR(tau_max, 0.31002, 0.01 * 0.31002);
  // Location to a tenth of the 0.004a scan step plus discretisation: 0.005a.
  EXPECT_NEAR(z_max, 0.4809, 0.005);
}

class SubsurfaceStressHamilton : public ::testing::TestWithParam<std::string>
{};

TEST_P(SubsurfaceStressHamilton, WholeLayersAgreeWithHamilton)
{
  // Every cell centre of the 128 x 128 grid over +-1.5a on four layers against
  // Hamilton's explicit normal-load stresses (docs/references.md §3.1); 1 % of p0
  // required.
  const int           n = 128;
  const SurfaceGrid   grid = axis_centred_grid(n, 3 * a / n);
  const std::vector<double> depths = {0.1 * a, 0.25 * a, 0.48 * a, 1.0 * a};
  const auto          start = std::chrono::steady_clock::now();
  const auto          evaluator = make_subsurface_stress(grid, depths, nu, method(GetParam()));
  const Field         p = hertz_pressure(grid), zero = grid.zeros();
  StressField         stress;
  evaluator->evaluate(p, zero, zero, stress);
  const double elapsed = seconds_since(start);
  double       worst   = 0;
  for (std::size_t k = 0; k < depths.size(); ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        {
          const Stress expected = fretsim::reference::hamilton_normal(grid.x(i), grid.y(j), depths[k], a, p0, nu);
          for (int c = 0; c < 6; ++c)
            worst = std::max(worst, std::abs(stress.at(static_cast<int>(k), c, j, i) - expected[c]) / p0);
        }
  std::printf("%s: max error vs Hamilton over 4 layers of 128^2: %.2e p0 (%.2f s)\n", GetParam().c_str(), worst,
              elapsed);
  EXPECT_LT(worst, 0.01);
}

INSTANTIATE_TEST_SUITE_P(Evaluators, SubsurfaceStressHamilton, ::testing::Values("direct", "fft"));

TEST(SubsurfaceStressHertz, HamiltonReferenceReproducesTable)
{
  // Self-check of tests/reference/hamilton.h against the P rows of docs/references.md
  // §3.3 (6 decimals: tolerance 1e-6).
  for (const auto &row : fretsim::reference::sliding_table())
    {
      const Stress s = fretsim::reference::hamilton_normal(row.x, row.y, row.z, 1.0, 1.0, nu);
      for (int c = 0; c < 6; ++c)
        EXPECT_NEAR(s[c], row.normal[c], 1e-6) << "(" << row.x << ", " << row.y << ", " << row.z << ") " << c;
    }
  // ... and its Q-part axis formula against the table's (0, 0, 0.5) Q row.
  EXPECT_NEAR(fretsim::reference::hertz_shear_axis_tau_xz(0.5, 1.0, 1.0), -0.269638, 1e-6);
}

// ---- sliding Hertz, q = mu p -----------------------------------------------------------

namespace
{
  /// 128 x 128 cells of a/40: cell centres at integer multiples of a/40, so
  /// every point of the docs/references.md §3.3 table is a cell centre.
  const int    sliding_n = 128;
  const double sliding_h = a / 40;

  int cell_of(double x_over_a) { return sliding_n / 2 + static_cast<int>(std::lround(x_over_a * 40)); }
} // namespace

TEST(SubsurfaceStressSliding, TableValuesAndSurface)
{
  const SurfaceGrid grid = axis_centred_grid(sliding_n, sliding_h);
  const auto        table = fretsim::reference::sliding_table();
  std::vector<double> depths = {0.0};
  for (const auto &row : table)
    depths.push_back(row.z * a);
  const auto  evaluator = make_subsurface_stress(grid, depths, nu, method("fft"));
  const Field p = hertz_pressure(grid), zero = grid.zeros();

  for (const double mu : {0.25, 0.5})
    {
      StressField stress;
      evaluator->evaluate(p, scaled(p, mu), zero, stress);

      // Subsurface: the §3.3 table, P row + mu Q row, within 2 % of p0 (required).
      double worst_table = 0;
      for (std::size_t k = 0; k < table.size(); ++k)
        {
          const auto &row = table[k];
          const int   i = cell_of(row.x), j = cell_of(row.y);
          ASSERT_NEAR(grid.x(i), row.x * a, 1e-9 * a);
          ASSERT_NEAR(grid.y(j), row.y * a, 1e-9 * a);
          for (int c = 0; c < 6; ++c)
            {
              const double expected = row.normal[c] + mu * row.shear[c];
              const double got      = stress.at(static_cast<int>(k) + 1, c, j, i) / p0;
              worst_table           = std::max(worst_table, std::abs(got - expected));
              EXPECT_NEAR(got, expected, 0.02)
                << "mu " << mu << " at (" << row.x << ", " << row.y << ", " << row.z << ")a component " << c;
            }
        }

      // Surface, inside the contact: Hertz surface stresses plus the closed
      // forms of the Hertz-shaped traction (docs/references.md §1.1, §3.2).
      double worst_surface = 0, worst_inner = 0;
      for (int j = 0; j < sliding_n; ++j)
        for (int i = 0; i < sliding_n; ++i)
          {
            const double x = grid.x(i), y = grid.y(j), r = std::hypot(x, y) / a;
            if (r > 1.0)
              continue;
            Stress       expected = fretsim::reference::hertz_surface(x, y, a, p0, nu);
            const Stress traction = fretsim::reference::hertz_shear_surface(x, y, a, mu * p0, nu);
            for (int c = 0; c < 6; ++c)
              expected[c] += traction[c];
            for (int c = 0; c < 6; ++c)
              {
                const double error = std::abs(stress.at(0, c, j, i) - expected[c]) / p0;
                worst_surface      = std::max(worst_surface, error);
                if (r <= 0.9)
                  worst_inner = std::max(worst_inner, error);
              }
          }
      std::printf("mu %.2f: table max error %.4f p0; surface max error r<=0.9a %.4f p0 (r<=a %.4f p0)\n", mu,
                  worst_table, worst_inner, worst_surface);
      // Within 0.9a the required 2 % of p0 holds (measured 0.5 % at mu = 0.25,
      // 1.1 % at mu = 0.5). In the outer ring of cells the piecewise-constant
      // traction cannot follow the square-root edge of q = mu p: the rim cells
      // err by ~0.2 mu p0 at h = a/40, shrinking like sqrt(h) (see
      // TrailingEdgePeak).
      EXPECT_LT(worst_inner, 0.02);
    }
}

TEST(SubsurfaceStressSliding, TrailingEdgePeak)
{
  // The surface sigma_x peaks at the trailing edge x = -a (docs/references.md §3.2):
  // p0 [(1-2nu)/3 + pi mu (4+nu)/8]. How the grid approaches it: grids whose
  // cell centres fall on the rim (h = a/k, odd cell count, centre cell on the
  // axis, loads sampled at centres so the rim cell carries p = q = 0). The
  // rim value converges like sqrt(h): the square-root edge of the traction
  // makes the last loaded cell carry ~ mu p0 sqrt(2h/a). So the value is
  // taken at that cell centre on grids h = a/20, a/40, a/80, the error ratio
  // per halving is checked to be ~sqrt 2, and the limit is the Richardson
  // extrapolation (sqrt(2) s(h/2) - s(h)) / (sqrt(2) - 1) of the two finer
  // grids, tested against the closed form within 2 % of p0.
  for (const double mu : {0.25, 0.5})
    {
      std::vector<double> rim;
      for (const int k : {20, 40, 80})
        {
          const int   n = 2 * static_cast<int>(std::ceil(1.1 * k)) + 1; // covers +-1.1a
          SurfaceGrid grid;
          grid.nx = grid.ny = n;
          grid.hx = grid.hy = a / k;
          grid.x_min = grid.y_min = -(n / 2 + 0.5) * grid.hx;
          const Field p = hertz_pressure(grid);
          StressField stress;
          make_subsurface_stress(grid, {0.0}, nu, method("fft"))->evaluate(p, scaled(p, mu), grid.zeros(), stress);
          const int i = n / 2 - k, j = n / 2;
          ASSERT_NEAR(grid.x(i), -a, 1e-12 * a);
          rim.push_back(stress.at(0, xx, j, i) / p0);
        }
      const double exact = fretsim::reference::sliding_trailing_edge_sigma_x(mu, nu);
      const double ratio = (exact - rim[1]) / (exact - rim[2]);
      const double extrapolated = (std::sqrt(2.0) * rim[2] - rim[1]) / (std::sqrt(2.0) - 1);
      std::printf("mu %.2f trailing edge sigma_x/p0: h=a/20 %.4f, a/40 %.4f, a/80 %.4f, extrapolated %.4f, "
                  "exact %.4f; error ratio a/40 : a/80 = %.3f\n",
                  mu, rim[0], rim[1], rim[2], extrapolated, exact, ratio);
      EXPECT_NEAR(extrapolated, exact, 0.02);
      // sqrt(h) convergence (ratio sqrt 2 = 1.414; measured 1.43): +-0.1.
      EXPECT_NEAR(ratio, std::sqrt(2.0), 0.1);
      // The raw values approach from below, monotonically.
      EXPECT_LT(rim[0], rim[1]);
      EXPECT_LT(rim[1], rim[2]);
      EXPECT_LT(rim[2], exact);
    }
}

// ---- DC-FFT against direct summation ------------------------------------------------

namespace
{
  /// A non-square grid with unequal cell sizes and three unrelated smooth loads.
  struct MixedCase
  {
    SurfaceGrid         grid;
    Field               p, qx, qy;
    std::vector<double> depths;
  };

  MixedCase mixed_case()
  {
    MixedCase m;
    m.grid.nx = 37;
    m.grid.ny = 22;
    m.grid.hx = 1.3e-5;
    m.grid.hy = 0.8e-5;
    m.grid.x_min = -0.2e-3;
    m.grid.y_min = -0.1e-3;
    m.p = m.qx = m.qy = m.grid.zeros();
    for (int j = 0; j < m.grid.ny; ++j)
      for (int i = 0; i < m.grid.nx; ++i)
        {
          const double u = static_cast<double>(i) / m.grid.nx, v = static_cast<double>(j) / m.grid.ny;
          const std::size_t k = m.grid.index(i, j);
          m.p[k]  = 1e9 * (1.0 + 0.5 * std::sin(7 * u + 3 * v)) * (u * (1 - u) > 0.05 ? 1.0 : 0.0);
          m.qx[k] = 3e8 * std::cos(5 * u - 2 * v + 0.3);
          m.qy[k] = -2e8 * u * v + 1e8 * std::sin(11 * v);
        }
    m.depths = {0.0, 0.3 * m.grid.hy, 2.5e-5, 1.0e-4};
    return m;
  }

  double max_abs(const std::vector<double> &v)
  {
    double m = 0;
    for (const double x : v)
      m = std::max(m, std::abs(x));
    return m;
  }
} // namespace

TEST(SubsurfaceStressEvaluators, FftEqualsDirectSummation)
{
  // DC-FFT is linear convolution, exact to round-off (docs/references.md §6.2-6.3:
  // 4e-16 relative for u_z); asserted below 1e-10 of the largest stress.
  const MixedCase m = mixed_case();
  StressField     direct, fft;
  make_subsurface_stress(m.grid, m.depths, nu, method("direct"))->evaluate(m.p, m.qx, m.qy, direct);
  make_subsurface_stress(m.grid, m.depths, nu, method("fft"))->evaluate(m.p, m.qx, m.qy, fft);
  ASSERT_EQ(direct.values.size(), fft.values.size());
  double difference = 0;
  for (std::size_t k = 0; k < fft.values.size(); ++k)
    difference = std::max(difference, std::abs(fft.values[k] - direct.values[k]));
  const double relative = difference / max_abs(direct.values);
  std::printf("fft vs direct, 37 x 22 cells, 4 layers: %.2e relative\n", relative);
  EXPECT_LT(relative, 1e-10);
}

TEST(SubsurfaceStressEvaluators, FftWithoutSpectrumCacheIsIdentical)
{
  // Layers beyond the spectrum memory budget are recomputed on every call. A
  // layer's spectra take 15 (nx+1)(ny+1) doubles; with a budget of 1.3 layers
  // one layer of this case is cached and three are not, with 0 none: both
  // must equal the fully cached evaluator bitwise (same arithmetic, the
  // spectra only live elsewhere).
  const MixedCase m = mixed_case();
  StressField     cached, partly, uncached;
  detail::make_fft_stress(m.grid, m.depths, nu)->evaluate(m.p, m.qx, m.qy, cached);
  detail::make_fft_stress(m.grid, m.depths, nu, 20 * 38 * 23 * sizeof(double))->evaluate(m.p, m.qx, m.qy, partly);
  detail::make_fft_stress(m.grid, m.depths, nu, 0)->evaluate(m.p, m.qx, m.qy, uncached);
  EXPECT_EQ(cached.values, partly.values);
  EXPECT_EQ(cached.values, uncached.values);
}

TEST(SubsurfaceStressEvaluators, DirectEqualsExplicitKernelSum)
{
  // The direct evaluator's kernel table and parity bookkeeping against a plain
  // sum of the public rectangle kernels over every cell, at a few field cells
  // (same formulas, different summation order: 1e-12 relative).
  const MixedCase m = mixed_case();
  StressField     direct;
  make_subsurface_stress(m.grid, m.depths, nu, method("direct"))->evaluate(m.p, m.qx, m.qy, direct);
  const double scale = max_abs(direct.values);
  for (const auto &cell : {std::array<int, 2>{0, 0}, std::array<int, 2>{36, 21}, std::array<int, 2>{17, 5}})
    for (std::size_t k = 0; k < m.depths.size(); ++k)
      {
        Stress sum{};
        for (int j = 0; j < m.grid.ny; ++j)
          for (int i = 0; i < m.grid.nx; ++i)
            {
              const RectangleStresses kernel =
                rectangle_stresses(m.grid.x(cell[0]) - m.grid.x(i), m.grid.y(cell[1]) - m.grid.y(j), m.depths[k],
                                   m.grid.hx / 2, m.grid.hy / 2, nu);
              const std::size_t l = m.grid.index(i, j);
              for (int c = 0; c < 6; ++c)
                sum[c] += kernel.pressure[c] * m.p[l] + kernel.shear_x[c] * m.qx[l] + kernel.shear_y[c] * m.qy[l];
            }
        for (int c = 0; c < 6; ++c)
          EXPECT_NEAR(direct.at(static_cast<int>(k), c, cell[1], cell[0]) / scale, sum[c] / scale, 1e-12)
            << "cell (" << cell[0] << ", " << cell[1] << ") layer " << k << " component " << c;
      }
}

TEST(SubsurfaceStressEvaluators, RepeatedCallsReuseState)
{
  // The FFT evaluator keeps plans, kernel spectra and buffers across calls: a
  // second call with other loads must equal a fresh evaluator (bitwise, same
  // arithmetic), and a zero load must give exactly zero.
  const MixedCase m    = mixed_case();
  const auto      warm = make_subsurface_stress(m.grid, m.depths, nu, method("fft"));
  StressField     first, second, fresh, none;
  warm->evaluate(m.p, m.qx, m.qy, first);
  warm->evaluate(m.qy, m.p, m.qx, second);
  make_subsurface_stress(m.grid, m.depths, nu, method("fft"))->evaluate(m.qy, m.p, m.qx, fresh);
  EXPECT_EQ(second.values, fresh.values);
  const Field zero = m.grid.zeros();
  warm->evaluate(zero, zero, zero, none);
  EXPECT_EQ(max_abs(none.values), 0.0);
  EXPECT_EQ(warm->name(), "fft");
}

TEST(SubsurfaceStressEvaluators, BadSettingsThrow)
{
  const MixedCase m = mixed_case();
  auto throws_with = [&](const SurfaceGrid &grid, const std::vector<double> &depths, double poisson,
                         const StressEvaluatorSettings &settings, const std::string &fragment) {
    try
      {
        make_subsurface_stress(grid, depths, poisson, settings);
        ADD_FAILURE() << "no exception, expected one mentioning '" << fragment << "'";
      }
    catch (const std::invalid_argument &e)
      {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
      }
  };
  throws_with(m.grid, m.depths, nu, method("spectral"), "unknown stress evaluator 'spectral'");
  throws_with(m.grid, {}, nu, method("fft"), "no depth layers");
  throws_with(m.grid, {0.0, -1e-6}, nu, method("direct"), "depth layer 1");
  throws_with(m.grid, {std::nan("")}, nu, method("fft"), "depths must be finite");
  throws_with(m.grid, m.depths, 0.7, method("fft"), "Poisson");
  SurfaceGrid empty = m.grid;
  empty.nx          = 0;
  throws_with(empty, m.depths, nu, method("direct"), "nx, ny >= 1");
  StressEvaluatorSettings mlmi = method("mlmi");
  mlmi.mlmi_levels             = -1;
  throws_with(m.grid, m.depths, nu, mlmi, "MLMI");
  // A load that does not match the grid.
  const auto  evaluator = make_subsurface_stress(m.grid, m.depths, nu, method("fft"));
  StressField stress;
  EXPECT_THROW(evaluator->evaluate(Field(3, 0.0), m.qx, m.qy, stress), std::invalid_argument);
  EXPECT_THROW(make_subsurface_stress(m.grid, m.depths, nu, method("direct"))->evaluate(m.p, m.qx, Field(), stress),
               std::invalid_argument);
}
