#include "newton_solver.h"

#include <arkode/arkode_arkstep.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <Eigen/Dense>

#include <utility>
#include <vector>

namespace fretsim::coupling
{
  namespace
  {
    /// A SUNDIALS direct linear solver for the Newton matrix of y = [q, q̇],
    ///     A = I - γJ = [[I, -γI], [-γL, I - γR]]   (J = [[0, I], [L, R]]),
    /// by its Schur complement: x₁ = b₁ + γx₂ and (A₂₂ - A₂₁A₁₂) x₂ = b₂ - A₂₁b₁,
    /// so that Eigen's blocked LU factorises an n × n matrix, not 2n × 2n
    /// (an eighth of the work: the factorisation was most of the
    /// integrator's own time). A matrix without that block structure is
    /// factorised whole.
    struct EigenLu
    {
      Eigen::PartialPivLU<Eigen::MatrixXd> lu;
      Eigen::MatrixXd lower_left; ///< A₂₁ (Schur form only)
      double          gamma = 0.0;
      bool            schur = false;
      /// Broyden's second method on the inverse: H = A⁻¹ + Σ_i c_i y_iᵀ / (y_iᵀ y_i)
      /// over the stage's iterations so far, each making H y_i = s_i for the
      /// change y_i of the right-hand side (Newton's residual, negated) along
      /// the correction s_i it followed. Cleared by a set-up and a new stage.
      void                        *arkode = nullptr; ///< set with secant updates or GMRES only
      std::vector<Eigen::VectorXd> secant_corrections, residual_changes;
      Eigen::VectorXd              last_rhs, last_solution;
      double                       stage_time = 0.0, stage_gamma = 0.0;

      /// Parts of J at the iterate rather than at the Jacobian's state
      /// (NewtonUpdates): Newton's matrix is updated by their change, of
      /// low rank, by Woodbury's identity. A ball that comes into contact
      /// after the Jacobian (no stiffness there) would otherwise throw the
      /// iterate from one side of its contact to the other.
      NewtonUpdates   updates;
      StiffnessChange change;
      // ΔS = U Wᵀ on the Schur complement, ΔL = -U Gᵀ on J's lower left (U = M⁻¹ R).
      Eigen::MatrixXd                      update_u, update_w, update_g, update_solved_u;
      Eigen::PartialPivLU<Eigen::MatrixXd> capacitance;
      long        setups = 0, setups_seen = -1;
      std::size_t evaluations_seen = 0;

      bool             krylov = false;
      JacobianProducts products;
      N_Vector         weights = nullptr; ///< ARKODE's error weights (krylov)
      static constexpr int most = 40; ///< Krylov vectors (no restart; then the best correction found)
      Eigen::MatrixXd      basis, hessenberg; // solve_krylov's work arrays, sized once

      /// The stage ARKODE's Newton iteration is at: its time, γ and iterate.
      struct Stage
      {
        double   time = 0.0, gamma = 0.0;
        N_Vector iterate = nullptr;
      };
      Stage stage() const
      {
        Stage    now;
        N_Vector predicted, stage_rhs, stage_data;
        void    *user;
        ARKStepGetNonlinearSystemData(arkode, &now.time, &predicted, &now.iterate, &stage_rhs, &now.gamma,
                                      &stage_data, &user);
        return now;
      }

      /// (I - γJ) x = b with J at the iterate, by GMRES (Saad & Schultz,
      /// left-preconditioned by the set-up matrix, in the error-weighted
      /// norm), from x = 0.
      void solve_krylov(const Eigen::Map<const Eigen::VectorXd> &rhs, Eigen::Map<Eigen::VectorXd> &solution);

