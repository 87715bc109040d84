// Love's rectangle influence coefficient and the DC-FFT convolution against
// docs/references.md §4.1 and §6.2-6.3.
#include <fretsim/contact/convolution.h>
#include <fretsim/contact/hertz.h>

#include <gtest/gtest.h>
#include <omp.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <random>
#include <thread>
#include <vector>

using namespace fretsim::contact;

namespace
{
  double max_abs(const Field &field)
  {
    double m = 0.0;
    for (const double v : field)
      m = std::max(m, std::abs(v));
    return m;
  }

  double max_abs_difference(const Field &a, const Field &b)
  {
    double m = 0.0;
    for (std::size_t c = 0; c < a.size(); ++c)
      m = std::max(m, std::abs(a[c] - b[c]));
    return m;
  }

  /// Smooth, nowhere symmetric kernel: any mix-up of di/dj, of their signs or
  /// of the wrap-around order changes the result at O(1).
  double asymmetric_kernel(int di, int dj)
  {
    return 1.0 / (1.0 + (di - 0.3) * (di - 0.3) + 2.0 * (dj + 0.7) * (dj + 0.7)) + 0.01 * di - 0.02 * dj +
           0.001 * di * dj;
  }

  /// Love's kernel (E' = 1.1e11 Pa) on a grid closed in x: the nearest image acts.
  InfluenceFunction love_around(const SurfaceGrid &ring)
  {
    return [ring](int di, int dj) {
      di = ((di % ring.nx) + ring.nx) % ring.nx;
      if (di > ring.nx / 2)
        di -= ring.nx;
      return influence::normal_displacement(di * ring.hx, dj * ring.hy, ring.hx, ring.hy, 1.1e11);
    };
  }

  Field random_field(const SurfaceGrid &grid, unsigned seed)
  {
    std::mt19937                           generator(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 2.0);
    Field                                  field(grid.size());
    for (double &v : field)
      v = uniform(generator);
    return field;
  }

  // One body with G = 1, nu = 0.3: u_z = (1 - nu)/(2 pi G) [F1] (docs/references.md
  // §4.1), i.e. 1/(pi E*) with E* = 2G/(1 - nu).
  const double check_modulus = 2.0 * 1.0 / (1.0 - 0.3);
} // namespace

