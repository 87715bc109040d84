// Craig–Bampton reduction with characteristic constraint modes: PETSc for the
// partitioned matrices and MUMPS factorisations, SLEPc for the eigen-solves.
#include "petsc_handles.h"

#include <fretsim/reduction/craig_bampton.h>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

namespace fretsim::reduction
{
  namespace
  {
    using Clock = std::chrono::steady_clock;

    double seconds_since(const Clock::time_point start)
    {
      return std::chrono::duration<double>(Clock::now() - start).count();
    }

    /// A direct solver: Cholesky by MUMPS (the matrices are symmetric
    /// positive definite: K_ii with the boundary held, K - σM with σ < 0).
    OwnedKSP cholesky_solver(Mat matrix, MPI_Comm comm)
    {
      FRETSIM_PETSC(MatSetOption(matrix, MAT_SYMMETRIC, PETSC_TRUE));
      FRETSIM_PETSC(MatSetOption(matrix, MAT_SPD, PETSC_TRUE));
      OwnedKSP ksp;
      FRETSIM_PETSC(KSPCreate(comm, ksp.out()));
      FRETSIM_PETSC(KSPSetOperators(ksp, matrix, matrix));
      FRETSIM_PETSC(KSPSetType(ksp, KSPPREONLY));
      PC pc;
      FRETSIM_PETSC(KSPGetPC(ksp, &pc));
      FRETSIM_PETSC(PCSetType(pc, PCCHOLESKY));
      FRETSIM_PETSC(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
      FRETSIM_PETSC(KSPSetUp(ksp));
      return ksp;
    }

    OwnedVec vector_like(Mat matrix)
    {
      OwnedVec v;
      FRETSIM_PETSC(MatCreateVecs(matrix, v.out(), nullptr));
      return v;
    }

    OwnedVec duplicate(Vec v)
    {
      OwnedVec copy;
      FRETSIM_PETSC(VecDuplicate(v, copy.out()));
      return copy;
    }

    /// aᵀ b for each pair, as a dense n_a × n_b row-major block.
    std::vector<double> dots(const std::vector<OwnedVec> &left, const std::vector<Vec> &right)
    {
      std::vector<double> result(left.size() * right.size());
      for (std::size_t k = 0; k < right.size(); ++k)
        {
          std::vector<PetscScalar> column(left.size());
          std::vector<Vec>         raw(left.begin(), left.end());
          FRETSIM_PETSC(VecMDot(right[k], static_cast<PetscInt>(raw.size()), raw.data(), column.data()));
          for (std::size_t j = 0; j < left.size(); ++j)
            result[j * right.size() + k] = column[j];
        }
      return result;
    }

    /// Reports an eigen-solve's converged count as a fraction of the wanted.
    struct EpsProgress
    {
      const ReductionSettings *settings;
      std::string              stage;
      PetscInt                 wanted;
    };

    PetscErrorCode eps_monitor(EPS, PetscInt, PetscInt n_converged, PetscScalar *, PetscScalar *, PetscReal *,
                               PetscInt, void *context)
    {
      const auto *p = static_cast<EpsProgress *>(context);
      if (p->settings->progress)
        p->settings->progress(p->stage, std::min(1.0, static_cast<double>(n_converged) / p->wanted));
      return 0;
    }

    double to_hz(const double eigenvalue) { return std::sqrt(std::max(0.0, eigenvalue)) / (2.0 * M_PI); }

    /// Solves with a progress monitor; throws unless `wanted` pairs converged.
    /// Returns how many did.
    PetscInt solve_eigenproblem(EPS eps, const ReductionSettings &settings, const std::string &stage,
                                const PetscInt wanted)
    {
      EpsProgress progress{&settings, stage, wanted};
      FRETSIM_PETSC(EPSMonitorSet(eps, eps_monitor, &progress, nullptr));
      FRETSIM_PETSC(EPSSolve(eps));
      PetscInt n_converged = 0;
      FRETSIM_PETSC(EPSGetConverged(eps, &n_converged));
      if (n_converged < wanted)
        throw std::runtime_error("reduction: only " + std::to_string(n_converged) + " of " + std::to_string(wanted) +
                                 " " + stage + " converged");
      return n_converged;
    }
  } // namespace

