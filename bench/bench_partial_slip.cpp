// The exact partial-slip solver (partial_slip.h) on the paper §4 case
// (R = 50 mm, P = 1250 N, mu = 0.53, steel, grid +-1.5a), harmonic shift at
// the paper amplitude 2.241 um (partial slip, Q*/muP = 0.42), 40 steps a cycle:
//   BM_ShiftStep/N/t       time of one load step in the steady loop (N^2
//                          cells, tolerance 1e-t), with CG iterations and
//                          FFT products per step as counters;
//   BM_FrettingCycles/N/t  two whole cycles from rest, with the loop error
//                          against Mindlin–Deresiewicz (max |Q - Q_MD| / muP)
//                          and against a tolerance-1e-12 run of the same grid
//                          (the solver's own error), and the energy error;
//   BM_BristleStep/N, BM_ElastoplasticBristleStep/N: the fast models' step.
// Target: ~0.07 s a step at 64^2, ~0.3 s at 128^2, loop within
// 2e-4 muP.
#include <fretsim/contact/bristle.h>
#include <fretsim/contact/elastoplastic_bristle.h>
#include <fretsim/contact/fretting_loop.h>
#include <fretsim/contact/material.h>
#include <fretsim/contact/mindlin.h>
#include <fretsim/contact/partial_slip.h>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

using namespace fretsim::contact;

namespace
{
  const double       mu = 0.53, load = 1250.0, radius = 0.05, amplitude = 2.241e-6;
  const int          steps_per_cycle = 40;
  const MaterialPair steel{{200e9, 0.3}, {200e9, 0.3}};
  const double       contact_radius = std::cbrt(3.0 * load * radius / (4.0 * steel.contact_modulus()));
  const double       peak_pressure  = 3.0 * load / (2.0 * M_PI * contact_radius * contact_radius);

  struct Case
  {
    SurfaceGrid grid;
    Field       pressure;
  };

  Case hertz_case(int cells)
  {
    Case c{SurfaceGrid::centred(cells, cells, 1.5 * contact_radius, 1.5 * contact_radius), {}};
    c.pressure = c.grid.zeros();
    for (int j = 0; j < cells; ++j)
      for (int i = 0; i < cells; ++i)
        {
          const double r2 = (c.grid.x(i) * c.grid.x(i) + c.grid.y(j) * c.grid.y(j)) / (contact_radius * contact_radius);
          c.pressure[c.grid.index(i, j)] = peak_pressure * std::sqrt(std::max(0.0, 1.0 - r2));
        }
    return c;
  }

  double shift(int step) { return amplitude * std::sin(2.0 * M_PI * step / steps_per_cycle); }

  PartialSlipSettings settings_for(int tolerance_exponent)
  {
    PartialSlipSettings settings;
    settings.tolerance = std::pow(10.0, -tolerance_exponent);
    return settings;
  }

  /// Forces of two cycles from rest.
  std::vector<double> cycle_forces(const Case &c, PartialSlipSolver &solver, int &iterations, int &convolutions)
  {
    std::vector<double> forces{0.0};
    iterations = convolutions = 0;
    for (int step = 1; step <= 2 * steps_per_cycle; ++step)
      {
        const auto &result = solver.advance(c.pressure, mu, shift(step) - shift(step - 1), 0.0);
        iterations += result.iterations;
        convolutions += result.convolutions;
        forces.push_back(result.force_x);
      }
    return forces;
  }

  const std::vector<double> &tight_reference(int cells)
  {
    static std::map<int, std::vector<double>> cache;
    auto                                     found = cache.find(cells);
    if (found == cache.end())
      {
        const Case        c = hertz_case(cells);
        PartialSlipSolver solver(c.grid, steel, settings_for(12));
        int               iterations = 0, convolutions = 0;
        found = cache.emplace(cells, cycle_forces(c, solver, iterations, convolutions)).first;
      }
    return found->second;
  }

