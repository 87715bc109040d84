#pragma once
// The deal.II side of ElasticModel and DisplacementField, shared by the fem
// sources (never installed).
#include "mesh_impl.h"

#include <fretsim/fem/elastic_model.h>

#include <deal.II/base/index_set.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include <chrono>

namespace fretsim::fem
{
  /// Lamé constants and density of one body.
  struct Lame
  {
    double lambda = 0.0;
    double mu     = 0.0;
    double rho    = 0.0;
  };

  struct ElasticModel::Impl
  {
    Impl(std::shared_ptr<const Mesh> mesh, const std::map<MaterialId, Material> &materials, unsigned int degree,
         const std::vector<Support> &supports);

    void setup_dofs(const std::vector<Support> &supports);
    void assemble_stiffness();
    void assemble_mass();

    MPI_Comm communicator() const { return mesh->impl().communicator(); }
    const Lame &material(unsigned int material_id) const;
    /// A ghosted copy of an owned vector, constraints applied.
    dealii::PETScWrappers::MPI::Vector ghosted(dealii::PETScWrappers::MPI::Vector owned) const;

    std::shared_ptr<const Mesh>               mesh;
    std::map<unsigned int, Lame>              lame;
    unsigned int                              degree;
    dealii::FESystem<3>                       fe;
    dealii::MappingQ<3>                       mapping;
    dealii::DoFHandler<3>                     dof_handler;
    dealii::IndexSet                          owned_dofs;
    dealii::IndexSet                          relevant_dofs;
    dealii::AffineConstraints<double>         constraints;
    dealii::PETScWrappers::MPI::SparseMatrix  stiffness;
    dealii::PETScWrappers::MPI::SparseMatrix  mass;
    bool                                      mass_assembled = false;
    Timings                                   timings;
  };

  struct DisplacementField::Impl
  {
    std::shared_ptr<const ElasticModel::Impl> model;
    dealii::PETScWrappers::MPI::Vector        displacement; ///< ghosted, constraints applied
    std::vector<InPlaneExpansion>             expansions;   ///< eigenstrains the stresses subtract
  };

  /// Stress of a body at a point: C : (ε - ε*).
  dealii::SymmetricTensor<2, 3> stress(const Lame &m, const dealii::SymmetricTensor<2, 3> &strain,
                                       double in_plane_eigenstrain);

  /// The load vector f of a static load (or of a transient load at one time),
  /// through the model's constraints.
  dealii::PETScWrappers::MPI::Vector assemble_load(const ElasticModel::Impl &model, const StaticLoad &load);

  /// The six rigid-body modes (translations along x, y, z; rotations e_k × x
  /// about the axes through the origin) as PETSc vectors laid out like K's
  /// columns, Euclidean-orthonormalised if asked. The caller destroys them.
  std::vector<Vec> rigid_body_modes(const ElasticModel::Impl &model, bool orthonormalise = true);

  /// Seconds since `start`.
  inline double seconds_since(const std::chrono::steady_clock::time_point start)
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
} // namespace fretsim::fem