TEST(SurfaceGrid, CentredGridAndIntegral)
{
  const auto grid = SurfaceGrid::centred(4, 2, 2.0, 0.5);
  EXPECT_DOUBLE_EQ(grid.hx, 1.0);
  EXPECT_DOUBLE_EQ(grid.hy, 0.5);
  EXPECT_DOUBLE_EQ(grid.x(0), -1.5);
  EXPECT_DOUBLE_EQ(grid.x(3), 1.5);
  EXPECT_DOUBLE_EQ(grid.y(0), -0.25);
  EXPECT_DOUBLE_EQ(grid.y(1), 0.25);
  EXPECT_EQ(grid.index(3, 1), 7u);
  Field field(grid.size());
  for (std::size_t c = 0; c < field.size(); ++c)
    field[c] = static_cast<double>(c);
  EXPECT_DOUBLE_EQ(integrate(grid, field), 28.0 * 0.5); // sum 0..7 times cell area
  EXPECT_THROW(integrate(grid, Field(3)), std::invalid_argument);
  EXPECT_THROW(SurfaceGrid::centred(0, 2, 1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(SurfaceGrid::centred(2, 2, 1.0, -1.0), std::invalid_argument);
}

TEST(Influence, ReferenceCheckNumbers)
{
  // docs/references.md §4.1 table, u_z(p) column, patch [-0.5,0.5] x [-0.3,0.3],
  // quoted to 10 digits (verified against dblquad to 1e-10).
  struct Row
  {
    double x, y, u_z;
  };
  for (const Row row : {Row{2.0, 1.0, 0.0302130593}, Row{0.7, -0.2, 0.1051774348}, Row{3.5, 2.2, 0.0162130350}})
    EXPECT_NEAR(influence::normal_displacement(row.x, row.y, 1.0, 0.6, check_modulus), row.u_z, 1e-10)
      << "(" << row.x << ", " << row.y << ")";
}

TEST(Influence, SelfInfluenceOfSquareCell)
{
  // [F1] = 4 h ln(1 + sqrt 2) at the centre of a square cell (docs/references.md
  // §4.1), to round-off, at any scale.
  for (const double h : {1e-6, 1.0, 1e3})
    {
      const double corner_sum = influence::normal_displacement(0.0, 0.0, h, h, check_modulus) * M_PI * check_modulus;
      EXPECT_NEAR(corner_sum / (4.0 * h * std::log(1.0 + std::sqrt(2.0))), 1.0, 1e-14) << "h = " << h;
    }
}

TEST(Influence, SymmetryEdgesAndFarField)
{
  const double hx = 2e-5, hy = 3e-5, modulus = 1e11;
  auto         K  = [&](double x, double y) { return influence::normal_displacement(x, y, hx, hy, modulus); };
  // Mirror symmetry of the Boussinesq kernel and the transpose symmetry of
  // the rectangle: exact up to round-off.
  for (const double x : {0.0, 0.3e-5, 1e-5, 7e-5})
    for (const double y : {0.0, 0.2e-5, 1.5e-5, 9e-5})
      {
        const double k = K(x, y);
        EXPECT_TRUE(std::isfinite(k) && k > 0.0);
        EXPECT_NEAR(K(-x, y), k, 1e-14 * k);
        EXPECT_NEAR(K(x, -y), k, 1e-14 * k);
        EXPECT_NEAR(influence::normal_displacement(y, x, hy, hx, modulus), k, 1e-14 * k);
      }
  // On the cell edges and corners a corner term has X = 0 or Y = 0, where
  // X ln(Y + rho) -> 0: the coefficient is finite and continuous there
  // (first order in the 1e-12 relative offset).
  for (const auto &point : {std::pair{0.5 * hx, 0.0}, std::pair{0.5 * hx, 0.5 * hy}, std::pair{0.0, -0.5 * hy},
                            std::pair{1.5 * hx, -0.5 * hy}})
    {
      const double on = K(point.first, point.second);
      EXPECT_TRUE(std::isfinite(on));
      EXPECT_NEAR(K(point.first * (1.0 + 1e-12), point.second * (1.0 + 1e-12)), on, 1e-9 * on);
    }
  // Far field: a point load hx*hy, u_z = hx hy/(pi E* r), up to the
  // quadrupole correction of relative order (h/r)^2 / 24 < 1e-5 at r = 100 h.
  const double r = 100.0 * hy;
  EXPECT_NEAR(K(0.6 * r, 0.8 * r) * M_PI * modulus * r / (hx * hy), 1.0, 1e-5);
}

TEST(SurfaceConvolution, DirectSumIsTheDefinition)
{
  // apply_direct is the reference for everything else: check it against the
  // definition w_i = sum_j K(i - j) u_j written out naively (round-off).
  const auto grid = SurfaceGrid::centred(9, 6, 1.0, 1.0);
  const SurfaceConvolution convolution(grid, asymmetric_kernel);
  const Field load = random_field(grid, 1);
  Field       direct;
  convolution.apply_direct(load, direct);
  for (int j = 0; j < grid.ny; ++j)
    for (int i = 0; i < grid.nx; ++i)
      {
        double sum = 0.0;
        for (int jj = 0; jj < grid.ny; ++jj)
          for (int ii = 0; ii < grid.nx; ++ii)
            sum += asymmetric_kernel(i - ii, j - jj) * load[grid.index(ii, jj)];
        EXPECT_NEAR(direct[grid.index(i, j)], sum, 1e-14 * max_abs(direct));
      }
}

TEST(SurfaceConvolution, FftEqualsDirectOnNonSquareGrid)
{
  // DC-FFT is linear convolution exactly (Liu, Wang & Liu 2000; docs/references.md
  // §6.2-6.3 found 4e-16): 1e-12 relative leaves room for FFT round-off.
  // Both evaluations, with a kernel even in nothing (complex row spectra)
  // and one even in x only, like Love's (real row spectra, the hot path of
  // the ring interface).
  using Method           = SurfaceConvolution::Method;
  const auto even_kernel = [](int di, int dj) { return asymmetric_kernel(std::abs(di), dj); };
  for (const auto &size : {std::pair{37, 20}, std::pair{20, 37}, std::pair{1, 13}, std::pair{16, 16}})
    for (const Method method : {Method::automatic, Method::two_dimensional, Method::rows_along_x})
      for (const bool even_in_x : {false, true})
        {
          const auto grid = SurfaceGrid::centred(size.first, size.second, 1.0, 1.0);
          const SurfaceConvolution convolution(grid, even_in_x ? InfluenceFunction(even_kernel) : asymmetric_kernel,
                                               false, method);
          const Field load = random_field(grid, 7);
          Field       fft, direct;
          convolution.apply(load, fft);
          convolution.apply_direct(load, direct);
          EXPECT_LT(max_abs_difference(fft, direct) / max_abs(direct), 1e-12)
            << size.first << " x " << size.second << ", method " << static_cast<int>(method) << ", even "
            << even_in_x;
        }
}

TEST(SurfaceConvolution, PeriodicInXIsTheDirectSumOverTheNearestImage)
{
  // A grid closed in x (the unrolled ring): with a periodic kernel the
  // unpadded FFT is the direct sum (which reads the same kernel), and a load
  // shifted across the seam gives the shifted result. Odd and even nx.
  for (const int nx : {37, 24})
    for (const auto method : {SurfaceConvolution::Method::two_dimensional, SurfaceConvolution::Method::rows_along_x})
    {
      const auto grid     = SurfaceGrid::centred(nx, 9, 1.0, 0.3);
      const auto periodic = [nx](int di, int dj) {
        di = ((di % nx) + nx) % nx;
        if (di > nx / 2)
          di -= nx;
        return asymmetric_kernel(di, dj);
      };
      const SurfaceConvolution convolution(grid, periodic, true, method);
      const Field              load = random_field(grid, 5);
      Field                    fft, direct, shifted_fft;
      convolution.apply(load, fft);
      convolution.apply_direct(load, direct);
      EXPECT_LT(max_abs_difference(fft, direct) / max_abs(direct), 1e-12) << nx;
      Field shifted(load.size());
      for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < nx; ++i)
          shifted[grid.index((i + 5) % nx, j)] = load[grid.index(i, j)];
      convolution.apply(shifted, shifted_fft);
      double worst = 0.0;
      for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < nx; ++i)
          worst = std::max(worst, std::abs(shifted_fft[grid.index((i + 5) % nx, j)] - fft[grid.index(i, j)]));
      EXPECT_LT(worst / max_abs(fft), 1e-12) << nx;
    }
}

