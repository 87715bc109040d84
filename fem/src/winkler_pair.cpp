// WinklerPairNewmark (winkler_foundation.h): ring and housing in one joint
// PETSc matrix. Each rank owns its ring rows and then its housing rows, so
// the joint layout is the two models' layouts side by side and the vectors
// are copied segment by segment. The layer's cells are gathered on every
// rank once (their joint DoF indices and weights), so a rank adds the layer
// to the rows it owns without talking to the others; the matrix's pattern
// holds every cell's coupling from the start (zeros where the set is open),
// so a new set only copies values and refactorises.
#include "newmark_rule.h"
#include "surface_grid_map_impl.h"
#include "winkler_active_set.h"

#include <fretsim/fem/winkler_foundation.h>

#include <deal.II/base/mpi.h>

#include <petscksp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_map>

namespace fretsim::fem
{
  namespace
  {
    using Clock = std::chrono::steady_clock;

    const std::string who = "fem::WinklerPairNewmark";

    void check_petsc(const PetscErrorCode error, const char *what)
    {
      if (error != 0)
        throw std::runtime_error(who + ": PETSc failed in " + what + " (error " +
                                 std::to_string(static_cast<int>(error)) + ")");
    }

    using OwnedVector = dealii::PETScWrappers::MPI::Vector;

    /// One body's place in the joint system.
    struct Body
    {
      ElasticModel         *model = nullptr;
      const SurfaceGridMap *map   = nullptr;
      std::vector<PetscInt> starts; ///< first owned DoF per rank, then n_dofs (size ranks + 1)
      PetscInt              begin = 0, end = 0; ///< this rank's owned DoFs
      OwnedVector           u, v;               ///< the Newmark state

      PetscInt local_size() const { return end - begin; }
      int      owner(PetscInt dof) const
      {
        return static_cast<int>(std::upper_bound(starts.begin(), starts.end(), dof) - starts.begin()) - 1;
      }
    };

    /// The ring's DoF i of rank r is joint i + (housing DoFs before rank r);
    /// the housing's j is j + (ring DoFs up to and with rank r).
    PetscInt joint_index(const Body &self, const Body &other, bool first, PetscInt dof)
    {
      const int rank = self.owner(dof);
      return dof + other.starts[static_cast<std::size_t>(first ? rank : rank + 1)];
    }

    /// K - σM of a body, a new PETSc matrix.
    Mat shifted_matrix(ElasticModel &model, double sigma)
    {
      Mat shifted;
      check_petsc(MatDuplicate(model.petsc_stiffness(), MAT_COPY_VALUES, &shifted), "MatDuplicate");
      check_petsc(MatAXPY(shifted, -sigma, model.petsc_mass(), SUBSET_NONZERO_PATTERN), "MatAXPY");
      return shifted;
    }
  } // namespace

  struct WinklerPairNewmark::Impl : WinklerStepRecord
  {
    MPI_Comm     comm;
    Body         ring, housing;
    WinklerLayer layer;
    double       k_area = 0.0;
    PetscInt     joint_begin = 0, joint_end = 0, joint_size = 0;
    /// Per layer cell, both bodies' joint DoF indices and weights w_c.
    std::vector<std::vector<PetscInt>> cell_dofs;
    std::vector<std::vector<double>>   cell_weights;

    /// The joint matrix for one shift σ and its factorisation.
    struct System
    {
      Mat                        base = nullptr;   ///< K - σM of both, the layer's pattern with zeros
      Mat                        matrix = nullptr; ///< base + the active cells' layer
      KSP                        ksp = nullptr;
      std::vector<unsigned char> factorised;       ///< the set `matrix` is factorised for
      ~System()
      {
        if (ksp)
          KSPDestroy(&ksp);
        if (matrix)
          MatDestroy(&matrix);
        if (base)
          MatDestroy(&base);
      }
    };
    std::unique_ptr<System> step_system;

    StaticLoad          ring_load; ///< at time t
    WinklerGridSolution start;     ///< the static start's foundation

    void gather_layer_cells();
    std::unique_ptr<System> build_system(double sigma) const;
    WinklerGridSolution     solve(System &system, const OwnedVector &ring_rhs, const OwnedVector &housing_rhs,
                                  const std::vector<unsigned char> &initial_active, OwnedVector &ring_u,
                                  OwnedVector &housing_u) const;

    /// First joint row per rank, then the joint size (size ranks + 1).
    std::vector<PetscInt> joint_starts;