  void BM_ShiftStep(benchmark::State &state)
  {
    const int         cells = static_cast<int>(state.range(0));
    const Case        c     = hertz_case(cells);
    PartialSlipSolver solver(c.grid, steel, settings_for(static_cast<int>(state.range(1))));
    // Into the steady loop first (plans the FFTs, builds the slip zone).
    int step = 1;
    for (; step <= steps_per_cycle + steps_per_cycle / 4; ++step)
      solver.advance(c.pressure, mu, shift(step) - shift(step - 1), 0.0);
    double iterations = 0.0, convolutions = 0.0, steps = 0.0;
    for (auto _ : state)
      {
        const auto &result = solver.advance(c.pressure, mu, shift(step) - shift(step - 1), 0.0);
        ++step;
        iterations += result.iterations;
        convolutions += result.convolutions;
        steps += 1.0;
      }
    state.counters["iterations"]   = iterations / steps;
    state.counters["convolutions"] = convolutions / steps;
  }

  void BM_FrettingCycles(benchmark::State &state)
  {
    const int   cells              = static_cast<int>(state.range(0));
    const int   tolerance_exponent = static_cast<int>(state.range(1));
    const Case  c                  = hertz_case(cells);
    const auto &reference          = tight_reference(cells);
    const MindlinLoop mindlin(mu, load, contact_radius, steel.tangential_modulus());
    std::vector<double> forces;
    int                 iterations = 0, convolutions = 0;
    for (auto _ : state)
      {
        state.PauseTiming();
        PartialSlipSolver solver(c.grid, steel, settings_for(tolerance_exponent));
        solver.advance(c.pressure, mu, 0.0, 0.0); // plan the FFTs outside the timing
        state.ResumeTiming();
        forces = cycle_forces(c, solver, iterations, convolutions);
      }
    FrettingLoop loop(steps_per_cycle);
    double       solver_error = 0.0;
    for (std::size_t i = 0; i < forces.size(); ++i)
      {
        loop.add(shift(static_cast<int>(i)), forces[i]);
        solver_error = std::max(solver_error, std::abs(forces[i] - reference[i]) / (mu * load));
      }
    const auto metrics                     = loop.last_cycle(mu * load, mindlin, amplitude);
    const double steps                     = 2.0 * steps_per_cycle;
    state.counters["step_s"]               = benchmark::Counter(steps, benchmark::Counter::kIsIterationInvariantRate |
                                                                      benchmark::Counter::kInvert);
    state.counters["iterations"]           = iterations / steps;
    state.counters["convolutions"]         = convolutions / steps;
    state.counters["loop_err_vs_MD"]       = metrics.error_vs_reference;
    state.counters["loop_err_vs_tight"]    = solver_error;
    state.counters["energy_err_vs_MD"]     = metrics.dissipated_energy / mindlin.dissipated_energy(amplitude) - 1.0;
  }

  void BM_BristleStep(benchmark::State &state)
  {
    const Case      c = hertz_case(static_cast<int>(state.range(0)));
    BristleTraction bristles(c.grid, BristleTraction::mindlin_stiffness(steel.tangential_modulus(), contact_radius));
    int             step = 1;
    for (auto _ : state)
      {
        bristles.advance(c.pressure, mu, shift(step) - shift(step - 1), 0.0);
        ++step;
        benchmark::DoNotOptimize(bristles.traction_x().data());
      }
  }

  void BM_ElastoplasticBristleStep(benchmark::State &state)
  {
    const Case                   c = hertz_case(static_cast<int>(state.range(0)));
    ElastoplasticBristleTraction bristles(
      c.grid, ElastoplasticBristleTraction::mindlin_stiffness(steel.tangential_modulus(), contact_radius));
    int step = 1;
    for (auto _ : state)
      {
        bristles.advance(c.pressure, mu, shift(step) - shift(step - 1), 0.0);
        ++step;
        benchmark::DoNotOptimize(bristles.traction_x().data());
      }
  }
} // namespace

BENCHMARK(BM_ShiftStep)->Args({64, 8})->Args({128, 8})->Args({64, 6})->Args({128, 6})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FrettingCycles)
  ->Args({64, 6})
  ->Args({64, 8})
  ->Args({128, 6})
  ->Args({128, 8})
  ->Unit(benchmark::kSecond)
  ->Iterations(1);
BENCHMARK(BM_BristleStep)->Arg(64)->Arg(128)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ElastoplasticBristleStep)->Arg(64)->Arg(128)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
