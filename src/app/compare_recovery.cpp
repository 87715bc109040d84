// `fretsim compare` at the run's loads: the reduced ring (the model and its
// truncations, solved statically and recovered on the interface grid and at
// the raceway) against the full FE ring, alone and on the Winkler foundation;
// the full-FE transients; a flexible housing against its reduced model.
#include "app/compare_stages.h"

#include <fretsim/fem/shifted_static_solver.h>
#include <fretsim/fem/stress_sampler.h>
#include <fretsim/fem/surface_grid_map.h>
#include <fretsim/fem/surface_point_map.h>
#include <fretsim/fem/winkler_foundation.h>
#include <fretsim/models/reduced_statics.h>
#include <fretsim/models/reduction.h>
#include <fretsim/reduction/craig_bampton.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <tuple>

namespace fretsim::app::compare
{
  using models::add_ball_row;
  using models::Truncation;

  namespace
  {
    using fem::BoundaryId;

    /// What the reduced model gives at an instant.
    struct Recovered
    {
      std::vector<double> q;
      std::vector<double> displacement;   ///< [cell][3] (u_r, u_θ, u_z)
      std::vector<double> grid_stress;    ///< [cell][6]
      std::vector<double> raceway_stress; ///< [point][6]
      std::vector<double> approach;       ///< r(ψ_j)·q per loaded ball [m]
      double              work    = 0.0;  ///< gᵀq [J]
      double              seconds = 0.0;  ///< load projection, factorisation, solve, recovery
    };

    void recover(const Truncation &t, const Instant &instant, Recovered &r)
    {
      r.displacement   = models::apply(t.grid_displacement, t.n, r.q);
      r.grid_stress    = models::apply(t.grid_stress, t.n, r.q);
      r.raceway_stress = models::apply(t.raceway_stress, t.n, r.q);
      r.approach.clear();
      std::vector<double> row(t.n);
      for (std::size_t b = 0; b < instant.ball_angles.size(); ++b)
        {
          std::fill(row.begin(), row.end(), 0.0);
          add_ball_row(t, instant.ball_angles[b], instant.ball_loads[b], 1.0, row);
          double a = 0.0;
          for (std::size_t j = 0; j < t.n; ++j)
            a += row[j] * r.q[j];
          r.approach.push_back(a);
        }
    }

    /// q = (K_r - σM_r)⁻¹ g_e, g_e the inertia-relieved
    /// g = Σ_j Q_j r(ψ_j) + Σ_c A (HT)_cᵀ (-p, τ_x, τ_y)_c; recovered.
    Recovered reduced_static(const Truncation &t, const Instant &instant, double cell_area)
    {
      Recovered  r;
      const auto start = Clock::now();
      std::vector<double> g(t.n, 0.0);
      for (std::size_t b = 0; b < instant.ball_angles.size(); ++b)
        add_ball_row(t, instant.ball_angles[b], instant.ball_loads[b], instant.ball_loads[b], g);
      const auto       &tr      = instant.tractions;
      const std::size_t n_cells = tr.pressure.size();
      for (std::size_t c = 0; c < n_cells; ++c)
        {
          const double traction[3] = {-tr.pressure[c] * cell_area, tr.shear_x[c] * cell_area, tr.shear_y[c] * cell_area};
          if (traction[0] == 0.0 && traction[1] == 0.0 && traction[2] == 0.0)
            continue;
          for (unsigned int d = 0; d < 3; ++d)
            {
              const double *row = t.grid_displacement.data() + (c * 3 + d) * t.n;
              for (std::size_t j = 0; j < t.n; ++j)
                g[j] += traction[d] * row[j];
            }
        }
      r.q = models::relieved_static(t, g);
      recover(t, instant, r);
      r.seconds = seconds_since(start);
      for (std::size_t j = 0; j < t.n; ++j)
        r.work += g[j] * r.q[j];
      return r;
    }

    /// The full FE solution at an instant, sampled where the reduced model is.
    struct FullSolution
    {
      std::array<std::vector<double>, 3> displacement; ///< u_r, u_θ, u_z per cell
      std::vector<double>                grid_stress, raceway_stress;
      /// Raceway points away from every ball (local_stress_zone) and their stresses.
      std::vector<std::size_t>           far_points;
      std::vector<double>                raceway_stress_far;
      std::vector<double>                approach; ///< fᵀu per unit ball load, per loaded ball [m]
      double                             work          = 0.0; ///< fᵀu [J]
      double                             solve_seconds = 0.0; ///< load assembly + solve
      double                             net_force     = 0.0; ///< |resultant| of the loads [N]
    };