  struct CraigBampton::Impl
  {
    Impl(fem::ElasticModel &model_in, ReductionSettings settings_in)
      : model(model_in)
      , settings(std::move(settings_in))
      , stiffness(model.petsc_stiffness())
      , mass(model.petsc_mass())
    {
      FRETSIM_PETSC(PetscObjectGetComm(reinterpret_cast<PetscObject>(stiffness), &comm));
      static_sigma = -std::pow(2.0 * M_PI * settings.static_shift_hz, 2);
    }

    void report(const std::string &stage, const double fraction) const
    {
      if (settings.progress)
        settings.progress(stage, fraction);
    }

    void partition();
    void factorise();
    void fixed_interface_modes();
    void interface_modes();
    void full_constraint_modes();
    void assemble_basis();
    ReducedMatrices reduced_matrices() const;

    /// u_i = Ψ x = -K_ii⁻¹ K_ib x.
    void apply_constraint_modes(Vec x_b, Vec u_i) const;
    /// y = S x = K_bb x + K_bi Ψx, given u_i = Ψx.
    void apply_schur(Vec x_b, Vec u_i, Vec y_b) const;
    /// y = M_G x = M_bb x + M_bi u + Ψᵀ(M_ib x + M_ii u), given u_i = Ψx.
    void apply_guyan_mass(Vec x_b, Vec u_i, Vec y_b) const;
    /// y = [(K - σM)⁻¹ M [x; Ψx]]_b: the interface search operator.
    void apply_interface_operator(Vec x_b, Vec y_b) const;
    static PetscErrorCode interface_operator_mult(Mat shell, Vec x, Vec y);

    fem::ElasticModel &model;
    ReductionSettings  settings;
    ReductionTimings   timings;
    MPI_Comm           comm = MPI_COMM_NULL;
    Mat                stiffness, mass; // owned by the model
    double             sigma = 0.0;        ///< the interface search shift
    double             static_sigma = 0.0; ///< the static solves' shift

    OwnedIS  boundary, interior;
    OwnedMat K_ii, K_ib, K_bb, M_ii, M_ib, M_bb, shifted_stiffness;
    OwnedKSP interior_solver, shifted_solver;
    OwnedMat static_stiffness;
    OwnedKSP static_solver; ///< K - σ_s M, factorised on first use
    // Work vectors of the operators (mutable: the operators are logically const).
    mutable OwnedVec work_i, work_i2, work_b, full_in, full_out;

    std::vector<double>   fixed_interface_eigenvalues, interface_eigenvalues;
    std::vector<OwnedVec> fixed_interface_shapes;  ///< Φ columns (interior)
    std::vector<OwnedVec> interface_shapes;        ///< V columns (boundary)
    std::vector<OwnedVec> interface_constraint;    ///< Ψ V columns (interior)
    std::vector<OwnedVec> basis;                   ///< T columns (full)
    PetscInt              n_boundary = 0, n_interior = 0;
  };