TEST(SurfaceConvolution, UnitLoadInACornerReproducesTheKernel)
{
  // A unit load at one corner cell must give K(i - i0, j - j0) over the whole
  // grid, including the extreme offsets +-(n - 1): a periodic (cyclic)
  // convolution or a wrong wrap-around index would mix the far side in.
  const int  nx = 11, ny = 7;
  const auto grid = SurfaceGrid::centred(nx, ny, 1.0, 1.0);
  const SurfaceConvolution convolution(grid, asymmetric_kernel);
  for (const auto &corner : {std::pair{0, 0}, std::pair{nx - 1, ny - 1}, std::pair{nx - 1, 0}})
    {
      Field load = grid.zeros(), result;
      load[grid.index(corner.first, corner.second)] = 1.0;
      convolution.apply(load, result);
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          EXPECT_NEAR(result[grid.index(i, j)], asymmetric_kernel(i - corner.first, j - corner.second), 1e-14)
            << "cell (" << i << ", " << j << ")";
    }
}

TEST(SurfaceConvolution, PlansAreReusableMovableAndThreadSafe)
{
  const auto grid = SurfaceGrid::centred(24, 17, 1.0, 1.0);
  SurfaceConvolution original(grid, asymmetric_kernel);
  const Field load = random_field(grid, 3), other = random_field(grid, 4);
  Field       first, second, between;
  original.apply(load, first);
  original.apply(other, between);
  original.apply(load, second);
  EXPECT_EQ(first, second); // same plan, same arrays: bitwise identical

  SurfaceConvolution moved(std::move(original));
  Field              after_move;
  moved.apply(load, after_move);
  EXPECT_EQ(after_move, first);
  EXPECT_EQ(moved.grid().nx, 24);

  // Concurrent calls share one plan; a caller that finds the work arrays busy
  // uses its own. Every result must equal the serial one bitwise.
  const int                n_threads = 4, calls_per_thread = 8;
  std::vector<Field>       results(n_threads * calls_per_thread);
  std::vector<std::thread> threads;
  for (int t = 0; t < n_threads; ++t)
    threads.emplace_back([&, t] {
      for (int call = 0; call < calls_per_thread; ++call)
        moved.apply(load, results[t * calls_per_thread + call]);
    });
  for (auto &thread : threads)
    thread.join();
  for (const auto &result : results)
    EXPECT_EQ(result, first);
  EXPECT_THROW(moved.apply(Field(3), results[0]), std::invalid_argument);
}