    /// Whether joint row j is a ring DoF (each rank's rows: its ring part first).
    bool is_ring_joint(PetscInt j) const
    {
      const std::size_t rank =
        static_cast<std::size_t>(std::upper_bound(joint_starts.begin(), joint_starts.end(), j) - joint_starts.begin()) - 1;
      return j < joint_starts[rank] + ring.starts[rank + 1] - ring.starts[rank];
    }

    PetscInt joint(const Body &body, PetscInt dof) const
    {
      return &body == &ring ? joint_index(ring, housing, true, dof) : joint_index(housing, ring, false, dof);
    }
  };

  void WinklerPairNewmark::Impl::gather_layer_cells()
  {
    // Each sample lives on the rank that owns its cell: every rank writes its
    // own and a sum over the ranks gives all (index + 1, 0 for none).
    const std::size_t cells = ring.map->grid().size();
    const unsigned int per_ring = ring.model->impl().fe.n_dofs_per_cell();
    const unsigned int per_housing = housing.model->impl().fe.n_dofs_per_cell();
    const std::size_t  per_cell = per_ring + per_housing;
    std::vector<double> indices(cells * per_cell, 0.0), weights(cells * per_cell, 0.0);
    std::vector<double> w;
    std::vector<dealii::types::global_dof_index> dofs;
    for (const Body *body : {&ring, &housing})
      {
        const auto        &model  = body->model->impl();
        const auto        &map    = body->map->impl();
        const std::size_t  offset = body == &ring ? 0 : per_ring;
        dofs.resize(model.fe.n_dofs_per_cell());
        for (const auto &s : map.samples)
          {
            map.pressure_weights(s, w);
            s.cell->get_dof_indices(dofs);
            for (std::size_t i = 0; i < dofs.size(); ++i)
              {
                const auto dof = dofs[i];
                if (model.constraints.is_constrained(dof))
                  {
                    const auto *entries = model.constraints.get_constraint_entries(dof);
                    if ((entries && !entries->empty()) || model.constraints.get_inhomogeneity(dof) != 0.0)
                      throw std::runtime_error(who + ": a layer cell's DoF is constrained other than to zero "
                                                     "(hanging nodes or a prescribed motion on the contact surface)");
                    continue; // held at zero: the layer does not move it
                  }
                const std::size_t k = s.grid_cell * per_cell + offset + i;
                indices[k] = static_cast<double>(joint(*body, static_cast<PetscInt>(dof)) + 1); // exact below 2⁵³
                weights[k] = w[i];
              }
          }
      }
    dealii::Utilities::MPI::sum(indices, comm, indices);
    dealii::Utilities::MPI::sum(weights, comm, weights);
    cell_dofs.assign(cells, {});
    cell_weights.assign(cells, {});
    for (std::size_t c = 0; c < cells; ++c)
      for (std::size_t i = 0; i < per_cell; ++i)
        if (indices[c * per_cell + i] > 0.0)
          {
            cell_dofs[c].push_back(static_cast<PetscInt>(indices[c * per_cell + i]) - 1);
            cell_weights[c].push_back(weights[c * per_cell + i]);
          }
  }

