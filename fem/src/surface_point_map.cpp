// Boundary points ↔ FE: one sample per point, H and its transpose applied
// sample by sample; and the quadrature of a ball's Hertz patch on the raceway.
#include "surface_point_map_impl.h"

#include "point_location.h"

#include <deal.II/base/mpi.h>

#include <cmath>
#include <sstream>

namespace fretsim::fem
{
  SurfacePointMap::Impl::Impl(const ElasticModel::Impl &model_in, const std::vector<Point3> &given,
                              const BoundaryId surface)
    : model(&model_in)
  {
    std::vector<dealii::Point<3>> search;
    search.reserve(given.size());
    for (const Point3 &p : given)
      search.emplace_back(p[0], p[1], p[2]);
    std::vector<std::size_t> missing;
    const auto               located = locate_points(*model, search, surface, missing);
    if (!missing.empty())
      {
        const Point3      &p = given[missing.front()];
        std::ostringstream message;
        message << "fem::SurfacePointMap: point " << missing.front() << " (" << p[0] << ", " << p[1] << ", " << p[2]
                << ") m is not on the mesh boundary " << to_string(surface) << " (" << missing.size() << " of "
                << given.size() << " points are off it)";
        throw std::invalid_argument(message.str());
      }

    const unsigned int  n = model->fe.n_dofs_per_cell();
    std::vector<double> moved(3 * given.size(), 0.0);
    for (const LocatedPoint &p : located)
      {
        Sample s{p.index, p.cell, std::vector<double>(n)};
        for (unsigned int k = 0; k < n; ++k)
          s.shape[k] = model->fe.shape_value(k, p.reference);
        const dealii::Point<3> x = model->mapping.transform_unit_to_real_cell(p.cell, p.reference);
        for (unsigned int d = 0; d < 3; ++d)
          moved[3 * p.index + d] = x[d];
        samples.push_back(std::move(s));
      }
    // Each point has one owner; the others contribute zeros.
    dealii::Utilities::MPI::sum(moved, model->communicator(), moved);
    points.resize(given.size());
    for (std::size_t k = 0; k < given.size(); ++k)
      points[k] = {moved[3 * k], moved[3 * k + 1], moved[3 * k + 2]};
  }

  void SurfacePointMap::Impl::add_forces(const std::vector<Vector3> &forces,
                                         dealii::PETScWrappers::MPI::Vector &rhs) const
  {
    if (forces.size() != points.size())
      throw std::invalid_argument("fem::SurfacePointMap: " + std::to_string(forces.size()) + " forces for " +
                                  std::to_string(points.size()) + " points");
    const unsigned int                           n = model->fe.n_dofs_per_cell();
    dealii::Vector<double>                       local(n);
    std::vector<dealii::types::global_dof_index> dof_indices(n);
    for (const Sample &s : samples)
      {
        const Vector3 &force = forces[s.point];
        for (unsigned int i = 0; i < n; ++i)
          local(i) = s.shape[i] * force[model->fe.system_to_component_index(i).first];
        s.cell->get_dof_indices(dof_indices);
        model->constraints.distribute_local_to_global(local, dof_indices, rhs);
      }
  }

  SurfacePointMap::SurfacePointMap(const ElasticModel &model, const std::vector<Point3> &points,
                                   const BoundaryId surface)
    : pimpl(std::make_unique<Impl>(model.impl(), points, surface))
  {
    // The map may outlive the model object, as a DisplacementField does.
    pimpl->owner = model.shared_impl();
  }
  SurfacePointMap::SurfacePointMap(std::unique_ptr<Impl> impl)
    : pimpl(std::move(impl))
  {}
  SurfacePointMap::~SurfacePointMap()                                 = default;
  SurfacePointMap::SurfacePointMap(SurfacePointMap &&) noexcept            = default;
  SurfacePointMap &SurfacePointMap::operator=(SurfacePointMap &&) noexcept = default;

  std::size_t                SurfacePointMap::n_points() const { return pimpl->points.size(); }
  const std::vector<Point3> &SurfacePointMap::points() const { return pimpl->points; }

  std::vector<Vector3> SurfacePointMap::interpolate(const DisplacementField &u) const
  {
    const auto &field = u.impl();
    if (field.model.get() != pimpl->model)
      throw std::invalid_argument("fem::SurfacePointMap: the field belongs to another model");
    const unsigned int     n = pimpl->model->fe.n_dofs_per_cell();
    std::vector<double>    values(3 * pimpl->points.size(), 0.0);
    dealii::Vector<double> local(n);
    for (const auto &s : pimpl->samples)
      {
        s.cell->get_dof_values(field.displacement, local);
        for (unsigned int i = 0; i < n; ++i)
          values[3 * s.point + pimpl->model->fe.system_to_component_index(i).first] += s.shape[i] * local(i);
      }
    dealii::Utilities::MPI::sum(values, pimpl->model->communicator(), values);
    std::vector<Vector3> result(pimpl->points.size());
    for (std::size_t k = 0; k < result.size(); ++k)
      result[k] = {values[3 * k], values[3 * k + 1], values[3 * k + 2]};
    return result;
  }

  Vector3 SurfacePointMap::nodal_force_sum(const std::vector<Vector3> &forces) const
  {
    if (forces.size() != pimpl->points.size())
      throw std::invalid_argument("fem::SurfacePointMap: " + std::to_string(forces.size()) + " forces for " +
                                  std::to_string(pimpl->points.size()) + " points");
    const auto         &model = *pimpl->model;
    const unsigned int  n     = model.fe.n_dofs_per_cell();
    std::vector<double> sum(3, 0.0);
    for (const auto &s : pimpl->samples)
      for (unsigned int i = 0; i < n; ++i)
        {
          const unsigned int c = model.fe.system_to_component_index(i).first;
          sum[c] += s.shape[i] * forces[s.point][c];
        }
    dealii::Utilities::MPI::sum(sum, model.communicator(), sum);
    return {sum[0], sum[1], sum[2]};
  }

