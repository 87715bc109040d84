#include <fretsim/models/reduced_statics.h>

#include <fretsim/coupling/bearing.h>
#include <fretsim/coupling/local_compliance.h>
#include <fretsim/coupling/ring_coupling.h>

#include <fretsim/fem/shifted_static_solver.h>
#include <fretsim/fem/surface_grid_map.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fretsim::models
{
  namespace
  {
    /// Rows of a row-major [items][n_full] operator, restricted to `columns`.
    std::vector<double> restrict_columns(const std::vector<double> &op, std::size_t n_full,
                                         const std::vector<std::size_t> &columns)
    {
      const std::size_t   rows = n_full == 0 ? 0 : op.size() / n_full;
      std::vector<double> result(rows * columns.size());
      for (std::size_t r = 0; r < rows; ++r)
        for (std::size_t c = 0; c < columns.size(); ++c)
          result[r * columns.size() + c] = op[r * n_full + columns[c]];
      return result;
    }

    /// Inertia relief of a generalised load, g - M_r R (Rᵀ M_r R)⁻¹ Rᵀ g (Rᵀ g
    /// is g's first six entries): the reduced counterpart of the full model's
    /// f - M Φ Φᵀ f (fem/shifted_static_solver.h).
    void relieve(const Truncation &t, std::vector<double> &g)
    {
      const std::vector<double> a =
        cholesky_solve(t.rigid_factor, rigid_modes, std::vector<double>(g.begin(), g.begin() + rigid_modes));
      for (std::size_t j = 0; j < t.n; ++j)
        for (std::size_t r = 0; r < rigid_modes; ++r)
          g[j] -= t.mass_rigid[j * rigid_modes + r] * a[r];
    }
  } // namespace

  Truncation truncate(const reduction::ReducedModel &model, unsigned int fixed_interface, unsigned int constraint,
                      const std::vector<std::size_t> &raceway_points, double sigma)
  {
    const auto       &m      = model.matrices;
    const std::size_t n_full = m.size();
    std::vector<std::size_t> columns;
    for (unsigned int j = 0; j < constraint; ++j)
      columns.push_back(j);
    for (unsigned int j = 0; j < fixed_interface; ++j)
      columns.push_back(m.n_constraint + j);
    Truncation t;
    t.fixed_interface = fixed_interface;
    t.constraint      = constraint;
    t.n               = columns.size();
    t.whole_model     = fixed_interface == m.n_modal && constraint == m.n_constraint;
    t.shifted.resize(t.n * t.n);
    for (std::size_t a = 0; a < t.n; ++a)
      for (std::size_t b = 0; b < t.n; ++b)
        {
          const std::size_t k = columns[a] * n_full + columns[b];
          t.shifted[a * t.n + b] = m.stiffness[k] - sigma * m.mass[k];
        }
    t.grid_displacement = restrict_columns(model.interface_grid.displacement, n_full, columns);
    t.grid_stress       = restrict_columns(model.interface_grid.stress, n_full, columns);
    std::vector<double> race;
    for (const std::size_t p : raceway_points)
      race.insert(race.end(), model.sample_points.stress.begin() + p * 6 * n_full,
                  model.sample_points.stress.begin() + (p + 1) * 6 * n_full);
    t.raceway_stress = restrict_columns(race, n_full, columns);
    t.approach       = restrict_columns(model.raceway.approach, n_full, columns);
    t.n_angles       = model.raceway.angles.size();
    t.footprint_loads = model.raceway.footprint_loads();
    t.mass_rigid.resize(t.n * rigid_modes);
    t.rigid_factor.resize(rigid_modes * rigid_modes);
    for (std::size_t a = 0; a < t.n; ++a)
      for (std::size_t r = 0; r < rigid_modes; ++r)
        t.mass_rigid[a * rigid_modes + r] = m.mass[columns[a] * n_full + r];
    for (std::size_t r = 0; r < rigid_modes; ++r)
      for (std::size_t c = 0; c < rigid_modes; ++c)
        t.rigid_factor[r * rigid_modes + c] = m.mass[r * n_full + c];
    cholesky(t.rigid_factor, rigid_modes);
    return t;
  }

  void cholesky(std::vector<double> &a, std::size_t n)
  {
    for (std::size_t j = 0; j < n; ++j)
      {
        double d = a[j * n + j];
        for (std::size_t k = 0; k < j; ++k)
          d -= a[j * n + k] * a[j * n + k];
        if (!(d > 0.0))
          throw std::runtime_error("reduced static solve: K_r - sigma M_r is not positive definite (coordinate " +
                                   std::to_string(j) + ")");
        a[j * n + j] = std::sqrt(d);
        for (std::size_t i = j + 1; i < n; ++i)
          {
            double s = a[i * n + j];
            for (std::size_t k = 0; k < j; ++k)
              s -= a[i * n + k] * a[j * n + k];
            a[i * n + j] = s / a[j * n + j];
          }
      }
  }

  std::vector<double> cholesky_solve(const std::vector<double> &l, std::size_t n, std::vector<double> b)
  {
    for (std::size_t i = 0; i < n; ++i)
      {
        for (std::size_t k = 0; k < i; ++k)
          b[i] -= l[i * n + k] * b[k];
        b[i] /= l[i * n + i];
      }
    for (std::size_t i = n; i-- > 0;)
      {
        for (std::size_t k = i + 1; k < n; ++k)
          b[i] -= l[k * n + i] * b[k];
        b[i] /= l[i * n + i];
      }
    return b;
  }


  // M_r-orthogonal to every rigid motion, as the relieved solutions are.
  void remove_rigid_motion(const Truncation &t, std::vector<double> &q)
  {
    std::vector<double> c(rigid_modes, 0.0);
    for (std::size_t j = 0; j < t.n; ++j)
      for (std::size_t r = 0; r < rigid_modes; ++r)
        c[r] += t.mass_rigid[j * rigid_modes + r] * q[j];
    const std::vector<double> a = cholesky_solve(t.rigid_factor, rigid_modes, c);
    for (std::size_t r = 0; r < rigid_modes; ++r)
      q[r] -= a[r];
  }

  std::vector<double> apply(const std::vector<double> &op, std::size_t n, const std::vector<double> &q)
  {
    const std::size_t   rows = n == 0 ? 0 : op.size() / n;
    std::vector<double> y(rows, 0.0);
    for (std::size_t r = 0; r < rows; ++r)
      {
        const double *row = op.data() + r * n;
        double        s   = 0.0;
        for (std::size_t j = 0; j < n; ++j)
          s += row[j] * q[j];
        y[r] = s;
      }
    return y;
  }

  void add_footprint_row(const Truncation &t, std::size_t footprint, double angle, double factor,
                         std::vector<double> &row)
  {
    const double spacing  = 2.0 * M_PI / static_cast<double>(t.n_angles);
    double       position = std::fmod(angle, 2.0 * M_PI);
    if (position < 0.0)
      position += 2.0 * M_PI;
    const double      scaled = position / spacing;
    const std::size_t k0     = static_cast<std::size_t>(scaled) % t.n_angles, k1 = (k0 + 1) % t.n_angles;
    const double      w      = scaled - std::floor(scaled);
    const double     *table  = t.approach.data() + footprint * t.n_angles * t.n;
    for (std::size_t j = 0; j < t.n; ++j)
      row[j] += factor * ((1.0 - w) * table[k0 * t.n + j] + w * table[k1 * t.n + j]);
  }

  void add_ball_row(const Truncation &t, double angle, double load, double factor, std::vector<double> &row)
  {
    const coupling::FootprintBlend blend = coupling::footprint_blend(t.footprint_loads, load);
    for (std::size_t m = 0; m < blend.count; ++m)
      add_footprint_row(t, blend.first + m, angle, factor * blend.weights[m], row);
  }


  bool starts_with_rigid_motions(const reduction::ReducedMatrices &matrices)
  {
    const auto  &f      = matrices.interface_frequencies_hz;
    const double cutoff = fem::ModalSettings{}.rigid_body_cutoff_hz;
    return f.size() > rigid_modes && f[rigid_modes - 1] < cutoff && f[rigid_modes] >= cutoff;
  }

  Truncation whole_model(const reduction::ReducedModel &model, double sigma)
  {
    return truncate(model, model.matrices.n_modal, model.matrices.n_constraint, {}, sigma);
  }

  std::vector<double> relieved_static(const Truncation &t, std::vector<double> g)
  {
    relieve(t, g);
    std::vector<double> factor = t.shifted;
    cholesky(factor, t.n);
    std::vector<double> q = cholesky_solve(factor, t.n, g);
    remove_rigid_motion(t, q); // none in exact arithmetic; the round-off 1/|σ| amplifies
    return q;
  }

  reduction::ResidualFlexibility residual_flexibility(fem::ShiftedStaticSolver &solver, const fem::SurfaceGridMap &map,
                                                      const Truncation &whole, const fem::CylinderGrid &grid,
                                                      const fem::RingGeometry &ring,
                                                      const std::vector<reduction::BallFootprint> &footprints,
                                                      int components, bool housing_bore)
  {
    const auto                     start = std::chrono::steady_clock::now();
    reduction::ResidualFlexibility residual;
    residual.column_angle = grid.x(0) / grid.radius;
    const double area     = grid.cell_area();
    std::vector<double> whole_factor;
    if (housing_bore)
      {
        whole_factor = whole.shifted;
        cholesky(whole_factor, whole.n);
      }
    // Every unit load with its generalised force Tᵀf and where its column
    // goes, solved by the full FE as one block.
    std::vector<fem::StaticLoad>       loads;
    std::vector<std::vector<double>>   generalised;
    std::vector<std::vector<double> *> columns;
    // each load its own tractions: the block solve reads them all at once
    std::vector<fem::GridTractions> units(static_cast<std::size_t>(components * grid.ny));
    for (int k = 0; k < components; ++k)
      for (int j = 0; j < grid.ny; ++j)
        {
          fem::GridTractions &unit = units[static_cast<std::size_t>(k * grid.ny + j)];
          for (auto *field : {&unit.pressure, &unit.shear_x, &unit.shear_y})
            field->assign(grid.size(), 0.0);
          auto             &field = k == 0 ? unit.pressure : k == 1 ? unit.shear_x : unit.shear_y;
          const std::size_t cell  = static_cast<std::size_t>(j) * grid.nx; // (0, j)
          field[cell]             = 1.0 / area;                            // 1 N on the cell
          loads.emplace_back().grid_tractions.push_back({&map, &unit});
          // Tᵀ f of that force: the cell's row of the component (the
          // pressure pushes into the body, so inward on the ring)
          std::vector<double> g(whole.grid_displacement.begin() + static_cast<std::ptrdiff_t>((3 * cell + k) * whole.n),
                                whole.grid_displacement.begin() + static_cast<std::ptrdiff_t>((3 * cell + k + 1) * whole.n));
          if (k == 0 && !housing_bore)
            for (double &value : g)
              value = -value;
          generalised.push_back(std::move(g));
          columns.push_back(&residual.traction[k]);
        }
    std::vector<std::vector<double>> ball_columns(footprints.size()); // one table per footprint, in order
    for (std::size_t f = 0; f < footprints.size(); ++f)
      {
        loads.emplace_back().ball_loads.push_back(reduction::unit_ball(ring, residual.column_angle, footprints[f]));
        std::vector<double> g(whole.n, 0.0);
        add_footprint_row(whole, f, residual.column_angle, 1.0, g);
        generalised.push_back(std::move(g));
        columns.push_back(&ball_columns[f]);
      }
    // u_r of the full FE solution minus the reduced model's, per cell.
    solver.solve_each(loads, [&](std::size_t i, const fem::DisplacementField &u) {
      std::vector<double>       u_r = map.interpolate(u).u_r;
      const std::vector<double> q   = housing_bore ? cholesky_solve(whole_factor, whole.n, generalised[i])
                                                   : relieved_static(whole, generalised[i]);
      const std::vector<double> reduced = apply(whole.grid_displacement, whole.n, q); // [cell][3]
      for (std::size_t c = 0; c < u_r.size(); ++c)
        u_r[c] -= reduced[3 * c];
      columns[i]->insert(columns[i]->end(), u_r.begin(), u_r.end());
      ++residual.solves;
    });
    for (const auto &column : ball_columns)
      residual.ball.insert(residual.ball.end(), column.begin(), column.end());
    residual.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return residual;
  }

  std::vector<double> residual_u_r(const reduction::ResidualFlexibility &residual,
                                   const std::vector<double> &footprint_loads, const fem::CylinderGrid &grid,
                                   const fem::GridTractions &tractions, const std::vector<double> &ball_angles,
                                   const std::vector<double> &ball_loads)
  {
    const int           nx = grid.nx, ny = grid.ny;
    const double        cell_area = grid.cell_area();
    const std::size_t   cells     = static_cast<std::size_t>(nx) * ny;
    std::vector<double> u(cells, 0.0);
    const std::array<const std::vector<double> *, 3> loads{&tractions.pressure, &tractions.shear_x,
                                                           &tractions.shear_y};
    for (int k = 0; k < 3; ++k)
      if (!residual.traction[k].empty())
        for (int j = 0; j < ny; ++j)
          for (int i0 = 0; i0 < nx; ++i0)
            {
              // the table is per unit force of the traction (the pressure pushing into the body)
              const double force = (*loads[k])[static_cast<std::size_t>(j * nx + i0)] * cell_area;
              if (force == 0.0)
                continue;
              const double *column = residual.traction[k].data() + static_cast<std::size_t>(j) * cells;
              for (int jj = 0; jj < ny; ++jj)
                for (int i = 0; i < nx; ++i)
                  u[static_cast<std::size_t>(jj * nx + i)] +=
                    force * column[static_cast<std::size_t>(jj * nx + (i - i0 + nx) % nx)];
            }
    if (!residual.ball.empty())
      coupling::add_ball_residual({nx, ny, grid.hx, grid.hy, grid.x_min, grid.y_min}, grid.radius, residual.ball,
                                  footprint_loads, residual.column_angle, ball_angles, ball_loads, u);
    return u;
  }

  double ResidualWinklerSolution::peak() const
  {
    return pressure.empty() ? 0.0 : *std::max_element(pressure.begin(), pressure.end());
  }

  double ResidualWinklerSolution::contact_fraction() const
  {
    const auto loaded = std::count_if(pressure.begin(), pressure.end(), [](double p) { return p > 0.0; });
    return pressure.empty() ? 0.0 : static_cast<double>(loaded) / static_cast<double>(pressure.size());
  }

  ResidualWinklerSolution winkler_with_residual(const Truncation &whole, const reduction::ResidualFlexibility &residual,
                                                const fem::CylinderGrid &grid, double normal_stiffness, double fit,
                                                const std::vector<double> &ball_angles,
                                                const std::vector<double> &ball_loads)
  {
    const auto        start = std::chrono::steady_clock::now();
    const std::size_t n = whole.n, cells = grid.size();
    const double      area = grid.cell_area();
    const contact::SurfaceGrid surface{grid.nx, grid.ny, grid.hx, grid.hy, grid.x_min, grid.y_min};
    coupling::LocalCompliance local(surface, 0.0, normal_stiffness, true, 1e-6, residual.inward_per_pressure(area));
    // The balls: their generalised load, and their residual u_r under the
    // layer (the table shifted to each ball, linear between columns).
    std::vector<double> g(n, 0.0), ball_residual(cells, 0.0);
    for (std::size_t b = 0; b < ball_angles.size(); ++b)
      add_ball_row(whole, ball_angles[b], ball_loads[b], ball_loads[b], g);
    coupling::add_ball_residual(surface, grid.radius, residual.ball, whole.footprint_loads, residual.column_angle,
                                ball_angles, ball_loads, ball_residual);
    using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    RowMatrix radial(cells, n); // the u_r rows
    for (std::size_t c = 0; c < cells; ++c)
      for (std::size_t j = 0; j < n; ++j)
        radial(c, j) = whole.grid_displacement[(3 * c) * n + j];
    const Eigen::Map<const RowMatrix> shifted(whole.shifted.data(), n, n);
    const Eigen::Map<const Eigen::VectorXd> load(g.data(), n);
    Eigen::VectorXd         q = Eigen::VectorXd::Zero(n);
    ResidualWinklerSolution solution;
    solution.pressure.assign(cells, 0.0);
    contact::Field penetration(cells);
    const double   scale = std::max(load.cwiseAbs().maxCoeff(), 1e-300);
    for (int it = 0; it < 50; ++it)
      {
        const Eigen::VectorXd u_r = radial * q;
        for (std::size_t c = 0; c < cells; ++c)
          penetration[c] = fit + u_r[static_cast<Eigen::Index>(c)] + ball_residual[c];
        local.solve(penetration, solution.pressure);
        const Eigen::Map<const Eigen::VectorXd> p(solution.pressure.data(), static_cast<Eigen::Index>(cells));
        const Eigen::VectorXd balance = shifted * q - load + area * (radial.transpose() * p);
        solution.iterations = it;
        if (balance.cwiseAbs().maxCoeff() <= 1e-6 * scale) // the pressure solve stops at 1e-7 of the penetration
          break;
        std::vector<std::size_t> loaded;
        for (std::size_t c = 0; c < cells; ++c)
          if (solution.pressure[c] > 0.0)
            loaded.push_back(c);
        RowMatrix rows(static_cast<Eigen::Index>(loaded.size()), n);
        for (std::size_t a = 0; a < loaded.size(); ++a)
          rows.row(static_cast<Eigen::Index>(a)) = radial.row(static_cast<Eigen::Index>(loaded[a]));
        std::vector<double> sensitivity;
        local.pressure_sensitivity(loaded, rows.data(), n, sensitivity);
        const Eigen::Map<const RowMatrix> by_penetration(sensitivity.data(), static_cast<Eigen::Index>(loaded.size()),
                                                         n);
        const Eigen::MatrixXd jacobian = shifted + area * (rows.transpose() * by_penetration);
        q -= jacobian.partialPivLu().solve(balance);
        if (it == 49)
          throw std::runtime_error("the reduced model with its residual flexibility did not converge on the layer");
      }
    solution.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return solution;
  }
} // namespace fretsim::models
