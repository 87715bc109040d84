// WinklerFoundationSolver (winkler_foundation.h): K - σM kept once; per
// active set a copy with the foundation cells' k_n A w_c w_cᵀ added through
// the grid map's samples, factorised by MUMPS Cholesky (the nonzero pattern
// never changes, so PETSc redoes only the numeric factorisation).
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

    ~Impl()
    {
      if (ksp)
        KSPDestroy(&ksp);
      if (shifted)
        MatDestroy(&shifted);
    }

    /// The sample's direction of the pressure force on the body, per local DoF:
    /// (w_c)_i = φ_i(x_c) · n_c.
    void weights(const SurfaceGridMap::Impl::Sample &s, double pressure_sign, std::vector<double> &w) const
    {
      const auto        &fe = model->impl().fe;
      const unsigned int n  = fe.n_dofs_per_cell();
      w.resize(n);
      for (unsigned int i = 0; i < n; ++i)
        w[i] = s.shape[i] * pressure_sign * s.e_r[fe.system_to_component_index(i).first];
    }
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
    const auto          start   = Clock::now();
    const auto         &model   = impl->model->impl();
    const auto         &map     = impl->map->impl();
    const unsigned int  n       = model.fe.n_dofs_per_cell();
    const std::size_t   cells   = map.grid.size();
    const double        k_area  = impl->layer.normal_stiffness * map.grid.cell_area();
    const double        fit     = impl->layer.radial_interference;
    const double        sign    = map.pressure_sign;
    Mat                 system  = impl->system.petsc_matrix();

    const dealii::PETScWrappers::MPI::Vector f = assemble_load(model, load);
    dealii::PETScWrappers::MPI::Vector       rhs(model.owned_dofs, model.communicator());
    dealii::PETScWrappers::MPI::Vector       u(model.owned_dofs, model.communicator()); // the current state
    dealii::PETScWrappers::MPI::Vector       candidate(model.owned_dofs, model.communicator());
    bool                                     have_state = false;
    std::vector<dealii::types::global_dof_index> dof_indices(n);
    std::vector<double>                          w;
    dealii::FullMatrix<double>                   cell_matrix(n, n);
    dealii::Vector<double>                       cell_rhs(n);

    WinklerGridSolution grid;
    ActiveSetSolver     callbacks;
    callbacks.solve = [&](const std::vector<unsigned char> &active) {
      const auto factor_start = Clock::now();
      check_petsc(MatCopy(impl->shifted, system, SAME_NONZERO_PATTERN), "MatCopy");
      rhs = f;
      for (const auto &s : map.samples)
        if (active[s.grid_cell])
          {
            impl->weights(s, sign, w);
            for (unsigned int i = 0; i < n; ++i)
              {
                cell_rhs(i) = k_area * fit * w[i];
                for (unsigned int j = 0; j < n; ++j)
                  cell_matrix(i, j) = k_area * w[i] * w[j];
              }
            s.cell->get_dof_indices(dof_indices);
            model.constraints.distribute_local_to_global(cell_matrix, cell_rhs, dof_indices, impl->system, rhs);
          }
      impl->system.compress(dealii::VectorOperation::add);
      rhs.compress(dealii::VectorOperation::add);
      check_petsc(KSPSetOperators(impl->ksp, system, system), "KSPSetOperators");
      check_petsc(KSPSetUp(impl->ksp), "KSPSetUp"); // the numeric factorisation
      grid.factorisation_seconds += seconds_since(factor_start);
      check_petsc(KSPSolve(impl->ksp, static_cast<const Vec &>(rhs), static_cast<const Vec &>(candidate)), "KSPSolve");
      KSPConvergedReason reason;
      check_petsc(KSPGetConvergedReason(impl->ksp, &reason), "KSPGetConvergedReason");
      if (reason < 0)
        throw std::runtime_error(who + ": the factorised solve failed (PETSc reason " +
                                 std::to_string(static_cast<int>(reason)) + ")");
      const GridDisplacements at =
        impl->map->interpolate(impl->model->field_from_vector(static_cast<const Vec &>(candidate)));
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
    iterate_active_set(cells, initial_active, impl->settings.max_iterations, k_area, who, callbacks, grid);

    const double foundation = foundation_pressure(impl->layer.normal_stiffness, k_area, grid);
    // Φ = ½ uᵀ(K - σM)u - fᵀu + the foundation's ½ Σ k_n A d₊².
    dealii::PETScWrappers::MPI::Vector shifted_u(model.owned_dofs, model.communicator());
    check_petsc(MatMult(impl->shifted, static_cast<const Vec &>(u), static_cast<const Vec &>(shifted_u)), "MatMult");
    grid.energy  = 0.5 * (u * shifted_u) - (f * u) + foundation;
    grid.seconds = seconds_since(start);
    return {std::move(grid), impl->model->field_from_vector(static_cast<const Vec &>(u))};
  }
} // namespace fretsim::fem
