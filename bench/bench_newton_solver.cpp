// The co-simulation's solver for Newton's matrix (coupling/newton_solver.h)
// with parts of the Jacobian kept at the iterate: one Newton iteration's
// share, the low-rank update for a new evaluation (M⁻¹ R, its solve through
// the set-up LU, the capacitance) and one solve.
//   BM_NewtonSolve/n/terms  n coordinates (160 the paper's ring, 300 with
//                           its flexible housing); terms 0 (the matrix as set
//                           up), 10 (five loaded balls at two states), 64
//                           (32 bristle cells, two terms each).
// Compare within one run: the update's cost against an evaluation of the
// contact forces (bench_interface_coupling).
#include "../src/coupling/newton_solver.h"

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <benchmark/benchmark.h>

#include <Eigen/Dense>

#include <random>

using namespace fretsim::coupling;

namespace
{
  void BM_NewtonSolve(benchmark::State &state)
  {
    const auto             n = static_cast<Eigen::Index>(state.range(0));
    const auto             terms = static_cast<std::size_t>(state.range(1));
    std::mt19937           generator(3);
    std::normal_distribution<double> normal;
    Eigen::MatrixXd        random(n, n);
    for (double &value : random.reshaped())
      value = normal(generator);
    const Eigen::MatrixXd mass = Eigen::MatrixXd::Identity(n, n) + 0.01 * random * random.transpose();
    const Eigen::LLT<Eigen::MatrixXd> factor(mass);
    Eigen::MatrixXd                   jacobian = Eigen::MatrixXd::Zero(2 * n, 2 * n);
    jacobian.topRightCorner(n, n).setIdentity();
    jacobian.bottomLeftCorner(n, n) = -1e8 * (Eigen::MatrixXd::Identity(n, n) + 0.01 * random * random.transpose());
    const double gamma = 2e-5;

    StiffnessChange fixed;
    for (std::size_t i = 0; i < terms; ++i)
      {
        for (Eigen::Index k = 0; k < n; ++k)
          {
            fixed.rows.push_back(normal(generator));
            fixed.by_position.push_back(1e7 * normal(generator));
          }
        fixed.by_velocity.push_back(i % 2 == 0 ? 10.0 : 0.0);
        ++fixed.terms;
      }
    std::size_t   evaluations = 0;
    NewtonUpdates updates;
    if (terms > 0)
      updates = {&factor, [&evaluations] { return evaluations; }, [&fixed](StiffnessChange &change) { change = fixed; }};

    SUNContext context = nullptr;
    SUNContext_Create(nullptr, &context);
    SUNMatrix A = SUNDenseMatrix(2 * n, 2 * n, context);
    Eigen::Map<Eigen::MatrixXd>(SM_DATA_D(A), 2 * n, 2 * n) =
      Eigen::MatrixXd::Identity(2 * n, 2 * n) - gamma * jacobian;
    SUNLinearSolver solver = make_newton_solver(context, updates);
    SUNLinSolSetup(solver, A);
    N_Vector x = N_VNew_Serial(2 * n, context), b = N_VNew_Serial(2 * n, context);
    N_VConst(1.0, b);
    for (auto _ : state)
      {
        ++evaluations; // a new evaluation: the update is formed again
        SUNLinSolSolve(solver, A, x, b, 0.0);
        benchmark::DoNotOptimize(N_VGetArrayPointer(x));
      }
    N_VDestroy(x);
    N_VDestroy(b);
    SUNLinSolFree(solver);
    SUNMatDestroy(A);
    SUNContext_Free(&context);
  }
} // namespace

BENCHMARK(BM_NewtonSolve)->ArgsProduct({{160, 300}, {0, 10, 64}})->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
