// Contact surface grid ↔ FE surface: one sample per grid cell centre, H and
// its transpose applied sample by sample.
#include "surface_grid_map_impl.h"

#include "point_location.h"

#include <deal.II/base/mpi.h>

namespace fretsim::fem
{
  SurfaceGridMap::SurfaceGridMap(const ElasticModel &model_in, const BoundaryId surface, const CylinderGrid &grid)
    : pimpl(std::make_unique<Impl>())
  {
    const auto &model = model_in.impl();
    pimpl->model      = &model;
    pimpl->grid       = grid;
    pimpl->pressure_sign =
      (surface == BoundaryId::ring_outer || surface == BoundaryId::housing_outer) ? -1.0 : 1.0;
    if (!(grid.radius > 0.0 && grid.nx > 0 && grid.ny > 0 && grid.hx > 0.0 && grid.hy > 0.0))
      throw std::invalid_argument("fem::SurfaceGridMap: the grid needs radius, nx, ny, hx, hy > 0");

    const unsigned int n = model.fe.n_dofs_per_cell();
    std::vector<dealii::Point<3>> centres;
    centres.reserve(grid.size());
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        {
          const double theta = grid.x(i) / grid.radius;
          centres.emplace_back(grid.radius * std::cos(theta), grid.radius * std::sin(theta), grid.y(j));
        }
    // Each centre is found by one rank and put on the discrete surface.
    std::vector<std::size_t> missing;
    const auto               located = locate_points(model, centres, surface, missing);
    if (!missing.empty())
      throw std::invalid_argument("fem::SurfaceGridMap: a grid cell centre lies off the mesh surface " +
                                  to_string(surface) + " (check radius, extent and sector)");
    for (const LocatedPoint &p : located)
      {
        const double theta = grid.x(static_cast<int>(p.index % grid.nx)) / grid.radius;
        Impl::Sample s;
        s.grid_cell = p.index;
        s.cell      = p.cell;
        s.shape.resize(n);
        for (unsigned int k = 0; k < n; ++k)
          s.shape[k] = model.fe.shape_value(k, p.reference);
        s.e_r     = dealii::Tensor<1, 3>({std::cos(theta), std::sin(theta), 0.0});
        s.e_theta = dealii::Tensor<1, 3>({-std::sin(theta), std::cos(theta), 0.0});
        s.e_z     = dealii::Tensor<1, 3>({0.0, 0.0, 1.0});
        pimpl->samples.push_back(std::move(s));
      }
  }

  SurfaceGridMap::~SurfaceGridMap()                             = default;
  SurfaceGridMap::SurfaceGridMap(SurfaceGridMap &&) noexcept        = default;
  SurfaceGridMap &SurfaceGridMap::operator=(SurfaceGridMap &&) noexcept = default;

  const CylinderGrid &SurfaceGridMap::grid() const { return pimpl->grid; }

  namespace
  {
    void check_sizes(const CylinderGrid &grid, const GridTractions &t)
    {
      if (t.pressure.size() != grid.size() || t.shear_x.size() != grid.size() || t.shear_y.size() != grid.size())
        throw std::invalid_argument("fem::SurfaceGridMap: tractions need nx*ny values per component");
    }
  } // namespace

  void SurfaceGridMap::Impl::pressure_weights(const Sample &s, std::vector<double> &w) const
  {
    const unsigned int n = model->fe.n_dofs_per_cell();
    w.resize(n);
    for (unsigned int i = 0; i < n; ++i)
      w[i] = s.shape[i] * pressure_sign * s.e_r[model->fe.system_to_component_index(i).first];
  }

  void SurfaceGridMap::Impl::add_forces(const GridTractions &t, dealii::PETScWrappers::MPI::Vector &rhs) const
  {
    check_sizes(grid, t);
    const unsigned int                           n = model->fe.n_dofs_per_cell();
    dealii::Vector<double>                       local(n);
    std::vector<dealii::types::global_dof_index> dof_indices(n);
    const double                                 area = grid.cell_area();
    for (const Sample &s : samples)
      {
        const std::size_t          k = s.grid_cell;
        const dealii::Tensor<1, 3> force =
          area * (pressure_sign * t.pressure[k] * s.e_r + t.shear_x[k] * s.e_theta + t.shear_y[k] * s.e_z);
        for (unsigned int i = 0; i < n; ++i)
          local(i) = s.shape[i] * force[model->fe.system_to_component_index(i).first];
        s.cell->get_dof_indices(dof_indices);
        model->constraints.distribute_local_to_global(local, dof_indices, rhs);
      }
  }

  Vector3 SurfaceGridMap::nodal_force_sum(const GridTractions &t) const
  {
    check_sizes(pimpl->grid, t);
    const auto        &model = *pimpl->model;
    const unsigned int n     = model.fe.n_dofs_per_cell();
    std::vector<double> sum(3, 0.0);
    for (const auto &s : pimpl->samples)
      {
        const std::size_t          k     = s.grid_cell;
        const dealii::Tensor<1, 3> force = pimpl->grid.cell_area() * (pimpl->pressure_sign * t.pressure[k] * s.e_r +
                                                                      t.shear_x[k] * s.e_theta + t.shear_y[k] * s.e_z);
        for (unsigned int i = 0; i < n; ++i)
          {
            const unsigned int c = model.fe.system_to_component_index(i).first;
            sum[c] += s.shape[i] * force[c];
          }
      }
    dealii::Utilities::MPI::sum(sum, model.communicator(), sum);
    return {sum[0], sum[1], sum[2]};
  }

  GridDisplacements SurfaceGridMap::interpolate(const DisplacementField &u) const
  {
    const auto        &field = u.impl();
    const unsigned int n     = pimpl->model->fe.n_dofs_per_cell();
    const std::size_t  size  = pimpl->grid.size();
    std::vector<double> values(3 * size, 0.0);
    dealii::Vector<double> local(n);
    for (const auto &s : pimpl->samples)
      {
        s.cell->get_dof_values(field.displacement, local);
        dealii::Tensor<1, 3> displacement;
        for (unsigned int i = 0; i < n; ++i)
          displacement[pimpl->model->fe.system_to_component_index(i).first] += s.shape[i] * local(i);
        values[s.grid_cell]            = displacement * s.e_r;
        values[size + s.grid_cell]     = displacement * s.e_theta;
        values[2 * size + s.grid_cell] = displacement * s.e_z;
      }
    dealii::Utilities::MPI::sum(values, pimpl->model->communicator(), values);
    GridDisplacements result;
    result.u_r.assign(values.begin(), values.begin() + size);
    result.u_theta.assign(values.begin() + size, values.begin() + 2 * size);
    result.u_z.assign(values.begin() + 2 * size, values.end());
    return result;
  }

  Vector3 SurfaceGridMap::total_force(const GridTractions &t) const
  {
    check_sizes(pimpl->grid, t);
    const auto &g = pimpl->grid;
    Vector3     total{0.0, 0.0, 0.0};
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i)
        {
          const std::size_t k     = static_cast<std::size_t>(j) * g.nx + i;
          const double      theta = g.x(i) / g.radius, a = g.cell_area();
          const double      pr = pimpl->pressure_sign * t.pressure[k];
          total[0] += a * (pr * std::cos(theta) - t.shear_x[k] * std::sin(theta));
          total[1] += a * (pr * std::sin(theta) + t.shear_x[k] * std::cos(theta));
          total[2] += a * t.shear_y[k];
        }
    return total;
  }
} // namespace fretsim::fem
