// MLMI against direct summation and DC-FFT: the Boussinesq deflection of a
// Hertz pressure (64^2 .. 512^2) and the subsurface stresses of sliding Hertz
// contact on 8 depth layers (64^2 .. 256^2; direct only up to 128^2).
// Each MLMI/FFT run reports its error against the DC-FFT result (exact to
// round-off against direct summation, docs/references.md §6.3) as a counter.
//
//   OMP_NUM_THREADS=1 ./bench/bench_mlmi   single thread
//   ./bench/bench_mlmi                     both cores
// (the deflection MLMI cases also take the thread count as an argument).
//
// Measured on the 2-core machine, idle, single thread (ms per evaluation):
//   deflection  n:     64     128     256     512
//     direct         9.66    154    2462   42273
//     DC-FFT         0.074   0.36   1.35    11.2
//     MLMI p=6       0.26    0.74   2.39    8.27   (error 6e-6 .. 1.7e-5 of max|w|)
//   stresses, 8 layers, p + mu p (mu = 0.5):
//     direct         422    5039     -
//     DC-FFT         1.20    6.33   26.9
//     MLMI p=6       22.5    59.8   137      (error 8e-5 .. 1.5e-4 p0)
// Two threads: MLMI stresses 137 -> 68 ms at 256^2 (x2.0, over outputs);
// MLMI deflection 2.39 -> 1.84 ms (x1.3, over rows of one kernel).
#include <fretsim/contact/convolution.h>
#include <fretsim/contact/hertz.h>
#include <fretsim/contact/multilevel_summation.h>
#include <fretsim/contact/subsurface_stress.h>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <vector>

using namespace fretsim::contact;

namespace
{
  // Paper case (docs/references.md §1.2): R = 50 mm, P = 1250 N, steel on steel.
  const double sphere_radius = 0.05, load = 1250.0, poisson = 0.3;
  const double contact_modulus = 200e9 / (2.0 * (1.0 - poisson * poisson));
  const double friction        = 0.5; // full-slip shear q_x = mu p

  HertzCircular hertz() { return HertzCircular::solve(load, sphere_radius, contact_modulus); }

  SurfaceGrid paper_grid(int n)
  {
    const double a = hertz().contact_radius;
    return SurfaceGrid::centred(n, n, 1.5 * a, 1.5 * a);
  }

  Field hertz_pressure(const SurfaceGrid &grid)
  {
    const auto h = hertz();
    Field      p(grid.size());
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        p[grid.index(i, j)] = h.pressure(grid.x(i), grid.y(j));
    return p;
  }

  InfluenceFunction love_kernel(const SurfaceGrid &grid)
  {
    const double hx = grid.hx, hy = grid.hy;
    return [hx, hy](int di, int dj) { return influence::normal_displacement(di * hx, dj * hy, hx, hy, contact_modulus); };
  }

  /// 8 layers from the surface to below the subsurface maximum.
  std::vector<double> eight_layers()
  {
    const double a = hertz().contact_radius;
    std::vector<double> z;
    for (const double f : {0.0, 0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1.0})
      z.push_back(f * a);
    return z;
  }

  double relative_max_error(const std::vector<double> &a, const std::vector<double> &b, double scale)
  {
    double e = 0.0;
    for (std::size_t c = 0; c < a.size(); ++c)
      e = std::max(e, std::fabs(a[c] - b[c]));
    return e / scale;
  }

  /// Reference deflection (DC-FFT) per grid size, computed once.
  const Field &reference_deflection(int n)
  {
    static std::map<int, Field> cache;
    auto                        it = cache.find(n);
    if (it == cache.end())
      {
        const auto grid = paper_grid(n);
        Field      w;
        SurfaceConvolution(grid, love_kernel(grid)).apply(hertz_pressure(grid), w);
        it = cache.emplace(n, std::move(w)).first;
      }
    return it->second;
  }

  double max_abs(const Field &f)
  {
    double m = 0.0;
    for (const double v : f)
      m = std::max(m, std::fabs(v));
    return m;
  }

  void BM_DeflectionDirect(benchmark::State &state)
  {
    const auto  grid = paper_grid(static_cast<int>(state.range(0)));
    const SurfaceConvolution convolution(grid, love_kernel(grid));
    const Field p = hertz_pressure(grid);
    Field       w;
    for (auto _ : state)
      {
        convolution.apply_direct(p, w);
        benchmark::DoNotOptimize(w.data());
      }
  }

