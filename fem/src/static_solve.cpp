// Static solutions: assemble the load, solve K u = f, apply the constraints.
#include "model_impl.h"
#include "surface_grid_map_impl.h"
#include "surface_point_map_impl.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/petsc_precondition.h>
#include <deal.II/lac/petsc_solver.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/lac/solver_control.h>

#include <petscksp.h>

namespace fretsim::fem
{
  namespace
  {
    using Clock = std::chrono::steady_clock;
  } // namespace

  dealii::PETScWrappers::MPI::Vector assemble_load(const ElasticModel::Impl &model, const StaticLoad &load)
    {
      dealii::PETScWrappers::MPI::Vector rhs(model.owned_dofs, model.communicator());
      const unsigned int                 n = model.fe.n_dofs_per_cell();
      dealii::Vector<double>             cell_rhs(n);
      std::vector<dealii::types::global_dof_index> dof_indices(n);

      std::map<unsigned int, double> pressure_on, expansion_of;
      for (const PressureLoad &p : load.pressures)
        pressure_on[static_cast<unsigned int>(p.boundary)] += p.pressure;
      for (const InPlaneExpansion &e : load.expansions)
        expansion_of[static_cast<unsigned int>(e.body)] += e.strain;

      const dealii::QGauss<3>   quadrature(model.degree + 1);
      const dealii::QGauss<2>   face_quadrature(model.degree + 1);
      dealii::FEValues<3>       fe_values(model.mapping, model.fe, quadrature,
                                          dealii::update_gradients | dealii::update_JxW_values);
      dealii::FEFaceValues<3>   fe_face_values(model.mapping, model.fe, face_quadrature,
                                               dealii::update_values | dealii::update_normal_vectors |
                                                 dealii::update_JxW_values);
      for (const auto &cell : model.dof_handler.active_cell_iterators())
        {
          if (!cell->is_locally_owned())
            continue;
          cell_rhs = 0.0;
          bool loaded = false;

          // Eigenstrain: f_i = ∫ (C:ε*) : ∇φ_i, with C:ε* = e (2λ I + 2μ (I - e_z⊗e_z)).
          if (const auto e = expansion_of.find(cell->material_id()); e != expansion_of.end())
            {
              const Lame  &m = model.material(cell->material_id());
              const double s_in_plane = 2.0 * (m.lambda + m.mu) * e->second, s_axial = 2.0 * m.lambda * e->second;
              fe_values.reinit(cell);
              for (unsigned int q = 0; q < quadrature.size(); ++q)
                for (unsigned int i = 0; i < n; ++i)
                  {
                    const unsigned int c = model.fe.system_to_component_index(i).first;
                    cell_rhs(i) += (c == 2 ? s_axial : s_in_plane) * fe_values.shape_grad(i, q)[c] * fe_values.JxW(q);
                  }
              loaded = true;
            }

          for (unsigned int f = 0; f < cell->n_faces(); ++f)
            {
              if (!cell->face(f)->at_boundary())
                continue;
              const auto p = pressure_on.find(cell->face(f)->boundary_id());
              if (p == pressure_on.end())
                continue;
              fe_face_values.reinit(cell, f);
              for (unsigned int q = 0; q < face_quadrature.size(); ++q)
                for (unsigned int i = 0; i < n; ++i)
                  {
                    const unsigned int c = model.fe.system_to_component_index(i).first;
                    cell_rhs(i) -= p->second * fe_face_values.normal_vector(q)[c] *
                                   fe_face_values.shape_value(i, q) * fe_face_values.JxW(q);
                  }
              loaded = true;
            }
          if (!loaded)
            continue;
          cell->get_dof_indices(dof_indices);
          model.constraints.distribute_local_to_global(cell_rhs, dof_indices, rhs);
        }
      for (const GridTractionLoad &g : load.grid_tractions)
        g.map->impl().add_forces(*g.tractions, rhs);
      for (const PointForceLoad &p : load.point_forces)
        p.map->impl().add_forces(p.forces, rhs);
      if (!load.ball_loads.empty())
        add_raceway_ball_loads(model, load.ball_loads, rhs);
      rhs.compress(dealii::VectorOperation::add);
      return rhs;
    }

  namespace
  {

