// WinklerFoundationSolver (winkler_foundation.h): K - σM kept once; per
// active set a copy with the foundation cells' k_n A w_c w_cᵀ added through
// the grid map's samples, factorised by MUMPS Cholesky (the nonzero pattern
// never changes, so PETSc redoes only the numeric factorisation).
#include "newmark_rule.h"
#include "surface_grid_map_impl.h"
#include "winkler_active_set.h"

#include <fretsim/fem/winkler_foundation.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <petscksp.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fretsim::fem
{
  namespace
  {
    using Clock = std::chrono::steady_clock;

    const std::string who = "fem::WinklerFoundationSolver";

    void check_petsc(const PetscErrorCode error, const char *what)
    {
      if (error != 0)
        throw std::runtime_error(who + ": PETSc failed in " + what + " (error " +
                                 std::to_string(static_cast<int>(error)) + ")");
    }
  } // namespace

  struct WinklerFoundationSolver::Impl
  {
    ElasticModel         *model = nullptr;
    const SurfaceGridMap *map   = nullptr;
    WinklerLayer          layer;
    WinklerSettings       settings;
    double                sigma = 0.0, setup_seconds = 0.0;
    Mat                   shifted = nullptr; ///< K - σM
    dealii::PETScWrappers::MPI::SparseMatrix system; ///< K - σM + the active cells' foundation
    KSP                   ksp = nullptr;
    /// The active set `system` holds the factorisation of (empty: none yet).
    std::vector<unsigned char> factorised;

    ~Impl()
    {
      if (ksp)
        KSPDestroy(&ksp);
      if (shifted)
        MatDestroy(&shifted);
    }

    /// The active-set iteration for the assembled load f; u receives the
    /// solution. Fills the grid side; `energy` holds only the foundation's part.
    WinklerGridSolution solve(const dealii::PETScWrappers::MPI::Vector &f,
                              const std::vector<unsigned char> &initial_active, dealii::PETScWrappers::MPI::Vector &u);
  };

  WinklerFoundationSolver::WinklerFoundationSolver(ElasticModel &model, const SurfaceGridMap &map,
                                                   const WinklerLayer &layer, const WinklerSettings &settings)
    : impl(std::make_unique<Impl>())
  {
    check_layer(layer, who);
    if (!(settings.shift_hz >= 0.0) || !std::isfinite(settings.shift_hz))
      throw std::invalid_argument(who + ": the shift must be finite and >= 0 Hz");
    if (map.impl().model != &model.impl())
      throw std::invalid_argument(who + ": the grid map was made on another model");
    const auto start = Clock::now();
    impl->model      = &model;
    impl->map        = &map;
    impl->layer      = layer;
    impl->settings   = settings;
    impl->sigma      = -std::pow(2.0 * M_PI * settings.shift_hz, 2);

    check_petsc(MatDuplicate(model.petsc_stiffness(), MAT_COPY_VALUES, &impl->shifted), "MatDuplicate");
    if (impl->sigma != 0.0) // M's pattern is K's (elastic_model.cpp), so a subset of it
      check_petsc(MatAXPY(impl->shifted, -impl->sigma, model.petsc_mass(), SUBSET_NONZERO_PATTERN), "MatAXPY");
    impl->system.reinit(model.impl().stiffness); // K's layout and pattern, values set per active set
    Mat system = impl->system.petsc_matrix();
    check_petsc(MatSetOption(system, MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption");
    check_petsc(MatSetOption(system, MAT_SPD, PETSC_TRUE), "MatSetOption");
    MPI_Comm comm = model.impl().communicator();
    check_petsc(KSPCreate(comm, &impl->ksp), "KSPCreate");
    check_petsc(KSPSetType(impl->ksp, KSPPREONLY), "KSPSetType");
    PC pc;
    check_petsc(KSPGetPC(impl->ksp, &pc), "KSPGetPC");
    check_petsc(PCSetType(pc, PCCHOLESKY), "PCSetType");
    check_petsc(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
    impl->setup_seconds = seconds_since(start);
  }

  WinklerFoundationSolver::~WinklerFoundationSolver() = default;

  double WinklerFoundationSolver::shift() const { return impl->sigma; }
  double WinklerFoundationSolver::setup_seconds() const { return impl->setup_seconds; }

  WinklerFoundationSolver::Solution WinklerFoundationSolver::solve(const StaticLoad                 &load,
                                                                   const std::vector<unsigned char> &initial_active)
  {
    const auto start = Clock::now();
    const auto &model = impl->model->impl();
    const dealii::PETScWrappers::MPI::Vector f = assemble_load(model, load);
    dealii::PETScWrappers::MPI::Vector       u(model.owned_dofs, model.communicator());
    WinklerGridSolution                      grid = impl->solve(f, initial_active, u);

    // Φ = ½ uᵀ(K - σM)u - fᵀu + the foundation's ½ Σ k_n A d₊².
    dealii::PETScWrappers::MPI::Vector shifted_u(model.owned_dofs, model.communicator());
    check_petsc(MatMult(impl->shifted, static_cast<const Vec &>(u), static_cast<const Vec &>(shifted_u)), "MatMult");
    grid.energy += 0.5 * (u * shifted_u) - (f * u);
    grid.seconds = seconds_since(start);
    return {std::move(grid), impl->model->field_from_vector(static_cast<const Vec &>(u))};
  }

  WinklerGridSolution WinklerFoundationSolver::Impl::solve(const dealii::PETScWrappers::MPI::Vector &f,
                                                           const std::vector<unsigned char>         &initial_active,
                                                           dealii::PETScWrappers::MPI::Vector       &u)
  {
    const auto        &model_impl = model->impl();
    const auto        &map_impl   = map->impl();
    const unsigned int n          = model_impl.fe.n_dofs_per_cell();
    const std::size_t  cells      = map_impl.grid.size();
    const double       k_area     = layer.normal_stiffness * map_impl.grid.cell_area();
    const double       fit        = layer.radial_interference;
    const double       sign       = map_impl.pressure_sign;
    Mat                system_mat = system.petsc_matrix();

    dealii::PETScWrappers::MPI::Vector rhs(model_impl.owned_dofs, model_impl.communicator());
    dealii::PETScWrappers::MPI::Vector candidate(model_impl.owned_dofs, model_impl.communicator());
    bool                               have_state = false;
    std::vector<dealii::types::global_dof_index> dof_indices(n);
    std::vector<double>                          w;
    dealii::FullMatrix<double>                   cell_matrix(n, n);
    dealii::Vector<double>                       cell_rhs(n);

    WinklerGridSolution grid;
    ActiveSetSolver     callbacks;
    callbacks.solve = [&](const std::vector<unsigned char> &active) {
      // A set already factorised (the last one of the previous solve, as a
      // transient's next step mostly starts from) keeps its factorisation.
      const bool refactorise = active != factorised;
      const auto factor_start = Clock::now();
      if (refactorise)
        check_petsc(MatCopy(shifted, system_mat, SAME_NONZERO_PATTERN), "MatCopy");
      rhs = f;
      for (const auto &s : map_impl.samples)
        if (active[s.grid_cell])
          {
            map_impl.pressure_weights(s, w);
            s.cell->get_dof_indices(dof_indices);
            for (unsigned int i = 0; i < n; ++i)
              cell_rhs(i) = k_area * fit * w[i];
            if (refactorise)
              {
                for (unsigned int i = 0; i < n; ++i)
                  for (unsigned int j = 0; j < n; ++j)
                    cell_matrix(i, j) = k_area * w[i] * w[j];
                model_impl.constraints.distribute_local_to_global(cell_matrix, cell_rhs, dof_indices, system, rhs);
              }
            else
              model_impl.constraints.distribute_local_to_global(cell_rhs, dof_indices, rhs);
          }
      if (refactorise)
        {
          system.compress(dealii::VectorOperation::add);
          factorised.clear(); // until the factorisation has succeeded
        }
      rhs.compress(dealii::VectorOperation::add);
      if (refactorise)
        {
          check_petsc(KSPSetOperators(ksp, system_mat, system_mat), "KSPSetOperators");
          check_petsc(KSPSetUp(ksp), "KSPSetUp"); // the numeric factorisation
          factorised = active;
          ++grid.factorisations;
          grid.factorisation_seconds += seconds_since(factor_start);
        }
      check_petsc(KSPSolve(ksp, static_cast<const Vec &>(rhs), static_cast<const Vec &>(candidate)), "KSPSolve");
      KSPConvergedReason reason;
      check_petsc(KSPGetConvergedReason(ksp, &reason), "KSPGetConvergedReason");
      if (reason < 0)
        throw std::runtime_error(who + ": the factorised solve failed (PETSc reason " +
                                 std::to_string(static_cast<int>(reason)) + ")");
      const GridDisplacements at = map->interpolate(model->field_from_vector(static_cast<const Vec &>(candidate)));
      // d = δ_fit - n·u with n = sign e_r.
      std::vector<double> penetration(cells);
      for (std::size_t c = 0; c < cells; ++c)
        penetration[c] = fit - sign * at.u_r[c];
      return penetration;
    };
    callbacks.accept = [&](double t) {
      if (!have_state || t == 1.0)
        u = candidate;
      else
        u.sadd(1.0 - t, t, candidate);
      have_state = true;
    };
    iterate_active_set(cells, initial_active, settings.max_iterations, k_area, who, callbacks, grid);
    grid.energy = foundation_pressure(layer.normal_stiffness, k_area, grid);
    return grid;
  }

  // ---- WinklerNewmark

  struct WinklerNewmark::Impl : WinklerStepRecord
  {
    ElasticModel                      *model = nullptr;
    const SurfaceGridMap              *map   = nullptr;
    WinklerLayer                       layer;
    std::unique_ptr<WinklerFoundationSolver> step; ///< σ = -4/Δt²
    dealii::PETScWrappers::MPI::Vector u, v;       ///< owned
    StaticLoad                         load;       ///< f at time t
  };

  WinklerNewmark::WinklerNewmark(ElasticModel &model, const SurfaceGridMap &map, const WinklerLayer &layer,
                                 const double time_step, const StaticLoad &initial_load, const double start_time,
                                 const std::vector<unsigned char> &initial_active)
    : pimpl(std::make_unique<Impl>())
  {
    if (!(time_step > 0.0) || !std::isfinite(time_step))
      throw std::invalid_argument("fem::WinklerNewmark: the time step must be finite and > 0 s");
    auto &p = *pimpl;
    p.model = &model;
    p.map   = &map;
    p.layer = layer;
    p.dt    = time_step;
    p.t     = start_time;
    p.load  = initial_load;
    const auto &m = model.impl();
    p.u.reinit(m.owned_dofs, m.communicator());
    p.v.reinit(m.owned_dofs, m.communicator());
    {
      WinklerFoundationSolver start(model, map, layer); // the free ring held by the 1 Hz shift
      const auto              s = start.solve(initial_load, initial_active);
      p.u                       = s.displacement.impl().displacement;
      p.state                   = s.grid;
      // As the steps' states hold it: the foundation's energy alone.
      p.state.energy = foundation_pressure(layer.normal_stiffness, layer.normal_stiffness * map.impl().grid.cell_area(),
                                           p.state);
    }
    WinklerSettings settings;
    settings.shift_hz = 1.0 / (M_PI * time_step); // σ = -(2π f_s)² = -4/Δt²
    p.step            = std::make_unique<WinklerFoundationSolver>(model, map, layer, settings);
  }

  WinklerNewmark::~WinklerNewmark() = default;

  const WinklerGridSolution &WinklerNewmark::advance(const StaticLoad &load)
  {
    auto       &p     = *pimpl;
    const auto  start = Clock::now();
    const auto &model = p.model->impl();
    // The step's load: f₊, and the previous end's f + G(u), G(u) being the
    // foundation's pressure at time t applied as a grid traction.
    const std::vector<double> zero(p.state.pressure.size(), 0.0);
    const GridTractions       previous_foundation{p.state.pressure, zero, zero};
    StaticLoad                previous = p.load;
    previous.grid_tractions.push_back({p.map, &previous_foundation});
    dealii::PETScWrappers::MPI::Vector rhs = assemble_load(model, load);
    rhs += assemble_load(model, previous);
    add_newmark_history(model, p.dt, p.u, p.v, rhs);
    dealii::PETScWrappers::MPI::Vector u_new(model.owned_dofs, model.communicator());
    WinklerGridSolution next = p.step->impl->solve(rhs, p.state.active, u_new);
    advance_newmark_state(p.dt, u_new, p.u, p.v);
    p.load = load;
    return p.add_step(std::move(next), seconds_since(start));
  }

  double WinklerNewmark::time() const { return pimpl->t; }
  double WinklerNewmark::time_step() const { return pimpl->dt; }
  unsigned int WinklerNewmark::steps() const { return pimpl->steps; }
  unsigned long WinklerNewmark::n_dofs() const { return pimpl->model->n_dofs(); }
  unsigned int WinklerNewmark::factorisations() const { return pimpl->factorisations; }
  double WinklerNewmark::factorisation_seconds() const { return pimpl->factorisation_seconds; }
  unsigned int WinklerNewmark::solves() const { return pimpl->solves; }
  double WinklerNewmark::step_seconds() const { return pimpl->seconds; }
  const WinklerGridSolution &WinklerNewmark::foundation() const { return pimpl->state; }

  double WinklerNewmark::energy() const
  {
    // ½vᵀMv + ½uᵀKu + ½ Σ k_n A d₊² - fᵀu
    const auto &p     = *pimpl;
    const auto &model = p.model->impl();
    const auto  f     = assemble_load(model, p.load);
    return 0.5 * model.mass.matrix_norm_square(p.v) + 0.5 * model.stiffness.matrix_norm_square(p.u) +
           p.state.energy - (f * p.u);
  }

  DisplacementField WinklerNewmark::displacement() const
  {
    return pimpl->model->field_from_vector(static_cast<const Vec &>(pimpl->u));
  }
} // namespace fretsim::fem
