// The whole ball-on-flat fretting history (contact::FrettingRun) of the paper
// case, configs/paper_concentrated.prm: steel on steel, R = 50 mm, P = 1250 N,
// mu = 0.53, amplitude 2.241 um, the 'exact masing' traction with levels a
// quarter cycle's steps apart, FFT stresses on 5 layers, running-mean Dang Van,
// 3 cycles x 200 steps, the Hertz pressure. One iteration = construction and
// all steps. Counters: the stage times of the run [s], D_max and the contact
// edge's D_max. BM_RiskErrorEstimate: the coarser reruns the scene adds to a
// 128^2 run. BM_ContactEdge: the run with and without the contact edge's risk.
//
//   build/bench/bench_fretting_run --benchmark_repetitions=3
//
// path: 0 = FrettingCase::superposed_stresses off (a stress evaluation per
// step, then the Dang Van step over the stress field), 1 = the default (the
// stresses composed from the virgin levels', summed within the Dang Van
// pass). threads: OpenMP threads (1 measures the work whatever the load of
// the machine; the traction solve is serial either way). tol: the exact
// solver's tolerance 10^-tol (6 as the shipped file sets it, 8 the default).
#include <fretsim/contact/fretting_run.h>

#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>
#include <utility>

using namespace fretsim::contact;

namespace
{
  FrettingCase paper_case()
  {
    FrettingCase c;
    c.materials            = MaterialPair{{200e9, 0.3}, {200e9, 0.3}};
    c.radius_x             = 0.05;
    c.radius_y             = 0.05;
    c.normal_load          = 1250.0;
    c.sliding_amplitude    = 2.241e-6;
    c.sliding_direction    = 0.0;
    c.period               = 1.0;
    c.cycles               = 3;
    c.steps_per_cycle      = 200;
    c.friction_coefficient = 0.53;
    c.traction_model       = TractionModel::exact_masing;
    c.exact.tolerance      = 1e-6;
    c.exact.masing_level_spacing = c.sliding_amplitude / (0.25 * c.steps_per_cycle);
    c.numerical_pressure         = false;
    c.normal                     = {1e-10, 5000};
    c.depth_layers               = {0.0, 3.75e-5, 7.5e-5, 1.5e-4, 3.6e-4};
    c.dang_van                   = DangVanConstants::from_fatigue_limits(690e6, 428e6);
    c.residual_stress            = ResidualStressCentre::running_mean;
    return c;
  }

  void BM_FrettingRun(benchmark::State &state)
  {
    const int    cells = static_cast<int>(state.range(0));
    FrettingCase c     = paper_case();
    c.superposed_stresses = state.range(1) != 0;
    c.exact.tolerance     = std::pow(10.0, -static_cast<double>(state.range(3)));
    const int threads     = omp_get_max_threads();
    omp_set_num_threads(static_cast<int>(state.range(2)));
    const SurfaceGrid  grid = fretting_grid(c, cells, cells, 1.5);
    FrettingStageTimes times;
    RiskMaximum        worst;
    for (auto _ : state)
      {
        FrettingRun run(c, grid);
        while (!run.finished())
          run.advance();
        times = run.stage_times();
        worst = run.risk_maximum();
        benchmark::DoNotOptimize(run.risk_max().data());
      }
    omp_set_num_threads(threads);
    state.counters["normal_s"]   = times.normal_contact;
    state.counters["traction_s"] = times.traction;
    state.counters["stresses_s"] = times.stresses;
    state.counters["dang_van_s"] = times.dang_van;
    state.counters["D_max"]      = worst.value;
  }

  void BM_ContactEdge(benchmark::State &state)
  {
    FrettingCase c      = paper_case();
    c.contact_edge_risk = state.range(0) != 0;
    // Estimated FFT plans, as the shipped file: no planning in the first run.
    c.exact.measure_fft_plans            = false;
    c.stress_evaluator.measure_fft_plans = false;
    const SurfaceGrid grid = fretting_grid(c, 128, 128, 1.5);
    double            edge = 0.0;
    for (auto _ : state)
      {
        FrettingRun run(c, grid);
        while (!run.finished())
          run.advance();
        if (const auto maximum = run.edge_risk_maximum())
          edge = maximum->value;
        benchmark::DoNotOptimize(run.risk_max().data());
      }
    state.counters["D_max_edge"] = edge;
  }

  /// The concentrated scene's grid and time-step error estimate of a 128^2
  /// run, as it reruns the history: on 32^2 and 64^2, on 32^2 at half the time
  /// step, and (the traction model check) 2 cycles on 32^2 with the exact
  /// model (the exact masing side is the 32^2 run's first 2 cycles); FFTW's
  /// estimated plans for the traction, as the scene sets them.
  void BM_RiskErrorEstimate(benchmark::State &state)
  {
    FrettingCase c                 = paper_case();
    c.superposed_stresses          = state.range(0) != 0;
    c.exact.measure_fft_plans      = false;
    const int threads              = omp_get_max_threads();
    omp_set_num_threads(static_cast<int>(state.range(1)));
    FrettingCase half_step = c;
    half_step.steps_per_cycle *= 2;
    half_step.exact.masing_level_spacing /= 2.0;
    FrettingCase exact = c;
    exact.cycles         = 2;
    exact.traction_model = TractionModel::exact;
    double sum = 0.0;
    for (auto _ : state)
      for (const auto &[k, cells] : {std::pair<const FrettingCase *, int>{&c, 32}, {&c, 64}, {&half_step, 32},
                                     {&exact, 32}})
        sum += fretting_risk_maximum(*k, fretting_grid(*k, cells, cells, 1.5)).value;
    benchmark::DoNotOptimize(sum);
    omp_set_num_threads(threads);
  }
} // namespace

BENCHMARK(BM_RiskErrorEstimate)
  ->ArgNames({"path", "threads"})
  ->ArgsProduct({{0, 1}, {2, 1}})
  ->Unit(benchmark::kSecond)
  ->UseRealTime()
  ->Iterations(1);

BENCHMARK(BM_FrettingRun)
  ->ArgNames({"n", "path", "threads", "tol"})
  ->ArgsProduct({{64, 128}, {0, 1}, {2, 1}, {6, 8}})
  ->Unit(benchmark::kSecond)
  ->UseRealTime()
  ->Iterations(1);

BENCHMARK(BM_ContactEdge)->ArgNames({"edge"})->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

BENCHMARK_MAIN();