    void check_petsc(const PetscErrorCode error, const char *what)
    {
      if (error != 0)
        throw std::runtime_error(std::string("fem::ElasticModel: PETSc failed in ") + what + " (error " +
                                 std::to_string(static_cast<int>(error)) + ")");
    }

  } // namespace

  std::vector<Vec> rigid_body_modes(const ElasticModel::Impl &model, const bool orthonormalise)
  {
    std::map<dealii::types::global_dof_index, dealii::Point<3>> points;
    dealii::DoFTools::map_dofs_to_support_points(model.mapping, model.dof_handler, points);
    std::vector<dealii::types::global_dof_index> dof_indices(model.fe.n_dofs_per_cell());
    std::map<dealii::types::global_dof_index, unsigned int> component_of;
    for (const auto &cell : model.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dof_indices);
          for (unsigned int i = 0; i < dof_indices.size(); ++i)
            if (model.owned_dofs.is_element(dof_indices[i]))
              component_of[dof_indices[i]] = model.fe.system_to_component_index(i).first;
        }
    std::vector<dealii::PETScWrappers::MPI::Vector> modes(6);
    for (auto &m : modes)
      m.reinit(model.owned_dofs, model.communicator());
    for (const auto &[dof, c] : component_of)
      {
        const dealii::Point<3> &x = points.at(dof);
        modes[c][dof]             = 1.0;
        // Rotation about axis k: u = e_k × x.
        for (unsigned int k = 0; k < 3; ++k)
          {
            dealii::Tensor<1, 3> axis;
            axis[k]                   = 1.0;
            const dealii::Tensor<1, 3> u = dealii::cross_product_3d(axis, static_cast<dealii::Tensor<1, 3>>(x));
            modes[3 + k][dof]         = u[c];
          }
      }
    std::vector<Vec> vecs(6);
    for (unsigned int i = 0; i < 6; ++i)
      {
        modes[i].compress(dealii::VectorOperation::insert);
        check_petsc(VecDuplicate(static_cast<Vec>(modes[i]), &vecs[i]), "VecDuplicate");
        check_petsc(VecCopy(static_cast<Vec>(modes[i]), vecs[i]), "VecCopy");
        if (!orthonormalise)
          continue;
        // Gram–Schmidt: MatNullSpaceCreate wants an orthonormal set.
        for (unsigned int j = 0; j < i; ++j)
          {
            PetscScalar dot;
            check_petsc(VecDot(vecs[i], vecs[j], &dot), "VecDot");
            check_petsc(VecAXPY(vecs[i], -dot, vecs[j]), "VecAXPY");
          }
        check_petsc(VecNormalize(vecs[i], nullptr), "VecNormalize");
      }
    return vecs;
  }

  namespace
  {
    unsigned int solve_gamg(const ElasticModel::Impl &model, const dealii::PETScWrappers::MPI::Vector &rhs,
                            dealii::PETScWrappers::MPI::Vector &solution, const SolverSettings &settings)
    {
      // K carries block size 3 (elastic_model.cpp), so GAMG aggregates nodes.
      // Declared symmetric, GAMG takes its graph as it is instead of
      // symmetrising it (A + Aᵀ: a copy of K for nothing).
      Mat K = static_cast<Mat>(model.stiffness);
      check_petsc(MatSetOption(K, MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption");
      check_petsc(MatSetOption(K, MAT_SPD, PETSC_TRUE), "MatSetOption");
      auto vecs = rigid_body_modes(model);
      MatNullSpace near_null;
      check_petsc(MatNullSpaceCreate(model.communicator(), PETSC_FALSE, 6, vecs.data(), &near_null),
                  "MatNullSpaceCreate");
      check_petsc(MatSetNearNullSpace(K, near_null), "MatSetNearNullSpace");
      KSP ksp;
      check_petsc(KSPCreate(model.communicator(), &ksp), "KSPCreate");
      check_petsc(KSPSetOperators(ksp, K, K), "KSPSetOperators");
      check_petsc(KSPSetType(ksp, KSPCG), "KSPSetType");
      // Relative to ‖b‖ in the unpreconditioned norm, as a user reads it.
      check_petsc(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
      check_petsc(KSPSetTolerances(ksp, settings.relative_tolerance, 1e-300, 1e300, settings.max_iterations),
                  "KSPSetTolerances");
      PC pc;
      check_petsc(KSPGetPC(ksp, &pc), "KSPGetPC");
      check_petsc(PCSetType(pc, PCGAMG), "PCSetType");
      // Measured on the Q2 6208 ring (tests/fem/slow_scaling.cpp, docs/performance.md):
      // a quadratic hexahedron couples a node with up to 125 others, so the
      // graph is already wide; squaring it for aggressive coarsening on the
      // first level (PETSc's default) costs more than it saves.
      check_petsc(PCGAMGSetAggressiveLevels(pc, 0), "PCGAMGSetAggressiveLevels");
      // Plain aggregation: the smoothed prolongator of a Q2 hexahedral mesh is
      // so dense that the Galerkin product P^T K P took 6 of 16 s at 194k
      // DoFs; unsmoothed, setup falls to a third for 20 % more iterations.
      check_petsc(PCGAMGSetNSmooths(pc, 0), "PCGAMGSetNSmooths");
      // Any setting can be changed at run time, e.g.
      // PETSC_OPTIONS='-fretsim_static_pc_gamg_threshold 0.02 -fretsim_static_ksp_view'.
      check_petsc(KSPSetOptionsPrefix(ksp, "fretsim_static_"), "KSPSetOptionsPrefix");
      check_petsc(KSPSetFromOptions(ksp), "KSPSetFromOptions");
      check_petsc(KSPSetUp(ksp), "KSPSetUp");
      check_petsc(KSPSolve(ksp, static_cast<Vec>(rhs), static_cast<Vec>(solution)), "KSPSolve");
      KSPConvergedReason reason;
      PetscInt           iterations = 0;
      KSPGetConvergedReason(ksp, &reason);
      KSPGetIterationNumber(ksp, &iterations);
      KSPDestroy(&ksp);
      MatSetNearNullSpace(K, nullptr);
      MatNullSpaceDestroy(&near_null);
      for (Vec &v : vecs)
        VecDestroy(&v);
      if (reason < 0)
        throw std::runtime_error("fem::ElasticModel: CG+GAMG did not converge (PETSc reason " +
                                 std::to_string(static_cast<int>(reason)) + ") after " +
                                 std::to_string(iterations) + " iterations");
      return static_cast<unsigned int>(iterations);
    }

    unsigned int solve(const ElasticModel::Impl &model, const dealii::PETScWrappers::MPI::Vector &rhs,
                       dealii::PETScWrappers::MPI::Vector &solution, const SolverSettings &settings)
    {
      if (settings.type == LinearSolver::direct)
        {
          dealii::SolverControl                    control(1, 0.0);
          dealii::PETScWrappers::SparseDirectMUMPS solver(control, model.communicator());
          solver.set_symmetric_mode(true);
          solver.solve(model.stiffness, solution, rhs);
          return 1;
        }
      if (settings.type == LinearSolver::cg_gamg)
        return solve_gamg(model, rhs, solution, settings);
      // PETSc's CG measures the preconditioned residual ‖B r‖, whose scale
      // the AMG sets; a reduction relative to the first one is what tells.
      dealii::ReductionControl control(settings.max_iterations, 1e-300, settings.relative_tolerance);
      dealii::PETScWrappers::SolverCG solver(control, model.communicator());
      dealii::PETScWrappers::PreconditionBoomerAMG::AdditionalData amg;
      amg.symmetric_operator = true;
      amg.strong_threshold   = 0.5; // hypre's advice for 3-D problems
      dealii::PETScWrappers::PreconditionBoomerAMG preconditioner(model.stiffness, amg);
      solver.solve(model.stiffness, solution, rhs, preconditioner);
      return control.last_step();
    }
  } // namespace

  DisplacementField ElasticModel::solve_static(const StaticLoad &load, const SolverSettings &settings)
  {
    auto       &model = *pimpl;
    const auto  start = Clock::now();
    const auto  rhs   = assemble_load(model, load);
    model.timings.assemble_load = seconds_since(start);

    const auto                         solve_start = Clock::now();
    dealii::PETScWrappers::MPI::Vector solution(model.owned_dofs, model.communicator());
    model.timings.iterations = solve(model, rhs, solution, settings);
    model.timings.solve      = seconds_since(solve_start);

    auto field          = std::make_unique<DisplacementField::Impl>();
    field->model        = pimpl;
    field->displacement = model.ghosted(std::move(solution));
    field->expansions   = load.expansions;
    return DisplacementField(std::move(field));
  }
} // namespace fretsim::fem