TEST(SurfaceConvolution, RowsAlongXGiveTheSameNumbersOnOneThreadAsOnTwo)
{
  // Rows along x split the rows into two parts, one per thread on grids
  // with work enough (nx ny² >= 2^19); every row goes through the same plan
  // whatever the thread count, so a run's numbers must not depend on it
  // (bitwise). Both kernels' paths: Love's (even in x, real row spectra; a
  // ring interface, closed in x, twice the paper's grid each way) and an
  // asymmetric one (complex), with an odd row count (unequal parts). Each
  // also against the direct sum (relative 1e-12: FFT round-off).
  const auto ring = SurfaceGrid::centred(720, 32, 2.0 * M_PI * 0.04, 0.018);
  const auto love = love_around(ring);
  const auto odd = SurfaceGrid::centred(1820, 17, 1.0, 1.0);
  const std::vector<SurfaceConvolution> convolutions = [&] {
    std::vector<SurfaceConvolution> list;
    list.emplace_back(ring, love, true, SurfaceConvolution::Method::rows_along_x);
    list.emplace_back(odd, asymmetric_kernel, false, SurfaceConvolution::Method::rows_along_x);
    return list;
  }();
  const int threads = omp_get_max_threads();
  for (const auto &convolution : convolutions)
    {
      const Field load = random_field(convolution.grid(), 5);
      Field       one, two, direct;
      omp_set_num_threads(1);
      convolution.apply(load, one);
      omp_set_num_threads(2);
      convolution.apply(load, two);
      omp_set_num_threads(threads);
      EXPECT_EQ(one, two);
      convolution.apply_direct(load, direct);
      EXPECT_LE(max_abs_difference(two, direct), 1e-12 * max_abs(direct));
    }
}