    /// max |a - b| / max |b| over the entries (strided views), NaN if empty.
    double relative_max_error(const std::vector<double> &a, std::size_t offset, std::size_t stride,
                              const std::vector<double> &b)
    {
      if (b.empty())
        return not_measured;
      double difference = 0.0, scale = 0.0;
      for (std::size_t k = 0; k < b.size(); ++k)
        {
          difference = std::max(difference, std::abs(a[offset + k * stride] - b[k]));
          scale      = std::max(scale, std::abs(b[k]));
        }
      return scale > 0.0 ? difference / scale : difference;
    }

    Errors measure(const Recovered &r, const FullSolution &f, bool galerkin)
    {
      Errors e;
      e.u_r            = relative_max_error(r.displacement, 0, 3, f.displacement[0]);
      e.u_theta        = relative_max_error(r.displacement, 1, 3, f.displacement[1]);
      e.u_z            = relative_max_error(r.displacement, 2, 3, f.displacement[2]);
      e.grid_stress    = relative_max_error(r.grid_stress, 0, 1, f.grid_stress);
      e.raceway_stress = relative_max_error(r.raceway_stress, 0, 1, f.raceway_stress);
      std::vector<double> far;
      for (const std::size_t p : f.far_points)
        far.insert(far.end(), r.raceway_stress.begin() + 6 * p, r.raceway_stress.begin() + 6 * (p + 1));
      e.raceway_stress_far = relative_max_error(far, 0, 1, f.raceway_stress_far);
      e.approach       = relative_max_error(r.approach, 0, 1, f.approach);
      // Ritz: the reduced solution minimises the energy norm of the error in
      // its subspace, and ‖u - Tq‖² = fᵀu - gᵀq (K - σM norm) when g = Tᵀf.
      // A negative value would say the reduced model is softer than the full
      // one, which Rayleigh–Ritz excludes (up to the ball-row interpolation).
      if (galerkin && f.work > 0.0)
        e.energy = std::copysign(std::sqrt(std::abs(f.work - r.work) / f.work), f.work - r.work);
      return e;
    }

    /// max |a - b| / max |b| and ‖a - b‖₂ / ‖b‖₂ (NaN if b is zero or empty).
    std::pair<double, double> field_errors(const std::vector<double> &a, const std::vector<double> &b)
    {
      double difference = 0.0, scale = 0.0, squared = 0.0, norm = 0.0;
      for (std::size_t k = 0; k < b.size(); ++k)
        {
          difference = std::max(difference, std::abs(a[k] - b[k]));
          scale      = std::max(scale, std::abs(b[k]));
          squared += (a[k] - b[k]) * (a[k] - b[k]);
          norm += b[k] * b[k];
        }
      if (!(scale > 0.0))
        return {not_measured, not_measured};
      return {difference / scale, std::sqrt(squared / norm)};
    }

    /// The pressure along the circumference in the grid's axial middle (the
    /// mean of the two middle rows when ny is even) [Pa].
    std::vector<double> mid_row(const fem::CylinderGrid &grid, const std::vector<double> &field)
    {
      std::vector<double> row(static_cast<std::size_t>(grid.nx), 0.0);
      const int           upper = grid.ny / 2, lower = grid.ny % 2 == 0 ? upper - 1 : upper;
      for (int i = 0; i < grid.nx; ++i)
        row[static_cast<std::size_t>(i)] = 0.5 * (field[static_cast<std::size_t>(lower * grid.nx + i)] +
                                                  field[static_cast<std::size_t>(upper * grid.nx + i)]);
      return row;
    }

    double max_abs(const std::vector<double> &values, std::size_t offset = 0, std::size_t stride = 1)
    {
      double m = 0.0;
      for (std::size_t k = offset; k < values.size(); k += stride)
        m = std::max(m, std::abs(values[k]));
      return m;
    }

    using BallLoad = std::function<fem::RacewayBallLoad(double, double)>;