  void CraigBampton::Impl::partition()
  {
    const auto start = Clock::now();
    report("partition", 0.0);
    if (settings.coupling_surfaces.empty())
      throw std::invalid_argument("reduction: no coupling surface given");
    const std::vector<long> on_boundary = model.owned_boundary_dofs(settings.coupling_surfaces);
    PetscInt                first, last;
    FRETSIM_PETSC(MatGetOwnershipRange(stiffness, &first, &last));
    std::vector<PetscInt> boundary_dofs(on_boundary.begin(), on_boundary.end()), interior_dofs;
    interior_dofs.reserve(static_cast<std::size_t>(last - first) - boundary_dofs.size());
    std::size_t next = 0;
    for (PetscInt i = first; i < last; ++i)
      {
        if (next < boundary_dofs.size() && boundary_dofs[next] == i)
          ++next;
        else
          interior_dofs.push_back(i);
      }
    FRETSIM_PETSC(ISCreateGeneral(comm, static_cast<PetscInt>(boundary_dofs.size()), boundary_dofs.data(),
                                  PETSC_COPY_VALUES, boundary.out()));
    FRETSIM_PETSC(ISCreateGeneral(comm, static_cast<PetscInt>(interior_dofs.size()), interior_dofs.data(),
                                  PETSC_COPY_VALUES, interior.out()));
    FRETSIM_PETSC(ISGetSize(boundary, &n_boundary));
    FRETSIM_PETSC(ISGetSize(interior, &n_interior));
    if (n_boundary == 0)
      throw std::invalid_argument("reduction: the coupling surfaces hold no DoFs (are the boundary ids on the mesh?)");
    if (n_interior <= static_cast<PetscInt>(settings.n_fixed_interface_modes))
      throw std::invalid_argument("reduction: " + std::to_string(settings.n_fixed_interface_modes) +
                                  " fixed-interface modes asked for, but only " + std::to_string(n_interior) +
                                  " interior DoFs");
    if (settings.n_characteristic_constraint_modes >= static_cast<unsigned int>(n_boundary))
      throw std::invalid_argument("reduction: " + std::to_string(settings.n_characteristic_constraint_modes) +
                                  " characteristic constraint modes asked for, but only " +
                                  std::to_string(n_boundary) + " boundary DoFs (use 0 to keep them all)");

    FRETSIM_PETSC(MatCreateSubMatrix(stiffness, interior, interior, MAT_INITIAL_MATRIX, K_ii.out()));
    FRETSIM_PETSC(MatCreateSubMatrix(stiffness, interior, boundary, MAT_INITIAL_MATRIX, K_ib.out()));
    FRETSIM_PETSC(MatCreateSubMatrix(stiffness, boundary, boundary, MAT_INITIAL_MATRIX, K_bb.out()));
    FRETSIM_PETSC(MatCreateSubMatrix(mass, interior, interior, MAT_INITIAL_MATRIX, M_ii.out()));
    FRETSIM_PETSC(MatCreateSubMatrix(mass, interior, boundary, MAT_INITIAL_MATRIX, M_ib.out()));
    FRETSIM_PETSC(MatCreateSubMatrix(mass, boundary, boundary, MAT_INITIAL_MATRIX, M_bb.out()));
    FRETSIM_PETSC(MatSetOption(M_ii, MAT_SYMMETRIC, PETSC_TRUE));

    work_i   = vector_like(K_ii);
    work_i2  = duplicate(work_i);
    work_b   = vector_like(K_bb);
    full_in  = vector_like(stiffness);
    full_out = duplicate(full_in);
    timings.partition = seconds_since(start);
  }

  void CraigBampton::Impl::factorise()
  {
    const auto start = Clock::now();
    report("factorising K_ii", 0.0);
    interior_solver = cholesky_solver(K_ii, comm);
    timings.factorisation = seconds_since(start);
  }

  /// K - σM, factorised: invertible for a free body too.
  static void shifted_factorisation(Mat stiffness, Mat mass, double sigma, OwnedMat &shifted, OwnedKSP &solver,
                             MPI_Comm comm)
  {
    FRETSIM_PETSC(MatDuplicate(stiffness, MAT_COPY_VALUES, shifted.out()));
    FRETSIM_PETSC(MatAXPY(shifted, -sigma, mass, SUBSET_NONZERO_PATTERN));
    solver = cholesky_solver(shifted, comm);
  }

