#pragma once
// The bearing-in-housing co-simulation (docs/theory.md §4): the reduced
// flexible outer ring
//     M_r q̈ + C_r q̇ + K_r q = Σ_j Q_j r(ψ_j) + Σ_c A (G_c T)ᵀ t_c
// driven by the cage-guided balls of a rigid, displaced and rotating inner
// ring, and held by the rigid housing through the interface contact. SUNDIALS
// ARKODE (ARKStep, diagonally implicit Runge–Kutta, adaptive steps, Newton with
// a dense analytic Jacobian) integrates y = [q, q̇]; the bristle states are
// committed after every accepted step (see ring_coupling.h). Structural
// damping is stiffness-proportional, C_r = β K_r with β = 2ζ / ω_1.
#include <fretsim/coupling/bearing.h>
#include <fretsim/coupling/ring_coupling.h>

#include <functional>
#include <memory>
#include <vector>

namespace fretsim::coupling
{
  /// How ARKODE guesses each implicit stage before Newton's iterations
  /// (ARKStepSetPredictorMethod 0..3).
  enum class StagePredictor
  {
    trivial        = 0, ///< the last step's solution
    maximum_order  = 1, ///< the last step's dense output, at its full order
    variable_order = 2, ///< the dense output, its order falling for later stages
    cutoff_order   = 3  ///< the dense output at full order for stages in the step's first half, linear after
  };

  struct IntegratorSettings
  {
    int    order                  = 3;     ///< DIRK order, 2..5 (ARKODE's default tables)
    double relative_tolerance     = 1e-4;  ///< [-]
    /// Absolute tolerance as a displacement: each coordinate's tolerance is the
    /// change that moves some interface point by this much [m].
    double displacement_tolerance = 1e-11;
    double maximum_step           = 0.0;   ///< [s], 0: no limit besides the output interval
    double initial_step           = 0.0;   ///< [s], 0: ARKODE's estimate
    long   maximum_steps          = 20000; ///< per output interval (then the run stops with a message)
    /// Newton iterations per stage before ARKODE cuts the step. The contact
    /// laws have kinks (cells opening, bristles reaching the limit) and the
    /// bristles' law bends within a step, so Newton on a matrix kept over
    /// steps converges linearly (updates shrinking by 0.3-0.6 each on the
    /// paper's case): with ARKODE's 3 a third of its steps failed there (with
    /// 12 a tenth to a sixth), each failure costing a fresh matrix and a
    /// quarter step (docs/bearing.md).
    int    maximum_newton_iterations = 12;
    /// Newton failures ARKODE allows in one step (each retried with a
    /// smaller step and a fresh matrix) before it gives up on the step, which
    /// is then retried with ARKODE's own Newton start and its own limit, 10
    /// (the fallback, docs/bearing.md).
    int    maximum_newton_failures = 10;
    /// Newton stops when its update's error-weighted norm is below this
    /// (ARKODE's nonlinear convergence coefficient, its default 0.1) [-].
    /// Looser saves iterations and steps, but a stiff Winkler layer alone
    /// carries the unconverged part into the bristles (docs/bearing.md: 0.3 already
    /// broke the small test ring's periodicity; with the half-space 0.5 held).
    double newton_tolerance = 0.1;
    /// The stages' starting guess. The dense output's (cutoff order) starts
    /// Newton far closer than the last solution on the paper's case, where
    /// the bristles' implicit Euler law bends within a step (k_t |ds| ~ μp):
    /// a third of the steps for a ball pass (docs/bearing.md).
    StagePredictor predictor = StagePredictor::cutoff_order;
    /// Steps between fresh Jacobians (and Newton matrix set-ups) besides
    /// those after a failed Newton iteration. ARKODE's 51 and 20 keep a matrix
    /// while the balls move the contact under it; every 5 steps the paper
    /// case takes two thirds of the steps for 0.7 of the time (docs/bearing.md).
    long jacobian_interval = 5;
    /// Each implicit stage's derivative taken from Newton's converged
    /// correction (ARKStepSetDeduceImplicitRhs) instead of a further
    /// right-hand side at the stage's solution. That evaluation, a pressure
    /// solve with the half-space, was a third of all; its value differs from
    /// the deduced one by Newton's unconverged part only (docs/bearing.md).
    bool deduce_stage_derivative = true;
    /// Broyden's secant updates of the Newton matrix between the Newton
    /// iterations of a stage: the loaded cells change within the iteration,
    /// so the matrix set up at its start misses the stiffness of cells that
    /// close and keeps that of cells that open; each update corrects it along
    /// the last correction for a few vector products (docs/bearing.md).
    bool secant_updates = true;
    /// Newton's matrix with the balls' stiffness of the iterate rather than
    /// of the Jacobian's state (a rank-one update per loaded ball): Hertz's
    /// stiffness grows as δ^1/2 from nothing, so a matrix set up before a
    /// ball's load rose misses it. With a flexible housing it cut the
    /// Newton failures by a fifth; with the rigid one it changed the step
    /// sequence without fewer failures and cost steps (docs/bearing.md).
    bool balls_at_iterate = false;
    /// The same for the bristles' stiffness ∂τ/∂ds of the cells where it
    /// changed most since the Jacobian (InterfaceContact::
    /// slip_stiffness_changes): a cell that turned from sticking to sliding
    /// or back has a kink between the two matrices.
    bool bristles_at_iterate = false;
    /// Newton's linear systems with the whole Jacobian at the iterate: GMRES
    /// on (I - γJ) with J v from the last evaluation's derivatives (the
    /// interface's pressure coupling solved by conjugate gradients, not
    /// factorised), preconditioned by Newton's matrix as set up. A flexible
    /// housing's conformal contact changes its stiffness within one Newton
    /// correction, and Newton with the matrix as set up failed in an eighth
    /// to a fifth of the steps; no secant updates then (docs/bearing.md).
    bool newton_krylov = false;
    /// With it, Newton's matrix is set up afresh at the next step once a step
    /// took more GMRES products than this per Newton iteration (else every
    /// jacobian_interval steps): on the paper case's flexible housing 8 gave
    /// as few failures as any and the shortest run against 4, 6, 12 or a
    /// fixed interval (docs/bearing.md) [-].
    double krylov_products_for_a_fresh_matrix = 8.0;
  };