TEST(SurfaceConvolution, RowPairKernelMatchesTheDenseSumOnTheClosedCircumference)
{
  // A kernel invariant along x only (the ring's residual compliance: rows
  // across the width differ) against the dense sum written out here from the
  // kernel itself, periodic in x (relative 1e-12: FFT round-off). Two paths:
  // a kernel even in x (real spectra; the ring interface's shape, 360 x 16)
  // and one that is not (complex), rows not symmetric (K(j, jj) != K(jj, j)).
  // And a translation-invariant kernel written as row pairs gives the
  // Toeplitz constructor's numbers.
  const auto even = [](int di, int j, int jj) {
    return std::exp(-0.05 * std::abs(di)) * (1.0 + 0.1 * j + 0.03 * jj * jj) / (1.0 + std::abs(j - jj));
  };
  const auto uneven = [](int di, int j, int jj) { return std::exp(-0.2 * std::abs(di + 1)) * (1.0 + j - 0.5 * jj) + 0.01 * di; };
  const auto ring = SurfaceGrid::centred(360, 16, 2.0 * M_PI * 0.04, 0.018);
  const auto odd  = SurfaceGrid::centred(24, 7, 1.0, 1.0);
  for (const auto &[grid, kernel] :
       {std::pair<SurfaceGrid, RowPairInfluenceFunction>{ring, even}, {odd, uneven}})
    {
      // K(di ± nx) = K(di): the nearest image's offset
      const auto periodic = [&, g = grid, k = kernel](int di, int j, int jj) {
        di = ((di % g.nx) + g.nx) % g.nx;
        return k(di > g.nx / 2 ? di - g.nx : di, j, jj);
      };
      const SurfaceConvolution convolution(grid, periodic);
      const Field              load = random_field(grid, 7);
      Field                    fast, direct(grid.size(), 0.0);
      convolution.apply(load, fast);
      for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i)
          for (int jj = 0; jj < grid.ny; ++jj)
            for (int ii = 0; ii < grid.nx; ++ii)
              direct[grid.index(i, j)] += periodic(i - ii, j, jj) * load[grid.index(ii, jj)];
      EXPECT_LE(max_abs_difference(fast, direct), 1e-12 * max_abs(direct));
    }
  const auto love = love_around(ring);
  const SurfaceConvolution toeplitz(ring, love, true, SurfaceConvolution::Method::rows_along_x);
  const SurfaceConvolution pairs(ring, RowPairInfluenceFunction([&](int di, int j, int jj) { return love(di, j - jj); }));
  const Field load = random_field(ring, 11);
  Field       by_offsets, by_pairs;
  toeplitz.apply(load, by_offsets);
  pairs.apply(load, by_pairs);
  EXPECT_LE(max_abs_difference(by_offsets, by_pairs), 1e-13 * max_abs(by_offsets));
}

TEST(SurfaceConvolution, HertzDisplacementDiscretisationCheck)
{
  // docs/references.md §6.3: Hertz pressure at cell centres on [-1.5a, 1.5a]^2,
  // combined u_z by the §4.1 coefficients vs Johnson's exact u_z. The table
  // is quoted to 3 digits; 0.5 % relative is half a unit of the last digit
  // at the smallest leading digit (1.26).
  struct Row
  {
    int    n;
    double max_error, centre_error;
  };
  const double modulus = 200e9 / 1.82;
  const auto   hertz   = HertzCircular::solve(1250.0, 0.05, modulus);
  const double a = hertz.contact_radius, u0 = hertz.normal_displacement(0.0, 0.0);
  for (const Row row : {Row{32, 3.54e-3, 1.26e-3}, Row{64, 8.62e-4, 1.66e-4}, Row{128, 4.71e-4, 6.79e-5}})
    {
      const auto grid = SurfaceGrid::centred(row.n, row.n, 1.5 * a, 1.5 * a);
      const SurfaceConvolution convolution(grid, [&](int di, int dj) {
        return influence::normal_displacement(di * grid.hx, dj * grid.hy, grid.hx, grid.hy, modulus);
      });
      Field pressure(grid.size()), displacement;
      for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i)
          pressure[grid.index(i, j)] = hertz.pressure(grid.x(i), grid.y(j));
      convolution.apply(pressure, displacement);
      double max_error = 0.0;
      for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i)
          max_error = std::max(max_error, std::abs(displacement[grid.index(i, j)] -
                                                   hertz.normal_displacement(grid.x(i), grid.y(j))));
      // "At centre": the cell whose lower-left corner is the origin.
      const int    c            = row.n / 2;
      const double centre_error = std::abs(displacement[grid.index(c, c)] - hertz.normal_displacement(grid.x(c), grid.y(c)));
      EXPECT_NEAR(max_error / u0 / row.max_error, 1.0, 5e-3) << "N = " << row.n;
      EXPECT_NEAR(centre_error / u0 / row.centre_error, 1.0, 5e-3) << "N = " << row.n;
      if (row.n <= 64)
        {
          Field direct;
          convolution.apply_direct(pressure, direct);
          // §6.3 last column: DC-FFT minus direct ~ 5e-16 relative.
          EXPECT_LT(max_abs_difference(displacement, direct) / max_abs(direct), 1e-13) << "N = " << row.n;
        }
    }
}

