#pragma once
// Newmark's average acceleration in displacement–velocity form, the parts
// NewmarkIntegrator (transient.h) and WinklerNewmark (winkler_foundation.h)
// share: with the effective matrix K + 4M/Δt² on the left,
//   right-hand side  += M (4u/Δt² + 4v/Δt) - K u     (plus the loads at both ends),
//   velocity         v₊ = 2(u₊ - u)/Δt - v.
#include "model_impl.h"

namespace fretsim::fem
{
  /// rhs += M (4u/Δt² + 4v/Δt) - K u.
  inline void add_newmark_history(const ElasticModel::Impl &model, double dt,
                                  const dealii::PETScWrappers::MPI::Vector &u,
                                  const dealii::PETScWrappers::MPI::Vector &v, dealii::PETScWrappers::MPI::Vector &rhs)
  {
    dealii::PETScWrappers::MPI::Vector w(model.owned_dofs, model.communicator()),
      product(model.owned_dofs, model.communicator());
    w.equ(4.0 / (dt * dt), u);
    w.add(4.0 / dt, v);
    model.mass.vmult(product, w);
    rhs += product;
    model.stiffness.vmult(product, u);
    rhs -= product;
  }

  /// v = 2(u_new - u)/Δt - v, then u = u_new.
  inline void advance_newmark_state(double dt, const dealii::PETScWrappers::MPI::Vector &u_new,
                                    dealii::PETScWrappers::MPI::Vector &u, dealii::PETScWrappers::MPI::Vector &v)
  {
    v.sadd(-1.0, 2.0 / dt, u_new);
    v.add(-2.0 / dt, u);
    u = u_new;
  }
} // namespace fretsim::fem
