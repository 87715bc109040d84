#include "app/compare_command.h"

#include "app/compare_housing.h"

#include <fretsim/output/results_file.h>
#include <fretsim/scenes/figures.h>
#include <fretsim/scenes/scene.h>

#include <fretsim/coupling/ring_coupling.h>
#include <fretsim/fem/parallel_environment.h>
#include <fretsim/fem/shifted_static_solver.h>
#include <fretsim/fem/stress_sampler.h>
#include <fretsim/fem/surface_grid_map.h>
#include <fretsim/fem/surface_point_map.h>
#include <fretsim/fem/winkler_foundation.h>
#include <fretsim/models/model_source.h>
#include <fretsim/models/reduced_statics.h>
#include <fretsim/models/reduction.h>
#include <fretsim/reduction/craig_bampton.h>
#include <fretsim/reduction/reduced_model.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <fstream>
#include <iomanip>
#include <limits>
#include <memory>
#include <optional>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace fretsim::app
{
  using models::HousingAround;
  using models::ResidualWinklerSolution;
  using models::add_ball_row;
  using models::apply;
  using models::relieved_static;
  using models::remove_rigid_motion;
  using models::residual_u_r;
  using models::winkler_with_residual;
  using models::RingHousingRequest;
  using models::Truncation;
  using models::build_ring_housing_mesh;
  using models::read_housing_around;
  using models::read_ring_housing_parameters;
  using models::read_ring_housing_request;
  using models::reduce_input_hash;
  using models::residual_flexibility;
  using models::rigid_modes;
  using models::starts_with_rigid_motions;
  using models::truncate;

  namespace
  {
    using Clock = std::chrono::steady_clock;
    using fem::BoundaryId;

    constexpr double not_measured = std::numeric_limits<double>::quiet_NaN();

    double seconds_since(const Clock::time_point start)
    {
      return std::chrono::duration<double>(Clock::now() - start).count();
    }

    const std::string bearing_scene = "bearing_housing";

    std::vector<unsigned int> counts(const SceneParameters &p, const std::string &path)
    {
      std::vector<unsigned int> result;
      for (const double value : p.get_double_list(path))
        {
          if (value != std::floor(value) || value < 0.0)
            p.reject(path, "expected non-negative whole numbers, got " + std::to_string(value));
          result.push_back(static_cast<unsigned int>(value));
        }
      if (result.empty())
        p.reject(path, "is empty; give at least one count");
      return result;
    }

    /// The run's snapshots as the results file holds them.
    struct RunFields
    {
      std::vector<double> time;                          ///< [nt]
      std::vector<double> pressure, shear_x, shear_y;    ///< [nt][ny][nx]
      std::vector<double> ball_angle, ball_load;         ///< [nt][Z]
      std::vector<double> modal_coordinates;             ///< [nt][n]
      std::size_t         n_snapshots = 0, n_balls = 0, n_cells = 0, n_coordinates = 0;
      double              ball_pass_frequency_hz = 0.0;  ///< 0 if the file has none
      /// The run's integrator steps, their wall time [s] and the inner ring's
      /// frequency [Hz]; 0 if the file has none (an older run).
      double              integrator_steps = 0.0, run_seconds = 0.0, inner_ring_frequency_hz = 0.0;
      bool                other_model = false;           ///< its ring's q has another size than the model's
      /// What else the run had between ring and housing: the half-space
      /// (its local_compliance attribute) or a flexible housing, whose
      /// coordinates follow the ring's in each row of modal_coordinates.
      std::string         local_compliance = "none";
      std::size_t         housing_coordinates = 0;
      /// The run's pressure is the Winkler check's problem (the ring on the
      /// layer over the rigid housing); otherwise, what it was instead.
      std::string         other_problem() const
      {
        if (housing_coordinates > 0)
          return "a flexible housing (" + std::to_string(housing_coordinates) + " coordinates)";
        if (local_compliance != "none")
          return "the half-space in series with the layer (local_compliance = " + local_compliance + ")";
        return "";
      }
    };

    /// One compared instant: the loads of a snapshot.
    struct Instant
    {
      std::size_t         snapshot = 0;
      double              time     = 0.0;
      std::vector<double> ball_angles, ball_loads; ///< balls with a load > 0
      fem::GridTractions  tractions;               ///< on the model's grid
      std::vector<double> run_q;                   ///< the run's modal coordinates
    };

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
      r.displacement   = apply(t.grid_displacement, t.n, r.q);
      r.grid_stress    = apply(t.grid_stress, t.n, r.q);
      r.raceway_stress = apply(t.raceway_stress, t.n, r.q);
      r.approach.clear();
      std::vector<double> row(t.n);
      for (const double angle : instant.ball_angles)
        {
          std::fill(row.begin(), row.end(), 0.0);
          add_ball_row(t, angle, 1.0, row);
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
        add_ball_row(t, instant.ball_angles[b], instant.ball_loads[b], g);
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
      r.q = relieved_static(t, g);
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
      /// Raceway points away from every ball (see far_from_balls) and their stresses.
      std::vector<std::size_t>           far_points;
      std::vector<double>                raceway_stress_far;
      std::vector<double>                approach; ///< fᵀu per unit ball load, per loaded ball [m]
      double                             work          = 0.0; ///< fᵀu [J]
      double                             solve_seconds = 0.0; ///< load assembly + solve
    };

    struct Errors
    {
      double u_r = not_measured, u_theta = not_measured, u_z = not_measured;
      double grid_stress = not_measured, raceway_stress = not_measured, raceway_stress_far = not_measured;
      double approach = not_measured, energy = not_measured;
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

    /// The ring on the scene's Winkler foundation under the instant's ball
    /// loads alone: the full FE pressure against this truncation's (NaN where
    /// a solve failed, or for columns of the whole model only).
    struct WinklerComparison
    {
      double normal_stiffness = 0.0, radial_interference = 0.0; ///< [Pa/m], [m]
      double full_peak = not_measured, reduced_peak = not_measured; ///< [Pa]
      /// max |p_r - p| / max p and ‖p_r - p‖₂ / ‖p‖₂ over the grid's cells.
      double error_max = not_measured, error_l2 = not_measured;
      /// The run's own (dynamic) pressure against the full Winkler solution,
      /// and against this model's static one (the whole model only).
      double run_error_max = not_measured, run_error_l2 = not_measured, run_vs_reduced_max = not_measured;
      double full_contact = not_measured, reduced_contact = not_measured; ///< contact fractions
      double full_iterations = not_measured, reduced_iterations = not_measured; ///< linear solves
      double full_seconds = not_measured, reduced_seconds = not_measured;
      /// The whole model with its residual flexibility in series on the
      /// same layer (winkler_with_residual: what the run solves): peak,
      /// errors against the full FE as above, Newton iterations, time.
      double residual_peak = not_measured, residual_error_max = not_measured, residual_error_l2 = not_measured;
      double residual_contact = not_measured, residual_iterations = not_measured, residual_seconds = not_measured;
    };

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

    /// What compare_pressure.csv holds: the profiles at one instant.
    struct PressureProfile
    {
      std::size_t                      instant = 0, snapshot = 0;
      double                           time = 0.0, full_peak = -1.0;
      std::vector<double>              full, run; ///< [nx] [Pa]
      std::vector<std::string>         reduced_names;
      std::vector<std::vector<double>> reduced; ///< per truncation, [nx] [Pa] (empty: the solve failed)
      std::string                      run_other_problem; ///< RunFields::other_problem()
    };

    struct Row
    {
      std::size_t  instant = 0, snapshot = 0;
      double       time = 0.0;
      unsigned int fixed_interface = 0, constraint = 0;
      std::size_t  size = 0;
      bool         whole_model = false;
      std::size_t  balls = 0;
      double       ball_load_sum = 0.0, max_pressure = 0.0;
      double       net_force = 0.0; ///< |resultant| of the loads, balanced by inertia relief [N]
      double       full_setup = 0.0, full_solve = 0.0, reduced = 0.0;
      /// The scales the errors are relative to: max |u_r| on the grid of the
      /// full and the reduced solution [m], max |σ| of the full one on the
      /// grid and at the raceway points [Pa].
      double       full_max_u_r = 0.0, reduced_max_u_r = 0.0, full_max_stress_grid = 0.0, full_max_stress_raceway = 0.0;
      double       full_max_u_r_balls = 0.0; ///< of the balls alone: over full_max_u_r, how much the parts cancel
      Errors       error, run;
      Errors       error_balls, error_tractions; ///< the balls alone, the interface tractions alone
      /// u_r on the grid with the whole model's residual flexibility added
      /// (ResidualFlexibility): the whole load, and the balls alone.
      double       error_u_r_residual = not_measured, error_u_r_residual_balls = not_measured;
      WinklerComparison winkler;
    };

    /// A full-FE transient of the ring on the run's Winkler foundation under
    /// the run's ball loads (fem::WinklerNewmark; no bristle tractions, so a
    /// lower bound on what a full-FE co-simulation costs), timed over a few
    /// of the run's mean steps.
    struct TransientTiming
    {
      bool          housing_meshed = false; ///< ring and housing joined by the layer, or the ring alone
      unsigned long dofs           = 0;     ///< of the full FE system
      unsigned int steps = 0, solves = 0, factorisations = 0;
      double       start_time = 0.0, time_step = 0.0;      ///< [s]
      double       start_seconds = 0.0, step_seconds = 0.0; ///< the static start, the steps [s]
      double       peak_pressure = 0.0;                     ///< after the last step [Pa]
      /// Factorisations of the static start and of the steps, and their time:
      /// the cost of one, for extrapolating to a run whose set changes more often.
      unsigned int factorisations_all = 0;
      double       factorisation_seconds_all = 0.0; ///< [s]
      double       reduced_per_step = 0.0;                  ///< the run's wall time per step [s]
      double       full_per_step() const { return step_seconds / steps; }
      double       mean_factorisation_seconds() const
      {
        return factorisation_seconds_all / std::max(1u, factorisations_all);
      }
    };

    /// The run's ball loads at time t, linear between its snapshots (angles
    /// along the shorter way round), balls without load left out.
    fem::StaticLoad ball_loads_at(const RunFields &run, double t,
                                  const std::function<fem::RacewayBallLoad(double, double)> &ball)
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
                                        const std::vector<double>                                 &run_pressure,
                                        const std::function<fem::RacewayBallLoad(double, double)> &ball, Make make)
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

    double max_abs(const std::vector<double> &values, std::size_t offset = 0, std::size_t stride = 1)
    {
      double m = 0.0;
      for (std::size_t k = offset; k < values.size(); k += stride)
        m = std::max(m, std::abs(values[k]));
      return m;
    }

    RunFields read_run(const CompareInputs &in, const reduction::ReducedModel &model)
    {
      const auto reject = [&](const std::string &problem) {
        throw InputError(in.source, "Compare/Results file", "'" + in.results_file + "' " + problem);
      };
      if (!std::filesystem::exists(in.results_file))
        reject("does not exist; run the scene first (`fretsim run " + in.source + "`)");
      RunFields r;
      const auto &grid = model.interface_grid.grid;
      try
        {
          using output::ResultsFile;
          std::vector<std::size_t> dims;
          r.time        = ResultsFile::read_dataset(in.results_file, "/time", &dims);
          r.n_snapshots = r.time.size();
          if (r.n_snapshots == 0)
            reject("holds no snapshot");
          for (const auto &[name, field] : {std::pair<const char *, std::vector<double> *>{"pressure", &r.pressure},
                                            {"shear_x", &r.shear_x},
                                            {"shear_y", &r.shear_y}})
            {
              *field = ResultsFile::read_dataset(in.results_file, std::string("/fields/") + name, &dims);
              if (dims != std::vector<std::size_t>{r.n_snapshots, static_cast<std::size_t>(grid.ny),
                                                   static_cast<std::size_t>(grid.nx)})
                reject(std::string("has /fields/") + name + " of another shape than [" + std::to_string(r.n_snapshots) +
                       ", " + std::to_string(grid.ny) + ", " + std::to_string(grid.nx) +
                       "] (snapshots, the model's interface grid): the run used another model");
            }
          r.n_cells    = grid.size();
          r.ball_angle = ResultsFile::read_dataset(in.results_file, "/fields/ball_angle", &dims);
          if (dims.size() != 2 || dims[0] != r.n_snapshots || dims[1] == 0)
            reject("has /fields/ball_angle of a shape other than [snapshots, balls]");
          r.n_balls   = dims[1];
          r.ball_load = ResultsFile::read_dataset(in.results_file, "/fields/ball_load", &dims);
          if (dims != std::vector<std::size_t>{r.n_snapshots, r.n_balls})
            reject("has /fields/ball_load of another shape than /fields/ball_angle");
          r.modal_coordinates = ResultsFile::read_dataset(in.results_file, "/fields/modal_coordinates", &dims);
          if (dims.size() != 2 || dims[0] != r.n_snapshots || dims[1] == 0)
            reject("has /fields/modal_coordinates of a shape other than [snapshots, coordinates]");
          r.n_coordinates = dims[1];
          // A run from before these were recorded (each came at its own
          // time) had the ring alone on the layer: the defaults stay.
          try
            {
              r.housing_coordinates = static_cast<std::size_t>(
                ResultsFile::read_double_attribute(in.results_file, "/", "housing_coordinates"));
            }
          catch (const std::exception &)
            {
            }
          try
            {
              r.local_compliance = ResultsFile::read_string_attribute(in.results_file, "/", "local_compliance");
            }
          catch (const std::exception &)
            {
            }
          if (r.housing_coordinates >= r.n_coordinates)
            reject("records " + std::to_string(r.housing_coordinates) + " housing coordinates of " +
                   std::to_string(r.n_coordinates) + " in /fields/modal_coordinates: none left for the ring");
          // A run with another model of the same ring (e.g. a larger n_cc)
          // still gives loads and pressures to compare; only its q is not.
          r.other_model = r.n_coordinates - r.housing_coordinates != model.matrices.size();
        }
      catch (const InputError &)
        {
          throw;
        }
      catch (const std::exception &error)
        {
          reject(std::string("cannot be read as a bearing_housing results file: ") + error.what());
        }
      try
        {
          r.ball_pass_frequency_hz =
            output::ResultsFile::read_double_attribute(in.results_file, "/", "ball_pass_frequency_hz");
        }
      catch (const std::exception &)
        {
          r.ball_pass_frequency_hz = 0.0; // spread the instants over the whole run instead
        }
      try
        {
          r.integrator_steps = output::ResultsFile::read_double_attribute(in.results_file, "/", "integrator_steps");
          r.run_seconds      = output::ResultsFile::read_double_attribute(in.results_file, "/", "run_seconds");
          r.inner_ring_frequency_hz =
            output::ResultsFile::read_double_attribute(in.results_file, "/", "inner_ring_frequency_hz");
        }
      catch (const std::exception &)
        {
          r.integrator_steps = r.run_seconds = r.inner_ring_frequency_hz = 0.0; // no timing to set the full one against
        }
      for (const double v : r.ball_load)
        if (!std::isfinite(v))
          reject("holds ball loads that are not finite");
      return r;
    }

    /// N snapshots spread evenly over the last ball-pass period (the load
    /// pattern repeats with it), or over the whole run if it is shorter; the
    /// last snapshot is always among them.
    std::vector<std::size_t> choose_snapshots(const std::vector<double> &time, unsigned int wanted, double bpf_hz)
    {
      std::vector<std::size_t> chosen;
      if (wanted >= time.size())
        {
          for (std::size_t k = 0; k < time.size(); ++k)
            chosen.push_back(k);
          return chosen;
        }
      const double t0 = time.front(), t1 = time.back();
      const double period = bpf_hz > 0.0 ? 1.0 / bpf_hz : 0.0;
      const double span   = period > 0.0 && period * (wanted - 1.0) / wanted <= t1 - t0 ? period : t1 - t0;
      for (unsigned int i = 0; i < wanted; ++i)
        {
          const double target = t1 - span * (wanted - 1.0 - i) / wanted;
          std::size_t  best   = 0;
          for (std::size_t k = 1; k < time.size(); ++k)
            if (std::abs(time[k] - target) < std::abs(time[best] - target))
              best = k;
          if (chosen.empty() || chosen.back() != best)
            chosen.push_back(best);
        }
      return chosen;
    }

    std::string format_list(const std::vector<unsigned int> &values)
    {
      std::ostringstream s;
      for (std::size_t k = 0; k < values.size(); ++k)
        s << (k ? ", " : "") << values[k];
      return s.str();
    }

    /// One line per full-FE transient: its timing against the run's.
    void write_transient_csv(const std::string &path, const std::vector<TransientTiming> &timings, const RunFields &run)
    {
      std::ofstream csv(path);
      csv << "housing_meshed,dofs,steps,time_step_s,start_time_s,solves,factorisations,start_s,full_s_per_step,"
             "run_steps,run_s,reduced_s_per_step,full_over_reduced,peak_pressure_Pa,factorisation_s\n"
          << std::setprecision(10);
      for (const TransientTiming &t : timings)
        csv << (t.housing_meshed ? 1 : 0) << ',' << t.dofs << ',' << t.steps << ',' << t.time_step << ','
            << t.start_time << ',' << t.solves << ',' << t.factorisations << ',' << t.start_seconds << ','
            << t.full_per_step() << ',' << run.integrator_steps << ',' << run.run_seconds << ',' << t.reduced_per_step
            << ',' << t.full_per_step() / t.reduced_per_step << ',' << t.peak_pressure << ','
            << t.mean_factorisation_seconds() << '\n';
    }

    void write_csv(const std::string &path, const std::vector<Row> &rows)
    {
      std::ofstream csv(path);
      csv << "instant,snapshot,time_s,fixed_interface_modes,characteristic_constraint_modes,reduced_size,"
             "whole_model,balls,ball_load_sum_N,max_pressure_Pa,net_force_N,full_setup_s,full_solve_s,reduced_s,"
             "error_u_r,error_u_theta,error_u_z,error_stress_grid,error_stress_raceway,error_stress_raceway_far,"
             "error_ball_approach,error_energy,run_error_u_r,run_error_u_theta,run_error_u_z,run_error_stress_grid,"
             "run_error_stress_raceway,run_error_stress_raceway_far,run_error_ball_approach,full_max_u_r_m,"
             "reduced_max_u_r_m,full_max_stress_grid_Pa,full_max_stress_raceway_Pa,full_max_u_r_balls_m,"
             "error_u_r_balls,error_stress_grid_balls,error_stress_raceway_balls,error_energy_balls,"
             "error_u_r_tractions,error_stress_grid_tractions,error_stress_raceway_tractions,error_energy_tractions,"
             "winkler_normal_stiffness_Pa_per_m,winkler_radial_interference_m,winkler_full_peak_pressure_Pa,"
             "winkler_reduced_peak_pressure_Pa,winkler_error_pressure_max,winkler_error_pressure_l2,"
             "winkler_full_contact_fraction,winkler_reduced_contact_fraction,winkler_full_iterations,"
             "winkler_reduced_iterations,winkler_full_s,winkler_reduced_s,winkler_run_error_pressure_max,"
             "winkler_run_error_pressure_l2,winkler_run_vs_reduced_error_pressure_max,"
             "error_u_r_with_residual,error_u_r_balls_with_residual,winkler_with_residual_peak_pressure_Pa,"
             "winkler_with_residual_error_pressure_max,winkler_with_residual_error_pressure_l2,"
             "winkler_with_residual_contact_fraction,winkler_with_residual_iterations,winkler_with_residual_s\n";
      csv << std::setprecision(10);
      for (const Row &r : rows)
        {
          csv << r.instant << ',' << r.snapshot << ',' << r.time << ',' << r.fixed_interface << ',' << r.constraint
              << ',' << r.size << ',' << (r.whole_model ? 1 : 0) << ',' << r.balls << ',' << r.ball_load_sum << ','
              << r.max_pressure << ',' << r.net_force << ',' << r.full_setup << ',' << r.full_solve << ',' << r.reduced;
          for (const Errors *e : {&r.error, &r.run})
            {
              csv << ',' << e->u_r << ',' << e->u_theta << ',' << e->u_z << ',' << e->grid_stress << ','
                  << e->raceway_stress << ',' << e->raceway_stress_far << ',' << e->approach;
              if (e == &r.error)
                csv << ',' << e->energy;
            }
          csv << ',' << r.full_max_u_r << ',' << r.reduced_max_u_r << ',' << r.full_max_stress_grid << ','
              << r.full_max_stress_raceway << ',' << r.full_max_u_r_balls;
          for (const Errors *e : {&r.error_balls, &r.error_tractions})
            csv << ',' << e->u_r << ',' << e->grid_stress << ',' << e->raceway_stress << ',' << e->energy;
          const WinklerComparison &w = r.winkler;
          for (const double v : {w.normal_stiffness, w.radial_interference, w.full_peak, w.reduced_peak, w.error_max,
                                 w.error_l2, w.full_contact, w.reduced_contact, w.full_iterations,
                                 w.reduced_iterations, w.full_seconds, w.reduced_seconds, w.run_error_max,
                                 w.run_error_l2, w.run_vs_reduced_max, r.error_u_r_residual,
                                 r.error_u_r_residual_balls, w.residual_peak, w.residual_error_max,
                                 w.residual_error_l2, w.residual_contact, w.residual_iterations, w.residual_seconds})
            csv << ',' << v;
          csv << '\n';
        }
      if (!csv)
        throw std::runtime_error("cannot write " + path);
    }

    /// compare_pressure.csv: one line per grid column along the circumference.
    void write_profile(const std::string &path, const fem::CylinderGrid &grid, const PressureProfile &profile)
    {
      std::ofstream csv(path);
      csv << "# pressure on the Winkler foundation in the interface grid's axial middle at instant " << profile.instant
          << " (snapshot " << profile.snapshot << ", t = " << std::setprecision(10) << profile.time
          << " s), the one with the highest full FE peak\n";
      if (!profile.run_other_problem.empty())
        csv << "# run_Pa is the run's own pressure, with " << profile.run_other_problem
            << ": not the layer-alone problem of the other columns\n";
      csv << "theta_deg,full_Pa,run_Pa";
      for (const std::string &name : profile.reduced_names)
        csv << ",reduced_" << name << "_Pa";
      csv << '\n';
      for (std::size_t i = 0; i < profile.full.size(); ++i)
        {
          csv << grid.x(static_cast<int>(i)) / grid.radius * 180.0 / M_PI << ',' << profile.full[i] << ','
              << profile.run[i];
          for (const auto &reduced : profile.reduced)
            csv << ',' << (reduced.empty() ? not_measured : reduced[i]);
          csv << '\n';
        }
      if (!csv)
        throw std::runtime_error("cannot write " + path);
    }

    std::string sci(double value, int width = 10)
    {
      std::ostringstream s;
      if (std::isnan(value))
        s << std::setw(width) << "-";
      else
        s << std::setw(width) << std::scientific << std::setprecision(2) << value;
      return s.str();
    }
  } // namespace

  CompareInputs read_compare_inputs(const std::string &config_file,
                                    const std::vector<std::pair<std::string, std::string>> &overrides)
  {
    // The bearing_housing scene declares Model/... and Compare/... (bearing_scene.cpp).
    SceneParameters::scene_of_file(config_file, {bearing_scene}); // rejects a file of another scene
    SceneParameters p = scenes::declare_parameters(bearing_scene);
    p.parse_file(config_file);
    for (const auto &[path, value] : overrides)
      p.set(path, value);

    CompareInputs in;
    in.source                    = config_file;
    const std::string reduction  = p.get("Model/Reduction configuration");
    if (reduction.empty())
      p.reject("Model/Reduction configuration", "is empty; name the ring_housing configuration of the reduced model");
    // The reduction configurations and model files as the scene resolves
    // them (with the ring's basis sizes the scene may set over its own).
    const models::ModelSource ring = models::ring_model_source(p);
    in.reduction_config            = ring.config;
    in.model_file                  = ring.file;
    in.model_overrides             = ring.overrides;
    in.results_file = p.get("Compare/Results file");
    if (in.results_file.empty())
      in.results_file =
        (std::filesystem::path("results") / std::filesystem::path(config_file).stem() / "results.h5").string();
    in.instants              = static_cast<unsigned int>(p.get_integer("Compare/Instants"));
    in.full_transient_steps  = static_cast<unsigned int>(p.get_integer("Compare/Full transient steps"));
    in.fixed_interface_modes = counts(p, "Compare/Fixed-interface modes");
    in.constraint_modes      = counts(p, "Compare/Characteristic constraint modes");
    for (const unsigned int c : in.constraint_modes)
      if (c == 0)
        p.reject("Compare/Characteristic constraint modes", "expected counts >= 1, got 0");
    if (const std::string housing = p.get("Compare/Full transient housing"); !housing.empty())
      {
        in.full_transient_housing_config =
          (std::filesystem::path(config_file).parent_path() / housing).lexically_normal().string();
        if (!std::filesystem::is_regular_file(in.full_transient_housing_config))
          p.reject("Compare/Full transient housing", "no file '" + in.full_transient_housing_config + "'");
      }
    in.normal_stiffness    = p.get_double("Interface/Normal stiffness");
    in.radial_interference = p.get_double("Interface/Radial interference");
    if (!p.get("Model/Housing reduction configuration").empty())
      {
        const models::ModelSource housing = models::housing_model_source(p);
        in.housing_reduction_config       = housing.config;
        in.housing_model_file             = housing.file;
      }
    return in;
  }

  std::vector<std::string> run_comparison(const CompareInputs &in, const std::string &output_directory, bool plots,
                                          std::ostream &out)
  {
    const auto reject = [&](const std::string &parameter, const std::string &problem) {
      throw InputError(in.source, parameter, problem);
    };
    if (in.instants == 0)
      reject("Compare/Instants", "must be at least 1");
    if (!(in.normal_stiffness > 0.0) || !std::isfinite(in.normal_stiffness))
      reject("Interface/Normal stiffness",
             "must be a finite k_n > 0 Pa/m (the Winkler layer the pressure is compared on), got " +
               std::to_string(in.normal_stiffness));
    if (!std::isfinite(in.radial_interference))
      reject("Interface/Radial interference", "must be finite");

    // ---- Everything is read and checked before MPI starts and before any file is written.
    const SceneParameters    ring_parameters = read_ring_housing_parameters(in.reduction_config, {});
    const RingHousingRequest body            = read_ring_housing_request(ring_parameters);
    if (body.bodies != "ring")
      reject("Model/Reduction configuration", "names '" + in.reduction_config + "' with Mesh/Bodies = " + body.bodies +
                                                "; the reduced model is of the ring alone (Mesh/Bodies = ring)");
    if (!body.gmsh_file.empty())
      reject("Model/Reduction configuration", "names '" + in.reduction_config +
                                                "', a Gmsh mesh; the balls are placed on the Ring section's raceway, "
                                                "which needs Mesh/Source = parametric");
    // The housing meshed for the second full-FE transient.
    std::optional<HousingAround> transient_housing;
    if (!in.full_transient_housing_config.empty())
      transient_housing =
        read_housing_around(in.full_transient_housing_config, body.ring, in.source, "Compare/Full transient housing");
    reduction::ReducedModel model;
    try
      {
        // The hash `fretsim reduce` writes for this configuration: a model made
        // from other inputs (geometry, mesh, material, mode counts) is refused.
        model = reduction::read_model_file(in.model_file, reduce_input_hash(in.reduction_config, in.model_overrides));
      }
    catch (const reduction::ModelFileError &error)
      {
        reject("Model/Model file", std::string(error.what()) + " (reduction configuration '" + in.reduction_config + "')");
      }
    const fem::CylinderGrid &grid = model.interface_grid.grid;
    if (grid.nx == 0)
      reject("Model/Model file", "'" + in.model_file + "' has no interface grid operators: reduce with Reduction/"
                                                       "Interface grid circumferential cells > 0");
    if (model.raceway.angles.empty())
      reject("Model/Model file", "'" + in.model_file + "' has no raceway ball operator: reduce with Reduction/"
                                                       "Raceway ball positions > 0");
    {
      // Inertia relief needs the rigid-body motions among the coordinates: the
      // first six characteristic constraint modes of a free ring (Guyan
      // eigenvalue 0; below the 1 Hz rigid-body cutoff of fem::ModalSettings).
      if (!starts_with_rigid_motions(model.matrices))
        reject("Model/Model file", "'" + in.model_file + "' does not start with the six rigid-body motions of the free "
                                                         "ring among its characteristic constraint modes (a free ring "
                                                         "reduced with Reduction/Characteristic constraint modes > 6 "
                                                         "does)");
    }
    const RunFields run = read_run(in, model);
    // A flexible housing's own model, checked now (nothing is built or
    // written before every input is read); compared after the ring.
    // A scene that names no housing model gets its ring compared and a note.
    std::optional<HousingComparison> housing;
    if (run.housing_coordinates > 0 && !in.housing_reduction_config.empty())
      {
        housing.emplace(in.source, in.housing_reduction_config, in.housing_model_file, body.ring, grid.size());
        if (housing->coordinates() != run.housing_coordinates)
          reject("Model/Housing model file", "'" + in.housing_model_file + "' has " +
                                               std::to_string(housing->coordinates()) + " coordinates; the run (" +
                                               in.results_file + ") had " + std::to_string(run.housing_coordinates));
      }
    // With a half-space or a flexible housing the run's pressure is not the
    // layer-alone problem the Winkler check solves: the two are not set
    // against each other.
    const bool run_on_layer = run.other_problem().empty();

    const auto  &matrices = model.matrices;
    const bool   reduced_interface = !matrices.interface_frequencies_hz.empty();
    std::vector<unsigned int> fixed_list, constraint_list, dropped_fixed, dropped_constraint;
    for (const unsigned int m : in.fixed_interface_modes)
      (m <= matrices.n_modal ? fixed_list : dropped_fixed).push_back(m);
    for (const unsigned int c : in.constraint_modes)
      (reduced_interface && c <= matrices.n_constraint && c >= rigid_modes ? constraint_list : dropped_constraint)
        .push_back(c);
    // The model itself is always among the truncations.
    std::vector<std::pair<unsigned int, unsigned int>> truncations;
    for (const unsigned int m : fixed_list)
      for (const unsigned int c : constraint_list)
        truncations.emplace_back(m, c);
    if (std::find(truncations.begin(), truncations.end(), std::make_pair(matrices.n_modal, matrices.n_constraint)) ==
        truncations.end())
      truncations.emplace_back(matrices.n_modal, matrices.n_constraint);
    std::sort(truncations.begin(), truncations.end());
    truncations.erase(std::unique(truncations.begin(), truncations.end()), truncations.end());

    const std::vector<std::size_t> snapshots = choose_snapshots(run.time, in.instants, run.ball_pass_frequency_hz);
    std::vector<Instant>           instants;
    for (const std::size_t k : snapshots)
      {
        Instant instant;
        instant.snapshot = k;
        instant.time     = run.time[k];
        for (std::size_t j = 0; j < run.n_balls; ++j)
          if (run.ball_load[k * run.n_balls + j] > 0.0)
            {
              instant.ball_angles.push_back(run.ball_angle[k * run.n_balls + j]);
              instant.ball_loads.push_back(run.ball_load[k * run.n_balls + j]);
            }
        const auto cells = [&](const std::vector<double> &field) {
          return std::vector<double>(field.begin() + k * run.n_cells, field.begin() + (k + 1) * run.n_cells);
        };
        instant.tractions.pressure = cells(run.pressure);
        instant.tractions.shear_x  = cells(run.shear_x);
        instant.tractions.shear_y  = cells(run.shear_y);
        if (!run.other_model) // the ring's coordinates, the first of the row
          instant.run_q.assign(run.modal_coordinates.begin() + k * run.n_coordinates,
                               run.modal_coordinates.begin() + k * run.n_coordinates + model.matrices.size());
        instants.push_back(std::move(instant));
      }

    // The raceway sample points: the line of the model's points inside the outer surface.
    std::vector<std::size_t>  raceway_points;
    std::vector<fem::Point3>  raceway_xyz;
    for (std::size_t p = 0; p < model.sample_points.points.size(); ++p)
      {
        const auto &x = model.sample_points.points[p];
        if (std::hypot(x[0], x[1]) < body.ring.outer_radius * (1.0 - 1e-6))
          {
            raceway_points.push_back(p);
            raceway_xyz.push_back(x);
          }
      }

    // ---- The full FE ring.
    std::unique_ptr<fem::ParallelEnvironment> mpi;
    if (!fem::ParallelEnvironment::active())
      mpi = std::make_unique<fem::ParallelEnvironment>();
    const bool root = fem::ParallelEnvironment::rank() == 0;
    std::vector<Row> rows;
    PressureProfile          profile;
    std::vector<std::string> winkler_notes; // failed Winkler solves, printed after the table
    double                   winkler_setup = 0.0;
    std::vector<TransientTiming> transients;      // the ring on the rigid foundation, then with the housing meshed
    std::vector<std::string>     transient_notes; // why one failed
    {
      const auto setup_start = Clock::now();
      auto       mesh        = std::make_shared<const fem::Mesh>(build_ring_housing_mesh(body, in.reduction_config));
      fem::ElasticModel         fe(mesh, body.materials, body.degree);
      fem::ShiftedStaticSolver  solver(fe, reduction::ReductionSettings{}.static_shift_hz, /*inertia_relief=*/true);
      const double              full_setup = seconds_since(setup_start);
      const double              sigma      = solver.shift();
      const fem::SurfaceGridMap map(fe, BoundaryId::ring_outer, grid);
      // A ball on the model's raceway, as the run placed it (Hertz patch of the model's footprint).
      const auto raceway_ball = [&](double angle, double force) {
        fem::RacewayBallLoad ball;
        ball.ring                      = body.ring;
        ball.angle                     = std::fmod(angle, 2.0 * M_PI);
        ball.contact_angle             = model.raceway.contact_angle;
        ball.semi_axis_circumferential = model.raceway.semi_axis_circumferential;
        ball.semi_axis_transverse      = model.raceway.semi_axis_transverse;
        ball.force                     = force;
        return ball;
      };
      // An instant's loads on the full FE ring: its tractions on the grid and
      // its loaded balls.
      const auto static_load = [&](const Instant &part) {
        fem::StaticLoad load;
        load.grid_tractions.push_back({&map, &part.tractions});
        for (std::size_t b = 0; b < part.ball_angles.size(); ++b)
          if (part.ball_loads[b] > 0.0)
            load.ball_loads.push_back(raceway_ball(part.ball_angles[b], part.ball_loads[b]));
        return load;
      };
      const fem::StressSampler  grid_sampler = fem::StressSampler::on_grid(fe, grid);
      std::unique_ptr<fem::StressSampler> raceway_sampler;
      if (!raceway_xyz.empty())
        raceway_sampler = std::make_unique<fem::StressSampler>(fe, raceway_xyz, fem::StressFrame::cylindrical);

      // The zone around a ball where the full FE carries the footprint's local
      // stress (smeared over its cells) and the reduced model, by design, does
      // not (Hertz does, ring_coupling.h): two FE cells, or three transverse
      // footprint semi-axes if that is wider [rad].
      const double race_radius = body.ring.has_groove() ? body.ring.groove_bottom_radius : body.ring.bore_radius;
      const double local_zone  = std::max(2.0 * 2.0 * M_PI / (body.divisions.circumferential << body.refinements),
                                          3.0 * model.raceway.semi_axis_transverse / race_radius);

      std::vector<Truncation> views;
      for (const auto &[m, c] : truncations)
        views.push_back(truncate(model, m, c, raceway_points, sigma));

      // The Winkler foundation: the full ring (K - σM kept, refactorised per
      // active set) and every truncation (dense, from its u_r rows), with the
      // static solves' shift.
      const fem::WinklerLayer layer{in.normal_stiffness, in.radial_interference};
      fem::WinklerSettings    winkler_settings;
      winkler_settings.shift_hz = reduction::ReductionSettings{}.static_shift_hz;
      fem::WinklerFoundationSolver           winkler(fe, map, layer, winkler_settings);
      std::vector<fem::ReducedWinklerSolver> reduced_winklers;
      winkler_setup = winkler.setup_seconds();
      for (const Truncation &view : views)
        {
          std::vector<double> radial(grid.size() * view.n);
          for (std::size_t c = 0; c < grid.size(); ++c)
            std::copy_n(view.grid_displacement.begin() + static_cast<std::ptrdiff_t>(c * 3 * view.n), view.n,
                        radial.begin() + static_cast<std::ptrdiff_t>(c * view.n));
          reduced_winklers.emplace_back(view.n, view.shifted, radial, grid.cell_area(), layer);
          profile.reduced_names.push_back("m" + std::to_string(view.fixed_interface) + "_ncc" +
                                          std::to_string(view.constraint));
        }

      // The whole model's residual flexibility, column by column: a unit
      // force of each traction component on each cell of the grid's first
      // column, and a unit ball at that column's angle, full FE and reduced.
      reduction::ResidualFlexibility residual;
      const auto whole = std::find_if(views.begin(), views.end(), [](const Truncation &v) { return v.whole_model; });
      if (whole != views.end())
        residual = residual_flexibility(solver, map, *whole, grid, raceway_ball, 3);

      if (root)
        {
          out << "model:        " << in.model_file << ": " << matrices.size() << " coordinates (" << matrices.n_constraint
              << " characteristic constraint + " << matrices.n_modal << " fixed-interface modes), interface grid "
              << grid.nx << " x " << grid.ny << ", " << model.raceway.angles.size() << " ball positions, "
              << raceway_points.size() << " raceway sample points\n"
              << "full FE:      " << fe.n_dofs() << " DoFs (FE_Q" << body.degree << ", "
              << fem::ParallelEnvironment::n_ranks() << " rank(s)); mesh, K, M and the factorisation of K - sigma M "
              << "(sigma = -(2 pi " << reduction::ReductionSettings{}.static_shift_hz << " Hz)^2) in " << std::fixed
              << std::setprecision(2) << full_setup << " s\n"
              << std::defaultfloat << "run:          " << in.results_file << ": " << run.n_snapshots
              << " snapshots, " << run.n_balls << " balls";
          if (run.ball_pass_frequency_hz > 0.0)
            out << ", ball pass " << run.ball_pass_frequency_hz << " Hz";
          if (!run_on_layer)
            out << "; with " << run.other_problem();
          out << "; instants at snapshots";
          for (const auto &i : instants)
            out << ' ' << i.snapshot;
          out << "\n";
          if (!residual.ball.empty())
            out << "residual:     R = K^-1 - T K_r^-1 T^T on the grid from " << residual.solves
                << " full and reduced solves (unit loads on the grid's first column, a unit ball) in " << std::fixed
                << std::setprecision(2) << residual.seconds << " s\n" << std::defaultfloat;
          if (run.other_model)
            out << "note:         the run used a model of " << run.n_coordinates << " coordinates, not this one's "
                << matrices.size() << ": its loads and pressures are compared, its own q is not\n";
          if (!dropped_fixed.empty())
            out << "note:         m' = " << format_list(dropped_fixed) << " left out (the model has m = "
                << matrices.n_modal << ")\n";
          if (!dropped_constraint.empty())
            out << "note:         n_cc' = " << format_list(dropped_constraint) << " left out ("
                << (reduced_interface ? "between the six rigid-body motions and the model's n_cc = " +
                                          std::to_string(matrices.n_constraint)
                                      : std::string("the model keeps every boundary DoF: no interface modes to truncate"))
                << ")\n";
          out << "\nerrors of the reduced model (m = " << matrices.n_modal << ", n_cc = " << matrices.n_constraint
              << ") against the full FE ring, max-norm relative to the full field's maximum\n"
              << "(u on the interface grid, stress on the grid and at the raceway points, ball approach r.q vs f.u,\n"
              << " energy norm of the Ritz error; 'run' = the run's own dynamic q, rigid motion removed, against the\n"
              << " full static solution; both models balance the loads' resultant F_net by rigid-body inertia;\n"
              << " 'race far': raceway points more than " << std::setprecision(3) << local_zone * 180.0 / M_PI
              << " deg from every ball, outside the footprint's local stress;\n"
              << " '+R': u_r with the basis's residual flexibility added, R = K^-1 - T K_r^-1 T^T taken circulant in"
                 " theta)\n" << std::defaultfloat
              << "  inst  snapshot      t [s]  balls   sum Q [N]  p_max [MPa]  F_net [N]  max u_r full/reduced [um]    u_r err  u_theta err    u_z err"
                 "  stress grid  stress race    race far   approach     energy  run u_r err  run stress"
                 "  u_r: balls alone  tractions alone  u_r +R   balls +R  full [s]  reduced [ms]\n";
        }

      for (std::size_t i = 0; i < instants.size(); ++i)
        {
          const Instant &instant = instants[i];
          // The balls alone and the tractions alone, each balanced by inertia
          // as the whole is: in a stiff housing the two nearly cancel, and
          // their own errors tell how well each is represented.
          Instant balls_only = instant, tractions_only = instant;
          for (auto *field : {&balls_only.tractions.pressure, &balls_only.tractions.shear_x, &balls_only.tractions.shear_y})
            std::fill(field->begin(), field->end(), 0.0);
          std::fill(tractions_only.ball_loads.begin(), tractions_only.ball_loads.end(), 0.0);

          // The loaded balls' patches on the raceway: their approach fᵀu per
          // unit load is the work-conjugate measure the raceway operator stores.
          std::vector<fem::RacewayBallLoad>                  unit_balls;
          std::vector<fem::PatchForces>                      patches;
          std::vector<std::unique_ptr<fem::SurfacePointMap>> patch_maps;
          for (const double angle : instant.ball_angles)
            {
              const fem::RacewayBallLoad ball = raceway_ball(angle, 1.0);
              unit_balls.push_back(ball);
              patches.push_back(fem::raceway_patch_forces(ball));
              patch_maps.push_back(std::make_unique<fem::SurfacePointMap>(fe, patches.back().points, BoundaryId::raceway));
            }
          const double area = grid.cell_area();
          double       net_force = 0.0;
          const auto   full_solution = [&](const Instant &part) {
            FullSolution                   full;
            const fem::DisplacementField u = solver.solve(static_load(part));
            full.solve_seconds             = solver.last_load_seconds() + solver.last_solve_seconds();
            const fem::Vector3 resultant   = solver.last_net_force();
            net_force = std::sqrt(resultant[0] * resultant[0] + resultant[1] * resultant[1] + resultant[2] * resultant[2]);
            const fem::GridDisplacements d = map.interpolate(u);
            full.displacement              = {d.u_r, d.u_theta, d.u_z};
            full.grid_stress               = grid_sampler.evaluate(u);
            if (raceway_sampler)
              full.raceway_stress = raceway_sampler->evaluate(u);
            for (std::size_t p = 0; p < raceway_xyz.size(); ++p)
              {
                const double theta = std::atan2(raceway_xyz[p][1], raceway_xyz[p][0]);
                bool         far   = true;
                for (const double psi : instant.ball_angles)
                  far = far && std::abs(std::remainder(theta - psi, 2.0 * M_PI)) >= local_zone;
                if (far)
                  {
                    full.far_points.push_back(p);
                    full.raceway_stress_far.insert(full.raceway_stress_far.end(), full.raceway_stress.begin() + 6 * p,
                                                   full.raceway_stress.begin() + 6 * (p + 1));
                  }
              }
            for (std::size_t c = 0; c < grid.size(); ++c)
              full.work += area * (-part.tractions.pressure[c] * d.u_r[c] + part.tractions.shear_x[c] * d.u_theta[c] +
                                   part.tractions.shear_y[c] * d.u_z[c]);
            for (std::size_t b = 0; b < unit_balls.size(); ++b)
              {
                const auto at = patch_maps[b]->interpolate(u);
                double     a  = 0.0;
                for (std::size_t p = 0; p < at.size(); ++p)
                  for (unsigned int k = 0; k < 3; ++k)
                    a += patches[b].forces[p][k] * at[p][k];
                full.approach.push_back(a);
                full.work += part.ball_loads[b] * a;
              }
            return full;
          };
          const FullSolution full_balls = full_solution(balls_only), full_tractions = full_solution(tractions_only);
          const FullSolution full = full_solution(instant); // last: its timing and resultant are reported

          double load_sum = 0.0, max_pressure = 0.0;
          for (const double q : instant.ball_loads)
            load_sum += q;
          for (const double p : instant.tractions.pressure)
            max_pressure = std::max(max_pressure, p);

          // The ring on the Winkler foundation under the balls alone: each
          // truncation first (the whole model's contact set is the full
          // solve's first guess), then the full FE ring.
          const auto where = [&](const Truncation &view) {
            return "instant " + std::to_string(i) + ", m' = " + std::to_string(view.fixed_interface) +
                   ", n_cc' = " + std::to_string(view.constraint) + ": ";
          };
          std::vector<std::unique_ptr<fem::WinklerGridSolution>> reduced_winkler(views.size());
          std::vector<unsigned char>                             first_guess;
          for (std::size_t v = 0; v < views.size(); ++v)
            {
              std::vector<double> g(views[v].n, 0.0);
              for (std::size_t b = 0; b < instant.ball_angles.size(); ++b)
                add_ball_row(views[v], instant.ball_angles[b], instant.ball_loads[b], g);
              try
                {
                  reduced_winkler[v] = std::make_unique<fem::WinklerGridSolution>(reduced_winklers[v].solve(g).grid);
                  if (views[v].whole_model)
                    first_guess = reduced_winkler[v]->active;
                }
              catch (const std::runtime_error &error)
                {
                  winkler_notes.push_back(where(views[v]) + error.what());
                }
            }
          std::optional<ResidualWinklerSolution> residual_winkler;
          if (!residual.empty())
            try
              {
                residual_winkler = winkler_with_residual(*whole, residual, grid, layer.normal_stiffness,
                                                         layer.radial_interference, instant.ball_angles,
                                                         instant.ball_loads);
              }
            catch (const std::runtime_error &error)
              {
                winkler_notes.push_back("instant " + std::to_string(i) + ", the model with R: " + error.what());
              }
          std::unique_ptr<fem::WinklerGridSolution> full_winkler;
          {
            fem::StaticLoad balls;
            for (std::size_t b = 0; b < unit_balls.size(); ++b)
              {
                balls.ball_loads.push_back(unit_balls[b]);
                balls.ball_loads.back().force = instant.ball_loads[b];
              }
            try
              {
                full_winkler = std::make_unique<fem::WinklerGridSolution>(winkler.solve(balls, first_guess).grid);
              }
            catch (const std::runtime_error &error)
              {
                winkler_notes.push_back("instant " + std::to_string(i) + ", full FE: " + error.what());
              }
          }
          if (full_winkler && full_winkler->peak_pressure() > profile.full_peak)
            {
              profile.instant   = i;
              profile.snapshot  = instant.snapshot;
              profile.time      = instant.time;
              profile.full_peak = full_winkler->peak_pressure();
              profile.full      = mid_row(grid, full_winkler->pressure);
              profile.run       = mid_row(grid, instant.tractions.pressure);
              profile.run_other_problem = run.other_problem();
              profile.reduced.assign(views.size(), {});
              for (std::size_t v = 0; v < views.size(); ++v)
                if (reduced_winkler[v])
                  profile.reduced[v] = mid_row(grid, reduced_winkler[v]->pressure);
            }
          for (const Truncation &view : views)
            {
              Row row;
              row.instant         = i;
              row.snapshot        = instant.snapshot;
              row.time            = instant.time;
              row.fixed_interface = view.fixed_interface;
              row.constraint      = view.constraint;
              row.size            = view.n;
              row.whole_model     = view.whole_model;
              row.balls           = std::count_if(instant.ball_loads.begin(), instant.ball_loads.end(),
                                                  [](double q) { return q > 0.0; });
              row.ball_load_sum   = load_sum;
              row.max_pressure    = max_pressure;
              row.net_force       = net_force;
              row.full_max_u_r            = max_abs(full.displacement[0]);
              row.full_max_u_r_balls      = max_abs(full_balls.displacement[0]);
              row.full_max_stress_grid    = max_abs(full.grid_stress);
              row.full_max_stress_raceway = max_abs(full.raceway_stress);
              row.full_setup      = full_setup;
              row.full_solve      = full.solve_seconds;
              const Recovered reduced = reduced_static(view, instant, area);
              row.reduced             = reduced.seconds;
              row.reduced_max_u_r     = max_abs(reduced.displacement, 0, 3);
              row.error               = measure(reduced, full, true);
              row.error_balls         = measure(reduced_static(view, balls_only, area), full_balls, true);
              row.error_tractions     = measure(reduced_static(view, tractions_only, area), full_tractions, true);
              if (view.whole_model && !residual.ball.empty())
                {
                  const auto with_residual = [&](const Recovered &r, const Instant &part, const FullSolution &f) {
                    std::vector<double> u_r = residual_u_r(residual, grid, part.tractions, part.ball_angles, part.ball_loads);
                    for (std::size_t c = 0; c < u_r.size(); ++c)
                      u_r[c] += r.displacement[3 * c];
                    return relative_max_error(u_r, 0, 1, f.displacement[0]);
                  };
                  row.error_u_r_residual       = with_residual(reduced, instant, full);
                  row.error_u_r_residual_balls = with_residual(reduced_static(view, balls_only, area), balls_only,
                                                               full_balls);
                }
              {
                auto             &w = row.winkler;
                const auto       *reduced_p = reduced_winkler[static_cast<std::size_t>(&view - views.data())].get();
                w.normal_stiffness    = layer.normal_stiffness;
                w.radial_interference = layer.radial_interference;
                if (full_winkler)
                  {
                    w.full_peak       = full_winkler->peak_pressure();
                    w.full_contact    = full_winkler->contact_fraction();
                    w.full_iterations = full_winkler->iterations;
                    w.full_seconds    = full_winkler->seconds;
                    if (view.whole_model && run_on_layer)
                      std::tie(w.run_error_max, w.run_error_l2) =
                        field_errors(instant.tractions.pressure, full_winkler->pressure);
                  }
                if (reduced_p)
                  {
                    w.reduced_peak       = reduced_p->peak_pressure();
                    w.reduced_contact    = reduced_p->contact_fraction();
                    w.reduced_iterations = reduced_p->iterations;
                    w.reduced_seconds    = reduced_p->seconds;
                    if (full_winkler)
                      std::tie(w.error_max, w.error_l2) = field_errors(reduced_p->pressure, full_winkler->pressure);
                    if (view.whole_model && run_on_layer)
                      w.run_vs_reduced_max = field_errors(instant.tractions.pressure, reduced_p->pressure).first;
                  }
                if (view.whole_model && residual_winkler)
                  {
                    w.residual_peak       = residual_winkler->peak();
                    w.residual_contact    = residual_winkler->contact_fraction();
                    w.residual_iterations = residual_winkler->iterations;
                    w.residual_seconds    = residual_winkler->seconds;
                    if (full_winkler)
                      std::tie(w.residual_error_max, w.residual_error_l2) =
                        field_errors(residual_winkler->pressure, full_winkler->pressure);
                  }
              }
              if (view.whole_model && !instant.run_q.empty())
                {
                  Recovered dynamic;
                  dynamic.q = instant.run_q;
                  remove_rigid_motion(view, dynamic.q); // the ring's rigid motion in the housing is no deformation
                  recover(view, instant, dynamic);
                  row.run = measure(dynamic, full, false);
                }
              rows.push_back(row);
              if (root && view.whole_model)
                out << std::setw(6) << i << std::setw(10) << instant.snapshot << std::setw(11) << std::setprecision(4)
                    << std::defaultfloat << instant.time << std::setw(7) << row.balls << std::setw(12) << std::fixed
                    << std::setprecision(1) << load_sum << std::setw(13) << std::setprecision(2) << 1e-6 * max_pressure
                    << ' ' << sci(net_force) << std::fixed << std::setprecision(3) << std::setw(13)
                    << 1e6 * row.full_max_u_r << std::setw(14) << 1e6 * row.reduced_max_u_r << ' '
                    << sci(row.error.u_r) << "   " << sci(row.error.u_theta) << ' ' << sci(row.error.u_z)
                    << "   " << sci(row.error.grid_stress) << "   " << sci(row.error.raceway_stress) << "  "
                    << sci(row.error.raceway_stress_far) << ' ' << sci(row.error.approach) << ' '
                    << sci(row.error.energy) << "   " << sci(row.run.u_r) << "  " << sci(row.run.grid_stress)
                    << ' ' << sci(row.error_balls.u_r) << "      " << sci(row.error_tractions.u_r) << "    "
                    << sci(row.error_u_r_residual) << ' ' << sci(row.error_u_r_residual_balls) << std::fixed
                    << std::setprecision(3) << std::setw(10) << full_setup + full.solve_seconds << std::setw(14)
                    << 1e3 * reduced.seconds << "\n"
                    << std::defaultfloat;
            }
        }

      // ---- The full-FE transient, timed over a few of the run's mean steps
      // from the first compared instant.
      if (in.full_transient_steps > 0 && run.integrator_steps > 0.0)
        {
          const fem::WinklerLayer layer{in.normal_stiffness, in.radial_interference};
          const auto time = [&](bool housing_meshed, auto make) {
            try
              {
                TransientTiming timing =
                  time_full_transient(run, instants.front().snapshot, in.full_transient_steps,
                                      instants.front().tractions.pressure, raceway_ball, make);
                timing.housing_meshed = housing_meshed;
                transients.push_back(timing);
              }
            catch (const std::runtime_error &error)
              {
                transient_notes.push_back(error.what());
              }
          };
          time(false, [&](double dt, const fem::StaticLoad &load, double t0, const auto &active) {
            return std::make_unique<fem::WinklerNewmark>(fe, map, layer, dt, load, t0, active);
          });
          if (transient_housing)
            {
              const RingHousingRequest &request = transient_housing->request;
              const auto                housing_mesh =
                std::make_shared<const fem::Mesh>(build_ring_housing_mesh(request, in.full_transient_housing_config));
              fem::ElasticModel housing_fe(housing_mesh, request.materials, request.degree, transient_housing->supports);
              const fem::SurfaceGridMap housing_map(housing_fe, BoundaryId::housing_bore, grid);
              time(true, [&](double dt, const fem::StaticLoad &load, double t0, const auto &active) {
                return std::make_unique<fem::WinklerPairNewmark>(fe, map, housing_fe, housing_map, layer, dt, load,
                                                                 t0, active);
              });
            }
        }
    } // the ring's FE objects go before the housing's are built

    // ---- A flexible housing: its full FE (held as it was reduced) under the
    // tractions the run passed to it, against its reduced model.
    std::vector<HousingComparison::Result> housing_results;
    if (housing)
      {
        std::vector<HousingComparison::Instant> housing_instants;
        for (const Instant &instant : instants)
          {
            HousingComparison::Instant h{instant.tractions.pressure, instant.tractions.shear_x,
                                         instant.tractions.shear_y, {}};
            if (!run.other_model) // the housing's coordinates follow the ring's in the row
              {
                const auto row = run.modal_coordinates.begin() +
                                 static_cast<std::ptrdiff_t>(instant.snapshot * run.n_coordinates +
                                                             model.matrices.size());
                h.run_q.assign(row, row + static_cast<std::ptrdiff_t>(run.housing_coordinates));
              }
            housing_instants.push_back(std::move(h));
          }
        housing_results = housing->run(housing_instants);
      } // the FE objects go before MPI stops

    std::vector<std::string> files;
    if (!root)
      return files;
    out << "full [s] = mesh + K + M + factorisation (once) + this instant's load assembly and solve\n";

    // ---- The pressure on the Winkler foundation, the model as used.
    out << "\npressure on the Winkler foundation under the run's ball loads alone (k_n = " << in.normal_stiffness
        << " Pa/m, radial interference " << in.radial_interference
        << " m; static, full FE against the model; errors over the interface grid relative to the full field:\n"
        << " max-norm / max p and L2; 'run' = the run's own pressure at the instant, with tractions and dynamics;\n"
        << " solves = linear solves of the active-set iteration, the full one starting from the model's contact set;"
        << " full set-up " << std::fixed << std::setprecision(2) << winkler_setup << std::defaultfloat << " s)\n"
        << "  inst  p_max full  model    run [MPa]  p err max   p err L2  contact full  model  solves full  model"
           "   full [s]  model [ms]  run vs full: max      L2  run vs model\n";
    for (const Row &r : rows)
      if (r.whole_model)
        {
          const auto &w = r.winkler;
          out << std::setw(6) << r.instant << std::fixed << std::setprecision(2) << std::setw(11)
              << 1e-6 * w.full_peak << std::setw(7) << 1e-6 * w.reduced_peak << std::setw(12) << 1e-6 * r.max_pressure
              << ' ' << sci(w.error_max) << ' ' << sci(w.error_l2) << std::setprecision(4) << std::setw(14)
              << w.full_contact << std::setw(7) << w.reduced_contact << std::setprecision(0) << std::setw(13)
              << w.full_iterations << std::setw(7) << w.reduced_iterations << std::setprecision(3) << std::setw(11)
              << w.full_seconds << std::setw(12) << 1e3 * w.reduced_seconds << "       " << sci(w.run_error_max)
              << ' ' << sci(w.run_error_l2) << "    " << sci(w.run_vs_reduced_max) << "\n"
              << std::defaultfloat;
        }
    if (std::any_of(rows.begin(), rows.end(), [](const Row &r) { return !std::isnan(r.winkler.residual_peak); }))
      {
        out << "the same with the model's residual flexibility in series (R = K^-1 - T K_r^-1 T^T, what the run "
               "solves with Interface/Ring residual flexibility):\n"
               "  inst  p_max full  model+R [MPa]  p err max   p err L2  contact model+R  Newton    [s]\n";
        for (const Row &r : rows)
          if (r.whole_model)
            {
              const auto &w = r.winkler;
              out << std::setw(6) << r.instant << std::fixed << std::setprecision(2) << std::setw(11)
                  << 1e-6 * w.full_peak << std::setw(15) << 1e-6 * w.residual_peak << ' ' << sci(w.residual_error_max)
                  << ' ' << sci(w.residual_error_l2) << std::setprecision(4) << std::setw(17) << w.residual_contact
                  << std::setprecision(0) << std::setw(8) << w.residual_iterations << std::setprecision(2)
                  << std::setw(7) << w.residual_seconds << "\n"
                  << std::defaultfloat;
            }
      }
    for (const std::string &note : winkler_notes)
      out << "note: Winkler solve failed at " << note << "\n";
    if (!run_on_layer)
      out << "note: the run had " << run.other_problem()
          << ": this check is of the model on the layer over the rigid housing alone, and the run's pressure is not "
             "compared with it (nan); the tables above and below use the run's own pressure and tractions on the "
             "ring\n";

    // ---- The study: the worst instant per truncation.
    out << "\nerror against the reduced model's size (worst of the " << instants.size()
        << " instants; reduced time: mean per instant, load projection + factorisation + solve + recovery)\n"
        << "     m'  n_cc'   size  reduced [ms]    u_r err  u_theta err    u_z err  stress grid  stress race    race far"
           "     energy  | Winkler: p err max   p err L2  peak ratio  solves  time [ms]\n";
    for (const auto &[m, c] : truncations)
      {
        Errors worst;
        double seconds = 0.0, winkler_max = not_measured, winkler_l2 = not_measured, winkler_seconds = 0.0;
        double worst_ratio = not_measured, most_solves = 0.0; // reduced / full peak farthest from 1
        std::size_t count = 0, size = 0;
        for (const Row &r : rows)
          if (r.fixed_interface == m && r.constraint == c)
            {
              const auto take = [](double &w, double v) { w = std::isnan(w) ? v : std::max(w, v); };
              take(worst.u_r, r.error.u_r);
              take(worst.u_theta, r.error.u_theta);
              take(worst.u_z, r.error.u_z);
              take(worst.grid_stress, r.error.grid_stress);
              take(worst.raceway_stress, r.error.raceway_stress);
              take(worst.raceway_stress_far, r.error.raceway_stress_far);
              take(worst.energy, r.error.energy);
              take(winkler_max, r.winkler.error_max);
              take(winkler_l2, r.winkler.error_l2);
              const double ratio = r.winkler.reduced_peak / r.winkler.full_peak;
              if (std::isnan(worst_ratio) || std::abs(ratio - 1.0) > std::abs(worst_ratio - 1.0))
                worst_ratio = ratio;
              most_solves = std::max(most_solves, std::isnan(r.winkler.reduced_iterations) ? 0.0 : r.winkler.reduced_iterations);
              winkler_seconds += std::isnan(r.winkler.reduced_seconds) ? 0.0 : r.winkler.reduced_seconds;
              seconds += r.reduced;
              size = r.size;
              ++count;
            }
        out << std::setw(7) << m << std::setw(7) << c << std::setw(7) << size << std::fixed << std::setprecision(3)
            << std::setw(14) << 1e3 * seconds / std::max<std::size_t>(count, 1) << ' ' << sci(worst.u_r) << "   "
            << sci(worst.u_theta) << ' ' << sci(worst.u_z) << "   " << sci(worst.grid_stress) << "   "
            << sci(worst.raceway_stress) << "  " << sci(worst.raceway_stress_far) << ' ' << sci(worst.energy)
            << "  |         " << sci(winkler_max) << ' ' << sci(winkler_l2) << std::fixed << std::setprecision(3)
            << std::setw(12) << worst_ratio << std::setprecision(0) << std::setw(8) << most_solves
            << std::setprecision(2) << std::setw(11) << 1e3 * winkler_seconds / std::max<std::size_t>(count, 1)
            << "\n"
            << std::defaultfloat;
      }

    // ---- The full-FE transient against the run.
    for (const TransientTiming &transient : transients)
      {
        out << std::setprecision(6);
        const double reduced_per_step = transient.reduced_per_step;
        const double steps_per_second = run.integrator_steps / run.time.back(); // of simulated time
        out << "\nfull-FE transient against the run ("
            << (transient.housing_meshed ? "ring and housing (" + in.full_transient_housing_config +
                                             ") meshed and joined by the layer"
                                         : std::string("the ring on the rigid Winkler foundation"))
            << ", Newmark, ball loads from the run, no bristle tractions"
            << (run_on_layer || transient.housing_meshed ? "" : ", without " + run.other_problem())
            << ": a lower bound on a full-FE co-simulation's cost)\n"
            << "  " << transient.dofs << " DoFs; " << transient.steps << " steps of dt = " << transient.time_step
            << " s (the run's mean: " << static_cast<long long>(run.integrator_steps) << " steps in " << run.time.back()
            << " s) from t = " << transient.start_time << " s; " << transient.solves << " linear solves, "
            << transient.factorisations << " factorisations; static start " << std::fixed << std::setprecision(2)
            << transient.start_seconds << " s (from the run's contact set); one factorisation "
            << transient.mean_factorisation_seconds() << " s (mean of "
            << transient.factorisations_all << "); peak pressure " << 1e-6 * transient.peak_pressure << " MPa\n"
            << std::defaultfloat << "  full FE: " << transient.full_per_step() << " s per step; the run: "
            << reduced_per_step << " s per step (its whole run: integration, contact, stresses, Dang Van)\n"
            << "  full / reduced: " << std::fixed << std::setprecision(1)
            << transient.full_per_step() / reduced_per_step << std::defaultfloat;
        if (run.inner_ring_frequency_hz > 0.0)
          out << "; per inner-ring revolution at the run's steps: full " << std::fixed << std::setprecision(0)
              << transient.full_per_step() * steps_per_second / run.inner_ring_frequency_hz << " s, reduced "
              << std::setprecision(1) << reduced_per_step * steps_per_second / run.inner_ring_frequency_hz << " s"
              << std::defaultfloat;
        out << "\n";
      }
    for (const std::string &note : transient_notes)
      out << "\nnote: a full-FE transient failed: " << note << "\n";
    if (transients.empty() && transient_notes.empty() && in.full_transient_steps > 0)
      out << "\nnote: no full-FE transient: the results file does not record the run's steps and time (a run made "
             "before they were written)\n";

    if (housing)
      {
        out << "\nthe flexible housing (" << in.housing_reduction_config << ", " << housing->coordinates()
            << " coordinates; full FE " << housing->full_dofs() << " DoFs, set-up " << std::fixed
            << std::setprecision(2) << housing->setup_seconds() << std::defaultfloat
            << " s) under the run's interface tractions, equal and opposite to the ring's; u_r on the bore grid,\n"
               " max |error| / max |u_r full|: the reduced model solved statically (alone, and '+R' with its "
               "residual flexibility of the pressure), and the run's own housing coordinates (with its dynamics)\n"
            << "  inst        t [s]  max u_r full [um]  reduced err         +R    run err  run vs reduced   full [s]  "
               "reduced [ms]\n";
        for (std::size_t i = 0; i < housing_results.size(); ++i)
          {
            const auto &h = housing_results[i];
            out << std::setw(6) << i << std::setw(13) << std::setprecision(6) << instants[i].time << std::fixed
                << std::setprecision(4) << std::setw(19) << 1e6 * h.full_max_u_r << std::defaultfloat << "  "
                << sci(h.reduced_error) << ' ' << sci(h.reduced_residual_error) << ' ' << sci(h.run_error) << "      "
                << sci(h.run_vs_reduced) << std::fixed
                << std::setprecision(3) << std::setw(11) << h.full_seconds << std::setw(14) << 1e3 * h.reduced_seconds << "\n"
                << std::defaultfloat;
          }
      }

    if (run.housing_coordinates > 0 && !housing)
      out << "\nnote: the run had " << run.other_problem()
          << ", but the scene names no Model/Housing reduction configuration: the housing is not compared\n";

    std::filesystem::create_directories(output_directory);
    if (housing)
      {
        const std::string housing_path = (std::filesystem::path(output_directory) / "compare_housing.csv").string();
        std::ofstream     csv(housing_path);
        csv << "instant,time_s,full_max_u_r_m,reduced_u_r_error,reduced_with_residual_u_r_error,run_u_r_error,"
               "run_vs_reduced_u_r,full_s,reduced_s\n"
            << std::setprecision(10);
        for (std::size_t i = 0; i < housing_results.size(); ++i)
          {
            const auto &h = housing_results[i];
            csv << i << ',' << instants[i].time << ',' << h.full_max_u_r << ',' << h.reduced_error << ','
                << h.reduced_residual_error << ',' << h.run_error << ',' << h.run_vs_reduced << ',' << h.full_seconds << ',' << h.reduced_seconds << '\n';
          }
        files.push_back(housing_path);
      }
    const std::string csv_path = (std::filesystem::path(output_directory) / "compare.csv").string();
    write_csv(csv_path, rows);
    files.push_back(csv_path);
    if (!transients.empty())
      {
        const std::string transient_path = (std::filesystem::path(output_directory) / "compare_transient.csv").string();
        write_transient_csv(transient_path, transients, run);
        files.push_back(transient_path);
      }
    if (!profile.full.empty())
      {
        const std::string profile_path = (std::filesystem::path(output_directory) / "compare_pressure.csv").string();
        write_profile(profile_path, grid, profile);
        files.push_back(profile_path);
      }
    if (plots)
      for (const auto &figure : scenes::run_plot_script("plot_compare.py", {csv_path}))
        files.push_back(figure);
    return files;
  }

  std::vector<std::string> run_compare_command(const CompareOptions &options, std::ostream &out)
  {
    const CompareInputs inputs = read_compare_inputs(options.config_file, options.overrides);
    const std::string   directory =
      options.output_directory.empty() ?
          (std::filesystem::path("results") / (std::filesystem::path(options.config_file).stem().string() + "-compare"))
          .string() :
          options.output_directory;
    return run_comparison(inputs, directory, options.plots, out);
  }
} // namespace fretsim::app