TEST(SurfaceConvolution, TheInverseOnTheClosedCircumferenceUndoesTheConvolution)
{
  // K⁻¹ (K u + s u) = u on the whole closed grid, for Love's kernel (real
  // spectra, Toeplitz rows) and a row-pair kernel that is not even in x
  // (complex spectra): relative 1e-10 (two FFT round trips through blocks
  // whose condition number is ~ max K̂ / s).
  const auto ring = SurfaceGrid::centred(90, 6, 2.0 * M_PI * 0.04, 0.018);
  const auto love = love_around(ring);
  const auto uneven = [&](int di, int j, int jj) {
    di = ((di % ring.nx) + ring.nx) % ring.nx;
    return 1e-16 * (std::exp(-0.3 * std::min(di, ring.nx - di)) * (1.0 + 0.1 * j) + 0.2 * std::sin(0.1 * di) * (j == jj));
  };
  std::vector<SurfaceConvolution> operators;
  operators.emplace_back(ring, love, true, SurfaceConvolution::Method::rows_along_x);
  operators.emplace_back(ring, RowPairInfluenceFunction(uneven));
  const double shift = 1e-17; // a layer of 1e17 Pa/m in series
  for (const auto &forward : operators)
    {
      const SurfaceConvolution inverse = forward.inverse(shift);
      const Field u = random_field(ring, 3);
      Field       ku, back;
      forward.apply(u, ku);
      for (std::size_t c = 0; c < u.size(); ++c)
        ku[c] += shift * u[c];
      inverse.apply(ku, back);
      EXPECT_LE(max_abs_difference(back, u), 1e-10 * max_abs(u));
    }
  const SurfaceConvolution open(ring, love, false);
  EXPECT_THROW(open.inverse(shift), std::logic_error);
}

TEST(SurfaceConvolution, InSinglePrecisionItMatchesTheDoublesToAFewMillionths)
{
  // The float path against the double one on the same operators: Love's
  // kernel by rows on the ring interface's closed 360 x 16 grid (real
  // spectra), a row-pair kernel not even in x (complex spectra) and Love's
  // kernel by the 2-D transform (48 x 40, open). Float's epsilon is 6e-8;
  // the transforms and the sums over the rows grow it to 1.3e-7 - 3.3e-7 of
  // the largest value (measured), bound 1e-6.
  const auto ring   = SurfaceGrid::centred(360, 16, 2.0 * M_PI * 0.04, 0.018);
  const auto odd    = SurfaceGrid::centred(24, 7, 1.0, 1.0);
  const auto square = SurfaceGrid::centred(48, 40, 1e-3, 0.8e-3);
  const auto uneven = [](int di, int j, int jj) {
    di = ((di % 24) + 24) % 24;
    return std::exp(-0.2 * std::abs(di + 1)) * (1.0 + j - 0.5 * jj) + 0.01 * di;
  };
  std::vector<SurfaceConvolution> operators;
  operators.emplace_back(ring, love_around(ring), true, SurfaceConvolution::Method::rows_along_x);
  operators.emplace_back(odd, RowPairInfluenceFunction(uneven));
  operators.emplace_back(square, InfluenceFunction([&](int di, int dj) {
                           return influence::normal_displacement(di * square.hx, dj * square.hy, square.hx, square.hy,
                                                                 1.1e11);
                         }));
  for (const auto &convolution : operators)
    {
      const auto &grid = convolution.grid();
      const Field load = random_field(grid, 5);
      Field       reference;
      convolution.apply(load, reference);
      const std::vector<float> single_load(load.begin(), load.end());
      std::vector<float>       single;
      convolution.apply(single_load, single);
      ASSERT_EQ(single.size(), grid.size());
      double worst = 0.0;
      for (std::size_t c = 0; c < grid.size(); ++c)
        worst = std::max(worst, std::abs(single[c] - reference[c]));
      std::printf("%d x %d: float against double %.2g of the largest value\n", grid.nx, grid.ny,
                  worst / max_abs(reference));
      EXPECT_LE(worst, 1e-6 * max_abs(reference)) << grid.nx << " x " << grid.ny;
      EXPECT_GT(worst, 0.0); // (it did run in float)
    }
}

