// Subsurface-stress evaluators: run time per call (loads -> sigma on the depth
// layers) for grids 32^2 .. 512^2 and 1/4/8 layers, single thread and both
// cores. Sliding Hertz loads (p, qx = 0.3 p, qy = 0.1 p: all three nonzero, so
// no evaluator can skip a load). Counters: construction time, error against
// direct summation (max over the field / p0, where direct is affordable) and
// resident memory added by the evaluator.
//
//   ./bench/bench_stresses --benchmark_filter='fft/256/8'
#include <fretsim/contact/subsurface_stress.h>

#include <benchmark/benchmark.h>
#include <omp.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <tuple>

using namespace fretsim::contact;

namespace
{
  const double nu = 0.3, a = 752.8e-6, p0 = 1053.2e6; // paper case, docs/references.md §1.2

  struct Case
  {
    SurfaceGrid         grid;
    std::vector<double> depths;
    Field               p, qx, qy;
  };

  Case make_case(int n, int layers)
  {
    Case c;
    c.grid.nx = c.grid.ny = n;
    c.grid.hx = c.grid.hy = 3 * a / n;
    c.grid.x_min = c.grid.y_min = -1.5 * a;
    for (int k = 0; k < layers; ++k)
      c.depths.push_back(layers == 1 ? 0.0 : k * 0.6 * a / (layers - 1)); // 0 .. 0.6a, through the Hertz maximum
    c.p = c.qx = c.qy = c.grid.zeros();
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        {
          const double rr = (c.grid.x(i) * c.grid.x(i) + c.grid.y(j) * c.grid.y(j)) / (a * a);
          const double p  = rr < 1 ? p0 * std::sqrt(1 - rr) : 0.0;
          c.p[c.grid.index(i, j)]  = p;
          c.qx[c.grid.index(i, j)] = 0.3 * p;
          c.qy[c.grid.index(i, j)] = 0.1 * p;
        }
    return c;
  }

  double resident_megabytes()
  {
    long  pages = 0, resident = 0;
    FILE *f = std::fopen("/proc/self/statm", "r");
    if (f)
      {
        if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2)
          resident = 0;
        std::fclose(f);
      }
    return resident * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1 << 20);
  }

  /// Direct-summation results, computed once per (n, layers) with both cores.
  const StressField *direct_reference(int n, int layers)
  {
    static std::map<std::pair<int, int>, std::unique_ptr<StressField>> cache;
    const auto key = std::make_pair(n, layers);
    if (n > 128)
      return nullptr; // 256^2 x 8 layers takes minutes: no reference there
    if (!cache.count(key))
      {
        const Case c = make_case(n, layers);
        StressEvaluatorSettings settings;
        settings.method = "direct";
        auto field = std::make_unique<StressField>();
        make_subsurface_stress(c.grid, c.depths, nu, settings)->evaluate(c.p, c.qx, c.qy, *field);
        cache[key] = std::move(field);
      }
    return cache[key].get();
  }

  void run(benchmark::State &state, const std::string &method)
  {
    const int n = static_cast<int>(state.range(0)), layers = static_cast<int>(state.range(1));
    const int threads = static_cast<int>(state.range(2));
    const Case c = make_case(n, layers);
    StressEvaluatorSettings settings;
    settings.method = method;
    omp_set_num_threads(threads);
    const double rss_before = resident_megabytes();
    const auto   start      = std::chrono::steady_clock::now();
    std::unique_ptr<SubsurfaceStress> evaluator;
    try
      {
        evaluator = make_subsurface_stress(c.grid, c.depths, nu, settings);
      }
    catch (const std::exception &e)
      {
        state.SkipWithError(e.what());
        return;
      }
    const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    StressField  stress;
    for (auto _ : state)
      {
        evaluator->evaluate(c.p, c.qx, c.qy, stress);
        benchmark::DoNotOptimize(stress.values.data());
      }
    state.counters["setup_s"] = setup;
    state.counters["memory_MB"] = resident_megabytes() - rss_before;
    omp_set_num_threads(2);
    if (method != "direct")
      if (const StressField *reference = direct_reference(n, layers))
        {
          double error = 0;
          for (std::size_t k = 0; k < stress.values.size(); ++k)
            error = std::max(error, std::abs(stress.values[k] - reference->values[k]));
          state.counters["err_vs_direct_p0"] = error / p0;
        }
  }

  void direct(benchmark::State &state) { run(state, "direct"); }
  void fft(benchmark::State &state) { run(state, "fft"); }
  void mlmi(benchmark::State &state) { run(state, "mlmi"); }

  void sizes(benchmark::internal::Benchmark *b, int largest)
  {
    for (int n = 32; n <= largest; n *= 2)
      for (const int layers : {1, 4, 8})
        for (const int threads : {1, 2})
          b->Args({n, layers, threads});
    b->ArgNames({"n", "layers", "threads"})->Unit(benchmark::kMillisecond)->UseRealTime();
  }
} // namespace

// Direct summation up to 128^2 (8 layers: ~10 s per call on one core); at
// 256^2 one layer only (~15 s single thread).
BENCHMARK(direct)->Apply([](benchmark::internal::Benchmark *b) {
  sizes(b, 128);
  b->Args({256, 1, 1})->Args({256, 1, 2})->Iterations(1);
});
BENCHMARK(fft)->Apply([](benchmark::internal::Benchmark *b) { sizes(b, 512); });
BENCHMARK(mlmi)->Apply([](benchmark::internal::Benchmark *b) { sizes(b, 512); });

BENCHMARK_MAIN();
