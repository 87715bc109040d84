// The co-simulation's solver for Newton's matrix keeps parts of the
// Jacobian at the iterate: the balls' share against a dense solve of I - γJ
// with J at the iterate, on a random ring where a ball comes into contact
// after the Jacobian's state; GMRES with the whole J at the iterate against
// the same solve; the bristles' change as the product it stands for.
#include <fretsim/coupling/ring_coupling.h>
#include "../../src/coupling/newton_solver.h"
#include "synthetic_rings.h"

#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <nvector/nvector_serial.h>

#include <Eigen/Dense>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

using namespace fretsim::coupling;

namespace
{
  using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

  constexpr std::size_t n = 5;

  std::vector<double> angles_at(double first)
  {
    std::vector<double> angles(9);
    for (int j = 0; j < 9; ++j)
      angles[j] = first + 2.0 * M_PI * j / 9;
    return angles;
  }

  struct BallState
  {
    RowMatrix by_position = RowMatrix::Zero(n, n), by_velocity = RowMatrix::Zero(n, n);
    int       loaded      = 0;
  };

  /// The balls' forces at inner ring displacement e_y and first ball angle,
  /// with their derivatives.
  BallState evaluate(BallContacts &balls, double e_y, double first_angle)
  {
    const double        e[2] = {2e-6, e_y}, e_rate[2] = {0.0, 1e-3};
    const auto          angles = angles_at(first_angle);
    std::vector<double> q(n, 0.0), v(n, 0.0), force(n, 0.0);
    for (std::size_t k = 0; k < n; ++k)
      {
        q[k] = 1e-6 * std::sin(1.0 + k);
        v[k] = 1e-3 * std::cos(2.0 + k);
      }
    BallState state;
    balls.add_forces(angles, 120.0, e, e_rate, q.data(), v.data(),
                     {force.data(), state.by_position.data(), state.by_velocity.data()});
    for (const double load : balls.loads())
      state.loaded += load > 0.0;
    return state;
  }

  /// A random ring's model with a mass and a stiffness coupling its
  /// coordinates, and the generator that made them (for the right-hand sides).
  struct System
  {
    ReducedRing                            ring = synthetic::random_ring(n, 8, 1, 9);
    std::mt19937                           generator{4};
    std::uniform_real_distribution<double> uniform{-1.0, 1.0};
    Eigen::MatrixXd                        mass, stiffness;
    System()
    {
      Eigen::MatrixXd coupling(n, n);
      for (double &value : coupling.reshaped())
        value = uniform(generator);
      mass      = 0.2 * Eigen::MatrixXd::Identity(n, n) + 0.01 * coupling * coupling.transpose();
      stiffness = Eigen::Map<const RowMatrix>(ring.stiffness.data(), n, n) + 2e7 * coupling * coupling.transpose();
    }
  };

  /// J = [[0, I], [M⁻¹(∂F/∂q - K), M⁻¹ ∂F/∂q̇]].
  Eigen::MatrixXd jacobian(const Eigen::MatrixXd &mass, const Eigen::MatrixXd &stiffness, const BallState &balls)
  {
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(2 * n, 2 * n);
    J.topRightCorner(n, n).setIdentity();
    J.bottomLeftCorner(n, n)  = mass.llt().solve(Eigen::MatrixXd(balls.by_position) - stiffness);
    J.bottomRightCorner(n, n) = mass.llt().solve(Eigen::MatrixXd(balls.by_velocity));
    return J;
  }

  /// The solver tests' case: Newton's matrix I - γJ set up (SUNDIALS' dense
  /// A) at one state of the balls, and the balls at another, where the cage
  /// has turned and the inner ring moved so that a ball unloaded at the
  /// set-up carries load; a random right-hand side b.
  struct TwoBallStates : System
  {
    static constexpr double           gamma = 2e-5;
    BallContacts                      balls{ring, 9, 7e9, 0.5, 10e-6};
    const BallState                   at_set_up   = evaluate(balls, 10e-6, 0.3);
    const BallContacts::Linearisation at_jacobian = balls.linearisation();
    const BallState                   now         = evaluate(balls, 40e-6, 0.45);
    Eigen::VectorXd                   b           = Eigen::VectorXd::NullaryExpr(2 * n, [this] { return uniform(generator); });
    SUNContext                        context     = nullptr;
    SUNMatrix                         A           = nullptr;
    N_Vector                          x = nullptr, rhs = nullptr;