  void BM_DeflectionFft(benchmark::State &state)
  {
    const auto  grid = paper_grid(static_cast<int>(state.range(0)));
    const SurfaceConvolution convolution(grid, love_kernel(grid));
    const Field p = hertz_pressure(grid);
    Field       w;
    for (auto _ : state)
      {
        convolution.apply(p, w);
        benchmark::DoNotOptimize(w.data());
      }
  }

  /// Args: n, threads, interpolation order.
  void BM_DeflectionMlmi(benchmark::State &state)
  {
    const int          n = static_cast<int>(state.range(0));
    const auto         grid = paper_grid(n);
    MultilevelSettings settings;
    settings.threads             = static_cast<int>(state.range(1));
    settings.interpolation_order = static_cast<int>(state.range(2));
    const auto start = std::chrono::steady_clock::now();
    const MultilevelSummation mlmi(grid, love_kernel(grid), settings);
    const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const Field p = hertz_pressure(grid);
    Field       w;
    for (auto _ : state)
      {
        mlmi.apply(p, w);
        benchmark::DoNotOptimize(w.data());
      }
    const Field &reference   = reference_deflection(n);
    state.counters["error"]  = relative_max_error(w, reference, max_abs(reference));
    state.counters["levels"] = mlmi.levels();
    state.counters["setup_s"] = setup;
  }

  struct StressCase
  {
    SurfaceGrid         grid;
    std::vector<double> depths;
    Field               p, qx, qy;
    double              p0;
  };

  StressCase stress_case(int n)
  {
    StressCase c;
    c.grid   = paper_grid(n);
    c.depths = eight_layers();
    c.p      = hertz_pressure(c.grid);
    c.qx     = c.p;
    for (double &v : c.qx)
      v *= friction;
    c.qy = c.grid.zeros();
    c.p0 = hertz().peak_pressure;
    return c;
  }

  const StressField &reference_stress(int n)
  {
    static std::map<int, StressField> cache;
    auto                              it = cache.find(n);
    if (it == cache.end())
      {
        const StressCase        c = stress_case(n);
        StressEvaluatorSettings settings;
        settings.method = "fft";
        StressField s;
        make_subsurface_stress(c.grid, c.depths, poisson, settings)->evaluate(c.p, c.qx, c.qy, s);
        it = cache.emplace(n, std::move(s)).first;
      }
    return it->second;
  }

  void stress_benchmark(benchmark::State &state, const char *method)
  {
    const int               n = static_cast<int>(state.range(0));
    const StressCase        c = stress_case(n);
    StressEvaluatorSettings settings;
    settings.method  = method;
    const auto start = std::chrono::steady_clock::now();
    const auto evaluator = make_subsurface_stress(c.grid, c.depths, poisson, settings);
    const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    StressField s;
    for (auto _ : state)
      {
        evaluator->evaluate(c.p, c.qx, c.qy, s);
        benchmark::DoNotOptimize(s.values.data());
      }
    state.counters["setup_s"] = setup;
    if (std::string(method) != "fft")
      state.counters["error_p0"] = relative_max_error(s.values, reference_stress(n).values, c.p0);
  }

  void BM_StressDirect(benchmark::State &state) { stress_benchmark(state, "direct"); }
  void BM_StressFft(benchmark::State &state) { stress_benchmark(state, "fft"); }
  void BM_StressMlmi(benchmark::State &state) { stress_benchmark(state, "mlmi"); }
} // namespace

BENCHMARK(BM_DeflectionDirect)->Arg(64)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DeflectionDirect)->Arg(512)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DeflectionFft)->Arg(64)->Arg(128)->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DeflectionMlmi)
  ->ArgsProduct({{64, 128, 256, 512}, {1, 2}, {6}})
  ->ArgNames({"n", "threads", "order"})
  ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DeflectionMlmi)
  ->ArgsProduct({{256}, {1}, {4, 8}})
  ->ArgNames({"n", "threads", "order"})
  ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StressDirect)->Arg(64)->Arg(128)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StressFft)->Arg(64)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StressMlmi)->Arg(64)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