  Point3 raceway_contact_point(const RingGeometry &ring, const double angle, const double contact_angle)
  {
    if (!ring.has_groove())
      return {ring.bore_radius * std::cos(angle), ring.bore_radius * std::sin(angle), 0.0};
    const double centre = ring.groove_bottom_radius - ring.groove_radius;
    const double r      = centre + ring.groove_radius * std::cos(contact_angle);
    return {r * std::cos(angle), r * std::sin(angle), ring.groove_radius * std::sin(contact_angle)};
  }

  Vector3 raceway_contact_normal(const double angle, const double contact_angle)
  {
    return {std::cos(contact_angle) * std::cos(angle), std::cos(contact_angle) * std::sin(angle),
            std::sin(contact_angle)};
  }

  PatchForces raceway_patch_forces(const RacewayBallLoad &ball)
  {
    const RingGeometry &ring = ball.ring;
    const double        a = ball.semi_axis_circumferential, b = ball.semi_axis_transverse;
    if (!(a > 0.0 && b > 0.0 && ball.force >= 0.0))
      throw std::invalid_argument("fem::raceway_patch_forces: needs semi-axes a, b > 0 and a force >= 0");
    if (ball.quadrature_rings < 1 || ball.quadrature_sectors < 4 || ball.quadrature_sectors % 2 != 0)
      throw std::invalid_argument("fem::raceway_patch_forces: needs >= 1 ring and an even number >= 4 of sectors");
    const bool grooved = ring.has_groove();
    if (!grooved && ball.contact_angle != 0.0)
      throw std::invalid_argument("fem::raceway_patch_forces: a plain bore has no contact angle");
    const double centre = grooved ? ring.groove_bottom_radius - ring.groove_radius : 0.0;
    if (grooved)
      {
        // The patch must stay on the arc, short of where it meets the lands.
        const double edge = std::asin(std::min(1.0, ring.groove_half_width() / ring.groove_radius));
        if (std::abs(ball.contact_angle) + b / ring.groove_radius >= edge)
          throw std::invalid_argument("fem::raceway_patch_forces: the contact ellipse (contact angle " +
                                      std::to_string(ball.contact_angle) + " rad, b = " + std::to_string(b) +
                                      " m) runs over the groove edge at " + std::to_string(edge) + " rad");
      }
    const Point3  contact        = raceway_contact_point(ring, ball.angle, ball.contact_angle);
    const double  contact_radius = std::hypot(contact[0], contact[1]);
    const Vector3 normal         = raceway_contact_normal(ball.angle, ball.contact_angle);

    // Exact annulus integrals of √(1-ρ²) ρ (the load) and √(1-ρ²) ρ² (its first moment).
    auto load   = [](const double r) { return -std::pow(1.0 - r * r, 1.5) / 3.0; };
    auto moment = [](const double r) {
      return (r * (2.0 * r * r - 1.0) * std::sqrt(std::max(0.0, 1.0 - r * r)) + std::asin(r)) / 8.0;
    };
    const unsigned int n_r = ball.quadrature_rings, n_phi = ball.quadrature_sectors;
    // ∫∫ √(1-ρ²) ρ dρ dφ over the unit disc is 2π/3.
    const double pressure_scale = ball.force / (2.0 * M_PI / 3.0);
    PatchForces  patch;
    for (unsigned int k = 0; k < n_r; ++k)
      {
        const double r0 = static_cast<double>(k) / n_r, r1 = static_cast<double>(k + 1) / n_r;
        const double weight = load(r1) - load(r0);
        const double rho    = (moment(r1) - moment(r0)) / weight;
        for (unsigned int j = 0; j < n_phi; ++j)
          {
            const double phi = (j + 0.5) * 2.0 * M_PI / n_phi;
            const double xi = a * rho * std::cos(phi), eta = b * rho * std::sin(phi);
            const double theta = ball.angle + xi / contact_radius;
            // On the groove arc at ψ = α + η/r_g, or on the bore at z = η.
            double r = ring.bore_radius, z = eta;
            if (grooved)
              {
                const double psi = ball.contact_angle + eta / ring.groove_radius;
                r = centre + ring.groove_radius * std::cos(psi), z = ring.groove_radius * std::sin(psi);
              }
            const double f = pressure_scale * weight * (2.0 * M_PI / n_phi);
            patch.points.push_back({r * std::cos(theta), r * std::sin(theta), z});
            patch.forces.push_back({f * normal[0], f * normal[1], f * normal[2]});
          }
      }
    return patch;
  }

  void add_raceway_ball_loads(const ElasticModel::Impl &model, const std::vector<RacewayBallLoad> &balls,
                              dealii::PETScWrappers::MPI::Vector &rhs)
  {
    std::vector<Point3>  points;
    std::vector<Vector3> forces;
    for (const RacewayBallLoad &ball : balls)
      {
        PatchForces patch = raceway_patch_forces(ball);
        points.insert(points.end(), patch.points.begin(), patch.points.end());
        forces.insert(forces.end(), patch.forces.begin(), patch.forces.end());
      }
    const SurfacePointMap::Impl map(model, points, BoundaryId::raceway);
    map.add_forces(forces, rhs);
  }
} // namespace fretsim::fem
