// Eigenmodes K φ = ω² M φ: SLEPc Krylov–Schur with shift-and-invert, the
// shifted operator K - σM factorised once by MUMPS.
#include "model_impl.h"

#include <deal.II/lac/slepc_solver.h>
#include <deal.II/lac/slepc_spectral_transformation.h>
#include <deal.II/lac/solver_control.h>

#include <slepceps.h>

#include <algorithm>
#include <numeric>

namespace fretsim::fem
{
  namespace
  {
    /// deal.II's Krylov–Schur wrapper with the spectral transformation's inner
    /// solve set to a direct factorisation; deal.II only offers iterative
    /// solvers there, which need a tight tolerance to keep the Krylov basis
    /// accurate and converge slowly on elasticity.
    class DirectShiftInvertKrylovSchur : public dealii::SLEPcWrappers::SolverKrylovSchur
    {
    public:
      using dealii::SLEPcWrappers::SolverKrylovSchur::SolverKrylovSchur;

      void factorise_with_mumps()
      {
        ST  st;
        KSP ksp;
        PC  pc;
        check(EPSGetST(eps, &st));
        check(STGetKSP(st, &ksp));
        check(KSPSetType(ksp, KSPPREONLY));
        check(KSPGetPC(ksp, &pc));
        // K - σM with σ < 0 is symmetric positive definite: Cholesky.
        check(PCSetType(pc, PCCHOLESKY));
        check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
      }

    private:
      static void check(const PetscErrorCode code)
      {
        if (code != 0)
          throw std::runtime_error("fem::ElasticModel::solve_modes: SLEPc/PETSc error " + std::to_string(code));
      }
    };
  } // namespace

  ModalSolution ElasticModel::solve_modes(const ModalSettings &settings)
  {
    auto      &model = *pimpl;
    const auto start = std::chrono::steady_clock::now();
    model.assemble_mass();

    // Up to six rigid-body modes come first (nearest to the shift).
    const unsigned int n_wanted = std::min<unsigned long>(settings.n_modes + 6, model.dof_handler.n_dofs() / 2);
    const double       omega_shift = 2.0 * M_PI * settings.shift_hz;
    const double       sigma       = -omega_shift * omega_shift;

    dealii::SolverControl                             control(1000, settings.tolerance, false, false);
    DirectShiftInvertKrylovSchur                      eigensolver(control, model.communicator());
    dealii::SLEPcWrappers::TransformationShiftInvert  shift_invert(
      model.communicator(), dealii::SLEPcWrappers::TransformationShiftInvert::AdditionalData(sigma));
    eigensolver.set_transformation(shift_invert);
    eigensolver.factorise_with_mumps();
    eigensolver.set_problem_type(EPS_GHEP);
    eigensolver.set_target_eigenvalue(sigma);
    eigensolver.set_which_eigenpairs(EPS_TARGET_MAGNITUDE);

    std::vector<PetscScalar>                        eigenvalues;
    std::vector<dealii::PETScWrappers::MPI::Vector> eigenvectors(
      n_wanted, dealii::PETScWrappers::MPI::Vector(model.owned_dofs, model.communicator()));
    eigensolver.solve(model.stiffness, model.mass, eigenvalues, eigenvectors, n_wanted);

    std::vector<unsigned int> order(eigenvalues.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](unsigned int a, unsigned int b) { return eigenvalues[a] < eigenvalues[b]; });

    ModalSolution result;
    const double  cutoff = 2.0 * M_PI * settings.rigid_body_cutoff_hz;
    for (const unsigned int k : order)
      {
        const double omega = std::sqrt(std::max(0.0, static_cast<double>(eigenvalues[k])));
        if (omega < cutoff)
          {
            ++result.n_rigid_body_modes;
            continue;
          }
        if (result.frequencies_hz.size() == settings.n_modes)
          break;
        result.frequencies_hz.push_back(omega / (2.0 * M_PI));
        auto field          = std::make_unique<DisplacementField::Impl>();
        field->model        = pimpl;
        field->displacement = model.ghosted(eigenvectors[k]);
        result.shapes.emplace_back(std::move(field));
      }
    result.seconds = seconds_since(start);
    return result;
  }
} // namespace fretsim::fem