    /// The run's ball loads at time t, linear between its snapshots (angles
    /// along the shorter way round), balls without load left out.
    fem::StaticLoad ball_loads_at(const RunFields &run, double t, const BallLoad &ball)
    {
      std::size_t k = 0;
      while (k + 2 < run.n_snapshots && run.time[k + 1] <= t)
        ++k;
      const std::size_t next = std::min(k + 1, run.n_snapshots - 1);
      const double      span = run.time[next] - run.time[k];
      const double      s    = span > 0.0 ? std::clamp((t - run.time[k]) / span, 0.0, 1.0) : 0.0;
      fem::StaticLoad   load;
      for (std::size_t j = 0; j < run.n_balls; ++j)
        {
          const double a0 = run.ball_angle[k * run.n_balls + j], a1 = run.ball_angle[next * run.n_balls + j];
          const double q  = (1.0 - s) * run.ball_load[k * run.n_balls + j] + s * run.ball_load[next * run.n_balls + j];
          if (q > 0.0)
            load.ball_loads.push_back(ball(a0 + s * std::remainder(a1 - a0, 2.0 * M_PI), q));
        }
      return load;
    }

    /// Times `steps` of the run's mean step from the run's time at
    /// `snapshot`; `make(time_step, initial_load, start_time, initial_active)`
    /// builds the integrator (fem::WinklerNewmark or fem::WinklerPairNewmark),
    /// its static start from the run's contact set at the snapshot (`run_pressure`).
    template <typename Make>
    TransientTiming time_full_transient(const RunFields &run, std::size_t snapshot, unsigned int steps,
                                        const std::vector<double> &run_pressure, const BallLoad &ball, Make make)
    {
      std::vector<unsigned char> run_active(run_pressure.size());
      for (std::size_t c = 0; c < run_pressure.size(); ++c)
        run_active[c] = run_pressure[c] > 0.0;
      TransientTiming timing;
      timing.time_step        = run.time.back() / run.integrator_steps; // the run's mean step
      timing.reduced_per_step = run.run_seconds / run.integrator_steps;
      // From the snapshot, or early enough that the balls move through every
      // step (the run's loads end with the run).
      timing.start_time = std::max(run.time.front(), std::min(run.time[snapshot], run.time.back() - steps * timing.time_step));
      const auto      start = Clock::now();
      fem::StaticLoad load  = ball_loads_at(run, timing.start_time, ball);
      auto            transient = make(timing.time_step, load, timing.start_time, run_active);
      timing.start_seconds      = seconds_since(start);
      timing.factorisations_all        = transient->foundation().factorisations;
      timing.factorisation_seconds_all = transient->foundation().factorisation_seconds;
      for (unsigned int k = 1; k <= steps; ++k)
        {
          load = ball_loads_at(run, timing.start_time + k * timing.time_step, ball);
          transient->advance(load);
        }
      timing.dofs           = transient->n_dofs();
      timing.steps          = transient->steps();
      timing.solves         = transient->solves();
      timing.factorisations = transient->factorisations();
      timing.step_seconds   = transient->step_seconds();
      timing.factorisations_all += transient->factorisations();
      timing.factorisation_seconds_all += transient->factorisation_seconds();
      timing.peak_pressure  = transient->foundation().peak_pressure();
      return timing;
    }

    /// The zone around a ball where the full FE carries the footprint's local
    /// stress (smeared over its cells) and the reduced model, by design, does
    /// not (Hertz does, ring_coupling.h): two FE cells, or three transverse
    /// semi-axes of the largest ball's footprint if that is wider [rad].
    double local_stress_zone(const Plan &plan)
    {
      const auto  &body        = plan.body;
      const double race_radius = body.ring.has_groove() ? body.ring.groove_bottom_radius : body.ring.bore_radius;
      double       largest     = 0.0;
      for (const auto &instant : plan.instants)
        for (const double load : instant.ball_loads)
          largest = std::max(largest, load);
      return std::max(2.0 * 2.0 * M_PI / (body.divisions.circumferential << body.refinements),
                      3.0 * plan.model.raceway.footprint_at(largest).semi_axis_transverse / race_radius);
    }

    /// Every truncation of the study, σ the static shift.
    std::vector<Truncation> truncations(const Plan &plan, double sigma)
    {
      std::vector<Truncation> views;
      for (const auto &[m, c] : plan.study.truncations)
        views.push_back(models::truncate(plan.model, m, c, plan.raceway_points, sigma));
      return views;
    }

    std::unique_ptr<fem::StressSampler> raceway_sampler_at(const fem::ElasticModel   &fe,
                                                           const std::vector<fem::Point3> &points)
    {
      if (points.empty())
        return nullptr;
      return std::make_unique<fem::StressSampler>(fe, points, fem::StressFrame::cylindrical);
    }

