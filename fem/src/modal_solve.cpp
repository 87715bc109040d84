// Eigenmodes K φ = ω² M φ: SLEPc Krylov–Schur with shift-and-invert, the
// shifted operator K - σM factorised once by MUMPS.
#include "model_impl.h"

#include <slepceps.h>

#include <algorithm>
#include <numeric>

namespace fretsim::fem
{
  namespace
  {
    void check(const PetscErrorCode code, const char *call)
    {
      if (code != 0)
        throw std::runtime_error(std::string("fem::ElasticModel::solve_modes: SLEPc/PETSc error ") +
                                 std::to_string(static_cast<int>(code)) + " in " + call);
    }
#define FRETSIM_SLEPC(call) check((call), #call)

    /// Owns a SLEPc eigensolver.
    struct Eigensolver
    {
      EPS eps = nullptr;
      ~Eigensolver()
      {
        if (eps != nullptr)
          EPSDestroy(&eps);
      }
    };
  } // namespace

  ModalSolution ElasticModel::solve_modes(const ModalSettings &settings)
  {
    auto      &model = *pimpl;
    const auto start = std::chrono::steady_clock::now();
    model.assemble_mass();

    // Up to six rigid-body modes come first (nearest to the shift).
    const PetscInt n_wanted    = std::min<unsigned long>(settings.n_modes + 6, model.dof_handler.n_dofs() / 2);
    const double   omega_shift = 2.0 * M_PI * settings.shift_hz;
    const double   sigma       = -omega_shift * omega_shift;

    // SLEPc directly rather than deal.II's wrapper: the wrapper's convergence
    // test is absolute, which under shift-and-invert (θ = 1/(λ - σ) ~ 1e-10)
    // stops the iteration before the second member of a degenerate pair (the
    // cos nθ / sin nθ modes of every ring) has emerged from round-off.
    Eigensolver solver;
    FRETSIM_SLEPC(EPSCreate(model.communicator(), &solver.eps));
    EPS eps = solver.eps;
    FRETSIM_SLEPC(EPSSetOperators(eps, static_cast<Mat>(model.stiffness), static_cast<Mat>(model.mass)));
    FRETSIM_SLEPC(EPSSetProblemType(eps, EPS_GHEP));
    FRETSIM_SLEPC(EPSSetType(eps, EPSKRYLOVSCHUR));
    FRETSIM_SLEPC(EPSSetDimensions(eps, n_wanted, PETSC_DEFAULT, PETSC_DEFAULT));
    FRETSIM_SLEPC(EPSSetTolerances(eps, settings.tolerance, 1000));
    FRETSIM_SLEPC(EPSSetConvergenceTest(eps, EPS_CONV_REL));
    ST  st;
    KSP ksp;
    PC  pc;
    FRETSIM_SLEPC(EPSGetST(eps, &st));
    FRETSIM_SLEPC(STSetType(st, STSINVERT));
    FRETSIM_SLEPC(STGetKSP(st, &ksp));
    FRETSIM_SLEPC(KSPSetType(ksp, KSPPREONLY));
    FRETSIM_SLEPC(KSPGetPC(ksp, &pc));
    // K - σM with σ < 0 is symmetric positive definite: Cholesky.
    FRETSIM_SLEPC(PCSetType(pc, PCCHOLESKY));
    FRETSIM_SLEPC(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
    FRETSIM_SLEPC(EPSSetTarget(eps, sigma));
    FRETSIM_SLEPC(EPSSetWhichEigenpairs(eps, EPS_TARGET_MAGNITUDE));
    FRETSIM_SLEPC(EPSSolve(eps));
    PetscInt n_converged = 0;
    FRETSIM_SLEPC(EPSGetConverged(eps, &n_converged));
    if (n_converged < n_wanted)
      throw std::runtime_error("fem::ElasticModel::solve_modes: only " + std::to_string(n_converged) + " of " +
                               std::to_string(n_wanted) + " eigenpairs converged");

    std::vector<std::pair<double, PetscInt>> order;
    for (PetscInt k = 0; k < n_converged; ++k)
      {
        PetscScalar value, imaginary;
        FRETSIM_SLEPC(EPSGetEigenvalue(eps, k, &value, &imaginary));
        order.emplace_back(value, k);
      }
    std::sort(order.begin(), order.end());

    ModalSolution result;
    const double  cutoff = 2.0 * M_PI * settings.rigid_body_cutoff_hz;
    for (const auto &[eigenvalue, k] : order)
      {
        const double omega = std::sqrt(std::max(0.0, eigenvalue));
        if (omega < cutoff)
          {
            ++result.n_rigid_body_modes;
            continue;
          }
        if (result.frequencies_hz.size() == settings.n_modes)
          break;
        dealii::PETScWrappers::MPI::Vector shape(model.owned_dofs, model.communicator());
        FRETSIM_SLEPC(EPSGetEigenvector(eps, k, static_cast<const Vec &>(shape), nullptr));
        // Mass-normalise: φᵀ M φ = 1.
        dealii::PETScWrappers::MPI::Vector mass_times_shape(model.owned_dofs, model.communicator());
        model.mass.vmult(mass_times_shape, shape);
        shape /= std::sqrt(shape * mass_times_shape);
        result.frequencies_hz.push_back(omega / (2.0 * M_PI));
        auto field          = std::make_unique<DisplacementField::Impl>();
        field->model        = pimpl;
        field->displacement = model.ghosted(shape);
        result.shapes.emplace_back(std::move(field));
      }
    result.seconds = seconds_since(start);
    return result;
  }
} // namespace fretsim::fem
