// Shifted static solves (shifted_static_solver.h): K - σM factorised once by
// MUMPS Cholesky, any number of loads solved with it.
#include "model_impl.h"

#include <fretsim/fem/shifted_static_solver.h>

#include <petscksp.h>

#include <algorithm>
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

    /// A dense block of right-hand sides or solutions, destroyed on any exit.
    struct DenseBlock
    {
      Mat mat = nullptr;
      ~DenseBlock()
      {
        if (mat)
          MatDestroy(&mat);
      }
    };
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

    /// f = the load's vector, relieved; the net force and moment recorded.
    void prepare_load(const StaticLoad &load);
    /// Throws if the last KSPSolve / KSPMatSolve failed.
    void check_solved() const;
    /// Projects the rigid-body motions out of a solution (with relief only).
    void remove_rigid_motion(Vec x) const;
    /// The loads in blocks of at most `columns` right-hand sides (KSPMatSolve:
    /// MatMatSolve of the MUMPS factor), each field handed to `use` in order.
    void solve_blocks(const std::vector<StaticLoad> &loads, std::size_t columns,
                      const std::function<void(std::size_t, const DisplacementField &)> &use);

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

  void ShiftedStaticSolver::Impl::prepare_load(const StaticLoad &load)
  {
    model->assemble_load_vector(load, f);
    for (unsigned int k = 0; k < 3; ++k)
      {
        check_petsc(VecDot(f, raw_modes[k], &net_force[k]), "VecDot");
        check_petsc(VecDot(f, raw_modes[3 + k], &net_moment[k]), "VecDot");
      }
    // Inertia relief: f_e = f - M Φ (Φᵀ f).
    for (std::size_t i = 0; i < modes.size(); ++i)
      {
        PetscScalar c;
        check_petsc(VecDot(f, modes[i], &c), "VecDot");
        check_petsc(VecAXPY(f, -c, mass_modes[i]), "VecAXPY");
      }
  }

  void ShiftedStaticSolver::Impl::check_solved() const
  {
    KSPConvergedReason reason;
    check_petsc(KSPGetConvergedReason(ksp, &reason), "KSPGetConvergedReason");
    if (reason < 0)
      throw std::runtime_error("fem::ShiftedStaticSolver: the factorised solve failed (PETSc reason " +
                               std::to_string(static_cast<int>(reason)) + ")");
  }

  void ShiftedStaticSolver::Impl::remove_rigid_motion(Vec x) const
  {
    // x is M-orthogonal to the rigid-body modes in exact arithmetic; the
    // round-off that 1/|σ| amplifies along them is projected out as well.
    for (std::size_t i = 0; i < modes.size(); ++i)
      {
        PetscScalar c;
        check_petsc(VecDot(x, mass_modes[i], &c), "VecDot");
        check_petsc(VecAXPY(x, -c, modes[i]), "VecAXPY");
      }
  }

  DisplacementField ShiftedStaticSolver::solve(const StaticLoad &load)
  {
    auto start = Clock::now();
    impl->prepare_load(load);
    impl->load_seconds = since(start);
    start              = Clock::now();
    check_petsc(KSPSolve(impl->ksp, impl->f, impl->u), "KSPSolve");
    impl->check_solved();
    impl->remove_rigid_motion(impl->u);
    impl->solve_seconds = since(start);
    return impl->model->field_from_vector(impl->u);
  }

  void ShiftedStaticSolver::solve_each(const std::vector<StaticLoad>                                  &loads,
                                       const std::function<void(std::size_t, const DisplacementField &)> &use,
                                       const std::size_t                                                columns)
  {
    impl->solve_blocks(loads, columns, use);
  }

  void ShiftedStaticSolver::Impl::solve_blocks(const std::vector<StaticLoad> &loads, const std::size_t columns,
                                               const std::function<void(std::size_t, const DisplacementField &)> &use)
  {
    if (columns == 0)
      throw std::invalid_argument("fem::ShiftedStaticSolver: a block needs at least one column");
    MPI_Comm comm;
    check_petsc(PetscObjectGetComm(reinterpret_cast<PetscObject>(shifted), &comm), "PetscObjectGetComm");
    PetscInt local_rows, rows;
    check_petsc(VecGetLocalSize(f, &local_rows), "VecGetLocalSize");
    check_petsc(VecGetSize(f, &rows), "VecGetSize");
    double assembling = 0.0, solving = 0.0;
    for (std::size_t first = 0; first < loads.size(); first += columns)
      {
        const std::size_t n = std::min(columns, loads.size() - first);
        DenseBlock        rhs, solution; // rows laid out as the vectors, all columns on every rank
        check_petsc(MatCreateDense(comm, local_rows, PETSC_DECIDE, rows, static_cast<PetscInt>(n), nullptr, &rhs.mat),
                    "MatCreateDense");
        check_petsc(MatCreateDense(comm, local_rows, PETSC_DECIDE, rows, static_cast<PetscInt>(n), nullptr,
                                   &solution.mat),
                    "MatCreateDense");
        auto start = Clock::now();
        for (std::size_t j = 0; j < n; ++j)
          {
            prepare_load(loads[first + j]);
            Vec column;
            check_petsc(MatDenseGetColumnVecWrite(rhs.mat, static_cast<PetscInt>(j), &column),
                        "MatDenseGetColumnVecWrite");
            check_petsc(VecCopy(f, column), "VecCopy");
            check_petsc(MatDenseRestoreColumnVecWrite(rhs.mat, static_cast<PetscInt>(j), &column),
                        "MatDenseRestoreColumnVecWrite");
          }
        assembling += since(start);
        start = Clock::now();
        check_petsc(KSPMatSolve(ksp, rhs.mat, solution.mat), "KSPMatSolve");
        check_solved();
        solving += since(start);
        for (std::size_t j = 0; j < n; ++j)
          {
            start = Clock::now();
            Vec column;
            check_petsc(MatDenseGetColumnVec(solution.mat, static_cast<PetscInt>(j), &column), "MatDenseGetColumnVec");
            remove_rigid_motion(column);
            solving += since(start);
            const DisplacementField u = model->field_from_vector(column);
            check_petsc(MatDenseRestoreColumnVec(solution.mat, static_cast<PetscInt>(j), &column),
                        "MatDenseRestoreColumnVec");
            use(first + j, u);
          }
      }
    load_seconds  = assembling;
    solve_seconds = solving;
  }

  double  ShiftedStaticSolver::shift() const { return impl->sigma; }
  Vector3 ShiftedStaticSolver::last_net_force() const { return impl->net_force; }
  Vector3 ShiftedStaticSolver::last_net_moment() const { return impl->net_moment; }
  double ShiftedStaticSolver::mass_seconds() const { return impl->mass_seconds; }
  double ShiftedStaticSolver::factorisation_seconds() const { return impl->factorisation_seconds; }
  double ShiftedStaticSolver::last_load_seconds() const { return impl->load_seconds; }
  double ShiftedStaticSolver::last_solve_seconds() const { return impl->solve_seconds; }
} // namespace fretsim::fem