  void CraigBampton::Impl::fixed_interface_modes()
  {
    const auto     start  = Clock::now();
    const PetscInt wanted = static_cast<PetscInt>(settings.n_fixed_interface_modes);
    fixed_interface_shapes.clear();
    fixed_interface_eigenvalues.clear();
    if (wanted == 0)
      return;
    OwnedEPS eps;
    FRETSIM_PETSC(EPSCreate(comm, eps.out()));
    FRETSIM_PETSC(EPSSetOperators(eps, K_ii, M_ii));
    FRETSIM_PETSC(EPSSetProblemType(eps, EPS_GHEP));
    FRETSIM_PETSC(EPSSetType(eps, EPSKRYLOVSCHUR));
    FRETSIM_PETSC(EPSSetDimensions(eps, wanted, PETSC_DEFAULT, PETSC_DEFAULT));
    FRETSIM_PETSC(EPSSetTolerances(eps, settings.eigen_tolerance, 1000));
    // Shift-and-invert about 0: K_ii is positive definite (the boundary is
    // held). SLEPc factorises its own operator (K_ii again, by MUMPS).
    ST st;
    FRETSIM_PETSC(EPSGetST(eps, &st));
    FRETSIM_PETSC(STSetType(st, STSINVERT));
    KSP st_solver;
    PC  st_factor;
    FRETSIM_PETSC(STGetKSP(st, &st_solver));
    FRETSIM_PETSC(KSPSetType(st_solver, KSPPREONLY));
    FRETSIM_PETSC(KSPGetPC(st_solver, &st_factor));
    FRETSIM_PETSC(PCSetType(st_factor, PCCHOLESKY));
    FRETSIM_PETSC(PCFactorSetMatSolverType(st_factor, MATSOLVERMUMPS));
    FRETSIM_PETSC(EPSSetTarget(eps, 0.0));
    FRETSIM_PETSC(EPSSetWhichEigenpairs(eps, EPS_TARGET_MAGNITUDE));
    const PetscInt n_converged = solve_eigenproblem(eps, settings, "fixed-interface modes", wanted);

    std::vector<std::pair<double, PetscInt>> order;
    for (PetscInt k = 0; k < n_converged; ++k)
      {
        PetscScalar value, imaginary;
        FRETSIM_PETSC(EPSGetEigenvalue(eps, k, &value, &imaginary));
        order.emplace_back(value, k);
      }
    std::sort(order.begin(), order.end());
    for (PetscInt j = 0; j < wanted; ++j)
      {
        OwnedVec shape = vector_like(K_ii);
        FRETSIM_PETSC(EPSGetEigenvector(eps, order[j].second, shape, nullptr));
        // Mass-normalise explicitly: φᵀ M_ii φ = 1.
        PetscScalar modal_mass;
        FRETSIM_PETSC(MatMult(M_ii, shape, work_i));
        FRETSIM_PETSC(VecDot(shape, work_i, &modal_mass));
        FRETSIM_PETSC(VecScale(shape, 1.0 / std::sqrt(modal_mass)));
        fixed_interface_eigenvalues.push_back(order[j].first);
        fixed_interface_shapes.push_back(std::move(shape));
      }
    timings.fixed_interface_modes = seconds_since(start);
  }

  void CraigBampton::Impl::apply_constraint_modes(Vec x_b, Vec u_i) const
  {
    FRETSIM_PETSC(MatMult(K_ib, x_b, work_i2));
    FRETSIM_PETSC(KSPSolve(interior_solver, work_i2, u_i));
    FRETSIM_PETSC(VecScale(u_i, -1.0));
  }

  void CraigBampton::Impl::apply_schur(Vec x_b, Vec u_i, Vec y_b) const
  {
    FRETSIM_PETSC(MatMult(K_bb, x_b, y_b));
    FRETSIM_PETSC(MatMultTransposeAdd(K_ib, u_i, y_b, y_b));
  }

  void CraigBampton::Impl::apply_guyan_mass(Vec x_b, Vec u_i, Vec y_b) const
  {
    FRETSIM_PETSC(MatMult(M_bb, x_b, y_b));
    FRETSIM_PETSC(MatMultTransposeAdd(M_ib, u_i, y_b, y_b));
    // Ψᵀ z = -K_bi K_ii⁻¹ z with z = M_ib x + M_ii u.
    FRETSIM_PETSC(MatMult(M_ib, x_b, work_i2));
    FRETSIM_PETSC(MatMultAdd(M_ii, u_i, work_i2, work_i2));
    OwnedVec solved = duplicate(work_i2);
    FRETSIM_PETSC(KSPSolve(interior_solver, work_i2, solved));
    OwnedVec back = duplicate(y_b);
    FRETSIM_PETSC(MatMultTranspose(K_ib, solved, back));
    FRETSIM_PETSC(VecAXPY(y_b, -1.0, back));
  }

