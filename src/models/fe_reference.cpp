#include <fretsim/contact/bristle.h>
#include <fretsim/contact/convolution.h>
#include <fretsim/models/fe_reference.h>
#include <fretsim/models/ring_stress.h>

#include "table_convolution.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace fretsim::models
{
  namespace
  {
    using detail::StackedConvolution;
    using detail::Vector;

    double dot(const Vector &a, const Vector &b)
    {
      double sum = 0.0;
      for (std::size_t k = 0; k < a.size(); ++k)
        sum += a[k] * b[k];
      return sum;
    }

  } // namespace

  struct FeReference::Impl
  {
    const InterfaceInfluence &ring;
    const InterfaceInfluence *housing;
    ReferenceInterface        law;
    ReferenceSettings         settings;
    fem::CylinderGrid         grid;
    int                       nx, ny, period;
    std::size_t               cells, n; ///< unknowns: [p | τ_θ | τ_z] × cells
    double                    area;
    bool                      friction;
    std::unique_ptr<StackedConvolution> compliance;
    std::unique_ptr<contact::SurfaceConvolution> preconditioner;
    std::unique_ptr<RingStressTable>             stress; ///< null: tables without stresses
    std::array<Vector, 6>     rigid;                         ///< B: rigid motions at the cells, [3][cell]
    Vector                    tangential_self; ///< the grid's own tangential compliance at each cell [m/Pa]

    // State: tractions (p and the bristles' τ_b = −shear on the ring), the
    // committed bristles and relative slip, the last loads.
    Vector         x, tau_committed, slip_committed;
    ReferenceLoads last;
    bool           started = false;

    Impl(const InterfaceInfluence &ring_in, const InterfaceInfluence *housing_in, const ReferenceInterface &law_in,
         const ReferenceSettings &settings_in)
      : ring(ring_in)
      , housing(housing_in)
      , law(law_in)
      , settings(settings_in)
      , grid(ring_in.grid)
    {
      nx = grid.nx;
      ny = grid.ny;
      if (housing && (housing->grid.nx != nx || housing->grid.ny != ny))
        throw std::invalid_argument("models::FeReference: the housing's tables are on another grid");
      if (!(law.normal_stiffness > 0.0) || !(law.tangential_stiffness > 0.0) || law.friction_coefficient < 0.0)
        throw std::invalid_argument("models::FeReference: need k_n > 0, k_t > 0 and mu >= 0");
      period   = housing ? std::lcm(ring.period, housing->period) : ring.period;
      cells    = grid.size();
      n        = 3 * cells;
      area     = grid.cell_area();
      friction = law.friction_coefficient > 0.0;
      build_compliance();
      if (ring.layers() > 0)
        stress = std::make_unique<RingStressTable>(ring);
      build_rigid_motions();
      build_tangential_self();
      x.assign(n, 0.0);
      tau_committed.assign(2 * cells, 0.0);
      slip_committed.assign(2 * cells, 0.0);
    }

    /// The compliance kernel: row c (0: closing of the gap, −(u_r,ring −
    /// u_r,housing); 1, 2: −(relative tangential displacement)) per unit p
    /// (k = 0) or bristle traction τ_b (k = 1, 2), which pushes the ring along
    /// −τ_b and the housing along +τ_b [m/Pa]. The table of a load on column
    /// ph is the body's phase ph mod P_body shifted by the multiple of P_body
    /// below ph.
    void build_compliance()
    {
      const auto kernel = [this](int ph, int b_row, int i, int a_row) {
        const int k = b_row / ny, b = b_row % ny, c = a_row / ny, a = a_row % ny;
        auto      shifted = [&](int body_period) { return ((i - (ph - ph % body_period)) % nx + nx) % nx; };
        const std::size_t cell_r = static_cast<std::size_t>(a) * nx + shifted(ring.period);
        const double      sign   = k == 0 ? 1.0 : -1.0;
        double value = -sign * ring.displacement[ring.displacement_index(ph % ring.period, k, b, cell_r, c)];
        if (housing)
          {
            const std::size_t cell_h = static_cast<std::size_t>(a) * nx + shifted(housing->period);
            value += housing->displacement[housing->displacement_index(ph % housing->period, k, b, cell_h, c)];
          }
        return area * value;
      };
      compliance = std::make_unique<StackedConvolution>(nx, 3 * ny, period, kernel);
      Vector diagonal(static_cast<std::size_t>(3 * ny), 1.0 / law.tangential_stiffness);
      std::fill(diagonal.begin(), diagonal.begin() + ny, 1.0 / law.normal_stiffness);
      preconditioner = std::make_unique<contact::SurfaceConvolution>(
        StackedConvolution(nx, 3 * ny, period, kernel, diagonal).inverse());
    }

    /// The diagonal of the compliance's tangential rows, max of the two
    /// directions, per cell (it repeats along θ with the period).
    void build_tangential_self()
    {
      tangential_self.assign(cells, 0.0);
      Vector unit(n, 0.0), y;
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < period && i < nx; ++i)
          for (int t = 1; t <= 2; ++t)
            {
              const std::size_t k = t * cells + static_cast<std::size_t>(j) * nx + i;
              unit[k]             = 1.0;
              apply_compliance(unit, y);
              unit[k] = 0.0;
              for (int i2 = i; i2 < nx; i2 += period)
                {
                  const std::size_t c = static_cast<std::size_t>(j) * nx + i2;
                  tangential_self[c]  = std::max(tangential_self[c], y[k]);
                }
            }
    }

    /// The six rigid motions of the ring at the cell centres, (u_r, u_θ, u_z).
    void build_rigid_motions()
    {
      for (auto &b : rigid)
        b.assign(n, 0.0);
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          {
            const std::size_t c  = static_cast<std::size_t>(j) * nx + i;
            const double      th = grid.x(i) / grid.radius, cs = std::cos(th), sn = std::sin(th), z = grid.y(j),
                         R = grid.radius;
            const double u[6][3] = {{cs, -sn, 0.0},        {sn, cs, 0.0},          {0.0, 0.0, 1.0},
                                    {-z * sn, -z * cs, R * sn}, {z * cs, -z * sn, -R * cs}, {0.0, R, 0.0}};
            for (int m = 0; m < 6; ++m)
              for (int d = 0; d < 3; ++d)
                rigid[m][d * cells + c] = u[m][d];
          }
    }

    /// The balls' share: ring displacement (u_r, u_θ, u_z) per cell [3][cell],
    /// and the resultant's work on the rigid motions.
    void ball_displacement(const ReferenceLoads &loads, Vector &u, std::array<double, 6> &force) const
    {
      u.assign(n, 0.0);
      force.fill(0.0);
      for (std::size_t b = 0; b < loads.ball_angles.size(); ++b)
        {
          const double q = loads.ball_loads[b];
          if (q == 0.0)
            continue;
          const double psi = loads.ball_angles[b];
          force[0] += q * std::cos(psi);
          force[1] += q * std::sin(psi);
          add_ball(psi, q, ring.ball_displacement, 3, 1, [&](std::size_t cell, int comp, double value) {
            u[static_cast<std::size_t>(comp) * cells + cell] += value;
          });
        }
    }

    template <typename Add>
    void add_ball(double psi, double q, const Vector &table, int components, std::size_t layers, Add add) const
    {
      detail::add_ball_tables(grid, ring.period, ring.ball_footprint_loads, psi, q, table, components, layers, add);
    }

    // ---- One increment.

    /// y = C x on every cell.
    void apply_compliance(const Vector &v, Vector &y) const { compliance->apply(v, y); }

    struct Increment
    {
      std::array<double, 6> force{}; ///< ball loads' work on the rigid motions / cell area
      Vector                ball;   ///< ring displacement from the balls [3][cell]
    };

    /// The operator of one linear solve on the active unknowns: C + L, L the
    /// layer's and the bristles' compliance (`diagonal` on every row and
    /// `coupling` [cell] between a cell's two tangential rows, symmetric
    /// positive definite per cell), the projection off the free rigid
    /// motions, and the preconditioner: the closed grid's inverse with the
    /// layer and the stuck bristles' compliance, except on the tangential
    /// rows of the cells whose bristle compliance (the smaller eigenvalue of
    /// their 2 × 2 block of L) exceeds the grid's own there plus a stuck
    /// bristle's (sliding cells), which take the inverse of that block.
    struct ActiveOperator
    {
      using Motions = Eigen::Matrix<double, 6, 1>;
      const Impl              &impl;
      const std::vector<char> &active;
      const Vector            &diagonal, &coupling;
      std::array<bool, 6>      free_modes;
      std::vector<char>        loose;
      Eigen::Matrix<double, 6, 6> pinv = Eigen::Matrix<double, 6, 6>::Zero(); ///< of BᵀB on the free motions
      mutable Vector           r_held;

      ActiveOperator(const Impl &impl_in, const std::vector<char> &active_in, const Vector &diagonal_in,
                     const Vector &coupling_in, const std::array<bool, 6> &free_modes_in)
        : impl(impl_in)
        , active(active_in)
        , diagonal(diagonal_in)
        , coupling(coupling_in)
        , free_modes(free_modes_in)
        , loose(impl.cells, 0)
      {
        const std::size_t cells = impl.cells;
        for (std::size_t c = 0; c < cells; ++c)
          if (active[cells + c] && active[2 * cells + c])
            {
              const double a = diagonal[cells + c], b = coupling[c], d = diagonal[2 * cells + c];
              const double smallest = 0.5 * (a + d) - std::sqrt(0.25 * (a - d) * (a - d) + b * b);
              loose[c] = smallest > impl.tangential_self[c] + 1.0 / impl.law.tangential_stiffness;
            }
        Eigen::Matrix<double, 6, 6> gram = Eigen::Matrix<double, 6, 6>::Zero();
        for (int a = 0; a < 6; ++a)
          for (int b = 0; b <= a; ++b)
            if (free_modes[a] && free_modes[b])
              {
                double sum = 0.0;
                for (std::size_t k = 0; k < impl.n; ++k)
                  if (active[k])
                    sum += impl.rigid[a][k] * impl.rigid[b][k];
                gram(a, b) = gram(b, a) = sum;
              }
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(gram);
        const double largest = std::max(eigen.eigenvalues().maxCoeff(), 1e-300);
        for (int m = 0; m < 6; ++m)
          if (eigen.eigenvalues()(m) > 1e-10 * largest)
            pinv += eigen.eigenvectors().col(m) * eigen.eigenvectors().col(m).transpose() / eigen.eigenvalues()(m);
      }

      /// Bᵀ v on the free motions and active rows.
      Motions bt(const Vector &v) const
      {
        Motions out = Motions::Zero();
        for (int m = 0; m < 6; ++m)
          if (free_modes[m])
            for (std::size_t k = 0; k < impl.n; ++k)
              if (active[k])
                out(m) += impl.rigid[m][k] * v[k];
        return out;
      }

      /// v += factor B c on the active rows.
      void add_b(const Motions &c, Vector &v, double factor) const
      {
        for (int m = 0; m < 6; ++m)
          if (c(m) != 0.0)
            for (std::size_t k = 0; k < impl.n; ++k)
              if (active[k])
                v[k] += factor * c(m) * impl.rigid[m][k];
      }

      void project(Vector &v) const { add_b(pinv * bt(v), v, -1.0); }

      void apply(const Vector &v, Vector &out) const
      {
        const std::size_t cells = impl.cells;
        impl.apply_compliance(v, out);
        for (std::size_t k = 0; k < impl.n; ++k)
          out[k] = active[k] ? out[k] + diagonal[k] * v[k] : 0.0;
        for (std::size_t c = 0; c < cells; ++c)
          if (coupling[c] != 0.0 && active[cells + c] && active[2 * cells + c])
            {
              out[cells + c] += coupling[c] * v[2 * cells + c];
              out[2 * cells + c] += coupling[c] * v[cells + c];
            }
      }

      void precondition(const Vector &r, Vector &z) const
      {
        const std::size_t cells = impl.cells;
        r_held                  = r;
        for (std::size_t c = 0; c < cells; ++c)
          if (loose[c])
            r_held[cells + c] = r_held[2 * cells + c] = 0.0;
        impl.compliance->apply_with(*impl.preconditioner, r_held, z);
        for (std::size_t k = 0; k < impl.n; ++k)
          if (!active[k])
            z[k] = 0.0;
        for (std::size_t c = 0; c < cells; ++c)
          if (loose[c])
            {
              const double a = diagonal[cells + c], b = coupling[c], d = diagonal[2 * cells + c], det = a * d - b * b;
              z[cells + c]     = (d * r[cells + c] - b * r[2 * cells + c]) / det;
              z[2 * cells + c] = (a * r[2 * cells + c] - b * r[cells + c]) / det;
            }
        project(z);
      }
    };

    /// Projected preconditioned conjugate gradients on the active unknowns,
    /// the others held at their values in `solution`, the rigid motions not
    /// in `free_modes` held at theirs in `e`:
    ///   (C + L) x − B e = rhs on the active rows, Bᵀ x = f for the free modes.
    /// Returns the iterations.
    int solve_linear(const std::vector<char> &active, const Vector &diagonal, const Vector &coupling,
                     const Vector &given_rhs, const std::array<double, 6> &f, const std::array<bool, 6> &free_modes,
                     Vector &solution, std::array<double, 6> &e) const
    {
      const ActiveOperator op(*this, active, diagonal, coupling, free_modes);
      // What the held unknowns and motions contribute.
      Vector held(n, 0.0), rhs(n, 0.0), y;
      for (std::size_t k = 0; k < n; ++k)
        if (!active[k])
          held[k] = solution[k];
      apply_compliance(held, y);
      for (std::size_t k = 0; k < n; ++k)
        if (active[k])
          {
            rhs[k] = given_rhs[k] - y[k];
            for (int m = 0; m < 6; ++m)
              if (!free_modes[m])
                rhs[k] += e[m] * rigid[m][k];
          }
      ActiveOperator::Motions f_vec = ActiveOperator::Motions::Zero();
      for (int m = 0; m < 6; ++m)
        if (free_modes[m])
          f_vec(m) = f[m] - dot(rigid[m], held);

      Vector x(n, 0.0);
      for (std::size_t k = 0; k < n; ++k)
        if (active[k])
          x[k] = solution[k];
      op.add_b(op.pinv * (f_vec - op.bt(x)), x, 1.0);
      const int its = conjugate_gradients(op, rhs, x);
      // The free motions: B e = (C + diag) x − rhs on the active rows.
      Vector q(n);
      op.apply(x, q);
      for (std::size_t k = 0; k < n; ++k)
        q[k] = active[k] ? q[k] - rhs[k] : 0.0;
      const ActiveOperator::Motions multipliers = op.pinv * op.bt(q);
      for (int m = 0; m < 6; ++m)
        if (free_modes[m])
          e[m] = multipliers(m);
      for (std::size_t k = 0; k < n; ++k)
        solution[k] = active[k] ? x[k] : held[k];
      return its;
    }

    /// Preconditioned conjugate gradients of `op` x = rhs from x, in the
    /// subspace the projection keeps; throws if the residual does not fall
    /// below the linear tolerance of the projected right-hand side.
    int conjugate_gradients(const ActiveOperator &op, const Vector &rhs, Vector &x) const
    {
      Vector r(n), z(n), p(n), q(n);
      op.apply(x, q);
      for (std::size_t k = 0; k < n; ++k)
        r[k] = op.active[k] ? rhs[k] - q[k] : 0.0;
      op.project(r);
      Vector rhs_active = rhs;
      op.project(rhs_active);
      const double stop = settings.linear_tolerance * std::max(std::sqrt(dot(rhs_active, rhs_active)), 1e-300);
      op.precondition(r, z);
      p               = z;
      double    rz    = dot(r, z);
      int       its   = 0;
      const int limit = static_cast<int>(std::min<std::size_t>(n, 5000));
      while (std::sqrt(dot(r, r)) > stop && its < limit)
        {
          op.apply(p, q);
          const double alpha = rz / dot(p, q);
          for (std::size_t k = 0; k < n; ++k)
            {
              x[k] += alpha * p[k];
              r[k] -= alpha * q[k];
            }
          op.project(r);
          op.precondition(r, z);
          const double rz_new = dot(r, z);
          const double beta   = rz_new / rz;
          rz                  = rz_new;
          for (std::size_t k = 0; k < n; ++k)
            p[k] = z[k] + beta * p[k];
          ++its;
        }
      if (std::sqrt(dot(r, r)) > stop)
        throw std::runtime_error("the full-FE reference's linear solve did not converge in " + std::to_string(its) +
                                 " conjugate gradient iterations");
      return its;
    }

    /// Relative displacements from tractions and rigid motion: gap closing
    /// d (penetration) [cell] and slip s [2][cell].
    void kinematics(const Vector &traction, const std::array<double, 6> &e, const Increment &inc, Vector &d,
                    Vector &s) const
    {
      Vector y;
      apply_compliance(traction, y);
      d.assign(cells, 0.0);
      s.assign(2 * cells, 0.0);
      for (std::size_t c = 0; c < cells; ++c)
        {
          double rigid_r = 0.0, rigid_t = 0.0, rigid_z = 0.0;
          for (int m = 0; m < 6; ++m)
            {
              rigid_r += e[m] * rigid[m][c];
              rigid_t += e[m] * rigid[m][cells + c];
              rigid_z += e[m] * rigid[m][2 * cells + c];
            }
          d[c]         = law.radial_interference + inc.ball[c] + rigid_r - y[c];
          s[c]         = inc.ball[cells + c] + rigid_t - y[cells + c];
          s[cells + c] = inc.ball[2 * cells + c] + rigid_z - y[2 * cells + c];
        }
    }

    /// The bristles' law at cell c linearised at the slip and pressure so
    /// far, into the cell's rows of `diagonal`, `coupling` and `rhs`: the
    /// secant form (geometrically relaxed towards the new secant unless
    /// `restart`, since the secant swings where the slip turns) or the
    /// tangent.
    void linearise_law(std::size_t c, const Increment &inc, const Vector &slip_increment, bool secant, bool restart,
                       Vector &diagonal, Vector &coupling, Vector &rhs) const
    {
      const double mu = law.friction_coefficient, kt = law.tangential_stiffness, mu_p = mu * x[c];
      const double ds_x = slip_increment[c], ds_y = slip_increment[cells + c];
      const double tau_x = tau_committed[c], tau_y = tau_committed[cells + c];
      const double numer        = std::hypot(tau_x + kt * ds_x, tau_y + kt * ds_y);
      double       secant_ratio = 1.0 + kt * std::hypot(ds_x, ds_y) / mu_p;
      if (numer > mu_p * secant_ratio)
        secant_ratio = numer / mu_p; // the Coulomb clamp
      if (secant)
        {
          for (int t = 0; t < 2; ++t)
            {
              const std::size_t k = (1 + t) * cells + c, h = t * cells + c;
              diagonal[k] = restart || diagonal[k] <= 0.0 ? secant_ratio / kt
                                                          : std::sqrt(diagonal[k] * secant_ratio / kt);
              rhs[k]      = tau_committed[h] / kt + inc.ball[k] - slip_committed[h];
            }
          coupling[c] = 0.0;
          return;
        }
      // The tangent: τ ≈ F + K (Δs − Δs⁰), K the symmetric part of ∂τ'/∂Δs
      // with its eigenvalues kept above a fraction of the secant's
      // k_t/secant (where the cell slides, τ' hardly changes along the
      // slip). In compliance form, with Δs = s_0 + B e − (C x)_t − s_old:
      //   (C x)_t + K⁻¹ τ − B e = K⁻¹ F − Δs⁰ + s_0 − s_old.
      contact::BristleStepDerivatives derivatives;
      const bool                      sliding_on = std::hypot(tau_x, tau_y) >= (1.0 - 1e-3) * mu_p;
      const contact::BristleStep      law_now =
        contact::bristle_step(tau_x, tau_y, kt, mu, x[c], ds_x, ds_y, sliding_on, derivatives);
      Eigen::Matrix2d stiffness;
      stiffness << derivatives.by_slip[0][0], derivatives.by_slip[0][1], derivatives.by_slip[1][0],
        derivatives.by_slip[1][1];
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> split(0.5 * (stiffness + stiffness.transpose()));
      const double          floor   = settings.tangent_floor * kt / secant_ratio;
      const Eigen::Vector2d inverse = split.eigenvalues().cwiseMax(floor).cwiseInverse();
      const Eigen::Matrix2d compliance_cell =
        split.eigenvectors() * inverse.asDiagonal() * split.eigenvectors().transpose();
      const Eigen::Vector2d rhs_cell =
        compliance_cell * Eigen::Vector2d(law_now.x, law_now.y) - Eigen::Vector2d(ds_x, ds_y) +
        Eigen::Vector2d(inc.ball[cells + c] - slip_committed[c], inc.ball[2 * cells + c] - slip_committed[cells + c]);
      diagonal[cells + c]     = compliance_cell(0, 0);
      diagonal[2 * cells + c] = compliance_cell(1, 1);
      coupling[c]             = compliance_cell(0, 1);
      rhs[cells + c]          = rhs_cell(0);
      rhs[2 * cells + c]      = rhs_cell(1);
    }

    /// The contact set: cells pulled apart leave, cells penetrating join
    /// (beyond the tolerance, so that a cell at the edge, whose pressure is
    /// round-off, does not flip back and forth). Returns the changes.
    int update_contact_set(std::vector<char> &contact, const Vector &d, double p_max)
    {
      const double p_tolerance = settings.tolerance * p_max, d_tolerance = p_tolerance / law.normal_stiffness;
      int          changes     = 0;
      for (std::size_t c = 0; c < cells; ++c)
        if (contact[c] && x[c] < -p_tolerance)
          {
            contact[c] = 0;
            x[c] = x[cells + c] = x[2 * cells + c] = 0.0;
            ++changes;
          }
        else if (!contact[c] && d[c] > d_tolerance)
          {
            contact[c] = 1;
            ++changes;
          }
      return changes;
    }

    /// The largest difference between the law at the slip the solves give
    /// and the tractions they give [Pa].
    double law_residual(const std::vector<char> &contact, const Vector &slip_increment) const
    {
      const double mu = law.friction_coefficient, kt = law.tangential_stiffness;
      double       change = 0.0;
      for (std::size_t c = 0; c < cells; ++c)
        if (friction && contact[c])
          {
            const contact::BristleStep exact =
              contact::bristle_step(tau_committed[c], tau_committed[cells + c], kt, mu * std::max(x[c], 0.0),
                                    slip_increment[c], slip_increment[cells + c]);
            change = std::max({change, std::abs(exact.x - x[cells + c]), std::abs(exact.y - x[2 * cells + c])});
          }
      return change;
    }

    /// Commits the law's exact tractions and the slip they went with.
    void commit(const std::vector<char> &contact, const Vector &slip_increment, const Vector &s)
    {
      const double mu = law.friction_coefficient, kt = law.tangential_stiffness;
      for (std::size_t c = 0; c < cells; ++c)
        {
          if (friction && contact[c] && x[c] > 0.0)
            {
              const contact::BristleStep exact =
                contact::bristle_step(tau_committed[c], tau_committed[cells + c], kt, mu * x[c], slip_increment[c],
                                      slip_increment[cells + c]);
              x[cells + c]     = exact.x;
              x[2 * cells + c] = exact.y;
            }
          else
            x[cells + c] = x[2 * cells + c] = 0.0;
          tau_committed[c]         = x[cells + c];
          tau_committed[cells + c] = x[2 * cells + c];
        }
      slip_committed = s;
    }

    /// One increment to `loads`: returns its iterations and linear iterations.
    std::pair<int, int> increment(const ReferenceLoads &loads, std::array<double, 6> &e)
    {
      Increment inc;
      ball_displacement(loads, inc.ball, inc.force);
      for (double &f : inc.force)
        f /= area;
      const double mu = law.friction_coefficient;
      // right-hand side: d_0 on the normal rows; τ_old/k_t + s_0 − s_old on the tangential rows
      Vector rhs(n, 0.0), diagonal(n, 0.0);
      for (std::size_t c = 0; c < cells; ++c)
        {
          rhs[c]      = law.radial_interference + inc.ball[c];
          diagonal[c] = 1.0 / law.normal_stiffness;
        }
      constexpr std::array<bool, 6> all_modes{true, true, true, true, true, true};
      std::vector<char>             contact(cells), active(n);
      for (std::size_t c = 0; c < cells; ++c)
        contact[c] = started ? x[c] > 0.0 : 1;
      Vector     d, s, slip_increment(2 * cells, 0.0), coupling(cells, 0.0);
      int        iterations = 0, linear = 0;
      // The tangent while the law's residual shrinks; once it grows (a slip
      // turning, the contact set moving), the secant iterations.
      double     last_change  = std::numeric_limits<double>::infinity();
      bool       secant_now   = !(friction && !settings.secant_iterations);
      int        secant_start = 0;
      const auto switch_to_secant = [&] {
        secant_now   = true;
        secant_start = iterations + 1;
      };
      for (; iterations < settings.max_iterations; ++iterations)
        {
          // A cell without pressure yet transmits no shear in this solve.
          std::fill(active.begin(), active.end(), 0);
          std::copy(contact.begin(), contact.end(), active.begin());
          for (std::size_t c = 0; c < cells && friction; ++c)
            {
              if (!contact[c] || !(mu * x[c] > 0.0))
                {
                  x[cells + c] = x[2 * cells + c] = 0.0;
                  coupling[c]                     = 0.0;
                  continue;
                }
              active[cells + c] = active[2 * cells + c] = 1;
              linearise_law(c, inc, slip_increment, secant_now, iterations == secant_start, diagonal, coupling, rhs);
            }
          const Vector                start   = x;
          const std::array<double, 6> start_e = e;
          try
            {
              linear += solve_linear(active, diagonal, coupling, rhs, inc.force, all_modes, x, e);
            }
          catch (const std::runtime_error &)
            {
              if (secant_now)
                throw;
              // the linear solve with a soft tangent failed: again with the secant
              x = start;
              e = start_e;
              switch_to_secant();
              continue;
            }
          kinematics(x, e, inc, d, s);
          for (std::size_t h = 0; h < 2 * cells; ++h)
            slip_increment[h] = s[h] - slip_committed[h];
          const double p_max    = *std::max_element(x.begin(), x.begin() + cells);
          const int    changes  = update_contact_set(contact, d, std::max(p_max, 0.0));
          const double relative = law_residual(contact, slip_increment) / (std::max(mu, 1.0) * std::max(p_max, 1e-300));
          const bool   grew     = relative > last_change;
          last_change           = relative;
          if (!secant_now && grew)
            switch_to_secant();
          if (changes == 0 && relative <= settings.tolerance)
            {
              ++iterations;
              break;
            }
        }
      if (iterations >= settings.max_iterations)
        throw std::runtime_error("the full-FE reference's increment at t = " + std::to_string(loads.time) +
                                 " s did not converge in " + std::to_string(settings.max_iterations) +
                                 " contact-set and friction-law iterations");
      commit(contact, slip_increment, s);
      return {iterations, linear};
    }

    /// The ring's stresses on the tables' layers under the balls and the
    /// ring's tractions (p pushing in, shear along +θ, +z).
    Vector ring_stress(const ReferenceLoads &loads, const Vector &pressure, const Vector &shear_x,
                       const Vector &shear_y) const
    {
      Vector out;
      if (stress)
        stress->evaluate(loads.ball_angles, loads.ball_loads, pressure, shear_x, shear_y, out);
      return out;
    }

    ReferenceState state(const ReferenceLoads &loads, const std::array<double, 6> &e, int iterations,
                         int linear) const
    {
      ReferenceState out;
      out.time              = loads.time;
      out.rigid_motion      = e;
      out.iterations        = iterations;
      out.linear_iterations = linear;
      out.pressure.assign(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(cells));
      out.shear_x.resize(cells);
      out.shear_y.resize(cells);
      for (std::size_t c = 0; c < cells; ++c)
        {
          out.shear_x[c] = -x[cells + c];
          out.shear_y[c] = -x[2 * cells + c];
        }
      out.stress = ring_stress(loads, out.pressure, out.shear_x, out.shear_y);
      return out;
    }
  };

  FeReference::FeReference(const InterfaceInfluence &ring, const InterfaceInfluence *housing,
                           const ReferenceInterface &law, const ReferenceSettings &settings)
    : impl(std::make_unique<Impl>(ring, housing, law, settings))
  {}
  FeReference::~FeReference() = default;

  std::vector<double> FeReference::ring_stress(const ReferenceLoads &loads, const std::vector<double> &pressure,
                                              const std::vector<double> &shear_x,
                                              const std::vector<double> &shear_y) const
  {
    return impl->ring_stress(loads, pressure, shear_x, shear_y);
  }

  ReferenceState FeReference::advance(const ReferenceLoads &next)
  {
    Impl &m = *impl;
    if (next.ball_angles.size() != next.ball_loads.size())
      throw std::invalid_argument("models::FeReference: ball angles and loads differ in number");
    ReferenceLoads from = m.last;
    if (!m.started)
      {
        from             = next;
        from.ball_loads.assign(next.ball_loads.size(), 0.0);
      }
    std::array<double, 6> e{};
    int                   iterations = 0, linear = 0;
    for (int step = 1; step <= m.settings.substeps; ++step)
      {
        const double   w = double(step) / m.settings.substeps;
        ReferenceLoads loads;
        loads.time = (1.0 - w) * from.time + w * next.time;
        for (std::size_t b = 0; b < next.ball_angles.size(); ++b)
          {
            // the cage turns forward: unwrap the angle from the last instant's
            double to = next.ball_angles[b];
            const double start = b < from.ball_angles.size() ? from.ball_angles[b] : to;
            to = start + std::remainder(to - start, 2.0 * M_PI);
            loads.ball_angles.push_back((1.0 - w) * start + w * to);
            loads.ball_loads.push_back((1.0 - w) * (b < from.ball_loads.size() ? from.ball_loads[b] : 0.0) +
                                       w * next.ball_loads[b]);
          }
        const auto [its, lin] = m.increment(loads, e);
        m.started             = true;
        iterations += its;
        linear += lin;
      }
    m.last = next;
    return m.state(next, e, iterations, linear);
  }
} // namespace fretsim::models