      /// Newton's matrix with the change at the last evaluation (once per
      /// evaluation and set-up).
      void update_stiffness()
      {
        if (!updates.change)
          return;
        const std::size_t evaluations = updates.evaluations();
        if (setups == setups_seen && evaluations == evaluations_seen)
          return;
        setups_seen      = setups;
        evaluations_seen = evaluations;
        update_u.resize(0, 0);
        if (!schur)
          return;
        const Eigen::Index n = lu.rows();
        change.clear();
        updates.change(change);
        if (change.terms == 0)
          return;
        const auto                              m = static_cast<Eigen::Index>(change.terms);
        const Eigen::Map<const Eigen::MatrixXd> rows(change.rows.data(), n, m);
        update_g = Eigen::Map<const Eigen::MatrixXd>(change.by_position.data(), n, m);
        // S = I - γR - γ²L gains M⁻¹ r (γ c r + γ² g)ᵀ per term.
        update_w = gamma * gamma * update_g;
        for (Eigen::Index i = 0; i < m; ++i)
          update_w.col(i) += gamma * change.by_velocity[i] * rows.col(i);
        update_u        = updates.mass->solve(rows);
        update_solved_u = lu.solve(update_u);
        capacitance.compute(Eigen::MatrixXd::Identity(m, m) + update_w.transpose() * update_solved_u);
      }

      Eigen::VectorXd solve_set_up(const Eigen::VectorXd &rhs) const
      {
        if (!schur)
          return lu.solve(rhs);
        const auto      n = lu.rows();
        Eigen::VectorXd solution(2 * n);
        if (update_u.size() == 0)
          solution.tail(n) = lu.solve(rhs.tail(n) - lower_left * rhs.head(n));
        else
          {
            const Eigen::VectorXd first = lu.solve(rhs.tail(n) - lower_left * rhs.head(n) -
                                                   gamma * (update_u * (update_g.transpose() * rhs.head(n))));
            solution.tail(n) = first - update_solved_u * capacitance.solve(update_w.transpose() * first);
          }
        solution.head(n) = rhs.head(n) + gamma * solution.tail(n);
        return solution;
      }

      Eigen::VectorXd solve_updated(const Eigen::VectorXd &rhs) const
      {
        Eigen::VectorXd solution = solve_set_up(rhs);
        for (std::size_t i = 0; i < secant_corrections.size(); ++i)
          solution += secant_corrections[i] * (residual_changes[i].dot(rhs) / residual_changes[i].squaredNorm());
        return solution;
      }

      void clear_secant_updates()
      {
        secant_corrections.clear();
        residual_changes.clear();
      }

      /// Adds the secant update from the last iteration unless `rhs` starts
      /// a stage (another stage time or γ: a new stage, step or attempt).
      void update_secant(const Eigen::VectorXd &rhs)
      {
        const Stage now = stage();
        if (now.time != stage_time || now.gamma != stage_gamma || last_rhs.size() != rhs.size())
          {
            clear_secant_updates();
            stage_time  = now.time;
            stage_gamma = now.gamma;
            return;
          }
        Eigen::VectorXd change = last_rhs - rhs;
        if (!(change.squaredNorm() > 0.0))
          return;
        Eigen::VectorXd correction = last_solution - solve_updated(change);
        secant_corrections.push_back(std::move(correction));
        residual_changes.push_back(std::move(change));
      }
    };