  void CraigBampton::Impl::apply_interface_operator(Vec x_b, Vec y_b) const
  {
    // S⁻¹ M_G x = E_bᵀ K⁻¹ M T_G x exactly (K⁻¹ = T_G S⁻¹ T_Gᵀ + [0 0; 0 K_ii⁻¹]
    // and E_bᵀ of the second term vanishes), so the Guyan mass never has to be
    // formed: two solves per application, with K - σM standing in for K.
    apply_constraint_modes(x_b, work_i);
    FRETSIM_PETSC(VecISCopy(full_out, boundary, SCATTER_FORWARD, x_b));
    FRETSIM_PETSC(VecISCopy(full_out, interior, SCATTER_FORWARD, work_i));
    FRETSIM_PETSC(MatMult(mass, full_out, full_in));
    FRETSIM_PETSC(KSPSolve(shifted_solver, full_in, full_out));
    FRETSIM_PETSC(VecISCopy(full_out, boundary, SCATTER_REVERSE, y_b));
  }

  PetscErrorCode CraigBampton::Impl::interface_operator_mult(Mat shell, Vec x, Vec y)
  {
    void *context = nullptr;
    MatShellGetContext(shell, &context);
    try
      {
        static_cast<const Impl *>(context)->apply_interface_operator(x, y);
        return 0;
      }
    catch (const std::exception &)
      {
        return PETSC_ERR_LIB;
      }
  }

