#pragma once
// The co-simulation's linear solver for Newton's matrix (internal to the
// coupling library): a SUNDIALS direct solver of A = I - γJ on y = [q, q̇]
// by its Schur complement, with parts of J kept at the iterate (a low-rank
// change, by Woodbury's identity) and, optionally, Broyden's secant updates
// between Newton's iterations.
#include <fretsim/coupling/ring_coupling.h>

#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>

#include <Eigen/Cholesky>

#include <functional>
#include <vector>

namespace fretsim::coupling
{
  /// How the force's derivatives at the last evaluation differ from the
  /// Jacobian's, as a sum of rank-one terms: ∂F/∂q gains -Σ_i r_i g_iᵀ and
  /// ∂F/∂q̇ gains -Σ_i c_i r_i r_iᵀ.
  struct StiffnessChange
  {
    std::size_t         terms = 0;
    std::vector<double> rows, by_position; ///< r_i, g_i: [term][n]
    std::vector<double> by_velocity;       ///< c_i: [term]
    void clear()
    {
      terms = 0;
      rows.clear();
      by_position.clear();
      by_velocity.clear();
    }
  };

  /// The balls' change between two of their evaluations (`now` and the
  /// Jacobian's): each loaded ball's rows at both, the Jacobian's negated.
  void add_ball_change(const BallContacts::Linearisation &now, const BallContacts::Linearisation &at_jacobian,
                       std::size_t n, StiffnessChange &change);
  /// The bristles' (InterfaceContact::slip_stiffness_changes' rows and
  /// A ΔS_c): two terms per cell.
  void add_slip_change(const std::vector<double> &rows, const std::vector<double> &changes, std::size_t n,
                       StiffnessChange &change);

  /// What the solver reads to keep Newton's matrix at the iterate: the mass
  /// matrix M (factorised, outliving the solver), the count of evaluations
  /// so far (the change is asked again only when it moved) and the change.
  struct NewtonUpdates
  {
    const Eigen::LLT<Eigen::MatrixXd>            *mass = nullptr;
    std::function<std::size_t()>                  evaluations;
    std::function<void(StiffnessChange &change)> change;
  };

  /// What GMRES reads to solve (I - γJ) x = b with J at the iterate.
  struct JacobianProducts
  {
    /// out = J v at (t, y), y the stage's iterate [q, q̇] (null without ARKODE).
    std::function<void(double t, const double *y, const double *v, double *out)> times;
    /// GMRES stops when its left-preconditioned residual (the correction's
    /// error as far as Newton's matrix holds J) has this error-weighted RMS
    /// norm [-].
    double tolerance = 0.0;
    /// GMRES's iterations so far, for the statistics (may be null).
    long *iterations = nullptr;
  };

  /// Free with SUNLinSolFree. Without `updates.change`: Newton's matrix as set up.
  SUNLinearSolver make_newton_solver(SUNContext context, const NewtonUpdates &updates);

  /// Broyden's secant updates between the iterations of ARKODE's stages.
  void set_secant_updates(SUNLinearSolver solver, void *arkode);
  /// Newton's systems by GMRES with J at the iterate, preconditioned by the
  /// matrix as set up (with its NewtonUpdates); no secant updates. Without
  /// `arkode` (a solve on its own): the set-up's γ and unit error weights.
  void set_krylov(SUNLinearSolver solver, void *arkode, const JacobianProducts &products);
} // namespace fretsim::coupling
