#include <fretsim/fem/shifted_static_solver.h>
#include <fretsim/fem/stress_sampler.h>
#include <fretsim/fem/surface_point_map.h>
#include <fretsim/models/interface_influence.h>
#include <fretsim/reduction/craig_bampton.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <stdexcept>

namespace fretsim::models
{
  std::array<double, 6> contact_frame_stress(const double *cyl)
  {
    // x = θ, y = axial z, z = depth = -r: xx = θθ, yy = zz, zz = rr,
    // yz = σ(z, -r) = -rz, xz = σ(θ, -r) = -rθ, xy = θz.
    return {cyl[1], cyl[2], cyl[0], -cyl[4], -cyl[5], cyl[3]};
  }

  namespace
  {
    /// s × s points evenly inside one grid cell, on the cylinder.
    std::vector<fem::Point3> cell_points(const fem::CylinderGrid &grid, int i, int j, int s)
    {
      std::vector<fem::Point3> points;
      for (int b = 0; b < s; ++b)
        for (int a = 0; a < s; ++a)
          {
            const double x = grid.x_min + (i + (a + 0.5) / s) * grid.hx, z = grid.y_min + (j + (b + 0.5) / s) * grid.hy;
            const double theta = x / grid.radius;
            points.push_back({grid.radius * std::cos(theta), grid.radius * std::sin(theta), z});
          }
      return points;
    }
  } // namespace

  struct InterfaceStressSampler::Impl
  {
    std::size_t                        points = 0;
    std::unique_ptr<fem::StressSampler> sampler;
  };