  void CraigBampton::Impl::interface_modes()
  {
    const auto start = Clock::now();
    const double lowest_fixed_interface_hz =
      fixed_interface_eigenvalues.empty() ? 0.0 : to_hz(fixed_interface_eigenvalues.front());
    const double shift_hz = settings.interface_shift_hz > 0.0 ? settings.interface_shift_hz : lowest_fixed_interface_hz / 50.0;
    if (!(shift_hz > 0.0))
      throw std::invalid_argument("reduction: set an interface shift when no fixed-interface mode is kept");
    sigma = -std::pow(2.0 * M_PI * shift_hz, 2);
    report("factorising K - sigma M", 0.0);
    shifted_factorisation(stiffness, mass, sigma, shifted_stiffness, shifted_solver, comm);
    timings.factorisation += seconds_since(start);

    const PetscInt wanted = static_cast<PetscInt>(settings.n_characteristic_constraint_modes);
    PetscInt       n_local;
    FRETSIM_PETSC(ISGetLocalSize(boundary, &n_local));
    OwnedMat shell;
    FRETSIM_PETSC(MatCreateShell(comm, n_local, n_local, n_boundary, n_boundary, this, shell.out()));
    FRETSIM_PETSC(MatShellSetOperation(shell, MATOP_MULT, reinterpret_cast<void (*)(void)>(interface_operator_mult)));

    // The operator is self-adjoint in the M_G inner product only; as a plain
    // (non-Hermitian) problem its eigenvalues are still real, and the
    // Rayleigh–Ritz step below restores exact M_G-orthogonality.
    OwnedEPS eps;
    FRETSIM_PETSC(EPSCreate(comm, eps.out()));
    FRETSIM_PETSC(EPSSetOperators(eps, shell, nullptr));
    FRETSIM_PETSC(EPSSetProblemType(eps, EPS_NHEP));
    FRETSIM_PETSC(EPSSetType(eps, EPSKRYLOVSCHUR));
    FRETSIM_PETSC(EPSSetWhichEigenpairs(eps, EPS_LARGEST_MAGNITUDE));
    FRETSIM_PETSC(EPSSetDimensions(eps, wanted, PETSC_DEFAULT, PETSC_DEFAULT));
    // The search only has to span the interface modes: Rayleigh–Ritz with the
    // exact Guyan pair then gives eigenvalues with errors of the order of the
    // squared residual, so 1e-7 here still yields ~1e-12 relative.
    FRETSIM_PETSC(EPSSetTolerances(eps, std::max(settings.eigen_tolerance, 1e-7), 1000));
    const PetscInt n_converged = solve_eigenproblem(eps, settings, "characteristic constraint modes", wanted);

    // Rayleigh–Ritz with the exact Guyan pair (S, M_G) in the space found.
    // The space is the converged invariant subspace (orthonormal Schur
    // vectors): eigenvectors of a non-Hermitian solve for a repeated
    // eigenvalue (every ring has cos/sin pairs) can come out nearly parallel.
    std::vector<OwnedVec> search(static_cast<std::size_t>(n_converged)), search_constraint, search_stiffness,
      search_mass;
    for (auto &x : search)
      x = vector_like(K_bb);
    {
      std::vector<Vec> raw(search.begin(), search.end());
      FRETSIM_PETSC(EPSGetInvariantSubspace(eps, raw.data()));
    }
    for (PetscInt k = 0; k < n_converged; ++k)
      {
        OwnedVec u = vector_like(K_ii), sx = vector_like(K_bb), mx = vector_like(K_bb);
        apply_constraint_modes(search[k], u);
        apply_schur(search[k], u, sx);
        apply_guyan_mass(search[k], u, mx);
        search_constraint.push_back(std::move(u));
        search_stiffness.push_back(std::move(sx));
        search_mass.push_back(std::move(mx));
      }
    const std::vector<Vec> stiffness_columns(search_stiffness.begin(), search_stiffness.end()),
      mass_columns(search_mass.begin(), search_mass.end());
    const auto      n = static_cast<Eigen::Index>(n_converged);
    Eigen::MatrixXd a = Eigen::Map<const Eigen::MatrixXd>(dots(search, stiffness_columns).data(), n, n);
    Eigen::MatrixXd b = Eigen::Map<const Eigen::MatrixXd>(dots(search, mass_columns).data(), n, n);
    a = 0.5 * (a + a.transpose()).eval();
    b = 0.5 * (b + b.transpose()).eval();
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ritz(a, b);
    if (ritz.info() != Eigen::Success)
      throw std::runtime_error("reduction: the interface Rayleigh–Ritz problem failed (dependent search vectors)");

    interface_shapes.clear();
    interface_constraint.clear();
    interface_eigenvalues.clear();
    const std::vector<Vec> x_raw(search.begin(), search.end()), u_raw(search_constraint.begin(), search_constraint.end());
    for (PetscInt j = 0; j < wanted; ++j)
      {
        std::vector<PetscScalar> weights(ritz.eigenvectors().col(j).data(),
                                         ritz.eigenvectors().col(j).data() + n_converged);
        OwnedVec v = vector_like(K_bb), u = vector_like(K_ii);
        FRETSIM_PETSC(VecSet(v, 0.0));
        FRETSIM_PETSC(VecSet(u, 0.0));
        FRETSIM_PETSC(VecMAXPY(v, n_converged, weights.data(), const_cast<Vec *>(x_raw.data())));
        FRETSIM_PETSC(VecMAXPY(u, n_converged, weights.data(), const_cast<Vec *>(u_raw.data())));
        interface_eigenvalues.push_back(ritz.eigenvalues()(j));
        interface_shapes.push_back(std::move(v));
        interface_constraint.push_back(std::move(u));
      }
    timings.interface_modes = seconds_since(start);
  }

