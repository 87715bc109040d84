// Newmark average acceleration in displacement–velocity form (transient.h),
// and Hertz patch pressures on a contact grid.
#include "newmark_rule.h"

#include <fretsim/fem/transient.h>

#include <petscksp.h>

#include <cmath>

namespace fretsim::fem
{
  using Clock = std::chrono::steady_clock;

  namespace
  {
    void check_petsc(const PetscErrorCode error, const char *what)
    {
      if (error != 0)
        throw std::runtime_error(std::string("fem::NewmarkIntegrator: PETSc failed in ") + what +
                                 " (error " + std::to_string(static_cast<int>(error)) + ")");
    }
  } // namespace

  GridTractions hertz_patch_tractions(const CylinderGrid &grid, const std::vector<HertzPatch> &patches)
  {
    GridTractions t;
    t.pressure.assign(grid.size(), 0.0);
    t.shear_x.assign(grid.size(), 0.0);
    t.shear_y.assign(grid.size(), 0.0);
    const double circumference = 2.0 * M_PI * grid.radius;
    std::vector<double> patch(grid.size());
    for (const HertzPatch &h : patches)
      {
        if (!(h.a > 0.0 && h.b > 0.0 && h.force >= 0.0))
          throw std::invalid_argument("fem::hertz_patch_tractions: a patch needs a, b > 0 and a force >= 0");
        double sum = 0.0;
        for (int j = 0; j < grid.ny; ++j)
          for (int i = 0; i < grid.nx; ++i)
            {
              // Nearest image around the circumference, so that a ball passing θ = 0 is whole.
              const double dx = std::remainder(grid.x(i) - h.x, circumference) / h.a, dy = (grid.y(j) - h.y) / h.b;
              const double s  = 1.0 - dx * dx - dy * dy;
              patch[j * grid.nx + i] = s > 0.0 ? std::sqrt(s) : 0.0;
              sum += patch[j * grid.nx + i];
            }
        if (sum == 0.0)
          {
            if (h.force > 0.0)
              throw std::invalid_argument("fem::hertz_patch_tractions: a patch covers no grid cell centre; refine "
                                          "the grid or check the patch position");
            continue;
          }
        // Cell-centre sampling of the semi-ellipsoid misses a few % of the
        // load on coarse grids; the shape is kept and the total made exact.
        const double scale = h.force / (sum * grid.cell_area());
        for (std::size_t k = 0; k < grid.size(); ++k)
          t.pressure[k] += scale * patch[k];
      }
    return t;
  }

  struct NewmarkIntegrator::Impl
  {
    ElasticModel                      *model_object = nullptr;
    ElasticModel::Impl                *model        = nullptr;
    double                             dt = 0.0, t = 0.0;
    dealii::PETScWrappers::MPI::Vector u, v, f; ///< owned; f is the load at time t
    Mat                                effective = nullptr;
    KSP                                ksp       = nullptr;
    double                             factorisation = 0.0, stepping = 0.0;

    ~Impl()
    {
      if (ksp)
        KSPDestroy(&ksp);
      if (effective)
        MatDestroy(&effective);
    }
  };

  NewmarkIntegrator::NewmarkIntegrator(ElasticModel &model_object, const double time_step,
                                       const StaticLoad &initial_load, const DisplacementField *initial_displacement,
                                       const double start_time)
    : pimpl(std::make_unique<Impl>())
  {
    if (!(time_step > 0.0))
      throw std::invalid_argument("fem::NewmarkIntegrator: the time step must be > 0");
    auto &p        = *pimpl;
    p.model_object = &model_object;
    p.model        = &model_object.impl();
    p.dt           = time_step;
    p.t            = start_time;
    auto &model    = *p.model;
    model.assemble_mass();
    p.u.reinit(model.owned_dofs, model.communicator());
    p.v.reinit(model.owned_dofs, model.communicator());
    if (initial_displacement)
      p.u = initial_displacement->impl().displacement;
    p.f = assemble_load(model, initial_load);

    const auto start = Clock::now();
    // K + 4M/Δt²: M's pattern is K's (one sparsity pattern for both).
    Mat stiffness = static_cast<Mat>(model.stiffness), mass = static_cast<Mat>(model.mass);
    check_petsc(MatDuplicate(stiffness, MAT_COPY_VALUES, &p.effective), "MatDuplicate");
    check_petsc(MatAXPY(p.effective, 4.0 / (p.dt * p.dt), mass, SUBSET_NONZERO_PATTERN), "MatAXPY");
    check_petsc(MatSetOption(p.effective, MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption");
    check_petsc(MatSetOption(p.effective, MAT_SPD, PETSC_TRUE), "MatSetOption");
    check_petsc(KSPCreate(model.communicator(), &p.ksp), "KSPCreate");
    check_petsc(KSPSetOperators(p.ksp, p.effective, p.effective), "KSPSetOperators");
    check_petsc(KSPSetType(p.ksp, KSPPREONLY), "KSPSetType");
    PC pc;
    check_petsc(KSPGetPC(p.ksp, &pc), "KSPGetPC");
    check_petsc(PCSetType(pc, PCCHOLESKY), "PCSetType");
    check_petsc(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
    check_petsc(KSPSetUp(p.ksp), "KSPSetUp (factorisation)");
    p.factorisation = seconds_since(start);
  }

  NewmarkIntegrator::~NewmarkIntegrator() = default;

  void NewmarkIntegrator::advance(const StaticLoad &load)
  {
    auto      &p     = *pimpl;
    auto      &model = *p.model;
    const auto start = Clock::now();
    const auto f_new = assemble_load(model, load);

    dealii::PETScWrappers::MPI::Vector rhs(model.owned_dofs, model.communicator()),
      u_new(model.owned_dofs, model.communicator());
    add_newmark_history(model, p.dt, p.u, p.v, rhs);
    rhs += p.f;
    rhs += f_new;
    check_petsc(KSPSolve(p.ksp, static_cast<Vec>(rhs), static_cast<Vec>(u_new)), "KSPSolve");
    advance_newmark_state(p.dt, u_new, p.u, p.v);
    p.f = f_new;
    p.t += p.dt;
    p.stepping += seconds_since(start);
  }

  double NewmarkIntegrator::time() const { return pimpl->t; }
  double NewmarkIntegrator::time_step() const { return pimpl->dt; }
  double NewmarkIntegrator::factorisation_seconds() const { return pimpl->factorisation; }
  double NewmarkIntegrator::step_seconds() const { return pimpl->stepping; }

  double NewmarkIntegrator::kinetic_energy() const { return 0.5 * pimpl->model->mass.matrix_norm_square(pimpl->v); }
  double NewmarkIntegrator::strain_energy() const
  {
    return 0.5 * pimpl->model->stiffness.matrix_norm_square(pimpl->u);
  }

  DisplacementField NewmarkIntegrator::displacement() const
  {
    auto field          = std::make_unique<DisplacementField::Impl>();
    field->model        = pimpl->model_object->shared_impl();
    field->displacement = pimpl->model->ghosted(pimpl->u);
    return DisplacementField(std::move(field));
  }
} // namespace fretsim::fem
