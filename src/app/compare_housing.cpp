#include "app/compare_housing.h"

#include <fretsim/support/parameters.h>

#include <fretsim/fem/surface_grid_map.h>
#include <fretsim/models/reduced_statics.h>
#include <fretsim/models/reduction.h>
#include <fretsim/reduction/reduced_model.h>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

namespace fretsim::app
{
  using models::HousingAround;
  using models::RingHousingRequest;
  using models::build_ring_housing_mesh;
  using models::read_housing_around;
  using models::residual_u_r;
  using models::reduce_input_hash;

  namespace
  {
    using Clock = std::chrono::steady_clock;

    double seconds_since(const Clock::time_point start)
    {
      return std::chrono::duration<double>(Clock::now() - start).count();
    }
  } // namespace

  struct HousingComparison::Impl
  {
    std::string                   config;
    RingHousingRequest            body;
    std::vector<fem::Support>     supports;
    reduction::ReducedModel       model;
    Eigen::LDLT<Eigen::MatrixXd>  stiffness; ///< K_h: held at its outside, positive definite
    double                        setup = 0.0;
    unsigned long                 dofs  = 0;

    /// u_r on the bore grid of the housing coordinates q.
    std::vector<double> radial(const Eigen::VectorXd &q) const
    {
      const std::size_t   n = model.matrices.size();
      std::vector<double> u_r(model.interface_grid.grid.size());
      for (std::size_t c = 0; c < u_r.size(); ++c)
        u_r[c] = Eigen::Map<const Eigen::VectorXd>(&model.interface_grid.displacement[c * 3 * n], n).dot(q);
      return u_r;
    }
  };

  HousingComparison::HousingComparison(const std::string &source, const std::string &config,
                                       const std::string &model_file, const fem::RingGeometry &ring,
                                       std::size_t grid_cells)
    : impl(std::make_unique<Impl>())
  {
    const auto reject = [&](const std::string &parameter, const std::string &problem) {
      throw InputError(source, parameter, problem);
    };
    Impl &d  = *impl;
    d.config = config;
    HousingAround housing = read_housing_around(config, ring, source, "Model/Housing reduction configuration");
    d.body                = std::move(housing.request);
    d.supports            = std::move(housing.supports);
    try
      {
        d.model = reduction::read_model_file(model_file, reduce_input_hash(config));
      }
    catch (const reduction::ModelFileError &error)
      {
        reject("Model/Housing model file", std::string(error.what()) + " (reduction configuration '" + config + "')");
      }
    if (d.model.interface_grid.grid.size() != grid_cells)
      reject("Model/Housing model file", "'" + model_file + "' has " +
                                           std::to_string(d.model.interface_grid.grid.size()) +
                                           " interface grid cells on its bore; the ring's grid has " +
                                           std::to_string(grid_cells));
    const std::size_t n = d.model.matrices.size();
    Eigen::MatrixXd   K(n, n);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j)
        K(i, j) = d.model.matrices.stiffness[i * n + j];
    d.stiffness.compute(K);
    if (d.stiffness.info() != Eigen::Success || d.stiffness.vectorD().minCoeff() <= 0.0)
      reject("Model/Housing model file", "'" + model_file + "': the reduced stiffness is not positive definite "
                                                              "(a housing held nowhere?)");
  }

  HousingComparison::~HousingComparison() = default;

  std::size_t HousingComparison::coordinates() const { return impl->model.matrices.size(); }
  double      HousingComparison::setup_seconds() const { return impl->setup; }
  unsigned long HousingComparison::full_dofs() const { return impl->dofs; }

  std::vector<HousingComparison::Result> HousingComparison::run(const std::vector<Instant> &instants)
  {
    Impl             &d     = *impl;
    const auto        start = Clock::now();
    auto              mesh  = std::make_shared<const fem::Mesh>(build_ring_housing_mesh(d.body, d.config));
    fem::ElasticModel fe(mesh, d.body.materials, d.body.degree, d.supports);
    const fem::SurfaceGridMap map(fe, fem::BoundaryId::housing_bore, d.model.interface_grid.grid);
    d.setup = seconds_since(start);
    d.dofs  = fe.n_dofs();

    const std::size_t       n     = d.model.matrices.size();
    const fem::CylinderGrid &grid = d.model.interface_grid.grid;
    const std::size_t       cells = grid.size();
    const double            area  = grid.cell_area();
    std::vector<Result> results;
    for (const Instant &instant : instants)
      {
        // The ring's traction on the housing: the run's pressure pushes into
        // the housing as it pushes into the ring (SurfaceGridMap's sign per
        // surface), the shear acts the other way.
        fem::GridTractions tractions{instant.pressure, instant.shear_x, instant.shear_y};
        for (std::size_t c = 0; c < cells; ++c)
          {
            tractions.shear_x[c] = -tractions.shear_x[c];
            tractions.shear_y[c] = -tractions.shear_y[c];
          }
        Result result;
        auto   clock = Clock::now();
        fem::StaticLoad load;
        load.grid_tractions.push_back({&map, &tractions});
        const std::vector<double> full = map.interpolate(fe.solve_static(load)).u_r;
        result.full_seconds            = seconds_since(clock);

        // Reduced: K_h q = Gᵀ (A t), t = (p, -τ_θ, -τ_z) in the bore's
        // cylindrical components (the co-simulation's relative-displacement
        // rows, transposed, with the housing's sign).
        clock = Clock::now();
        Eigen::VectorXd force = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
        for (std::size_t c = 0; c < cells; ++c)
          {
            const double *rows = &d.model.interface_grid.displacement[c * 3 * n];
            for (std::size_t j = 0; j < n; ++j)
              force[static_cast<Eigen::Index>(j)] +=
                area * (tractions.pressure[c] * rows[j] + tractions.shear_x[c] * rows[n + j] +
                        tractions.shear_y[c] * rows[2 * n + j]);
          }
        const std::vector<double> reduced = d.radial(d.stiffness.solve(force));
        result.reduced_seconds            = seconds_since(clock);

        for (const double value : full)
          result.full_max_u_r = std::max(result.full_max_u_r, std::abs(value));
        const auto error = [&](const std::vector<double> &u_r, const std::vector<double> &reference) {
          double worst = 0.0;
          for (std::size_t c = 0; c < cells; ++c)
            worst = std::max(worst, std::abs(u_r[c] - reference[c]));
          return worst / result.full_max_u_r;
        };
        result.reduced_error          = error(reduced, full);
        result.reduced_residual_error = std::numeric_limits<double>::quiet_NaN();
        if (!d.model.residual.empty())
          {
            std::vector<double> with_residual = residual_u_r(d.model.residual, {}, grid, tractions, {}, {});
            for (std::size_t c = 0; c < cells; ++c)
              with_residual[c] += reduced[c];
            result.reduced_residual_error = error(with_residual, full);
          }
        result.run_error      = std::numeric_limits<double>::quiet_NaN();
        result.run_vs_reduced = std::numeric_limits<double>::quiet_NaN();
        if (instant.run_q.size() == n)
          {
            const std::vector<double> run = d.radial(
              Eigen::Map<const Eigen::VectorXd>(instant.run_q.data(), static_cast<Eigen::Index>(n)));
            result.run_error      = error(run, full);
            result.run_vs_reduced = error(run, reduced);
          }
        results.push_back(result);
      }
    return results;
  }
} // namespace fretsim::app
