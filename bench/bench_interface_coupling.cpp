// The co-simulation's housing interface transfer (coupling/ring_coupling.h)
// at the paper's size: 160 reduced coordinates, a 360 × 16 interface grid,
// the upper half of the ring pressed into the housing (half the cells loaded:
// more than the patches under the balls in the bearing_housing scene, so an
// upper bound for the Jacobian):
//   BM_InterfaceForces/0  one right-hand side (tractions and their generalised
//                         force), what ARKODE calls most;
//   BM_InterfaceForces/1  the same with ∂f/∂q and ∂f/∂q̇ (a Newton setup);
//   BM_InterfaceAccept    the bristle update after an accepted step;
//   BM_InterfaceDerivative/0  one product (∂f/∂q) dq + (∂f/∂q̇) dv at the last
//                         evaluation (Newton-Krylov's J v), the layer alone;
//   BM_InterfaceDerivative/1  the same with a residual flexibility (Love's
//                         half-space as its table) and the layer's closure:
//                         the pressure's coupling solved too.
//   BM_LoopDispatch/0  0.2 ms of one thread's work, the others' reference;
//   BM_LoopDispatch/1  the same, then an empty OpenMP region of two threads
//                      (under OMP_WAIT_POLICY=passive its start wakes a
//                      sleeping thread);
//   BM_LoopDispatch/2  the same through coupling::ThreadTeam, whose worker
//                      spins for the next task: what the interface's loops
//                      pay to start on two threads.
// Counter: loaded cells. Compare variants within one run (noisy machines).
#include <fretsim/coupling/ring_coupling.h>

#include "../src/coupling/thread_team.h"

#include <fretsim/contact/convolution.h>

#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>
#include <vector>

using namespace fretsim;
using namespace fretsim::coupling;

namespace
{
  constexpr std::size_t coordinates = 160;

  /// A ring whose first two coordinates are the rigid translations (so that
  /// q_y > 0 presses the upper half into the housing) and whose others are
  /// random shapes of unit amplitude.
  ReducedRing paper_sized_ring()
  {
    const double radius = 0.04, width = 0.018;
    const int    around = 360, across = 16;
    ReducedRing  ring;
    ring.n = coordinates;
    ring.mass.assign(coordinates * coordinates, 0.0);
    ring.stiffness.assign(coordinates * coordinates, 0.0);
    for (std::size_t j = 0; j < coordinates; ++j)
      {
        ring.mass[j * coordinates + j]      = 0.2;
        ring.stiffness[j * coordinates + j] = j < 6 ? 0.0 : 1e9 * j;
      }
    ring.lowest_elastic_frequency_hz = 1000.0;
    ring.interface_radius            = radius;
    ring.interface_grid.nx           = around;
    ring.interface_grid.ny           = across;
    ring.interface_grid.hx           = 2.0 * M_PI * radius / around;
    ring.interface_grid.hy           = width / across;
    ring.interface_grid.y_min        = -0.5 * width;
    std::mt19937                           generator(7);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    ring.interface_displacement.resize(ring.interface_grid.size() * 3 * coordinates);
    for (int j = 0; j < across; ++j)
      for (int i = 0; i < around; ++i)
        {
          const double theta = ring.interface_grid.x(i) / radius;
          double *rows = &ring.interface_displacement[ring.interface_grid.index(i, j) * 3 * coordinates];
          for (std::size_t k = 0; k < 3 * coordinates; ++k)
            rows[k] = uniform(generator);
          rows[0] = std::cos(theta), rows[1] = std::sin(theta);
          rows[coordinates] = -std::sin(theta), rows[coordinates + 1] = std::cos(theta);
        }
    ring.raceway_angles = 8;
    ring.raceway_approach.assign(8 * coordinates, 0.0);
    return ring;
  }

  struct Setup
  {
    ReducedRing         ring = paper_sized_ring();
    InterfaceSettings   settings;
    std::vector<double> q, v, force, by_position, by_velocity;