    TwoBallStates()
    {
      if (SUNContext_Create(nullptr, &context) != 0)
        throw std::runtime_error("SUNContext_Create failed");
      A = SUNDenseMatrix(2 * n, 2 * n, context);
      Eigen::Map<Eigen::MatrixXd>(SM_DATA_D(A), 2 * n, 2 * n) = newton_matrix(at_set_up);
      x   = N_VNew_Serial(2 * n, context);
      rhs = N_VNew_Serial(2 * n, context);
    }
    ~TwoBallStates()
    {
      N_VDestroy(x);
      N_VDestroy(rhs);
      SUNMatDestroy(A);
      SUNContext_Free(&context);
    }
    TwoBallStates(const TwoBallStates &)            = delete;
    TwoBallStates &operator=(const TwoBallStates &) = delete;

    Eigen::MatrixXd newton_matrix(const BallState &state) const
    {
      return Eigen::MatrixXd::Identity(2 * n, 2 * n) - gamma * jacobian(mass, stiffness, state);
    }

    /// `solver`'s solution of A x = b after its set-up with A; frees it.
    Eigen::VectorXd solve(SUNLinearSolver solver)
    {
      EXPECT_EQ(SUNLinSolSetup(solver, A), 0);
      Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(rhs), 2 * n) = b;
      EXPECT_EQ(SUNLinSolSolve(solver, A, x, rhs, 0.0), 0);
      SUNLinSolFree(solver);
      return Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(x), 2 * n);
    }
  };
} // namespace

TEST(BallContacts, TheirLinearisationIsTheirShareOfTheJacobian)
{
  // ∂F/∂q = -Σ r (k r + cΩ s)ᵀ and ∂F/∂q̇ = -Σ c r rᵀ rebuilt from
  // linearisation() against add_forces' own derivatives, to rounding.
  const auto   ring = synthetic::random_ring(n, 8, 1, 9);
  BallContacts balls(ring, 9, 7e9, 0.5, 10e-6);
  const auto   state = evaluate(balls, 40e-6, 0.3);
  ASSERT_GT(state.loaded, 1);
  ASSERT_LT(state.loaded, 9);
  const auto     &lin = balls.linearisation();
  RowMatrix       by_position = RowMatrix::Zero(n, n), by_velocity = RowMatrix::Zero(n, n);
  for (std::size_t j = 0; j < 9; ++j)
    {
      const Eigen::Map<const Eigen::VectorXd> r(lin.rows.data() + j * n, n), s(lin.slopes.data() + j * n, n);
      by_position -= r * (lin.by_deflection[j] * r + lin.by_deflection_rate[j] * lin.cage_speed * s).transpose();
      by_velocity -= lin.by_deflection_rate[j] * r * r.transpose();
    }
  EXPECT_LT((by_position - state.by_position).norm(), 1e-12 * state.by_position.norm());
  EXPECT_LT((by_velocity - state.by_velocity).norm(), 1e-12 * state.by_velocity.norm());
}

TEST(NewtonSolver, KeepsTheBallsShareOfNewtonsMatrixAtTheIterate)
{
  // Newton's matrix set up at one state of the balls, solved at another
  // where the cage has turned and the inner ring moved, so that a ball
  // unloaded at the set-up carries load: the solve must be that of
  // I - γJ with J at the new state (measured 3e-16; bound 1e-10), and
  // differ from the set-up's own by more than 1 % (measured 7.6 %).
  TwoBallStates states;
  ASSERT_GT(states.now.loaded, states.at_set_up.loaded);
  const Eigen::LLT<Eigen::MatrixXd> factor(states.mass);
  const NewtonUpdates               at_the_iterate{&factor, [] { return std::size_t(1); },
                                     [&](StiffnessChange &change) {
                                       add_ball_change(states.balls.linearisation(), states.at_jacobian, n, change);
                                     }};
  const Eigen::VectorXd updated   = states.solve(make_newton_solver(states.context, at_the_iterate));
  const Eigen::VectorXd as_set_up = states.solve(make_newton_solver(states.context, {}));
  const Eigen::VectorXd exact     = states.newton_matrix(states.now).partialPivLu().solve(states.b);
  EXPECT_LT((updated - exact).norm(), 1e-10 * exact.norm());
  EXPECT_LT((as_set_up - states.newton_matrix(states.at_set_up).partialPivLu().solve(states.b)).norm(),
            1e-10 * exact.norm());
  EXPECT_GT((as_set_up - exact).norm(), 1e-2 * exact.norm());
  std::printf("updated %.2e, as set up %.2e off the solve at the iterate\n", (updated - exact).norm() / exact.norm(),
              (as_set_up - exact).norm() / exact.norm());
}

