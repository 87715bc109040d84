#include <fretsim/coupling/cosimulation.h>

#include "newton_solver.h"

#include <arkode/arkode_arkstep.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace fretsim::coupling
{
  namespace
  {
    using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    using Clock     = std::chrono::steady_clock;

    double seconds_since(Clock::time_point start)
    {
      return std::chrono::duration<double>(Clock::now() - start).count();
    }

    /// Eigen's own products run on one thread while it lives. The run's
    /// matrices (160² for the integrator, the Jacobian's loaded cells × 160)
    /// are too small for its OpenMP GEMM: each product's fork and join cost
    /// more than the second thread saved (one ball pass of the paper case:
    /// the integrator's own time 5.9 → 0.8 s, the run 1.45× faster on 2
    /// cores AMD EPYC busy with other work). The contact's loops over the
    /// cells keep their threads.
    struct EigenSerial
    {
      int threads = Eigen::nbThreads();
      EigenSerial() { Eigen::setNbThreads(1); }
      ~EigenSerial() { Eigen::setNbThreads(threads); }
      EigenSerial(const EigenSerial &)            = delete;
      EigenSerial &operator=(const EigenSerial &) = delete;
    };

    /// C¹ smooth step s(x) = 3x² - 2x³ on [0, 1] and its derivative.
    void smooth_step(double x, double &value, double &slope)
    {
      if (x >= 1.0)
        {
          value = 1.0;
          slope = 0.0;
          return;
        }
      x     = std::max(x, 0.0);
      value = x * x * (3.0 - 2.0 * x);
      slope = 6.0 * x * (1.0 - x);
    }
  } // namespace

  struct BearingCosimulation::Impl
  {
    CosimulationSettings settings;
    std::size_t          n;
    double               cage;
    RowMatrix            mass_inverse_stiffness, mass_inverse_damping;
    Eigen::LLT<Eigen::MatrixXd> mass;
    InterfaceContact     interface;
    BallContacts         balls;
    IntegratorStatistics stats;
    std::vector<double>  absolute_tolerance;
    // Work arrays of the right-hand side and Jacobian.
    std::vector<double> force, by_position, by_velocity;
    std::vector<double> ball_scratch; // set_ball_loads' generalised force, unused
    bool                ball_residual;  // the ring has a residual flexibility: the interface takes the ball loads
    // With the reciprocal term: the grid and ball table through which the
    // pressure moves the raceway under the balls (the table empty without it).
    contact::SurfaceGrid residual_grid;
    double               residual_radius, residual_column_angle;
    std::vector<double>  residual_ball, footprint_loads;
    // The last two accepted pressures and their times, for the extrapolation.
    contact::Field       pressure_now, pressure_before, pressure_guess;
    double               time_now = 0.0, time_before = 0.0;
    std::string         last_error;
    // The balls' derivatives in the last Jacobian (the Newton solver keeps
    // them at the iterate), and the evaluations of the forces so far.
    BallContacts::Linearisation balls_at_jacobian;
    std::vector<double>         evaluated_state, derivative; // jacobian_times: the last evaluation's y, and dF
    std::size_t                 evaluations = 0;

    Impl(const ReducedRing &ring, const CosimulationSettings &s)
      : settings(s)
      , n(ring.n)
      , cage(cage_speed(s.bearing, s.inner_ring_speed))
      , interface(ring, s.interface)
      , balls(ring, s.bearing.ball_count, s.ball_stiffness, s.ball_damping, s.bearing.radial_clearance)
      , force(ring.n)
      , by_position(ring.n * ring.n)
      , by_velocity(ring.n * ring.n)
      , ball_scratch(ring.n)
      , ball_residual(!ring.residual_ball.empty())
      , residual_grid(ring.interface_grid)
      , residual_radius(ring.interface_radius)
      , residual_column_angle(ring.residual_column_angle)
      , residual_ball(s.pressure_residual_at_balls ? ring.residual_ball : std::vector<double>())
      , footprint_loads(ring.raceway_footprint_loads)
      , pressure_now(ring.interface_grid.size(), 0.0)
      , pressure_before(pressure_now)
    {
      const Eigen::Map<const RowMatrix> M(ring.mass.data(), n, n), K(ring.stiffness.data(), n, n);
      mass.compute(M);
      if (mass.info() != Eigen::Success)
        throw std::invalid_argument("co-simulation: the reduced mass matrix is not positive definite");
      mass_inverse_stiffness = mass.solve(Eigen::MatrixXd(K));
      const double beta      = 2.0 * s.damping_ratio / (2.0 * M_PI * ring.lowest_elastic_frequency_hz);
      mass_inverse_damping   = beta * mass_inverse_stiffness;

      // A coordinate's tolerance is the change that moves the interface or
      // the raceway by the displacement tolerance somewhere.
      absolute_tolerance.assign(2 * n, 0.0);
      // Velocities are held only loosely (the displacement tolerance per
      // 10 ns): the motion is quasi-static at the ball pass rate, and the
      // bristle update after every step kicks the stiff contact modes, whose
      // velocity transients would otherwise set the step size.
      // A coordinate that moves neither (a flexible housing's fixed-interface
      // modes) gets the tightest tolerance of the others.
      const double velocity_scale = 1.0 / 1e-8;
      double       tightest       = 1.0;
      for (std::size_t j = 0; j < n; ++j)
        {
          double largest = 0.0;
          for (std::size_t row = 0; row < ring.interface_displacement.size() / n; ++row)
            largest = std::max(largest, std::abs(ring.interface_displacement[row * n + j]));
          for (std::size_t k = 0; k < ring.raceway_approach.size() / n; ++k)
            largest = std::max(largest, std::abs(ring.raceway_approach[k * n + j]));
          absolute_tolerance[j] = largest > 0.0 ? s.integrator.displacement_tolerance / largest : 0.0;
          if (largest > 0.0)
            tightest = std::min(tightest, absolute_tolerance[j]);
        }
      for (std::size_t j = 0; j < n; ++j)
        {
          if (absolute_tolerance[j] == 0.0)
            absolute_tolerance[j] = tightest;
          absolute_tolerance[n + j] = absolute_tolerance[j] * velocity_scale;
        }
    }

    std::vector<double> ball_angles(double t) const
    {
      std::vector<double> angles(settings.bearing.ball_count);
      for (unsigned int j = 0; j < angles.size(); ++j)
        angles[j] = settings.first_ball_angle + 2.0 * M_PI * j / angles.size() + cage * t;
      return angles;
    }

    void inner_ring(double t, double displacement[2], double velocity[2]) const
    {
      double value = 1.0, slope = 0.0;
      if (settings.ramp_time > 0.0)
        smooth_step(t / settings.ramp_time, value, slope);
      const double rate = settings.ramp_time > 0.0 ? slope / settings.ramp_time : 0.0;
      displacement[0]   = settings.inner_displacement_x * value;
      displacement[1]   = settings.inner_displacement_y * value;
      velocity[0]       = settings.inner_displacement_x * rate;
      velocity[1]       = settings.inner_displacement_y * rate;
    }

    /// Generalised contact force at (t, q, q̇), and its derivatives if asked.
    void contact_forces(double t, const double *q, const double *v, bool jacobian)
    {
      const auto start = Clock::now();
      std::fill(force.begin(), force.end(), 0.0);
      ForceOutput out{force.data(), nullptr, nullptr};
      if (jacobian)
        {
          std::fill(by_position.begin(), by_position.end(), 0.0);
          std::fill(by_velocity.begin(), by_velocity.end(), 0.0);
          out.by_position = by_position.data();
          out.by_velocity = by_velocity.data();
        }
      double e[2], e_rate[2];
      inner_ring(t, e, e_rate);
      const std::vector<double> angles = ball_angles(t);
      set_raceway_residual(t, angles);
      set_ball_loads(angles, e, e_rate, q, v);
      // The interface's forces first, then the balls': the sums in the
      // order they always had (a stiff layer's chatter follows the rounding).
      interface.add_forces(q, v, out);
      raceway_residual_from(interface.trial_pressure(), angles);
      balls.add_forces(angles, cage, e, e_rate, q, v, out);
      ++evaluations;
      if (settings.integrator.newton_krylov)
        {
          evaluated_state.assign(q, q + n);
          evaluated_state.insert(evaluated_state.end(), v, v + n);
        }
      stats.contact_seconds += seconds_since(start);
    }

    /// The ball loads at (q, q̇) to the interface, where the ring's residual
    /// flexibility turns them into penetration (a second, cheap evaluation
    /// of the balls: nine rows); without one, nothing.
    void set_ball_loads(const std::vector<double> &angles, const double e[2], const double e_rate[2], const double *q,
                        const double *v)
    {
      if (!ball_residual)
        return;
      std::fill(ball_scratch.begin(), ball_scratch.end(), 0.0);
      balls.add_forces(angles, cage, e, e_rate, q, v, {ball_scratch.data(), nullptr, nullptr});
      interface.set_ball_loads(angles, balls.loads());
    }

    /// The pressure's residual displacement of the raceway under the balls
    /// at time t and `angles`, to the balls (empty without it), from the
    /// pressure extrapolated linearly from the last two accepted steps: the
    /// balls' first guess in an evaluation, before the interface's solve.
    std::vector<double> set_raceway_residual(double t, const std::vector<double> &angles)
    {
      if (residual_ball.empty())
        return {};
      const contact::Field *pressure = &pressure_now;
      if (time_now > time_before && t != time_now)
        {
          // At most two of the last step ahead: after a much shorter step its
          // change would be mostly the solve's tolerance, magnified.
          const double ahead = std::min((t - time_now) / (time_now - time_before), 2.0);
          pressure_guess.resize(pressure_now.size());
          for (std::size_t c = 0; c < pressure_now.size(); ++c)
            pressure_guess[c] = std::max(pressure_now[c] + ahead * (pressure_now[c] - pressure_before[c]), 0.0);
          pressure = &pressure_guess;
        }
      return raceway_residual_from(*pressure, angles);
    }

    /// The same from a given pressure field: after the interface's solve,
    /// its own pressure (one Gauss–Seidel sweep: the balls then carry the
    /// residual of the pressure they pushed into, to the loop's gain, about
    /// 0.02 on the paper case, of the extrapolation's error).
    std::vector<double> raceway_residual_from(const contact::Field &pressure, const std::vector<double> &angles)
    {
      if (residual_ball.empty())
        return {};
      // The balls' footprints of their last loads.
      auto inward = pressure_residual_at_balls(residual_grid, residual_radius, residual_ball, footprint_loads,
                                               residual_column_angle, angles, balls.loads(), pressure);
      balls.set_raceway_residual(inward);
      return inward;
    }

    /// The paper's bristle update at the accepted state (t, q, q̇), with the
    /// ball loads there; then the raceway's residual from the new pressure,
    /// and the sweep's correction of the extrapolated one.
    void accept(double t, const double *q, const double *v)
    {
      double e[2], e_rate[2];
      inner_ring(t, e, e_rate);
      const std::vector<double> angles = ball_angles(t);
      const std::vector<double> used   = set_raceway_residual(t, angles);
      set_ball_loads(angles, e, e_rate, q, v);
      interface.accept(q, v);
      if (residual_ball.empty())
        return;
      pressure_before.swap(pressure_now);
      pressure_now = interface.pressure();
      time_before  = time_now;
      time_now     = t;
      const std::vector<double> updated = set_raceway_residual(t, angles);
      for (std::size_t j = 0; j < updated.size(); ++j)
        {
          stats.raceway_residual_largest = std::max(stats.raceway_residual_largest, std::abs(updated[j]));
          stats.raceway_residual_largest_correction =
            std::max(stats.raceway_residual_largest_correction, std::abs(updated[j] - used[j]));
        }
    }

    int rhs(double t, const double *y, double *y_rate)
    {
      const double *q = y, *v = y + n;
      contact_forces(t, q, v, false);
      const Eigen::Map<const Eigen::VectorXd> qv(q, n), vv(v, n), f(force.data(), n);
      Eigen::Map<Eigen::VectorXd>(y_rate, n) = vv;
      Eigen::Map<Eigen::VectorXd> acceleration(y_rate + n, n);
      acceleration = mass.solve(f);
      acceleration.noalias() -= mass_inverse_stiffness * qv + mass_inverse_damping * vv;
      for (std::size_t k = 0; k < 2 * n; ++k)
        if (!std::isfinite(y_rate[k]))
          return 1; // recoverable: ARKODE retries with a smaller step
      return 0;
    }

    /// J = [[0, I], [M⁻¹(∂F/∂q - K), M⁻¹(∂F/∂q̇ - C)]] into a column-major dense matrix.
    int jacobian(double t, const double *y, double *columns, long leading)
    {
      contact_forces(t, y, y + n, true);
      balls_at_jacobian = balls.linearisation();
      const Eigen::Map<const RowMatrix> dq(by_position.data(), n, n), dv(by_velocity.data(), n, n);
      const Eigen::MatrixXd lower_left  = mass.solve(Eigen::MatrixXd(dq)) - mass_inverse_stiffness;
      const Eigen::MatrixXd lower_right = mass.solve(Eigen::MatrixXd(dv)) - mass_inverse_damping;
      Eigen::Map<Eigen::MatrixXd, 0, Eigen::OuterStride<>> J(columns, 2 * n, 2 * n, Eigen::OuterStride<>(leading));
      J.setZero();
      J.topRightCorner(n, n).setIdentity();
      J.bottomLeftCorner(n, n)  = lower_left;
      J.bottomRightCorner(n, n) = lower_right;
      return J.allFinite() ? 0 : 1;
    }

    /// J v at (t, y) (IntegratorSettings::newton_krylov): the interface's
    /// and the balls' derivatives at the last evaluation, which is at y in
    /// Newton's iteration (else evaluated there first).
    void jacobian_times(double t, const double *y, const double *v, double *out)
    {
      if (!std::equal(y, y + 2 * n, evaluated_state.begin(), evaluated_state.end()))
        contact_forces(t, y, y + n, false);
      const auto start = Clock::now();
      derivative.assign(n, 0.0);
      interface.add_derivative(v, v + n, derivative.data());
      balls.linearisation().add_derivative(v, v + n, derivative.data());
      const Eigen::Map<const Eigen::VectorXd> by_position(v, n), by_velocity(v + n, n),
        force_change(derivative.data(), n);
      Eigen::Map<Eigen::VectorXd>(out, n) = by_velocity;
      Eigen::Map<Eigen::VectorXd> acceleration(out + n, n);
      acceleration = mass.solve(force_change);
      acceleration.noalias() -= mass_inverse_stiffness * by_position + mass_inverse_damping * by_velocity;
      stats.contact_seconds += seconds_since(start);
    }

    /// How the force's derivatives at the last evaluation differ from the
    /// last Jacobian's where the settings keep them at the iterate: the
    /// balls' and the bristles' of the cells that changed most.
    void stiffness_change(StiffnessChange &change) const
    {
      if (settings.integrator.balls_at_iterate)
        add_ball_change(balls.linearisation(), balls_at_jacobian, n, change);
      if (settings.integrator.bristles_at_iterate)
        {
          std::vector<double> rows, changes;
          interface.slip_stiffness_changes(rows, changes);
          add_slip_change(rows, changes, n, change);
        }
    }
  };

  namespace
  {
    int arkode_rhs(realtype t, N_Vector y, N_Vector y_rate, void *data)
    {
      try
        {
          return static_cast<BearingCosimulation::Impl *>(data)->rhs(t, N_VGetArrayPointer(y),
                                                                      N_VGetArrayPointer(y_rate));
        }
      catch (const std::exception &error)
        {
          static_cast<BearingCosimulation::Impl *>(data)->last_error = error.what();
          return -1;
        }
    }

    int arkode_jacobian(realtype t, N_Vector y, N_Vector, SUNMatrix J, void *data, N_Vector, N_Vector, N_Vector)
    {
      try
        {
          return static_cast<BearingCosimulation::Impl *>(data)->jacobian(t, N_VGetArrayPointer(y), SM_DATA_D(J),
                                                                           SM_ROWS_D(J));
        }
      catch (const std::exception &error)
        {
          static_cast<BearingCosimulation::Impl *>(data)->last_error = error.what();
          return -1;
        }
    }

    void arkode_error(int, const char *, const char *function, char *message, void *data)
    {
      auto &last = static_cast<BearingCosimulation::Impl *>(data)->last_error;
      last       = std::string(function) + ": " + message;
    }

    /// Owners of the SUNDIALS objects (C handles with their own destroy calls).
    struct Sundials
    {
      SUNContext      context = nullptr;
      N_Vector        state = nullptr, tolerance = nullptr;
      SUNMatrix       matrix = nullptr;
      SUNLinearSolver solver = nullptr;
      void           *arkode = nullptr;
      ~Sundials()
      {
        if (arkode)
          ARKStepFree(&arkode);
        if (solver)
          SUNLinSolFree(solver);
        if (matrix)
          SUNMatDestroy(matrix);
        if (tolerance)
          N_VDestroy(tolerance);
        if (state)
          N_VDestroy(state);
        if (context)
          SUNContext_Free(&context);
      }
    };

    void check(int flag, const char *call, const std::string &detail = "")
    {
      if (flag < 0)
        throw std::runtime_error(std::string("co-simulation: ") + call + " failed (" +
                                 ARKStepGetReturnFlagName(flag) + ")" + (detail.empty() ? "" : ": " + detail));
    }

    /// ARKODE's implicit stepper on y = [q, q̇] from y = 0, with the settings'
    /// tolerances and Newton iteration and the Schur-complement LU above.
    void create_integrator(Sundials &sun, BearingCosimulation::Impl &d)
    {
      const std::size_t n = d.n;
      const auto       &s = d.settings;
      check(SUNContext_Create(nullptr, &sun.context), "SUNContext_Create");
      sun.state     = N_VNew_Serial(static_cast<sunindextype>(2 * n), sun.context);
      sun.tolerance = N_VNew_Serial(static_cast<sunindextype>(2 * n), sun.context);
      double *y     = N_VGetArrayPointer(sun.state);
      std::fill(y, y + 2 * n, 0.0);
      std::copy(d.absolute_tolerance.begin(), d.absolute_tolerance.end(), N_VGetArrayPointer(sun.tolerance));
      sun.arkode = ARKStepCreate(nullptr, arkode_rhs, 0.0, sun.state, sun.context);
      if (sun.arkode == nullptr)
        throw std::runtime_error("co-simulation: ARKStepCreate failed");
      check(ARKStepSetUserData(sun.arkode, &d), "ARKStepSetUserData");
      check(ARKStepSetErrHandlerFn(sun.arkode, arkode_error, &d), "ARKStepSetErrHandlerFn");
      check(ARKStepSVtolerances(sun.arkode, s.integrator.relative_tolerance, sun.tolerance), "ARKStepSVtolerances");
      sun.matrix = SUNDenseMatrix(static_cast<sunindextype>(2 * n), static_cast<sunindextype>(2 * n), sun.context);
      if (s.integrator.bristles_at_iterate)
        d.interface.track_slip_stiffness();
      NewtonUpdates updates;
      if (s.integrator.balls_at_iterate || s.integrator.bristles_at_iterate)
        updates = {&d.mass, [&d] { return d.evaluations; }, [&d](StiffnessChange &change) { d.stiffness_change(change); }};
      sun.solver = make_newton_solver(sun.context, updates);
      check(ARKStepSetLinearSolver(sun.arkode, sun.solver, sun.matrix), "ARKStepSetLinearSolver");
      if (s.integrator.newton_krylov)
        {
          d.interface.keep_derivatives();
          JacobianProducts products;
          products.times = [&d](double t, const double *y, const double *v, double *out) {
            d.jacobian_times(t, y, v, out);
          };
          // ARKODE's own share of Newton's tolerance for an iterative linear solve (its eplifac).
          products.tolerance  = 0.05 * s.integrator.newton_tolerance;
          products.iterations = &d.stats.krylov_iterations;
          set_krylov(sun.solver, sun.arkode, products);
          // GMRES solves with the stage's own γ.
          check(ARKStepSetLinearSolutionScaling(sun.arkode, SUNFALSE), "ARKStepSetLinearSolutionScaling");
        }
      else if (s.integrator.secant_updates)
        {
          set_secant_updates(sun.solver, sun.arkode);
          // The updates need the correction Newton takes to be the solve's:
          // no rescaling for a γ that changed since the set-up.
          check(ARKStepSetLinearSolutionScaling(sun.arkode, SUNFALSE), "ARKStepSetLinearSolutionScaling");
        }
      check(ARKStepSetJacFn(sun.arkode, arkode_jacobian), "ARKStepSetJacFn");
      check(ARKStepSetOrder(sun.arkode, s.integrator.order), "ARKStepSetOrder");
      check(ARKStepSetNonlinConvCoef(sun.arkode, s.integrator.newton_tolerance), "ARKStepSetNonlinConvCoef");
      check(ARKStepSetDeduceImplicitRhs(sun.arkode, s.integrator.deduce_stage_derivative ? SUNTRUE : SUNFALSE),
            "ARKStepSetDeduceImplicitRhs");
      check(ARKStepSetJacEvalFrequency(sun.arkode, s.integrator.jacobian_interval), "ARKStepSetJacEvalFrequency");
      check(ARKStepSetLSetupFrequency(sun.arkode, static_cast<int>(s.integrator.jacobian_interval)),
            "ARKStepSetLSetupFrequency");

      if (s.integrator.maximum_step > 0.0)
        check(ARKStepSetMaxStep(sun.arkode, s.integrator.maximum_step), "ARKStepSetMaxStep");
      if (s.integrator.initial_step > 0.0)
        check(ARKStepSetInitStep(sun.arkode, s.integrator.initial_step), "ARKStepSetInitStep");
    }

    /// The run's state at time t, y = [q, q̇] (the balls' forces evaluated
    /// again for their loads).
    Snapshot take_snapshot(BearingCosimulation::Impl &d, double t, const double *y)
    {
      const std::size_t               n = d.n;
      Snapshot                      snap;
      snap.time               = t;
      snap.pressure           = &d.interface.pressure();
      snap.shear_x            = &d.interface.shear_x();
      snap.shear_y            = &d.interface.shear_y();
      snap.effective_friction = d.interface.effective_friction();
      snap.contact_fraction   = d.interface.contact_fraction();
      snap.slip_fraction      = d.interface.slip_fraction();
      d.interface.resultant(snap.interface_force_x, snap.interface_force_y);
      snap.q.assign(y, y + n);
      snap.ball_angles = d.ball_angles(t);
      double e[2], e_rate[2];
      d.inner_ring(t, e, e_rate);
      std::vector<double> scratch(n, 0.0);
      d.balls.add_forces(snap.ball_angles, d.cage, e, e_rate, y, y + n, {scratch.data(), nullptr, nullptr});
      snap.ball_loads = d.balls.loads();
      for (std::size_t j = 0; j < snap.ball_loads.size(); ++j)
        {
          snap.ball_force_x += snap.ball_loads[j] * std::cos(snap.ball_angles[j]);
          snap.ball_force_y += snap.ball_loads[j] * std::sin(snap.ball_angles[j]);
        }
      snap.inner_displacement_y = e[1];
      return snap;
    }

    /// The integrator's counters, read however the run ends.
    struct Counters
    {
      void *arkode;
      IntegratorStatistics &stats;
      const InterfaceContact &interface;
      ~Counters()
      {
        if (const auto *local = interface.local_compliance())
          stats.local_compliance = local->statistics();
        long nfe = 0, nfi = 0;
        ARKStepGetNumSteps(arkode, &stats.steps);
        ARKStepGetNumRhsEvals(arkode, &nfe, &nfi);
        stats.rhs_evaluations = nfi;
        ARKStepGetNumNonlinSolvIters(arkode, &stats.newton_iterations);
        ARKStepGetNumNonlinSolvConvFails(arkode, &stats.newton_failures);
        ARKStepGetNumErrTestFails(arkode, &stats.error_test_failures);
        ARKStepGetNumJacEvals(arkode, &stats.jacobian_evaluations);
        ARKStepGetNumLinSolvSetups(arkode, &stats.linear_setups);
        ARKStepGetLastStep(arkode, &stats.last_step);
      }
    };

    /// How the Newton iteration of a stage starts. The settings' start (a
    /// dense-output guess, many iterations) is the fast one, but on a stiff
    /// case it can settle a stage where the error test then rejects every
    /// step down to ARKODE's smallest (a housing 10⁴ times stiffer than steel
    /// did). Such a step is retried from the last accepted state with
    /// ARKODE's own start, the last solution and 3 iterations, for the rest
    /// of that output interval.
    struct NewtonStart
    {
      StagePredictor predictor;
      int            iterations, failures;

      bool operator!=(const NewtonStart &other) const
      {
        return predictor != other.predictor || iterations != other.iterations || failures != other.failures;
      }
    };

    struct NewtonStarts
    {
      NewtonStart settings, arkode;
      bool        can_fall_back() const { return settings != arkode; }
    };

    NewtonStarts newton_starts(const IntegratorSettings &integrator)
    {
      return {{integrator.predictor, integrator.maximum_newton_iterations, integrator.maximum_newton_failures},
              {StagePredictor::trivial, 3, 10}}; // ARKODE's own defaults
    }

    void set_newton_start(void *arkode, const NewtonStart &start)
    {
      check(ARKStepSetPredictorMethod(arkode, static_cast<int>(start.predictor)), "ARKStepSetPredictorMethod");
      check(ARKStepSetMaxNonlinIters(arkode, start.iterations), "ARKStepSetMaxNonlinIters");
      check(ARKStepSetMaxConvFails(arkode, start.failures), "ARKStepSetMaxConvFails");
    }

    [[noreturn]] void throw_integrator_failure(double t, const std::string &why, const std::string &detail)
    {
      std::ostringstream message;
      message << "the integrator failed at t = " << t << " s (" << why << ")" << detail
              << ". Try a smaller Integrator/Maximum step, a looser Integrator/Relative tolerance, or "
                 "a softer Interface/Normal stiffness.";
      throw std::runtime_error(message.str());
    }

    /// Newton iterations and GMRES products so far.
    struct KrylovCount
    {
      long newton_iterations = 0, products = 0;
    };

    KrylovCount krylov_count(void *arkode, const BearingCosimulation::Impl &d)
    {
      KrylovCount count;
      ARKStepGetNumNonlinSolvIters(arkode, &count.newton_iterations);
      count.products = d.stats.krylov_iterations;
      return count;
    }

    /// With Newton-Krylov: Newton's matrix (GMRES's preconditioner) set up
    /// afresh at the next step when this one took more than the settings'
    /// products per Newton iteration, else at the settings' interval.
    void refresh_when_gmres_slows(void *arkode, BearingCosimulation::Impl &d, const KrylovCount &before)
    {
      const KrylovCount after = krylov_count(arkode, d);
      const double products_per_iteration = static_cast<double>(after.products - before.products) /
                                            static_cast<double>(std::max(1L, after.newton_iterations -
                                                                               before.newton_iterations));
      const bool fresh    = products_per_iteration > d.settings.integrator.krylov_products_for_a_fresh_matrix;
      const long interval = fresh ? 1 : d.settings.integrator.jacobian_interval;
      d.stats.krylov_fresh_matrices += fresh;
      check(ARKStepSetJacEvalFrequency(arkode, interval), "ARKStepSetJacEvalFrequency");
      check(ARKStepSetLSetupFrequency(arkode, static_cast<int>(interval)), "ARKStepSetLSetupFrequency");
    }

    /// Steps from t to t_out one ARKODE step at a time, each accepted step
    /// followed by the paper's bristle update; falls back to ARKODE's Newton
    /// start for the rest of the interval on a failed step.
    void integrate_interval(Sundials &sun, BearingCosimulation::Impl &d, const NewtonStarts &starts, double t_out,
                            double &t)
    {
      const long maximum_steps = d.settings.integrator.maximum_steps;
      double    *y             = N_VGetArrayPointer(sun.state);
      check(ARKStepSetStopTime(sun.arkode, t_out), "ARKStepSetStopTime");
      bool fallen_back       = false;
      long steps_in_interval = 0;
      while (t < t_out * (1.0 - 1e-12))
        {
          // ARKODE's own step limit counts per call, and each call here is one step.
          if (++steps_in_interval > maximum_steps)
            {
              std::ostringstream why;
              why << "more than " << maximum_steps << " steps in one output interval; smallest step "
                  << d.stats.smallest_step << " s";
              throw_integrator_failure(t, why.str(), "");
            }
          const auto        start        = Clock::now();
          const double      contact_time = d.stats.contact_seconds;
          const KrylovCount before       = krylov_count(sun.arkode, d);
          const int         flag         = ARKStepEvolve(sun.arkode, t_out, sun.state, &t, ARK_ONE_STEP);
          if (d.settings.integrator.newton_krylov)
            refresh_when_gmres_slows(sun.arkode, d, before);
          d.stats.integrator_seconds += seconds_since(start) - (d.stats.contact_seconds - contact_time);
          if ((flag == ARK_ERR_FAILURE || flag == ARK_CONV_FAILURE) && starts.can_fall_back() && !fallen_back)
            {
              set_newton_start(sun.arkode, starts.arkode);
              fallen_back = true;
              ++d.stats.fallbacks;
              continue;
            }
          if (flag < 0)
            throw_integrator_failure(t, ARKStepGetReturnFlagName(flag),
                                     d.last_error.empty() ? "" : ": " + d.last_error);
          double step = 0.0;
          ARKStepGetLastStep(sun.arkode, &step);
          d.stats.smallest_step = std::min(d.stats.smallest_step, step);
          d.stats.largest_step  = std::max(d.stats.largest_step, step);
          const auto accept_start = Clock::now();
          d.accept(t, y, y + d.n); // the paper's bristle update after the step
          d.stats.contact_seconds += seconds_since(accept_start);
        }
      if (fallen_back)
        set_newton_start(sun.arkode, starts.settings);
    }
  } // namespace

  BearingCosimulation::BearingCosimulation(const ReducedRing &ring, const CosimulationSettings &s)
  {
    ring.check();
    const auto positive = [](double value) { return value > 0.0 && std::isfinite(value); };
    if (!positive(s.duration) || !positive(s.output_interval) || !positive(s.ball_stiffness) ||
        !(s.ramp_time >= 0.0) || !(s.damping_ratio >= 0.0) || !positive(ring.lowest_elastic_frequency_hz))
      throw std::invalid_argument("co-simulation: duration, output interval, ball stiffness and the lowest elastic "
                                  "frequency must be positive; ramp time and damping ratio >= 0");
    if (s.integrator.order < 2 || s.integrator.order > 5 || s.integrator.jacobian_interval < 1 ||
        s.integrator.maximum_newton_iterations < 1 || s.integrator.maximum_newton_failures < 1 ||
        !positive(s.integrator.relative_tolerance) ||
        !positive(s.integrator.displacement_tolerance) || !positive(s.integrator.newton_tolerance))
      throw std::invalid_argument("co-simulation: integrator order must be 2..5, the Jacobian interval, Newton "
                                  "iterations and failures >= 1 and tolerances positive");
    impl = std::make_unique<Impl>(ring, s);
  }

  BearingCosimulation::~BearingCosimulation() = default;

  const IntegratorStatistics &BearingCosimulation::statistics() const { return impl->stats; }

  std::vector<double> BearingCosimulation::ball_angles(double time) const { return impl->ball_angles(time); }

  const LocalCompliance *BearingCosimulation::local_compliance() const { return impl->interface.local_compliance(); }

  bool BearingCosimulation::run(const std::function<bool(const Snapshot &)> &observe)
  {
    Impl       &d = *impl;
    const auto &s = d.settings;
    Sundials    sun;
    const EigenSerial serial;
    create_integrator(sun, d);
    const double *y = N_VGetArrayPointer(sun.state);
    Counters      counters{sun.arkode, d.stats, d.interface};

    d.accept(0.0, y, y + d.n);
    if (!observe(take_snapshot(d, 0.0, y)))
      return false;
    const long   outputs = std::lround(s.duration / s.output_interval);
    double       t       = 0.0;
    d.stats.smallest_step = s.duration;
    const NewtonStarts starts = newton_starts(s.integrator);
    set_newton_start(sun.arkode, starts.settings);
    for (long k = 1; k <= outputs; ++k)
      {
        const double t_out = k * s.output_interval;
        integrate_interval(sun, d, starts, t_out, t);
        if (!observe(take_snapshot(d, t_out, y)))
          return false;
      }
    return true;
  }
} // namespace fretsim::coupling