    void EigenLu::solve_krylov(const Eigen::Map<const Eigen::VectorXd> &rhs, Eigen::Map<Eigen::VectorXd> &solution)
    {
      const Eigen::Index size = rhs.size();
      // The stage's time, iterate, γ and error weights; without ARKODE (a
      // solve on its own) the set-up's γ and unit weights.
      Stage           now{0.0, gamma, nullptr};
      Eigen::VectorXd w = Eigen::VectorXd::Ones(size);
      if (arkode != nullptr)
        {
          now = stage();
          if (weights == nullptr)
            weights = N_VClone(now.iterate);
          ARKStepGetErrWeights(arkode, weights);
          w = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(weights), size);
        }
      const double *y     = now.iterate ? N_VGetArrayPointer(now.iterate) : nullptr;
      const double  scale = 1.0 / std::sqrt(static_cast<double>(size)); // the RMS norm's
      // Arnoldi on W P⁻¹ A W⁻¹ (left-preconditioned: its residual is the
      // error of the correction in Newton's own norm, as far as P holds A).
      basis.resize(size, most + 1);
      hessenberg.setZero(most + 1, most);
      auto           &V = basis, &H = hessenberg;
      Eigen::VectorXd cosines(most), sines(most), g = Eigen::VectorXd::Zero(most + 1), product(size);
      const Eigen::VectorXd start = solve_set_up(rhs).cwiseProduct(w);
      g(0)                        = start.norm();
      if (!(g(0) * scale > products.tolerance))
        {
          solution = start.cwiseQuotient(w);
          return;
        }
      V.col(0) = start / g(0);
      int k    = 0;
      while (k < most && std::abs(g(k)) * scale > products.tolerance)
        {
          const Eigen::VectorXd direction = V.col(k).cwiseQuotient(w);
          products.times(now.time, y, direction.data(), product.data());
          Eigen::VectorXd next = solve_set_up(direction - now.gamma * product).cwiseProduct(w);
          for (int i = 0; i <= k; ++i) // modified Gram–Schmidt
            {
              H(i, k) = V.col(i).dot(next);
              next -= H(i, k) * V.col(i);
            }
          H(k + 1, k) = next.norm();
          if (H(k + 1, k) > 0.0)
            V.col(k + 1) = next / H(k + 1, k);
          for (int i = 0; i < k; ++i) // the earlier rotations on the new column
            {
              const double upper = cosines(i) * H(i, k) + sines(i) * H(i + 1, k);
              H(i + 1, k)        = -sines(i) * H(i, k) + cosines(i) * H(i + 1, k);
              H(i, k)            = upper;
            }
          const double radius = std::hypot(H(k, k), H(k + 1, k));
          if (!(radius > 0.0))
            break; // (a singular operator: keep what was found)
          cosines(k)          = H(k, k) / radius;
          sines(k)            = H(k + 1, k) / radius;
          H(k, k)             = radius;
          H(k + 1, k)         = 0.0;
          g(k + 1)            = -sines(k) * g(k);
          g(k) *= cosines(k);
          ++k;
        }
      if (products.iterations)
        *products.iterations += k;
      const Eigen::VectorXd coefficients =
        H.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(g.head(k));
      solution = (V.leftCols(k) * coefficients).cwiseQuotient(w);
    }

