#pragma once
// The deal.II side of SurfacePointMap, shared with the load assembly.
#include "model_impl.h"

#include <fretsim/fem/surface_point_map.h>

#include <deal.II/lac/petsc_vector.h>

namespace fretsim::fem
{
  struct SurfacePointMap::Impl
  {
    /// One point, located in a cell this rank owns.
    struct Sample
    {
      std::size_t                                 point;
      dealii::DoFHandler<3>::active_cell_iterator cell;
      std::vector<double>                         shape; ///< φ_i at the point, per cell DoF
    };

    /// Locates the points (throws std::invalid_argument for one off `surface`).
    Impl(const ElasticModel::Impl &model, const std::vector<Point3> &points, BoundaryId surface);

    /// Set when the map was made from an ElasticModel: the discretisation
    /// then lives as long as the map.
    std::shared_ptr<const ElasticModel::Impl> owner;
    const ElasticModel::Impl                 *model = nullptr;
    std::vector<Point3>                       points; ///< on the discrete surface
    std::vector<Sample>                       samples;

    /// rhs += Hᵀ F, through the model's constraints.
    void add_forces(const std::vector<Vector3> &forces, dealii::PETScWrappers::MPI::Vector &rhs) const;
  };

  /// rhs += the nodal forces of the balls' Hertz patches (one map for all).
  void add_raceway_ball_loads(const ElasticModel::Impl &model, const std::vector<RacewayBallLoad> &balls,
                              dealii::PETScWrappers::MPI::Vector &rhs);
} // namespace fretsim::fem