    Setup()
      : q(coordinates, 0.0), v(coordinates, 0.0), force(coordinates), by_position(coordinates * coordinates),
        by_velocity(coordinates * coordinates)
    {
      settings.normal_stiffness = settings.tangential_stiffness = 1e15;
      settings.normal_damping_time                              = 1e-6;
      std::mt19937                           generator(3);
      std::uniform_real_distribution<double> uniform(-1.0, 1.0);
      for (std::size_t j = 2; j < coordinates; ++j)
        q[j] = 1e-10 * uniform(generator), v[j] = 1e-5 * uniform(generator);
      q[1] = 1e-7; // 0.1 µm up: the upper half loaded, up to ~100 MPa
    }
  };

  /// Argument 0: the tractions' generalised force alone; 1: with ∂f/∂q and ∂f/∂q̇.
  void BM_InterfaceForces(benchmark::State &state)
  {
    Setup            s;
    InterfaceContact contact(s.ring, s.settings);
    contact.accept(s.q.data(), s.v.data());
    const bool jacobian = state.range(0) != 0;
    for (auto _ : state)
      {
        if (jacobian)
          {
            std::fill(s.by_position.begin(), s.by_position.end(), 0.0);
            std::fill(s.by_velocity.begin(), s.by_velocity.end(), 0.0);
          }
        contact.add_forces(s.q.data(), s.v.data(),
                           {s.force.data(), jacobian ? s.by_position.data() : nullptr,
                            jacobian ? s.by_velocity.data() : nullptr});
        benchmark::DoNotOptimize(s.force.data());
        benchmark::DoNotOptimize(s.by_position.data());
      }
    state.counters["loaded_cells"] = contact.contact_fraction() * s.ring.interface_grid.size();
  }
  BENCHMARK(BM_InterfaceForces)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

  void BM_InterfaceAccept(benchmark::State &state)
  {
    Setup            s;
    InterfaceContact contact(s.ring, s.settings);
    for (auto _ : state)
      contact.accept(s.q.data(), s.v.data());
    state.counters["loaded_cells"] = contact.contact_fraction() * s.ring.interface_grid.size();
  }
  BENCHMARK(BM_InterfaceAccept)->Unit(benchmark::kMillisecond);

  void BM_InterfaceDerivative(benchmark::State &state)
  {
    Setup s;
    if (state.range(0) != 0)
      { // Love's half-space of steel on both sides as the bodies' residual flexibility
        const auto &grid = s.ring.interface_grid;
        s.ring.residual_pressure.assign(grid.size() * grid.ny, 0.0);
        for (int jj = 0; jj < grid.ny; ++jj)
          for (int j = 0; j < grid.ny; ++j)
            for (int i = 0; i < grid.nx; ++i)
              s.ring.residual_pressure[jj * grid.size() + grid.index(i, j)] = contact::influence::normal_displacement(
                (i > grid.nx / 2 ? i - grid.nx : i) * grid.hx, (j - jj) * grid.hy, grid.hx, grid.hy, 1.15e11);
        s.settings.normal_stiffness = 1e16;
        s.settings.closure_pressure = 3e7;
      }
    InterfaceContact contact(s.ring, s.settings);
    contact.keep_derivatives();
    contact.accept(s.q.data(), s.v.data());
    contact.add_forces(s.q.data(), s.v.data(), {s.force.data(), nullptr, nullptr});
    std::vector<double> out(coordinates);
    for (auto _ : state)
      {
        std::fill(out.begin(), out.end(), 0.0);
        contact.add_derivative(s.q.data(), s.v.data(), out.data());
        benchmark::DoNotOptimize(out.data());
      }
    state.counters["loaded_cells"] = contact.contact_fraction() * s.ring.interface_grid.size();
  }
  BENCHMARK(BM_InterfaceDerivative)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

  void BM_LoopDispatch(benchmark::State &state)
  {
    const auto work = [] {
      double sum = 0.0;
      for (int i = 0; i < 50000; ++i)
        benchmark::DoNotOptimize(sum += 1e-9 * i);
    };
    std::atomic<int> parts{0};
    for (auto _ : state)
      {
        work();
        if (state.range(0) == 1)
          {
#pragma omp parallel num_threads(2)
            parts.fetch_add(1);
          }
        else if (state.range(0) == 2)
          coupling::ThreadTeam::shared().run([&](const coupling::TeamPart &) { parts.fetch_add(1); });
      }
    benchmark::DoNotOptimize(parts.load());
  }
  BENCHMARK(BM_LoopDispatch)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);
} // namespace

BENCHMARK_MAIN();