    /// The Winkler foundation solved with the static solves' shift.
    fem::WinklerSettings static_winkler_settings()
    {
      fem::WinklerSettings settings;
      settings.shift_hz = reduction::ReductionSettings{}.static_shift_hz;
      return settings;
    }

    /// An instant's loaded balls as unit patches on the raceway: their
    /// approach fᵀu per unit load is the work-conjugate measure the raceway
    /// operator stores.
    struct BallPatches
    {
      std::vector<fem::RacewayBallLoad>                  unit_balls;
      std::vector<fem::PatchForces>                      patches;
      std::vector<std::unique_ptr<fem::SurfacePointMap>> maps;
    };

    /// The ring on the Winkler foundation at an instant (null where a solve failed).
    struct InstantWinkler
    {
      std::vector<std::unique_ptr<fem::WinklerGridSolution>> reduced; ///< per truncation
      std::optional<models::ResidualWinklerSolution>         residual;
      std::unique_ptr<fem::WinklerGridSolution>              full;
    };

    /// An instant with what the full FE ring gave at it.
    struct InstantSolution
    {
      std::size_t index = 0;
      Instant     whole;
      /// The balls alone and the tractions alone, each balanced by inertia
      /// as the whole is: in a stiff housing the two nearly cancel, and
      /// their own errors tell how well each is represented.
      Instant        balls_only, tractions_only;
      FullSolution   full, full_balls, full_tractions;
      double         load_sum = 0.0, max_pressure = 0.0;
      InstantWinkler winkler;
    };

    /// The full FE ring of the reduction configuration with its samplers, its
    /// Winkler foundation, and the truncations beside it on the same layer.
    /// Collective.
    class RingComparison
    {
    public:
      RingComparison(const CompareInputs &in, const Plan &plan)
        : in(in)
        , plan(plan)
        , grid(plan.grid())
        , mesh(std::make_shared<const fem::Mesh>(models::build_ring_housing_mesh(plan.body, in.reduction_config)))
        , fe(mesh, plan.body.materials, plan.body.degree)
        , solver(fe, reduction::ReductionSettings{}.static_shift_hz, /*inertia_relief=*/true)
        , full_setup(seconds_since(setup_start))
        , map(fe, BoundaryId::ring_outer, grid)
        , grid_sampler(fem::StressSampler::on_grid(fe, grid))
        , raceway_sampler(raceway_sampler_at(fe, plan.raceway_xyz))
        , local_zone(local_stress_zone(plan))
        , views(truncations(plan, solver.shift()))
        , layer{in.normal_stiffness, in.radial_interference}
        , winkler(fe, map, layer, static_winkler_settings())
      {
        // Every truncation on the layer: dense, from its u_r rows.
        found.winkler_setup = winkler.setup_seconds();
        for (const Truncation &view : views)
          {
            std::vector<double> radial(grid.size() * view.n);
            for (std::size_t c = 0; c < grid.size(); ++c)
              std::copy_n(view.grid_displacement.begin() + static_cast<std::ptrdiff_t>(c * 3 * view.n), view.n,
                          radial.begin() + static_cast<std::ptrdiff_t>(c * view.n));
            reduced_winklers.emplace_back(view.n, view.shifted, radial, grid.cell_area(), layer);
            found.profile.reduced_names.push_back("m" + std::to_string(view.fixed_interface) + "_ncc" +
                                                  std::to_string(view.constraint));
          }
        // The whole model's residual flexibility, column by column: a unit
        // force of each traction component on each cell of the grid's first
        // column, and a unit ball at that column's angle, full FE and reduced.
        const auto whole_view =
          std::find_if(views.begin(), views.end(), [](const Truncation &v) { return v.whole_model; });
        if (whole_view != views.end())
          {
            whole    = &*whole_view;
            residual = models::residual_flexibility(solver, map, *whole, grid, plan.body.ring,
                                                    plan.model.raceway.footprints, 3);
          }
      }

      FullRingSetup setup() const { return {fe.n_dofs(), full_setup, &residual, local_zone}; }

      /// A row per truncation at instant `i`; the whole model's printed to `out` (if any).
      void compare_instant(std::size_t i, std::ostream *out)
      {
        const InstantSolution s = solve_instant(i);
        keep_profile(s);
        for (std::size_t v = 0; v < views.size(); ++v)
          {
            const Row row = compare_view(v, s);
            found.rows.push_back(row);
            if (out && views[v].whole_model)
              print_instant(*out, row);
          }
      }