  void CraigBampton::Impl::full_constraint_modes()
  {
    const auto start = Clock::now();
    interface_shapes.clear();
    interface_constraint.clear();
    interface_eigenvalues.clear();
    PetscInt first, last;
    FRETSIM_PETSC(VecGetOwnershipRange(work_b, &first, &last));
    for (PetscInt j = 0; j < n_boundary; ++j)
      {
        OwnedVec e = vector_like(K_bb), u = vector_like(K_ii);
        FRETSIM_PETSC(VecSet(e, 0.0));
        if (j >= first && j < last)
          FRETSIM_PETSC(VecSetValue(e, j, 1.0, INSERT_VALUES));
        FRETSIM_PETSC(VecAssemblyBegin(e));
        FRETSIM_PETSC(VecAssemblyEnd(e));
        apply_constraint_modes(e, u);
        interface_shapes.push_back(std::move(e));
        interface_constraint.push_back(std::move(u));
        if (j % 64 == 0)
          report("constraint modes", static_cast<double>(j) / n_boundary);
      }
    timings.constraint_modes = seconds_since(start);
  }

  void CraigBampton::Impl::assemble_basis()
  {
    basis.clear();
    for (std::size_t j = 0; j < interface_shapes.size(); ++j)
      {
        OwnedVec t = duplicate(full_in);
        FRETSIM_PETSC(VecSet(t, 0.0));
        FRETSIM_PETSC(VecISCopy(t, boundary, SCATTER_FORWARD, interface_shapes[j]));
        FRETSIM_PETSC(VecISCopy(t, interior, SCATTER_FORWARD, interface_constraint[j]));
        basis.push_back(std::move(t));
      }
    for (const OwnedVec &phi : fixed_interface_shapes)
      {
        OwnedVec t = duplicate(full_in);
        FRETSIM_PETSC(VecSet(t, 0.0));
        FRETSIM_PETSC(VecISCopy(t, interior, SCATTER_FORWARD, phi));
        basis.push_back(std::move(t));
      }
  }

  ReducedMatrices CraigBampton::Impl::reduced_matrices() const
  {
    ReducedMatrices reduced;
    reduced.n_constraint    = static_cast<unsigned int>(interface_shapes.size());
    reduced.n_modal         = static_cast<unsigned int>(fixed_interface_shapes.size());
    reduced.n_boundary_dofs = static_cast<unsigned long>(n_boundary);
    reduced.n_interior_dofs = static_cast<unsigned long>(n_interior);
    const std::size_t n     = basis.size();

    auto project = [&](Mat matrix, double &asymmetry) {
      std::vector<Vec> images;
      std::vector<OwnedVec> owned;
      for (std::size_t k = 0; k < n; ++k)
        {
          owned.push_back(duplicate(full_in));
          FRETSIM_PETSC(MatMult(matrix, basis[k], owned.back()));
          images.push_back(owned.back());
          report("reduced matrices", (static_cast<double>(k) + 1) / (2.0 * n));
        }
      std::vector<double> a = dots(basis, images);
      double              largest = 0.0, skew = 0.0;
      for (std::size_t j = 0; j < n; ++j)
        for (std::size_t k = 0; k < n; ++k)
          {
            largest = std::max(largest, std::abs(a[j * n + k]));
            skew    = std::max(skew, std::abs(a[j * n + k] - a[k * n + j]));
          }
      asymmetry = largest > 0.0 ? skew / largest : 0.0;
      for (std::size_t j = 0; j < n; ++j)
        for (std::size_t k = 0; k < j; ++k)
          a[j * n + k] = a[k * n + j] = 0.5 * (a[j * n + k] + a[k * n + j]);
      return a;
    };
    reduced.stiffness = project(stiffness, reduced.stiffness_asymmetry);
    reduced.mass      = project(mass, reduced.mass_asymmetry);
    for (const double lambda : fixed_interface_eigenvalues)
      reduced.fixed_interface_frequencies_hz.push_back(to_hz(lambda));
    for (const double lambda : interface_eigenvalues)
      reduced.interface_frequencies_hz.push_back(to_hz(lambda));
    return reduced;
  }

  CraigBampton::CraigBampton(fem::ElasticModel &model, ReductionSettings settings)
    : impl(std::make_unique<Impl>(model, std::move(settings)))
  {}
  CraigBampton::~CraigBampton() = default;

  const ReductionTimings &CraigBampton::timings() const { return impl->timings; }
  std::size_t             CraigBampton::size() const { return impl->basis.size(); }

