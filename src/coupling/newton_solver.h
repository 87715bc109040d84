#pragma once
// The co-simulation's linear solver for Newton's matrix (internal to the
// coupling library): a SUNDIALS direct solver of A = I - γJ on y = [q, q̇]
// by its Schur complement, with the balls' share of J kept at the iterate
// and, optionally, Broyden's secant updates between Newton's iterations.
#include <fretsim/coupling/ring_coupling.h>

#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>

#include <Eigen/Cholesky>

namespace fretsim::coupling
{
  /// What the solver reads to keep the balls' share of Newton's matrix
  /// current: the mass matrix M (factorised) and the balls' derivatives at
  /// their last evaluation and at the Jacobian's (all outliving the solver).
  struct NewtonBalls
  {
    const Eigen::LLT<Eigen::MatrixXd>  *mass        = nullptr;
    const BallContacts::Linearisation *now         = nullptr;
    const BallContacts::Linearisation *at_jacobian = nullptr;
  };

  /// Free with SUNLinSolFree. `balls` with null pointers: Newton's matrix as set up.
  SUNLinearSolver make_newton_solver(SUNContext context, const NewtonBalls &balls);

  /// Broyden's secant updates between the iterations of ARKODE's stages.
  void set_secant_updates(SUNLinearSolver solver, void *arkode);
} // namespace fretsim::coupling