      /// The full-FE transients, timed over a few of the run's mean steps
      /// from the first compared instant.
      void time_transients()
      {
        const Instant &first = plan.instants.front();
        const auto     time  = [&](bool housing_meshed, auto make) {
          try
            {
              TransientTiming timing = time_full_transient(plan.run, first.snapshot, in.full_transient_steps,
                                                           first.tractions.pressure, ball_load(), make);
              timing.housing_meshed = housing_meshed;
              found.transients.push_back(timing);
            }
          catch (const std::runtime_error &error)
            {
              found.transient_notes.push_back(error.what());
            }
        };
        time(false, [&](double dt, const fem::StaticLoad &load, double t0, const auto &active) {
          return std::make_unique<fem::WinklerNewmark>(fe, map, layer, dt, load, t0, active);
        });
        if (plan.transient_housing)
          {
            const models::RingHousingRequest &request      = plan.transient_housing->request;
            const auto                        housing_mesh = std::make_shared<const fem::Mesh>(
              models::build_ring_housing_mesh(request, in.full_transient_housing_config));
            fem::ElasticModel housing_fe(housing_mesh, request.materials, request.degree,
                                         plan.transient_housing->supports);
            const fem::SurfaceGridMap housing_map(housing_fe, BoundaryId::housing_bore, grid);
            time(true, [&](double dt, const fem::StaticLoad &load, double t0, const auto &active) {
              return std::make_unique<fem::WinklerPairNewmark>(fe, map, housing_fe, housing_map, layer, dt, load,
                                                               t0, active);
            });
          }
      }

      RingResults take_results() { return std::move(found); }

    private:
      /// A ball of `load` on the model's raceway, as the run placed it: the
      /// Hertz patch of the model's footprint at that load (or its fixed
      /// one), carrying `force` (the load, or 1 N for a unit patch).
      fem::RacewayBallLoad raceway_ball(double angle, double load, double force) const
      {
        const reduction::BallFootprint footprint = plan.model.raceway.footprint_at(load);
        fem::RacewayBallLoad ball = reduction::unit_ball(plan.body.ring, std::fmod(angle, 2.0 * M_PI), footprint);
        ball.contact_angle        = plan.model.raceway.contact_angle;
        ball.force                = force;
        return ball;
      }

      BallLoad ball_load() const
      {
        return [this](double angle, double force) { return raceway_ball(angle, force, force); };
      }

      /// An instant's loads on the full FE ring: its tractions on the grid and
      /// its loaded balls.
      fem::StaticLoad static_load(const Instant &part) const
      {
        fem::StaticLoad load;
        load.grid_tractions.push_back({&map, &part.tractions});
        for (std::size_t b = 0; b < part.ball_angles.size(); ++b)
          if (part.ball_loads[b] > 0.0)
            load.ball_loads.push_back(raceway_ball(part.ball_angles[b], part.ball_loads[b], part.ball_loads[b]));
        return load;
      }

      BallPatches ball_patches(const Instant &instant) const
      {
        BallPatches balls;
        for (std::size_t b = 0; b < instant.ball_angles.size(); ++b)
          {
            const fem::RacewayBallLoad ball = raceway_ball(instant.ball_angles[b], instant.ball_loads[b], 1.0);
            balls.unit_balls.push_back(ball);
            balls.patches.push_back(fem::raceway_patch_forces(ball));
            balls.maps.push_back(
              std::make_unique<fem::SurfacePointMap>(fe, balls.patches.back().points, BoundaryId::raceway));
          }
        return balls;
      }

      InstantSolution solve_instant(std::size_t i)
      {
        InstantSolution s;
        s.index      = i;
        s.whole      = plan.instants[i];
        s.balls_only = s.tractions_only = s.whole;
        for (auto *field : {&s.balls_only.tractions.pressure, &s.balls_only.tractions.shear_x,
                            &s.balls_only.tractions.shear_y})
          std::fill(field->begin(), field->end(), 0.0);
        std::fill(s.tractions_only.ball_loads.begin(), s.tractions_only.ball_loads.end(), 0.0);

        const BallPatches balls = ball_patches(s.whole);
        s.full_balls            = full_solution(s.balls_only, balls);
        s.full_tractions        = full_solution(s.tractions_only, balls);
        s.full                  = full_solution(s.whole, balls); // last: its timing and resultant are reported
        for (const double q : s.whole.ball_loads)
          s.load_sum += q;
        for (const double p : s.whole.tractions.pressure)
          s.max_pressure = std::max(s.max_pressure, p);
        s.winkler = solve_winkler(i, s.whole, balls);
        return s;
      }