TEST(NewtonSolver, GmresSolvesNewtonsSystemWithTheJacobianAtTheIterate)
{
  // The same two ball states: Newton's matrix set up at the first, J v
  // given at the second. GMRES, preconditioned by the set-up matrix, must
  // give the dense solve at the second (at a tolerance of 1e-12 within 2n
  // iterations, the whole Krylov space; measured 9e-16 in 8), and stop
  // early at a loose one with an error to match (1e-2: 2 iterations, 4e-4).
  TwoBallStates states;
  ASSERT_GT(states.now.loaded, states.at_set_up.loaded);
  const Eigen::MatrixXd J_now = jacobian(states.mass, states.stiffness, states.now);
  const Eigen::VectorXd exact = states.newton_matrix(states.now).partialPivLu().solve(states.b);
  const auto            solve = [&](double tolerance, long &iterations) {
    SUNLinearSolver  solver = make_newton_solver(states.context, {});
    JacobianProducts products;
    products.times = [&](double, const double *, const double *v, double *out) {
      Eigen::Map<Eigen::VectorXd>(out, 2 * n) = J_now * Eigen::Map<const Eigen::VectorXd>(v, 2 * n);
    };
    products.tolerance  = tolerance;
    products.iterations = &iterations;
    set_krylov(solver, nullptr, products);
    return states.solve(solver);
  };
  long         tight_iterations = 0, loose_iterations = 0;
  const double scale = exact.norm() / std::sqrt(2.0 * n); // the RMS norm's
  const auto   tight = solve(1e-12, tight_iterations), loose = solve(1e-2 * scale, loose_iterations);
  const double tight_error = (tight - exact).norm() / exact.norm(), loose_error = (loose - exact).norm() / exact.norm();
  std::printf("GMRES: %ld iterations, %.2e off the solve at the iterate; loose: %ld, %.2e\n", tight_iterations,
              tight_error, loose_iterations, loose_error);
  EXPECT_LT(tight_error, 1e-10);
  EXPECT_LE(tight_iterations, static_cast<long>(2 * n));
  EXPECT_LT(loose_iterations, tight_iterations);
  EXPECT_LT(loose_error, 1e-2);
}

TEST(NewtonSolver, TheBristlesChangeIsTheirRowsAroundTheirStiffnessChange)
{
  // Two cells' tangential rows T (2 × n) and A ΔS (2 × 2, not symmetric):
  // the terms must make ∂F/∂q change by -Σ Tᵀ (A ΔS) T, to rounding.
  std::mt19937                           generator(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double>                    rows(2 * 2 * n), changes(2 * 4);
  for (double &value : rows)
    value = uniform(generator);
  for (double &value : changes)
    value = 1e8 * uniform(generator);
  StiffnessChange change;
  add_slip_change(rows, changes, n, change);
  ASSERT_EQ(change.terms, 4u);
  Eigen::MatrixXd from_terms = Eigen::MatrixXd::Zero(n, n), expected = Eigen::MatrixXd::Zero(n, n);
  for (std::size_t i = 0; i < change.terms; ++i)
    {
      EXPECT_EQ(change.by_velocity[i], 0.0);
      from_terms -= Eigen::Map<const Eigen::VectorXd>(change.rows.data() + i * n, n) *
                    Eigen::Map<const Eigen::VectorXd>(change.by_position.data() + i * n, n).transpose();
    }
  for (std::size_t cell = 0; cell < 2; ++cell)
    {
      const Eigen::Map<const Eigen::Matrix<double, 2, Eigen::Dynamic, Eigen::RowMajor>> T(rows.data() + 2 * cell * n,
                                                                                            2, n);
      const Eigen::Map<const Eigen::Matrix<double, 2, 2, Eigen::RowMajor>> A(changes.data() + 4 * cell);
      expected -= T.transpose() * A * T;
    }
  EXPECT_LT((from_terms - expected).norm(), 1e-12 * expected.norm());
}
