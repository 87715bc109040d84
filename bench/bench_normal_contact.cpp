// DC-FFT against direct summation, and the full Polonsky-Keer normal solve,
// on the paper case (R = 50 mm, P = 1250 N, steel; grid +-1.5a).
#include <fretsim/contact/hertz.h>
#include <fretsim/contact/normal_contact.h>

#include <benchmark/benchmark.h>

#include <cmath>

using namespace fretsim::contact;

namespace
{
  const double sphere_radius = 0.05, load = 1250.0, contact_modulus = 200e9 / (2.0 * (1.0 - 0.3 * 0.3));

  SurfaceGrid paper_grid(int n)
  {
    const double a = HertzCircular::solve(load, sphere_radius, contact_modulus).contact_radius;
    return SurfaceGrid::centred(n, n, 1.5 * a, 1.5 * a);
  }

  SurfaceConvolution love_operator(const SurfaceGrid &grid)
  {
    return SurfaceConvolution(grid, [&](int di, int dj) {
      return influence::normal_displacement(di * grid.hx, dj * grid.hy, grid.hx, grid.hy, contact_modulus);
    });
  }

  Field hertz_pressure(const SurfaceGrid &grid)
  {
    const auto hertz = HertzCircular::solve(load, sphere_radius, contact_modulus);
    Field      pressure(grid.size());
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        pressure[grid.index(i, j)] = hertz.pressure(grid.x(i), grid.y(j));
    return pressure;
  }

  void BM_ConvolutionFft(benchmark::State &state)
  {
    const auto  grid        = paper_grid(static_cast<int>(state.range(0)));
    const auto  convolution = love_operator(grid);
    const Field pressure    = hertz_pressure(grid);
    Field       displacement;
    for (auto _ : state)
      {
        convolution.apply(pressure, displacement);
        benchmark::DoNotOptimize(displacement.data());
      }
    state.counters["cells"] = static_cast<double>(grid.size());
  }

  void BM_ConvolutionDirect(benchmark::State &state)
  {
    const auto  grid        = paper_grid(static_cast<int>(state.range(0)));
    const auto  convolution = love_operator(grid);
    const Field pressure    = hertz_pressure(grid);
    Field       displacement;
    for (auto _ : state)
      {
        convolution.apply_direct(pressure, displacement);
        benchmark::DoNotOptimize(displacement.data());
      }
    state.counters["cells"] = static_cast<double>(grid.size());
  }

  /// The ring interface's grid (paper scene: 360 x 16 cells over the
  /// circumference and the width, closed in x): the evaluations of the same
  /// convolution, first arg as listed below; second the axial cells (where
  /// SurfaceConvolution's automatic choice switches).
  void BM_ConvolutionRingInterface(benchmark::State &state)
  {
    const SurfaceGrid grid = SurfaceGrid::centred(360, static_cast<int>(state.range(1)), M_PI * 0.04, 0.009);
    const auto kernel = [&](int di, int dj) {
      di = ((di % grid.nx) + grid.nx) % grid.nx;
      if (di > grid.nx / 2)
        di -= grid.nx;
      return influence::normal_displacement(di * grid.hx, dj * grid.hy, grid.hx, grid.hy, contact_modulus);
    };
    // 0: 2-D FFT, 1: rows along x, 2: the same kernel as row pairs (how
    // the ring's residual flexibility joins it: ny² kernel rows); 3 and 4:
    // 1 and 2 in single precision (the interface's conjugate gradients)
    const bool               single = state.range(0) >= 3;
    const int                method = single ? static_cast<int>(state.range(0)) - 2 : static_cast<int>(state.range(0));
    const SurfaceConvolution convolution =
      method == 2
        ? SurfaceConvolution(grid, RowPairInfluenceFunction([&](int di, int j, int jj) { return kernel(di, j - jj); }))
        : SurfaceConvolution(grid, kernel, true,
                             method == 0 ? SurfaceConvolution::Method::two_dimensional
                                         : SurfaceConvolution::Method::rows_along_x);
    Field pressure(grid.size()), displacement;
    for (std::size_t c = 0; c < pressure.size(); ++c)
      pressure[c] = c % 360 < 180 ? 1e6 : 0.0;
    const std::vector<float> single_pressure(pressure.begin(), pressure.end());
    std::vector<float>       single_displacement;
    for (auto _ : state)
      {
        if (single)
          {
            convolution.apply(single_pressure, single_displacement);
            benchmark::DoNotOptimize(single_displacement.data());
          }
        else
          {
            convolution.apply(pressure, displacement);
            benchmark::DoNotOptimize(displacement.data());
          }
      }
  }

  void BM_OperatorSetup(benchmark::State &state)
  {
    const auto grid = paper_grid(static_cast<int>(state.range(0)));
    for (auto _ : state)
      benchmark::DoNotOptimize(love_operator(grid));
  }

  void BM_NormalSolve(benchmark::State &state)
  {
    const auto grid = paper_grid(static_cast<int>(state.range(0)));
    Field      initial_gap(grid.size());
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        initial_gap[grid.index(i, j)] = (grid.x(i) * grid.x(i) + grid.y(j) * grid.y(j)) / (2.0 * sphere_radius);
    const NormalContactSolver solver(grid, contact_modulus);
    int                       iterations = 0;
    for (auto _ : state)
      {
        const auto result = solver.solve(initial_gap, load);
        iterations        = result.iterations;
        benchmark::DoNotOptimize(result.pressure.data());
      }
    state.counters["cg_iterations"] = iterations;
  }
} // namespace

BENCHMARK(BM_ConvolutionFft)->RangeMultiplier(2)->Range(32, 256)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ConvolutionDirect)->RangeMultiplier(2)->Range(32, 256)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ConvolutionRingInterface)
  ->ArgsProduct({{0, 1, 2, 3, 4}, {16, 24, 32}})
  ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_OperatorSetup)->RangeMultiplier(2)->Range(64, 256)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NormalSolve)->RangeMultiplier(2)->Range(64, 256)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