TEST(SurfaceConvolution, SharedByTwoThreadsItGivesTheSameNumbersAsApply)
{
  // apply_shared on two threads against apply on one, bitwise: the ring's
  // rows (split between the threads), a row-pair kernel with complex
  // spectra on an odd row count, and the 2-D transform (applied whole by
  // part 0). Three shared applies in a row with a wait between each, as
  // the conjugate gradients call them; each thread writes its part's rows of
  // the load and reads its part's rows of the result only.
  const auto ring   = SurfaceGrid::centred(360, 16, 2.0 * M_PI * 0.04, 0.018);
  const auto odd    = SurfaceGrid::centred(24, 7, 1.0, 1.0);
  const auto square = SurfaceGrid::centred(48, 40, 1e-3, 0.8e-3);
  std::vector<SurfaceConvolution> operators;
  operators.emplace_back(ring, love_around(ring), true, SurfaceConvolution::Method::rows_along_x);
  operators.emplace_back(odd, RowPairInfluenceFunction([](int di, int j, int jj) {
                           di = ((di % 24) + 24) % 24;
                           return std::exp(-0.2 * std::abs(di + 1)) * (1.0 + j - 0.5 * jj) + 0.01 * di;
                         }));
  operators.emplace_back(square, InfluenceFunction([&](int di, int dj) {
                           return influence::normal_displacement(di * square.hx, dj * square.hy, square.hx, square.hy,
                                                                 1.1e11);
                         }));
  EXPECT_EQ(operators[0].shared_split_row(), 8);
  EXPECT_EQ(operators[2].shared_split_row(), 0);
  for (const auto &convolution : operators)
    {
      const auto       &grid = convolution.grid();
      const std::size_t split =
        static_cast<std::size_t>(convolution.shared_split_row() > 0 ? convolution.shared_split_row() : grid.ny / 2) *
        grid.nx;
      std::vector<std::vector<float>> loads, expected;
      for (unsigned seed = 0; seed < 3; ++seed)
        {
          const Field load = random_field(grid, 11 + seed);
          loads.emplace_back(load.begin(), load.end());
          expected.emplace_back();
          convolution.apply(loads.back(), expected.back());
        }
      std::vector<float> load(grid.size()), result(grid.size());
      std::vector<std::vector<float>> results(3);
      std::atomic<int>                arrived{0}, generation{0};
      const auto                      wait = [&] {
        const int now = generation.load();
        if (arrived.fetch_add(1) == 1)
          {
            arrived.store(0);
            generation.fetch_add(1);
            return;
          }
        while (generation.load() == now)
          std::this_thread::yield();
      };
      const auto part = [&](int part) {
        const std::size_t begin = part == 0 ? 0 : split, end = part == 0 ? split : grid.size();
        for (int round = 0; round < 3; ++round)
          {
            std::copy(loads[round].begin() + begin, loads[round].begin() + end, load.begin() + begin);
            convolution.apply_shared(load, result, part, wait);
            if (part == 0)
              results[round].assign(grid.size(), 0.0f);
            wait();
            std::copy(result.begin() + begin, result.begin() + end, results[round].begin() + begin);
            wait();
          }
      };
      std::thread other(part, 1);
      part(0);
      other.join();
      for (int round = 0; round < 3; ++round)
        EXPECT_EQ(results[round], expected[round]) << grid.nx << " x " << grid.ny << ", round " << round;
    }
}