  std::unique_ptr<WinklerPairNewmark::Impl::System> WinklerPairNewmark::Impl::build_system(const double sigma) const
  {
    auto system = std::make_unique<System>();
    const PetscInt local = joint_end - joint_begin;
    // The layer couples a ring row to the housing DoFs of its cells and back;
    // the same body's DoFs of a cell are in that body's pattern already.
    std::unordered_map<PetscInt, std::vector<PetscInt>> coupling; // owned joint row -> the other body's columns
    for (const auto &dofs : cell_dofs)
      for (const PetscInt row : dofs)
        if (row >= joint_begin && row < joint_end)
          {
            auto &columns = coupling[row];
            for (const PetscInt column : dofs)
              columns.push_back(column);
          }
    Mat         shifted[2] = {shifted_matrix(*ring.model, sigma), shifted_matrix(*housing.model, sigma)};
    const Body *bodies[2]  = {&ring, &housing};
    for (auto &[row, columns] : coupling)
      {
        const bool ring_row = is_ring_joint(row);
        columns.erase(std::remove_if(columns.begin(), columns.end(),
                                     [&](PetscInt column) { return is_ring_joint(column) == ring_row; }),
                      columns.end());
        std::sort(columns.begin(), columns.end());
        columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
      }

    std::vector<PetscInt> diagonal(static_cast<std::size_t>(local), 0), off_diagonal(static_cast<std::size_t>(local), 0);
    const auto count = [&](PetscInt row, PetscInt column) {
      auto &n = column >= joint_begin && column < joint_end ? diagonal : off_diagonal;
      ++n[static_cast<std::size_t>(row - joint_begin)];
    };
    for (int b = 0; b < 2; ++b)
      for (PetscInt i = bodies[b]->begin; i < bodies[b]->end; ++i)
        {
          PetscInt           n;
          const PetscInt    *columns;
          check_petsc(MatGetRow(shifted[b], i, &n, &columns, nullptr), "MatGetRow");
          const PetscInt row = joint(*bodies[b], i);
          for (PetscInt k = 0; k < n; ++k)
            count(row, joint(*bodies[b], columns[k]));
          check_petsc(MatRestoreRow(shifted[b], i, &n, &columns, nullptr), "MatRestoreRow");
          if (const auto found = coupling.find(row); found != coupling.end())
            for (const PetscInt column : found->second)
              count(row, column);
        }
    check_petsc(MatCreateAIJ(comm, local, local, joint_size, joint_size, 0, diagonal.data(), 0, off_diagonal.data(),
                             &system->base),
                "MatCreateAIJ");
    std::vector<PetscInt> mapped;
    std::vector<double>   zeros;
    for (int b = 0; b < 2; ++b)
      {
        for (PetscInt i = bodies[b]->begin; i < bodies[b]->end; ++i)
          {
            PetscInt           n;
            const PetscInt    *columns;
            const PetscScalar *values;
            check_petsc(MatGetRow(shifted[b], i, &n, &columns, &values), "MatGetRow");
            const PetscInt row = joint(*bodies[b], i);
            mapped.resize(static_cast<std::size_t>(n));
            for (PetscInt k = 0; k < n; ++k)
              mapped[static_cast<std::size_t>(k)] = joint(*bodies[b], columns[k]);
            check_petsc(MatSetValues(system->base, 1, &row, n, mapped.data(), values, INSERT_VALUES), "MatSetValues");
            check_petsc(MatRestoreRow(shifted[b], i, &n, &columns, &values), "MatRestoreRow");
            if (const auto found = coupling.find(row); found != coupling.end())
              {
                zeros.assign(found->second.size(), 0.0);
                check_petsc(MatSetValues(system->base, 1, &row, static_cast<PetscInt>(found->second.size()),
                                         found->second.data(), zeros.data(), INSERT_VALUES),
                            "MatSetValues");
              }
          }
        MatDestroy(&shifted[b]);
      }
    check_petsc(MatAssemblyBegin(system->base, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
    check_petsc(MatAssemblyEnd(system->base, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
    check_petsc(MatDuplicate(system->base, MAT_COPY_VALUES, &system->matrix), "MatDuplicate");
    check_petsc(MatSetOption(system->matrix, MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption");
    check_petsc(MatSetOption(system->matrix, MAT_SPD, PETSC_TRUE), "MatSetOption");
    check_petsc(KSPCreate(comm, &system->ksp), "KSPCreate");
    check_petsc(KSPSetType(system->ksp, KSPPREONLY), "KSPSetType");
    PC pc;
    check_petsc(KSPGetPC(system->ksp, &pc), "KSPGetPC");
    check_petsc(PCSetType(pc, PCCHOLESKY), "PCSetType");
    check_petsc(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
    return system;
  }

  WinklerGridSolution WinklerPairNewmark::Impl::solve(System &system, const OwnedVector &ring_rhs,
                                                      const OwnedVector                &housing_rhs,
                                                      const std::vector<unsigned char> &initial_active,
                                                      OwnedVector &ring_u, OwnedVector &housing_u) const
  {
    const std::size_t cells = cell_dofs.size();
    const double      fit   = layer.radial_interference;
    const PetscInt    local = joint_end - joint_begin;
    Vec               rhs, candidate, u;
    check_petsc(VecCreateMPI(comm, local, joint_size, &rhs), "VecCreateMPI");
    check_petsc(VecDuplicate(rhs, &candidate), "VecDuplicate");
    check_petsc(VecDuplicate(rhs, &u), "VecDuplicate");
    // Joint <-> body vectors, segment by segment (this rank's ring rows, then its housing rows).
    const auto copy_segments = [&](Vec joint_vector, const Vec ring_vector, const Vec housing_vector, bool to_joint) {
      PetscScalar *joint_values;
      check_petsc(VecGetArray(joint_vector, &joint_values), "VecGetArray");
      PetscInt offset = 0;
      for (const Vec part : {ring_vector, housing_vector})
        {
          PetscInt     n;
          PetscScalar *values;
          check_petsc(VecGetLocalSize(part, &n), "VecGetLocalSize");
          check_petsc(VecGetArray(part, &values), "VecGetArray");
          if (to_joint)
            std::copy(values, values + n, joint_values + offset);
          else
            std::copy(joint_values + offset, joint_values + offset + n, values);
          check_petsc(VecRestoreArray(part, &values), "VecRestoreArray");
          offset += n;
        }
      check_petsc(VecRestoreArray(joint_vector, &joint_values), "VecRestoreArray");
    };
    const auto split = [&](Vec joint_vector, OwnedVector &ring_part, OwnedVector &housing_part) {
      copy_segments(joint_vector, static_cast<const Vec &>(ring_part), static_cast<const Vec &>(housing_part), false);
    };
    OwnedVector ring_part(ring_u), housing_part(housing_u);
    copy_segments(rhs, static_cast<const Vec &>(ring_rhs), static_cast<const Vec &>(housing_rhs), true);

    WinklerGridSolution grid;
    bool                have_state = false;
    std::vector<double> values;
    ActiveSetSolver     callbacks;
    callbacks.solve = [&](const std::vector<unsigned char> &active) {
      const bool refactorise  = active != system.factorised;
      const auto factor_start = Clock::now();
      Vec        layer_rhs;
      check_petsc(VecDuplicate(rhs, &layer_rhs), "VecDuplicate");
      check_petsc(VecCopy(rhs, layer_rhs), "VecCopy");
      PetscScalar *b;
      check_petsc(VecGetArray(layer_rhs, &b), "VecGetArray");
      if (refactorise)
        check_petsc(MatCopy(system.base, system.matrix, SAME_NONZERO_PATTERN), "MatCopy");
      // The active cells' k_n A w_c w_cᵀ and k_n A δ_fit w_c, on the rows this rank owns.
      for (std::size_t c = 0; c < cells; ++c)
        if (active[c])
          {
            const auto &dofs = cell_dofs[c];
            const auto &w    = cell_weights[c];
            values.resize(dofs.size());
            for (std::size_t i = 0; i < dofs.size(); ++i)
              if (dofs[i] >= joint_begin && dofs[i] < joint_end)
                {
                  b[dofs[i] - joint_begin] += k_area * fit * w[i];
                  if (refactorise)
                    {
                      for (std::size_t j = 0; j < dofs.size(); ++j)
                        values[j] = k_area * w[i] * w[j];
                      check_petsc(MatSetValues(system.matrix, 1, &dofs[i], static_cast<PetscInt>(dofs.size()),
                                               dofs.data(), values.data(), ADD_VALUES),
                                  "MatSetValues");
                    }
                }
          }
      check_petsc(VecRestoreArray(layer_rhs, &b), "VecRestoreArray");
      if (refactorise)
        {
          check_petsc(MatAssemblyBegin(system.matrix, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
          check_petsc(MatAssemblyEnd(system.matrix, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
          system.factorised.clear(); // until the factorisation has succeeded
          check_petsc(KSPSetOperators(system.ksp, system.matrix, system.matrix), "KSPSetOperators");
          check_petsc(KSPSetUp(system.ksp), "KSPSetUp"); // the numeric factorisation
          system.factorised = active;
          ++grid.factorisations;
          grid.factorisation_seconds += seconds_since(factor_start);
        }
      check_petsc(KSPSolve(system.ksp, layer_rhs, candidate), "KSPSolve");
      VecDestroy(&layer_rhs);
      KSPConvergedReason reason;
      check_petsc(KSPGetConvergedReason(system.ksp, &reason), "KSPGetConvergedReason");
      if (reason < 0)
        throw std::runtime_error(who + ": the factorised solve failed (PETSc reason " +
                                 std::to_string(static_cast<int>(reason)) + ")");
      // d = δ_fit - n·(H u) - n'·(H' u'), each map's n = its pressure_sign e_r.
      split(candidate, ring_part, housing_part);
      const auto at_ring =
        ring.map->interpolate(ring.model->field_from_vector(static_cast<const Vec &>(ring_part))).u_r;
      const auto at_housing =
        housing.map->interpolate(housing.model->field_from_vector(static_cast<const Vec &>(housing_part))).u_r;
      const double ring_sign = ring.map->impl().pressure_sign, housing_sign = housing.map->impl().pressure_sign;
      std::vector<double> penetration(cells);
      for (std::size_t c = 0; c < cells; ++c)
        penetration[c] = fit - ring_sign * at_ring[c] - housing_sign * at_housing[c];
      return penetration;
    };
    callbacks.accept = [&](double step) {
      if (!have_state || step == 1.0)
        check_petsc(VecCopy(candidate, u), "VecCopy");
      else
        check_petsc(VecAXPBY(u, step, 1.0 - step, candidate), "VecAXPBY");
      have_state = true;
    };
    try
      {
        iterate_active_set(cells, initial_active, WinklerSettings{}.max_iterations, k_area, who, callbacks, grid);
      }
    catch (...)
      {
        VecDestroy(&u);
        VecDestroy(&candidate);
        VecDestroy(&rhs);
        throw;
      }
    grid.energy = foundation_pressure(layer.normal_stiffness, k_area, grid);
    split(u, ring_u, housing_u);
    VecDestroy(&u);
    VecDestroy(&candidate);
    VecDestroy(&rhs);
    return grid;
  }

  WinklerPairNewmark::WinklerPairNewmark(ElasticModel &ring_model, const SurfaceGridMap &ring_map,
                                         ElasticModel &housing_model, const SurfaceGridMap &housing_map,
                                         const WinklerLayer &layer, const double time_step,
                                         const StaticLoad &initial_ring_load, const double start_time,
                                         const std::vector<unsigned char> &initial_active)
    : pimpl(std::make_unique<Impl>())
  {
    check_layer(layer, who);
    if (!(time_step > 0.0) || !std::isfinite(time_step))
      throw std::invalid_argument(who + ": the time step must be finite and > 0 s");
    if (ring_map.impl().model != &ring_model.impl() || housing_map.impl().model != &housing_model.impl())
      throw std::invalid_argument(who + ": a grid map was made on another model");
    const CylinderGrid &a = ring_map.grid(), &b = housing_map.grid();
    if (a.nx != b.nx || a.ny != b.ny || std::abs(a.hx * a.hy - b.hx * b.hy) > 1e-12 * a.hx * a.hy)
      throw std::invalid_argument(who + ": the two surfaces' grids differ (" + std::to_string(a.nx) + " x " +
                                  std::to_string(a.ny) + " against " + std::to_string(b.nx) + " x " +
                                  std::to_string(b.ny) + " cells, or their areas)");
    if (ring_map.impl().pressure_sign * housing_map.impl().pressure_sign >= 0.0)
      throw std::invalid_argument(who + ": the layer needs an outer surface on one body and a bore on the other");
    const auto start = Clock::now();
    auto      &p     = *pimpl;
    p.comm           = ring_model.impl().communicator();
    p.layer          = layer;
    p.k_area         = layer.normal_stiffness * a.cell_area();
    p.dt             = time_step;
    p.t              = start_time;
    p.ring_load      = initial_ring_load;
    const unsigned int ranks = dealii::Utilities::MPI::n_mpi_processes(p.comm);
    for (auto [body, model, map] : {std::tuple{&p.ring, &ring_model, &ring_map},
                                    std::tuple{&p.housing, &housing_model, &housing_map}})
      {
        body->model = model;
        body->map   = map;
        const auto &owned = model->impl().owned_dofs;
        if (!owned.is_contiguous())
          throw std::runtime_error(who + ": a model's owned DoFs are not one range");
        body->begin = owned.n_elements() ? static_cast<PetscInt>(owned.nth_index_in_set(0)) : 0;
        body->end   = body->begin + static_cast<PetscInt>(owned.n_elements());
        // The ranks' first owned DoFs in order: the ranges are consecutive.
        const auto sizes = dealii::Utilities::MPI::all_gather(p.comm, static_cast<PetscInt>(owned.n_elements()));
        body->starts.assign(ranks + 1, 0);
        for (unsigned int r = 0; r < ranks; ++r)
          body->starts[r + 1] = body->starts[r] + sizes[r];
        if (body->starts[dealii::Utilities::MPI::this_mpi_process(p.comm)] != body->begin)
          throw std::runtime_error(who + ": a model's ranks do not own consecutive DoF ranges");
        body->u.reinit(owned, p.comm);
        body->v.reinit(owned, p.comm);
      }
    p.joint_starts.resize(ranks + 1);
    for (unsigned int r = 0; r <= ranks; ++r)
      p.joint_starts[r] = p.ring.starts[r] + p.housing.starts[r];
    const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(p.comm);
    p.joint_begin = p.joint_starts[rank];
    p.joint_end   = p.joint_starts[rank + 1];
    p.joint_size  = p.joint_starts.back();
    p.gather_layer_cells();

    // The joint static start, both bodies with the 1 Hz shift.
    {
      auto              system = p.build_system(-std::pow(2.0 * M_PI * WinklerSettings{}.shift_hz, 2));
      const OwnedVector ring_f = assemble_load(ring_model.impl(), initial_ring_load);
      const OwnedVector housing_f(housing_model.impl().owned_dofs, p.comm);
      p.state         = p.solve(*system, ring_f, housing_f, initial_active, p.ring.u, p.housing.u);
      p.state.seconds = seconds_since(start);
      p.start         = p.state;
    }
    p.step_system = p.build_system(-4.0 / (time_step * time_step));
  }

  WinklerPairNewmark::~WinklerPairNewmark() = default;

  const WinklerGridSolution &WinklerPairNewmark::advance(const StaticLoad &ring_load)
  {
    auto      &p     = *pimpl;
    const auto start = Clock::now();
    // Each body's load: its own at both ends (the housing has none) and the
    // layer's pressure at time t as a grid traction through its map.
    const std::vector<double> zero(p.state.pressure.size(), 0.0);
    const GridTractions       previous_layer{p.state.pressure, zero, zero};
    StaticLoad                ring_previous = p.ring_load, housing_previous;
    ring_previous.grid_tractions.push_back({p.ring.map, &previous_layer});
    housing_previous.grid_tractions.push_back({p.housing.map, &previous_layer});
    const auto &ring_model = p.ring.model->impl(), &housing_model = p.housing.model->impl();
    OwnedVector ring_rhs = assemble_load(ring_model, ring_load);
    ring_rhs += assemble_load(ring_model, ring_previous);
    add_newmark_history(ring_model, p.dt, p.ring.u, p.ring.v, ring_rhs);
    OwnedVector housing_rhs = assemble_load(housing_model, housing_previous);
    add_newmark_history(housing_model, p.dt, p.housing.u, p.housing.v, housing_rhs);

    OwnedVector ring_new(ring_model.owned_dofs, p.comm), housing_new(housing_model.owned_dofs, p.comm);
    WinklerGridSolution next = p.solve(*p.step_system, ring_rhs, housing_rhs, p.state.active, ring_new, housing_new);
    advance_newmark_state(p.dt, ring_new, p.ring.u, p.ring.v);
    advance_newmark_state(p.dt, housing_new, p.housing.u, p.housing.v);
    p.ring_load = ring_load;
    return p.add_step(std::move(next), seconds_since(start));
  }

  double WinklerPairNewmark::time() const { return pimpl->t; }
  double WinklerPairNewmark::time_step() const { return pimpl->dt; }
  unsigned int WinklerPairNewmark::steps() const { return pimpl->steps; }
  unsigned int WinklerPairNewmark::factorisations() const { return pimpl->factorisations; }
  double WinklerPairNewmark::factorisation_seconds() const { return pimpl->factorisation_seconds; }
  unsigned int WinklerPairNewmark::solves() const { return pimpl->solves; }
  double WinklerPairNewmark::step_seconds() const { return pimpl->seconds; }
  unsigned long WinklerPairNewmark::n_dofs() const { return static_cast<unsigned long>(pimpl->joint_size); }
  const WinklerGridSolution &WinklerPairNewmark::foundation() const { return pimpl->state; }
  const WinklerGridSolution &WinklerPairNewmark::start() const { return pimpl->start; }

  DisplacementField WinklerPairNewmark::ring_displacement() const
  {
    return pimpl->ring.model->field_from_vector(static_cast<const Vec &>(pimpl->ring.u));
  }

  DisplacementField WinklerPairNewmark::housing_displacement() const
  {
    return pimpl->housing.model->field_from_vector(static_cast<const Vec &>(pimpl->housing.u));
  }

  double WinklerPairNewmark::energy() const
  {
    const auto &p      = *pimpl;
    double      energy = p.state.energy - (assemble_load(p.ring.model->impl(), p.ring_load) * p.ring.u);
    for (const Body *body : {&p.ring, &p.housing})
      {
        const auto &model = body->model->impl();
        energy += 0.5 * model.mass.matrix_norm_square(body->v) + 0.5 * model.stiffness.matrix_norm_square(body->u);
      }
    return energy;
  }
} // namespace fretsim::fem
