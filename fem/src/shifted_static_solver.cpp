// Shifted static solves (shifted_static_solver.h): K - σM factorised once by
// MUMPS Cholesky, any number of loads solved with it.
#include "model_impl.h"

#include <fretsim/fem/shifted_static_solver.h>

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

    double since(const Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

    void check_petsc(const PetscErrorCode error, const char *what)
    {
      if (error != 0)
        throw std::runtime_error(std::string("fem::ShiftedStaticSolver: PETSc failed in ") + what + " (error " +
                                 std::to_string(static_cast<int>(error)) + ")");
    }
  } // namespace

  struct ShiftedStaticSolver::Impl
  {
    ElasticModel *model = nullptr;
    double        sigma = 0.0;
    Mat           shifted = nullptr;
    KSP           ksp     = nullptr;
    Vec           f = nullptr, u = nullptr;
    double        mass_seconds = 0.0, factorisation_seconds = 0.0, load_seconds = 0.0, solve_seconds = 0.0;
    /// Rigid-body modes as built (translations, rotations: the resultants'
    /// weights); with relief also M-orthonormal ones and M times them.
    std::vector<Vec> raw_modes, modes, mass_modes;
    Vector3          net_force{0.0, 0.0, 0.0}, net_moment{0.0, 0.0, 0.0};

    ~Impl()
    {
      for (auto *list : {&raw_modes, &modes, &mass_modes})
        for (Vec &v : *list)
          VecDestroy(&v);
      if (u)
        VecDestroy(&u);
      if (f)
        VecDestroy(&f);
      if (ksp)
        KSPDestroy(&ksp);
      if (shifted)
        MatDestroy(&shifted);
    }
  };

  ShiftedStaticSolver::ShiftedStaticSolver(ElasticModel &model, const double shift_hz, const bool inertia_relief)
    : impl(std::make_unique<Impl>())
  {
    if (!(shift_hz >= 0.0))
      throw std::invalid_argument("fem::ShiftedStaticSolver: the shift must be >= 0 Hz");
    impl->model = &model;
    impl->sigma = -std::pow(2.0 * M_PI * shift_hz, 2);
    Mat stiffness = model.petsc_stiffness();
    Mat mass      = nullptr;
    if (impl->sigma != 0.0 || inertia_relief)
      {
        const auto start   = Clock::now();
        mass               = model.petsc_mass(); // assembled on first use
        impl->mass_seconds = since(start);
      }
    const auto start = Clock::now();
    check_petsc(MatDuplicate(stiffness, MAT_COPY_VALUES, &impl->shifted), "MatDuplicate");
    if (impl->sigma != 0.0) // M's pattern is K's (elastic_model.cpp), so a subset of it
      check_petsc(MatAXPY(impl->shifted, -impl->sigma, mass, SUBSET_NONZERO_PATTERN), "MatAXPY");
    check_petsc(MatSetOption(impl->shifted, MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption");
    check_petsc(MatSetOption(impl->shifted, MAT_SPD, PETSC_TRUE), "MatSetOption");
    MPI_Comm comm;
    check_petsc(PetscObjectGetComm(reinterpret_cast<PetscObject>(impl->shifted), &comm), "PetscObjectGetComm");
    check_petsc(KSPCreate(comm, &impl->ksp), "KSPCreate");
    check_petsc(KSPSetOperators(impl->ksp, impl->shifted, impl->shifted), "KSPSetOperators");
    check_petsc(KSPSetType(impl->ksp, KSPPREONLY), "KSPSetType");
    PC pc;
    check_petsc(KSPGetPC(impl->ksp, &pc), "KSPGetPC");
    check_petsc(PCSetType(pc, PCCHOLESKY), "PCSetType");
    check_petsc(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
    check_petsc(KSPSetUp(impl->ksp), "KSPSetUp"); // the factorisation
    check_petsc(MatCreateVecs(impl->shifted, &impl->u, &impl->f), "MatCreateVecs");
    impl->factorisation_seconds = since(start);

    impl->raw_modes = rigid_body_modes(model.impl(), false);
    if (inertia_relief)
      {
        // M-orthonormal by modified Gram–Schmidt in the M inner product.
        for (std::size_t i = 0; i < impl->raw_modes.size(); ++i)
          {
            Vec phi, m_phi;
            check_petsc(VecDuplicate(impl->raw_modes[i], &phi), "VecDuplicate");
            check_petsc(VecCopy(impl->raw_modes[i], phi), "VecCopy");
            check_petsc(VecDuplicate(phi, &m_phi), "VecDuplicate");
            for (std::size_t j = 0; j < i; ++j)
              {
                PetscScalar dot;
                check_petsc(VecDot(phi, impl->mass_modes[j], &dot), "VecDot");
                check_petsc(VecAXPY(phi, -dot, impl->modes[j]), "VecAXPY");
              }
            check_petsc(MatMult(mass, phi, m_phi), "MatMult");
            PetscScalar norm2;
            check_petsc(VecDot(phi, m_phi, &norm2), "VecDot");
            if (!(norm2 > 0.0))
              throw std::runtime_error("fem::ShiftedStaticSolver: a rigid-body mode has no mass");
            check_petsc(VecScale(phi, 1.0 / std::sqrt(norm2)), "VecScale");
            check_petsc(VecScale(m_phi, 1.0 / std::sqrt(norm2)), "VecScale");
            impl->modes.push_back(phi);
            impl->mass_modes.push_back(m_phi);
          }
      }
  }

  ShiftedStaticSolver::~ShiftedStaticSolver() = default;

  DisplacementField ShiftedStaticSolver::solve(const StaticLoad &load)
  {
    auto start = Clock::now();
    impl->model->assemble_load_vector(load, impl->f);
    for (unsigned int k = 0; k < 3; ++k)
      {
        check_petsc(VecDot(impl->f, impl->raw_modes[k], &impl->net_force[k]), "VecDot");
        check_petsc(VecDot(impl->f, impl->raw_modes[3 + k], &impl->net_moment[k]), "VecDot");
      }
    // Inertia relief: f_e = f - M Φ (Φᵀ f).
    for (std::size_t i = 0; i < impl->modes.size(); ++i)
      {
        PetscScalar c;
        check_petsc(VecDot(impl->f, impl->modes[i], &c), "VecDot");
        check_petsc(VecAXPY(impl->f, -c, impl->mass_modes[i]), "VecAXPY");
      }
    impl->load_seconds = since(start);
    start              = Clock::now();
    check_petsc(KSPSolve(impl->ksp, impl->f, impl->u), "KSPSolve");
    KSPConvergedReason reason;
    check_petsc(KSPGetConvergedReason(impl->ksp, &reason), "KSPGetConvergedReason");
    if (reason < 0)
      throw std::runtime_error("fem::ShiftedStaticSolver: the factorised solve failed (PETSc reason " +
                               std::to_string(static_cast<int>(reason)) + ")");
    // u is M-orthogonal to the rigid-body modes in exact arithmetic; the
    // round-off that 1/|σ| amplifies along them is projected out as well.
    for (std::size_t i = 0; i < impl->modes.size(); ++i)
      {
        PetscScalar c;
        check_petsc(VecDot(impl->u, impl->mass_modes[i], &c), "VecDot");
        check_petsc(VecAXPY(impl->u, -c, impl->modes[i]), "VecAXPY");
      }
    impl->solve_seconds = since(start);
    return impl->model->field_from_vector(impl->u);
  }

  double  ShiftedStaticSolver::shift() const { return impl->sigma; }
  Vector3 ShiftedStaticSolver::last_net_force() const { return impl->net_force; }
  Vector3 ShiftedStaticSolver::last_net_moment() const { return impl->net_moment; }
  double ShiftedStaticSolver::mass_seconds() const { return impl->mass_seconds; }
  double ShiftedStaticSolver::factorisation_seconds() const { return impl->factorisation_seconds; }
  double ShiftedStaticSolver::last_load_seconds() const { return impl->load_seconds; }
  double ShiftedStaticSolver::last_solve_seconds() const { return impl->solve_seconds; }
} // namespace fretsim::fem