  struct CosimulationSettings
  {
    BearingGeometry    bearing;
    double             ball_stiffness      = 0.0; ///< K of Q = K δ^{3/2} (both contacts in series) [N/m^1.5]
    double             ball_damping        = 0.0; ///< Hunt–Crossley α [s/m]
    InterfaceSettings  interface;
    double             inner_ring_speed    = 0.0; ///< ω_i [rad/s]
    double             inner_displacement_x = 0.0, inner_displacement_y = 0.0; ///< final e [m]
    /// e(t) = e · s(t/t_r), s the C¹ smooth step, so that the ring is not hit.
    double             ramp_time           = 0.0; ///< [s]
    double             first_ball_angle    = 0.0; ///< ψ_0 [rad]
    double             duration            = 0.0; ///< [s]
    double             output_interval     = 0.0; ///< [s]
    double             damping_ratio       = 0.02;///< ζ at the lowest elastic frequency [-]
    /// With the ring's residual flexibility for the balls (ReducedRing::
    /// residual_ball): the reciprocal term too, the interface pressure's
    /// residual displacement of the raceway under each ball joining its
    /// deflection (pressure_residual_at_balls). In each evaluation the balls
    /// first take it from the pressure extrapolated from the last two
    /// accepted steps, then, after the interface's solve, from that solve's
    /// pressure (one Gauss–Seidel sweep, no second pressure solve); the
    /// sweep's correction is measured (IntegratorStatistics).
    bool               pressure_residual_at_balls = true;
    IntegratorSettings integrator;
  };

  /// The state at an output time, valid during the observer call.
  struct Snapshot
  {
    double                     time = 0.0;
    const contact::Field      *pressure = nullptr, *shear_x = nullptr, *shear_y = nullptr;
    contact::Field             effective_friction;
    std::vector<double>        ball_angles, ball_loads; ///< [rad], [N]
    std::vector<double>        q;                       ///< modal coordinates
    double contact_fraction = 0.0, slip_fraction = 0.0;
    double interface_force_x = 0.0, interface_force_y = 0.0; ///< housing on ring [N]
    double ball_force_x = 0.0, ball_force_y = 0.0;           ///< balls on ring [N]
    double inner_displacement_y = 0.0;                        ///< [m]
  };

  struct IntegratorStatistics
  {
    long   steps = 0, rhs_evaluations = 0, newton_iterations = 0, newton_failures = 0, error_test_failures = 0,
           jacobian_evaluations = 0, linear_setups = 0;
    /// GMRES iterations (IntegratorSettings::newton_krylov), each a J v, and
    /// the steps after which Newton's matrix was set up afresh for GMRES.
    long   krylov_iterations = 0, krylov_fresh_matrices = 0;
    double last_step = 0.0, smallest_step = 0.0, largest_step = 0.0; ///< [s]
    /// Output intervals finished with ARKODE's own Newton start (the last
    /// solution, 3 iterations) after the settings' Newton failed a step.
    long   fallbacks = 0;
    double integrator_seconds = 0.0; ///< wall time inside ARKODE, contact loads excluded
    double contact_seconds    = 0.0; ///< wall time of the contact loads and their Jacobians
    /// The pressure's residual displacement of the raceway under the balls
    /// (CosimulationSettings::pressure_residual_at_balls): its largest value
    /// over the accepted steps, and the largest correction the sweep made to
    /// it at an acceptance (the extrapolated pressure's against the accepted
    /// pressure's; what the balls and the pressure still disagree by is the
    /// loop's gain times that) [m]; 0 without it.
    double raceway_residual_largest = 0.0, raceway_residual_largest_correction = 0.0;
    /// The interface's half-space solves, if it has one (in contact_seconds).
    LocalCompliance::Statistics local_compliance;
  };

  class BearingCosimulation
  {
  public:
    /// Throws std::invalid_argument for settings that cannot run.
    BearingCosimulation(const ReducedRing &ring, const CosimulationSettings &settings);
    ~BearingCosimulation();

    /// Integrates from 0 to the duration, calling `observe` at t = 0 and at
    /// every output time; stops early (returning false) when `observe` returns
    /// false. Throws std::runtime_error if the integrator fails, naming the
    /// time and ARKODE's reason.
    bool run(const std::function<bool(const Snapshot &)> &observe);

    const IntegratorStatistics &statistics() const;
    /// The interface's pressure solve (its half-space completion), or null
    /// without a local compliance.
    const LocalCompliance *local_compliance() const;
    /// Ball angles at time t [rad].
    std::vector<double> ball_angles(double time) const;

    struct Impl; // public so that the SUNDIALS callbacks can reach it

  private:
    std::unique_ptr<Impl> impl;
  };
} // namespace fretsim::coupling