  ReducedMatrices CraigBampton::run()
  {
    const auto start = Clock::now();
    impl->partition();
    impl->factorise();
    impl->fixed_interface_modes();
    if (impl->settings.n_characteristic_constraint_modes == 0)
      impl->full_constraint_modes();
    else
      impl->interface_modes();
    const auto matrices_start = Clock::now();
    impl->assemble_basis();
    ReducedMatrices reduced        = impl->reduced_matrices();
    impl->timings.reduced_matrices = seconds_since(matrices_start);
    impl->timings.total            = seconds_since(start);
    return reduced;
  }

  fem::DisplacementField CraigBampton::basis_field(const unsigned int j) const
  {
    return impl->model.field_from_vector(impl->basis.at(j));
  }

  std::vector<double> CraigBampton::project_load(const fem::StaticLoad &load) const
  {
    impl->model.assemble_load_vector(load, impl->full_in);
    std::vector<PetscScalar> result(impl->basis.size());
    std::vector<Vec>         raw(impl->basis.begin(), impl->basis.end());
    FRETSIM_PETSC(VecMDot(impl->full_in, static_cast<PetscInt>(raw.size()), raw.data(), result.data()));
    return {result.begin(), result.end()};
  }

  fem::DisplacementField CraigBampton::full_static(const fem::StaticLoad &load) const
  {
    if (!impl->static_solver)
      shifted_factorisation(impl->stiffness, impl->mass, impl->static_sigma, impl->static_stiffness,
                            impl->static_solver, impl->comm);
    impl->model.assemble_load_vector(load, impl->full_in);
    FRETSIM_PETSC(KSPSolve(impl->static_solver, impl->full_in, impl->full_out));
    return impl->model.field_from_vector(impl->full_out);
  }

  fem::DisplacementField CraigBampton::expand(const std::vector<double> &q) const
  {
    if (q.size() != impl->basis.size())
      throw std::invalid_argument("reduction: expand() needs one value per reduced coordinate");
    std::vector<Vec> raw(impl->basis.begin(), impl->basis.end());
    FRETSIM_PETSC(VecSet(impl->full_out, 0.0));
    FRETSIM_PETSC(VecMAXPY(impl->full_out, static_cast<PetscInt>(raw.size()), q.data(), raw.data()));
    return impl->model.field_from_vector(impl->full_out);
  }

  fem::DisplacementField CraigBampton::reduced_static(const fem::StaticLoad &load, const ReducedMatrices &reduced) const
  {
    const std::vector<double> f = project_load(load);
    const auto                n = static_cast<Eigen::Index>(reduced.size());
    const Eigen::MatrixXd     k = Eigen::Map<const Eigen::MatrixXd>(reduced.stiffness.data(), n, n);
    const Eigen::MatrixXd     m = Eigen::Map<const Eigen::MatrixXd>(reduced.mass.data(), n, n);
    const Eigen::VectorXd     q = (k - impl->static_sigma * m).ldlt().solve(Eigen::Map<const Eigen::VectorXd>(f.data(), n));
    return expand(std::vector<double>(q.data(), q.data() + n));
  }

  std::vector<double> reduced_frequencies_hz(const ReducedMatrices &reduced)
  {
    const auto            n = static_cast<Eigen::Index>(reduced.size());
    const Eigen::MatrixXd k = Eigen::Map<const Eigen::MatrixXd>(reduced.stiffness.data(), n, n);
    const Eigen::MatrixXd m = Eigen::Map<const Eigen::MatrixXd>(reduced.mass.data(), n, n);
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(k, m, Eigen::EigenvaluesOnly);
    if (solver.info() != Eigen::Success)
      throw std::runtime_error("reduction: the reduced eigenproblem failed (mass matrix not positive definite)");
    std::vector<double> frequencies;
    for (Eigen::Index j = 0; j < n; ++j)
      frequencies.push_back(to_hz(solver.eigenvalues()(j)));
    std::sort(frequencies.begin(), frequencies.end());
    return frequencies;
  }
} // namespace fretsim::reduction