      FullSolution full_solution(const Instant &part, const BallPatches &balls)
      {
        FullSolution                   full;
        const fem::DisplacementField u = solver.solve(static_load(part));
        full.solve_seconds             = solver.last_load_seconds() + solver.last_solve_seconds();
        const fem::Vector3 resultant   = solver.last_net_force();
        full.net_force = std::sqrt(resultant[0] * resultant[0] + resultant[1] * resultant[1] + resultant[2] * resultant[2]);
        const fem::GridDisplacements d = map.interpolate(u);
        full.displacement              = {d.u_r, d.u_theta, d.u_z};
        full.grid_stress               = grid_sampler.evaluate(u);
        if (raceway_sampler)
          full.raceway_stress = raceway_sampler->evaluate(u);
        for (std::size_t p = 0; p < plan.raceway_xyz.size(); ++p)
          {
            const double theta = std::atan2(plan.raceway_xyz[p][1], plan.raceway_xyz[p][0]);
            bool         far   = true;
            for (const double psi : part.ball_angles)
              far = far && std::abs(std::remainder(theta - psi, 2.0 * M_PI)) >= local_zone;
            if (far)
              {
                full.far_points.push_back(p);
                full.raceway_stress_far.insert(full.raceway_stress_far.end(), full.raceway_stress.begin() + 6 * p,
                                               full.raceway_stress.begin() + 6 * (p + 1));
              }
          }
        const double area = grid.cell_area();
        for (std::size_t c = 0; c < grid.size(); ++c)
          full.work += area * (-part.tractions.pressure[c] * d.u_r[c] + part.tractions.shear_x[c] * d.u_theta[c] +
                               part.tractions.shear_y[c] * d.u_z[c]);
        for (std::size_t b = 0; b < balls.unit_balls.size(); ++b)
          {
            const auto at = balls.maps[b]->interpolate(u);
            double     a  = 0.0;
            for (std::size_t p = 0; p < at.size(); ++p)
              for (unsigned int k = 0; k < 3; ++k)
                a += balls.patches[b].forces[p][k] * at[p][k];
            full.approach.push_back(a);
            full.work += part.ball_loads[b] * a;
          }
        return full;
      }

      /// The ring on the Winkler foundation under the balls alone: each
      /// truncation first (the whole model's contact set is the full
      /// solve's first guess), then the full FE ring.
      InstantWinkler solve_winkler(std::size_t i, const Instant &instant, const BallPatches &balls)
      {
        const auto where = [&](const Truncation &view) {
          return "instant " + std::to_string(i) + ", m' = " + std::to_string(view.fixed_interface) +
                 ", n_cc' = " + std::to_string(view.constraint) + ": ";
        };
        InstantWinkler solutions;
        solutions.reduced.resize(views.size());
        std::vector<unsigned char> first_guess;
        for (std::size_t v = 0; v < views.size(); ++v)
          {
            std::vector<double> g(views[v].n, 0.0);
            for (std::size_t b = 0; b < instant.ball_angles.size(); ++b)
              add_ball_row(views[v], instant.ball_angles[b], instant.ball_loads[b], instant.ball_loads[b], g);
            try
              {
                solutions.reduced[v] = std::make_unique<fem::WinklerGridSolution>(reduced_winklers[v].solve(g).grid);
                if (views[v].whole_model)
                  first_guess = solutions.reduced[v]->active;
              }
            catch (const std::runtime_error &error)
              {
                found.winkler_notes.push_back(where(views[v]) + error.what());
              }
          }
        if (!residual.empty())
          try
            {
              solutions.residual = models::winkler_with_residual(*whole, residual, grid, layer.normal_stiffness,
                                                                 layer.radial_interference, instant.ball_angles,
                                                                 instant.ball_loads);
            }
          catch (const std::runtime_error &error)
            {
              found.winkler_notes.push_back("instant " + std::to_string(i) + ", the model with R: " + error.what());
            }
        fem::StaticLoad ball_loads;
        for (std::size_t b = 0; b < balls.unit_balls.size(); ++b)
          {
            ball_loads.ball_loads.push_back(balls.unit_balls[b]);
            ball_loads.ball_loads.back().force = instant.ball_loads[b];
          }
        try
          {
            solutions.full = std::make_unique<fem::WinklerGridSolution>(winkler.solve(ball_loads, first_guess).grid);
          }
        catch (const std::runtime_error &error)
          {
            found.winkler_notes.push_back("instant " + std::to_string(i) + ", full FE: " + error.what());
          }
        return solutions;
      }