    SUNLinearSolver_Type eigen_lu_type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }

    /// Whether A's upper blocks are [I, -γI] exactly (they are for J's [0, I]).
    bool has_velocity_block_structure(const Eigen::Map<const Eigen::MatrixXd> &a, Eigen::Index n, double &gamma)
    {
      if (a.rows() != 2 * n || a.cols() != 2 * n)
        return false;
      gamma = -a(0, n);
      return a.topLeftCorner(n, n).isIdentity(0.0) &&
             (a.topRightCorner(n, n) + gamma * Eigen::MatrixXd::Identity(n, n)).isZero(0.0);
    }

    int eigen_lu_setup(SUNLinearSolver solver, SUNMatrix A)
    {
      auto      &d = *static_cast<EigenLu *>(solver->content);
      const auto rows = SM_ROWS_D(A), columns = SM_COLUMNS_D(A);
      const Eigen::Map<const Eigen::MatrixXd> a(SM_DATA_D(A), rows, columns);
      const Eigen::Index                      n = rows / 2;
      d.clear_secant_updates();
      d.last_rhs.resize(0);
      ++d.setups;
      d.schur = rows % 2 == 0 && has_velocity_block_structure(a, n, d.gamma);
      if (d.schur)
        {
          d.lower_left = a.bottomLeftCorner(n, n);
          d.lu.compute(a.bottomRightCorner(n, n) + d.gamma * d.lower_left); // A₂₂ - A₂₁(-γI)
        }
      else
        d.lu.compute(a);
      return 0;
    }

    int eigen_lu_solve(SUNLinearSolver solver, SUNMatrix, N_Vector x, N_Vector b, realtype)
    {
      auto      &d    = *static_cast<EigenLu *>(solver->content);
      const auto size = d.schur ? 2 * d.lu.rows() : d.lu.rows();
      const Eigen::Map<const Eigen::VectorXd> rhs(N_VGetArrayPointer(b), size);
      Eigen::Map<Eigen::VectorXd>             solution(N_VGetArrayPointer(x), size);
      d.update_stiffness();
      if (d.krylov)
        {
          d.solve_krylov(rhs, solution);
          return 0;
        }
      if (d.arkode == nullptr)
        {
          solution = d.solve_set_up(rhs);
          return 0;
        }
      d.update_secant(rhs);
      d.last_rhs      = rhs;
      d.last_solution = d.solve_updated(rhs);
      solution        = d.last_solution;
      return 0;
    }

    int eigen_lu_free(SUNLinearSolver solver)
    {
      if (auto *d = static_cast<EigenLu *>(solver->content); d && d->weights)
        N_VDestroy(d->weights);
      delete static_cast<EigenLu *>(solver->content);
      solver->content = nullptr;
      SUNLinSolFreeEmpty(solver);
      return 0;
    }
  } // namespace

  namespace
  {
    void add_term(const double *row, const Eigen::VectorXd &by_position, double by_velocity, StiffnessChange &change)
    {
      const auto n = static_cast<std::size_t>(by_position.size());
      change.rows.insert(change.rows.end(), row, row + n);
      change.by_position.insert(change.by_position.end(), by_position.data(), by_position.data() + n);
      change.by_velocity.push_back(by_velocity);
      ++change.terms;
    }
  } // namespace

  void add_ball_change(const BallContacts::Linearisation &now, const BallContacts::Linearisation &at_jacobian,
                       std::size_t n, StiffnessChange &change)
  {
    const auto size = static_cast<Eigen::Index>(n);
    for (const auto *state : {&now, &at_jacobian})
      {
        const double sign = state == &now ? 1.0 : -1.0;
        for (std::size_t j = 0; j < state->by_deflection.size(); ++j)
          {
            const double k = state->by_deflection[j], c = state->by_deflection_rate[j];
            if (k == 0.0 && c == 0.0)
              continue;
            const Eigen::Map<const Eigen::VectorXd> r(state->rows.data() + j * n, size),
              slope(state->slopes.data() + j * n, size);
            add_term(r.data(), sign * (k * r + c * state->cage_speed * slope), sign * c, change);
          }
      }
  }

  void add_slip_change(const std::vector<double> &rows, const std::vector<double> &changes, std::size_t n,
                       StiffnessChange &change)
  {
    const auto size = static_cast<Eigen::Index>(n);
    for (std::size_t cell = 0; cell < changes.size() / 4; ++cell)
      {
        const Eigen::Map<const Eigen::VectorXd> t0(rows.data() + 2 * cell * n, size), t1(t0.data() + n, size);
        const double *a = changes.data() + 4 * cell; // A ΔS_c, row-major
        add_term(t0.data(), a[0] * t0 + a[1] * t1, 0.0, change);
        add_term(t1.data(), a[2] * t0 + a[3] * t1, 0.0, change);
      }
  }

  SUNLinearSolver make_newton_solver(SUNContext context, const NewtonUpdates &updates)
  {
    SUNLinearSolver solver = SUNLinSolNewEmpty(context);
    auto           *d      = new EigenLu;
    if (updates.mass != nullptr && updates.evaluations && updates.change)
      d->updates = updates;
    solver->content      = d;
    solver->ops->gettype = eigen_lu_type;
    solver->ops->setup   = eigen_lu_setup;
    solver->ops->solve   = eigen_lu_solve;
    solver->ops->free    = eigen_lu_free;
    return solver;
  }

  void set_secant_updates(SUNLinearSolver solver, void *arkode)
  {
    static_cast<EigenLu *>(solver->content)->arkode = arkode;
  }

  void set_krylov(SUNLinearSolver solver, void *arkode, const JacobianProducts &products)
  {
    auto *d     = static_cast<EigenLu *>(solver->content);
    d->arkode   = arkode;
    d->krylov   = true;
    d->products = products;
  }
} // namespace fretsim::coupling
