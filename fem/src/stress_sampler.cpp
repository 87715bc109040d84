// Stresses at points: located once, ∇φ_i stored per point, evaluated by a
// gather per snapshot (see stress_sampler.h for the method and its accuracy).
#include "model_impl.h"
#include "point_location.h"

#include <fretsim/fem/stress_sampler.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/fe/fe_values.h>

#include <algorithm>
#include <cmath>

namespace fretsim::fem
{
  struct StressSampler::Impl
  {
    struct Sample
    {
      std::size_t                                 point;
      dealii::DoFHandler<3>::active_cell_iterator cell;
      std::vector<dealii::Tensor<1, 3>>           gradients; ///< ∇φ_i at the point, per cell DoF
    };

    std::shared_ptr<const ElasticModel::Impl> model;
    std::vector<Point3>                       points;
    StressFrame                               frame = StressFrame::cartesian;
    std::vector<Sample>                       samples; ///< the points this rank evaluates
  };

  StressSampler::StressSampler(std::unique_ptr<Impl> impl)
    : pimpl(std::move(impl))
  {}
  StressSampler::~StressSampler()                              = default;
  StressSampler::StressSampler(StressSampler &&) noexcept        = default;
  StressSampler &StressSampler::operator=(StressSampler &&) noexcept = default;

  std::size_t                StressSampler::n_points() const { return pimpl->points.size(); }
  const std::vector<Point3> &StressSampler::points() const { return pimpl->points; }
  StressFrame                StressSampler::frame() const { return pimpl->frame; }

  StressSampler::StressSampler(const ElasticModel &model_in, const std::vector<Point3> &points,
                               const StressFrame frame)
    : pimpl(std::make_unique<Impl>())
  {
    // The sampler may outlive the model object, as a DisplacementField does.
    pimpl->model  = model_in.shared_impl();
    pimpl->points = points;
    pimpl->frame  = frame;
    const auto        &model = *pimpl->model;
    const unsigned int n     = model.fe.n_dofs_per_cell();

    std::vector<dealii::Point<3>> search;
    search.reserve(points.size());
    for (const Point3 &p : points)
      search.emplace_back(p[0], p[1], p[2]);
    std::vector<std::size_t> missing;
    const auto               located = locate_points(model, search, std::nullopt, missing);
    if (!missing.empty())
      {
        const Point3 &p = points[missing.front()];
        throw std::invalid_argument("fem::StressSampler: point " + std::to_string(missing.front()) + " (" +
                                    std::to_string(p[0]) + ", " + std::to_string(p[1]) + ", " +
                                    std::to_string(p[2]) + ") m lies off the mesh");
      }
    for (const LocatedPoint &p : located)
      {
        Impl::Sample s;
        s.point = p.index;
        s.cell  = p.cell;
        dealii::FEValues<3> fe_values(model.mapping, model.fe,
                                      dealii::Quadrature<3>(std::vector<dealii::Point<3>>{p.reference}),
                                      dealii::update_gradients);
        fe_values.reinit(s.cell);
        s.gradients.resize(n);
        for (unsigned int i = 0; i < n; ++i)
          s.gradients[i] = fe_values.shape_grad(i, 0);
        pimpl->samples.push_back(std::move(s));
      }
  }

  StressSampler StressSampler::on_grid(const ElasticModel &model, const CylinderGrid &grid, const StressFrame frame)
  {
    std::vector<Point3> points;
    points.reserve(grid.size());
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        {
          const double theta = grid.x(i) / grid.radius;
          points.push_back({grid.radius * std::cos(theta), grid.radius * std::sin(theta), grid.y(j)});
        }
    return StressSampler(model, points, frame);
  }

  std::vector<double> StressSampler::evaluate(const DisplacementField &u) const
  {
    const auto &field = u.impl();
    const auto &model = *pimpl->model;
    if (field.model.get() != pimpl->model.get())
      throw std::invalid_argument("fem::StressSampler: the field belongs to another model");
    const unsigned int     n = model.fe.n_dofs_per_cell();
    dealii::Vector<double> local(n);
    std::vector<double>    result(6 * pimpl->points.size(), 0.0);
    for (const auto &s : pimpl->samples)
      {
        s.cell->get_dof_values(field.displacement, local);
        dealii::Tensor<2, 3> grad;
        for (unsigned int i = 0; i < n; ++i)
          grad[model.fe.system_to_component_index(i).first] += local(i) * s.gradients[i];
        double e = 0.0;
        for (const InPlaneExpansion &x : field.expansions)
          if (static_cast<unsigned int>(x.body) == s.cell->material_id())
            e += x.strain;
        dealii::SymmetricTensor<2, 3> sigma = stress(model.material(s.cell->material_id()), dealii::symmetrize(grad), e);
        if (pimpl->frame == StressFrame::cylindrical)
          {
            const Point3        &p = pimpl->points[s.point];
            const double         r = std::hypot(p[0], p[1]);
            dealii::Tensor<2, 3> q; // rows: e_r, e_θ, e_z
            q[0][0] = p[0] / r, q[0][1] = p[1] / r;
            q[1][0] = -p[1] / r, q[1][1] = p[0] / r;
            q[2][2] = 1.0;
            sigma   = dealii::symmetrize(q * static_cast<dealii::Tensor<2, 3>>(sigma) * dealii::transpose(q));
          }
        double *row = &result[6 * s.point];
        row[0] = sigma[0][0], row[1] = sigma[1][1], row[2] = sigma[2][2];
        row[3] = sigma[1][2], row[4] = sigma[0][2], row[5] = sigma[0][1];
      }
    // Each point has exactly one owner; the others contribute zeros.
    dealii::Utilities::MPI::sum(result, model.communicator(), result);
    return result;
  }
} // namespace fretsim::fem