      /// compare_pressure.csv's profiles: those of the instant with the highest full peak.
      void keep_profile(const InstantSolution &s)
      {
        const auto      &full    = s.winkler.full;
        PressureProfile &profile = found.profile;
        if (!full || !(full->peak_pressure() > profile.full_peak))
          return;
        profile.instant           = s.index;
        profile.snapshot          = s.whole.snapshot;
        profile.time              = s.whole.time;
        profile.full_peak         = full->peak_pressure();
        profile.full              = mid_row(grid, full->pressure);
        profile.run               = mid_row(grid, s.whole.tractions.pressure);
        profile.run_other_problem = plan.run.other_problem();
        profile.reduced.assign(views.size(), {});
        for (std::size_t v = 0; v < views.size(); ++v)
          if (s.winkler.reduced[v])
            profile.reduced[v] = mid_row(grid, s.winkler.reduced[v]->pressure);
      }

      /// Truncation `v` against the full FE ring at the instant.
      Row compare_view(std::size_t v, const InstantSolution &s) const
      {
        const Truncation &view    = views[v];
        const Instant    &instant = s.whole;
        const double      area    = grid.cell_area();
        Row               row;
        row.instant         = s.index;
        row.snapshot        = instant.snapshot;
        row.time            = instant.time;
        row.fixed_interface = view.fixed_interface;
        row.constraint      = view.constraint;
        row.size            = view.n;
        row.whole_model     = view.whole_model;
        row.balls           = std::count_if(instant.ball_loads.begin(), instant.ball_loads.end(),
                                            [](double q) { return q > 0.0; });
        row.ball_load_sum   = s.load_sum;
        row.max_pressure    = s.max_pressure;
        row.net_force       = s.full.net_force;
        row.full_max_u_r            = max_abs(s.full.displacement[0]);
        row.full_max_u_r_balls      = max_abs(s.full_balls.displacement[0]);
        row.full_max_stress_grid    = max_abs(s.full.grid_stress);
        row.full_max_stress_raceway = max_abs(s.full.raceway_stress);
        row.full_setup      = full_setup;
        row.full_solve      = s.full.solve_seconds;
        const Recovered reduced = reduced_static(view, instant, area);
        row.reduced             = reduced.seconds;
        row.reduced_max_u_r     = max_abs(reduced.displacement, 0, 3);
        row.error               = measure(reduced, s.full, true);
        row.error_balls         = measure(reduced_static(view, s.balls_only, area), s.full_balls, true);
        row.error_tractions     = measure(reduced_static(view, s.tractions_only, area), s.full_tractions, true);
        if (view.whole_model && !residual.ball.empty())
          {
            row.error_u_r_residual       = error_with_residual(reduced, instant, s.full);
            row.error_u_r_residual_balls =
              error_with_residual(reduced_static(view, s.balls_only, area), s.balls_only, s.full_balls);
          }
        row.winkler = compare_winkler(v, s);
        if (view.whole_model && !instant.run_q.empty())
          {
            Recovered dynamic;
            dynamic.q = instant.run_q;
            models::remove_rigid_motion(view, dynamic.q); // the ring's rigid motion in the housing is no deformation
            recover(view, instant, dynamic);
            row.run = measure(dynamic, s.full, false);
          }
        return row;
      }

      /// u_r of the reduced solution with the whole model's residual
      /// flexibility added, against the full FE's.
      double error_with_residual(const Recovered &r, const Instant &part, const FullSolution &f) const
      {
        std::vector<double> u_r =
          models::residual_u_r(residual, plan.model.raceway.footprint_loads(), grid, part.tractions, part.ball_angles,
                               part.ball_loads);
        for (std::size_t c = 0; c < u_r.size(); ++c)
          u_r[c] += r.displacement[3 * c];
        return relative_max_error(u_r, 0, 1, f.displacement[0]);
      }