  InterfaceStressSampler::InterfaceStressSampler(const fem::ElasticModel &model, const fem::CylinderGrid &grid,
                                                 const std::vector<double> &depths, bool ring)
    : impl(std::make_unique<Impl>())
  {
    // A point on an element face takes one side's stress, and which side is
    // the search's choice, not the same from one column to the next: the
    // mean of points a millionth of a cell to either side along θ, the axis
    // and the depth is the same for every column the mesh repeats over.
    const double             d_theta = 1e-6 * grid.hx / grid.radius, d_z = 1e-6 * grid.hy, d_r = 1e-6 * grid.hx;
    std::vector<fem::Point3> points;
    for (const double depth : depths)
      for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i)
          for (const double sr : {-1.0, 1.0})
            for (const double sz : {-1.0, 1.0})
              for (const double st : {-1.0, 1.0})
                {
                  const double below = std::max(depth + sr * d_r, 0.0), r = grid.radius + (ring ? -below : below),
                               theta = grid.x(i) / grid.radius + st * d_theta;
                  points.push_back({r * std::cos(theta), r * std::sin(theta), grid.y(j) + sz * d_z});
                }
    impl->points  = points.size() / samples_per_point;
    impl->sampler = std::make_unique<fem::StressSampler>(model, points, fem::StressFrame::cylindrical);
  }

  InterfaceStressSampler::~InterfaceStressSampler() = default;

  std::vector<double> InterfaceStressSampler::evaluate(const fem::DisplacementField &u) const
  {
    const std::vector<double> cylindrical = impl->sampler->evaluate(u);
    std::vector<double>       local(6 * impl->points, 0.0);
    for (std::size_t p = 0; p < impl->points; ++p)
      for (std::size_t q = 0; q < samples_per_point; ++q)
        {
          const auto sample = contact_frame_stress(&cylindrical[6 * (p * samples_per_point + q)]);
          for (int c = 0; c < 6; ++c)
            local[6 * p + c] += sample[c] / samples_per_point;
        }
    return local;
  }

  InterfaceInfluence interface_influence(fem::ElasticModel &model, const fem::CylinderGrid &grid,
                                         const InfluenceRequest &request)
  {
    const auto         start = std::chrono::steady_clock::now();
    const bool         ring  = request.support == InfluenceSupport::free_ring;
    const int          s     = request.points_per_side;
    InterfaceInfluence t;
    t.grid   = grid;
    t.depths = request.depths;
    t.dofs   = model.n_dofs();
    if (request.circumferential_cells == 0 || s < 1)
      throw std::invalid_argument("models::interface_influence: need the mesh's cells around and s >= 1");
    t.period = grid.nx / std::gcd(grid.nx, static_cast<int>(request.circumferential_cells));
    const fem::BoundaryId surface = ring ? fem::BoundaryId::ring_outer : fem::BoundaryId::housing_bore;

    fem::ShiftedStaticSolver solver(model, ring ? reduction::ReductionSettings{}.static_shift_hz : 0.0, ring);
    // Every cell's points, for the displacement means.
    std::vector<fem::Point3> all_points;
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        for (const auto &p : cell_points(grid, i, j, s))
          all_points.push_back(p);
    const fem::SurfacePointMap sampler(model, all_points, surface);
    std::unique_ptr<InterfaceStressSampler> stress_sampler;
    if (!t.depths.empty())
      stress_sampler = std::make_unique<InterfaceStressSampler>(model, grid, t.depths, ring);

    const std::size_t cells = grid.size(), per_cell = static_cast<std::size_t>(s * s);
    // Displacement means and stresses of one solution, appended to the tables.
    const auto record = [&](const fem::DisplacementField &u, std::vector<double> &displacement,
                            std::vector<double> &stress) {
      const std::vector<fem::Vector3> samples = sampler.interpolate(u);
      for (std::size_t c = 0; c < cells; ++c)
        {
          double mean[3] = {0.0, 0.0, 0.0};
          for (std::size_t q = 0; q < per_cell; ++q)
            {
              const fem::Point3  &x = sampler.points()[c * per_cell + q];
              const fem::Vector3 &v = samples[c * per_cell + q];
              const double        r = std::hypot(x[0], x[1]), cs = x[0] / r, sn = x[1] / r;
              mean[0] += cs * v[0] + sn * v[1];
              mean[1] += -sn * v[0] + cs * v[1];
              mean[2] += v[2];
            }
          for (const double m : mean)
            displacement.push_back(m / per_cell);
        }
      if (stress_sampler)
        {
          const std::vector<double> local = stress_sampler->evaluate(u);
          stress.insert(stress.end(), local.begin(), local.end());
        }
      ++t.solves;
    };

    // Every load of the tables first, in the tables' order, then solved in
    // blocks (with one column at a time the factor's solves are ~10× slower).
    std::vector<std::unique_ptr<fem::SurfacePointMap>> cell_maps; // per (phase, jj): the three components share it
    for (int phase = 0; phase < t.period; ++phase)
      for (int jj = 0; jj < grid.ny; ++jj)
        cell_maps.push_back(std::make_unique<fem::SurfacePointMap>(model, cell_points(grid, phase, jj, s), surface));
    std::vector<fem::StaticLoad> loads;
    for (int phase = 0; phase < t.period; ++phase)
      for (int k = 0; k < 3; ++k)
        for (int jj = 0; jj < grid.ny; ++jj)
          {
            const std::vector<fem::Point3> points = cell_points(grid, phase, jj, s);
            fem::PointForceLoad forces{cell_maps[static_cast<std::size_t>(phase * grid.ny + jj)].get(), {}};
            for (const auto &x : points)
              {
                const double r = std::hypot(x[0], x[1]), cs = x[0] / r, sn = x[1] / r;
                // pressure pushes into the body: inward on a ring, outward on a bore
                const double f = 1.0 / double(per_cell), radial = ring ? -f : f;
                forces.forces.push_back(k == 0   ? std::array<double, 3>{radial * cs, radial * sn, 0.0}
                                        : k == 1 ? std::array<double, 3>{-f * sn, f * cs, 0.0}
                                                 : std::array<double, 3>{0.0, 0.0, f});
              }
            loads.emplace_back().point_forces.push_back(std::move(forces));
          }
    const std::size_t cell_loads = loads.size();
    t.ball_footprint_loads = request.ball_footprint_loads;
    if (request.balls) // footprint-major: [footprint][phase]
      {
        std::vector<std::vector<fem::RacewayBallLoad>> per_phase;
        for (int phase = 0; phase < t.period; ++phase)
          per_phase.push_back(request.balls(grid.x(phase) / grid.radius));
        for (std::size_t f = 0; f < per_phase.front().size(); ++f)
          for (int phase = 0; phase < t.period; ++phase)
            loads.emplace_back().ball_loads.push_back(per_phase[static_cast<std::size_t>(phase)][f]);
      }
    solver.solve_each(loads, [&](std::size_t i, const fem::DisplacementField &u) {
      if (i < cell_loads)
        record(u, t.displacement, t.stress);
      else
        record(u, t.ball_displacement, t.ball_stress);
    });
    t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return t;
  }
} // namespace fretsim::models
