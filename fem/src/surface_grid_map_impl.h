#pragma once
// The deal.II side of SurfaceGridMap, shared with the load assembly.
#include "model_impl.h"

#include <fretsim/fem/surface_grid_map.h>

#include <deal.II/lac/petsc_vector.h>

namespace fretsim::fem
{
  struct SurfaceGridMap::Impl
  {
    /// One grid cell centre, located in a cell this rank owns.
    struct Sample
    {
      std::size_t                                       grid_cell;
      dealii::DoFHandler<3>::active_cell_iterator       cell;
      std::vector<double>                               shape; ///< φ_i at the centre, per cell DoF
      dealii::Tensor<1, 3>                              e_r, e_theta, e_z;
    };

    const ElasticModel::Impl *model = nullptr; ///< the model outlives the map
    CylinderGrid              grid;
    /// Pressure acts against the outward normal ±e_r: -1 on outer surfaces,
    /// +1 on bores.
    double              pressure_sign = -1.0;
    std::vector<Sample> samples;

    /// The sample's direction of the pressure force on the body, per cell
    /// DoF: (w_c)_i = φ_i(x_c) · (pressure_sign e_r) (the Winkler solvers).
    void pressure_weights(const Sample &s, std::vector<double> &w) const;

    /// rhs += Hᵀ (A t), through the model's constraints.
    void add_forces(const GridTractions &t, dealii::PETScWrappers::MPI::Vector &rhs) const;
  };
} // namespace fretsim::fem