      /// Truncation `v`'s pressure on the Winkler foundation against the full FE's.
      WinklerComparison compare_winkler(std::size_t v, const InstantSolution &s) const
      {
        const bool  whole_model = views[v].whole_model;
        const auto &full        = s.winkler.full;
        const auto *reduced     = s.winkler.reduced[v].get();
        const auto &run_p       = s.whole.tractions.pressure;
        WinklerComparison w;
        w.normal_stiffness    = layer.normal_stiffness;
        w.radial_interference = layer.radial_interference;
        if (full)
          {
            w.full_peak       = full->peak_pressure();
            w.full_contact    = full->contact_fraction();
            w.full_iterations = full->iterations;
            w.full_seconds    = full->seconds;
            if (whole_model && plan.run_on_layer)
              std::tie(w.run_error_max, w.run_error_l2) = field_errors(run_p, full->pressure);
          }
        if (reduced)
          {
            w.reduced_peak       = reduced->peak_pressure();
            w.reduced_contact    = reduced->contact_fraction();
            w.reduced_iterations = reduced->iterations;
            w.reduced_seconds    = reduced->seconds;
            if (full)
              std::tie(w.error_max, w.error_l2) = field_errors(reduced->pressure, full->pressure);
            if (whole_model && plan.run_on_layer)
              w.run_vs_reduced_max = field_errors(run_p, reduced->pressure).first;
          }
        const auto &with_residual = s.winkler.residual;
        if (whole_model && with_residual)
          {
            w.residual_peak       = with_residual->peak();
            w.residual_contact    = with_residual->contact_fraction();
            w.residual_iterations = with_residual->iterations;
            w.residual_seconds    = with_residual->seconds;
            if (full)
              std::tie(w.residual_error_max, w.residual_error_l2) =
                field_errors(with_residual->pressure, full->pressure);
          }
        return w;
      }

      const CompareInputs     &in;
      const Plan              &plan;
      const fem::CylinderGrid &grid;
      RingResults              found;

      // Declared in the order they are built: the solver factorises fe's
      // K - σM, the samplers and maps read fe, the Winkler solvers map and layer.
      const Clock::time_point             setup_start = Clock::now();
      std::shared_ptr<const fem::Mesh>    mesh;
      fem::ElasticModel                   fe;
      fem::ShiftedStaticSolver            solver;
      const double                        full_setup; ///< mesh, K, M and the factorisation [s]
      const fem::SurfaceGridMap           map;
      const fem::StressSampler            grid_sampler;
      std::unique_ptr<fem::StressSampler> raceway_sampler;
      const double                        local_zone;
      const std::vector<Truncation>       views;
      const fem::WinklerLayer             layer;
      fem::WinklerFoundationSolver        winkler; ///< the full ring's, refactorised per active set
      std::vector<fem::ReducedWinklerSolver> reduced_winklers; ///< per truncation
      reduction::ResidualFlexibility      residual; ///< the whole model's; empty without it
      const Truncation                   *whole = nullptr;
    };
  } // namespace

  RingResults compare_ring(const CompareInputs &in, const Plan &plan, std::ostream *out)
  {
    RingComparison ring(in, plan);
    if (out)
      print_setup(*out, in, plan, ring.setup());
    for (std::size_t i = 0; i < plan.instants.size(); ++i)
      ring.compare_instant(i, out);
    if (in.full_transient_steps > 0 && plan.run.integrator_steps > 0.0)
      ring.time_transients();
    return ring.take_results();
  }

  std::vector<HousingComparison::Result> compare_housing(const Plan &plan)
  {
    if (!plan.housing)
      return {};
    const RunFields                         &run = plan.run;
    std::vector<HousingComparison::Instant> housing_instants;
    for (const Instant &instant : plan.instants)
      {
        HousingComparison::Instant h{instant.tractions.pressure, instant.tractions.shear_x, instant.tractions.shear_y,
                                     {}};
        if (!run.other_model) // the housing's coordinates follow the ring's in the row
          {
            const auto row = run.modal_coordinates.begin() +
                             static_cast<std::ptrdiff_t>(instant.snapshot * run.n_coordinates +
                                                         plan.model.matrices.size());
            h.run_q.assign(row, row + static_cast<std::ptrdiff_t>(run.housing_coordinates));
          }
        housing_instants.push_back(std::move(h));
      }
    return plan.housing->run(housing_instants);
  }
} // namespace fretsim::app::compare
