#pragma once
// The stages of `fretsim compare` (compare_command.h) and what each hands to
// the next: the inputs read and checked into a Plan (compare_inputs.cpp), the
// reduced and the full FE models at the run's loads (compare_recovery.cpp),
// and the tables and files (compare_report.cpp).
#include "app/compare_command.h"
#include "app/compare_housing.h"

#include <fretsim/fem/elastic_model.h>
#include <fretsim/fem/surface_grid_map.h>
#include <fretsim/models/reduction.h>
#include <fretsim/reduction/reduced_model.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <iosfwd>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace fretsim::app::compare
{
  using Clock = std::chrono::steady_clock;

  constexpr double not_measured = std::numeric_limits<double>::quiet_NaN();

  inline double seconds_since(const Clock::time_point start)
  {
    return std::chrono::duration<double>(Clock::now() - start).count();
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

  /// The truncations (m', n_cc') studied, the model itself always among
  /// them, and the counts asked for that the model cannot give.
  struct Study
  {
    std::vector<std::pair<unsigned int, unsigned int>> truncations; ///< sorted, unique
    std::vector<unsigned int> dropped_fixed, dropped_constraint;
    bool                      reduced_interface = false; ///< the model has interface modes to truncate
  };

  /// Everything the comparison works on, read and checked before MPI starts
  /// and before any file is written.
  struct Plan
  {
    models::RingHousingRequest           body;              ///< the ring of the reduction configuration
    std::optional<models::HousingAround> transient_housing; ///< meshed for the second full-FE transient
    reduction::ReducedModel              model;
    RunFields                            run;
    /// A flexible housing's own model, compared after the ring (null: none).
    std::unique_ptr<HousingComparison> housing;
    /// The run's pressure is the layer-alone problem the Winkler check solves
    /// (not so with a half-space or a flexible housing).
    bool                 run_on_layer = true;
    Study                study;
    std::vector<Instant> instants;
    /// The model's sample points on the raceway line (inside the outer
    /// surface): their indices and coordinates.
    std::vector<std::size_t> raceway_points;
    std::vector<fem::Point3> raceway_xyz;

    const fem::CylinderGrid &grid() const { return model.interface_grid.grid; }
  };

  /// Checks every input (InputError naming `in.source` and the parameter)
  /// and reads what the comparison needs.
  Plan read_plan(const CompareInputs &in);

  struct Errors
  {
    double u_r = not_measured, u_theta = not_measured, u_z = not_measured;
    double grid_stress = not_measured, raceway_stress = not_measured, raceway_stress_far = not_measured;
    double approach = not_measured, energy = not_measured;
  };

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

  /// One line of compare.csv: a truncation at an instant.
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

  /// What the full FE ring set up, for the heading of the tables.
  struct FullRingSetup
  {
    unsigned long                         dofs    = 0;
    double                                seconds = 0.0; ///< mesh, K, M and the factorisation of K - σM
    const reduction::ResidualFlexibility *residual = nullptr;
    /// The zone around a ball where the full FE carries the footprint's
    /// local stress and the reduced model does not [rad].
    double                                local_zone = 0.0;
  };

  /// What the ring's comparison found.
  struct RingResults
  {
    std::vector<Row>             rows;
    PressureProfile              profile;
    std::vector<std::string>     winkler_notes; ///< failed Winkler solves, printed after the table
    double                       winkler_setup = 0.0;
    std::vector<TransientTiming> transients;      ///< the ring on the rigid foundation, then with the housing meshed
    std::vector<std::string>     transient_notes; ///< why one failed
  };

  /// The reduced model and its truncations against the full FE ring at every
  /// instant, and the full-FE transients. Collective; `out` (null on the
  /// ranks that do not print) gets the heading and a line per instant as
  /// they come. The ring's FE objects are gone when it returns.
  RingResults compare_ring(const CompareInputs &in, const Plan &plan, std::ostream *out);

  /// A flexible housing's full FE under the tractions the run passed to it,
  /// against its reduced model (none without plan.housing). Collective.
  std::vector<HousingComparison::Result> compare_housing(const Plan &plan);

  /// The heading of the ring's table, and one line of it (the whole model's rows).
  void print_setup(std::ostream &out, const CompareInputs &in, const Plan &plan, const FullRingSetup &full);
  void print_instant(std::ostream &out, const Row &row);

  /// The tables after the ring's: the Winkler pressure, the study of the
  /// truncations, the full-FE transients and the flexible housing.
  void print_summary(std::ostream &out, const CompareInputs &in, const Plan &plan, const RingResults &ring,
                     const std::vector<HousingComparison::Result> &housing);

  /// The CSV files and, with `plots`, the figure; returns their paths.
  std::vector<std::string> write_files(const std::string &output_directory, bool plots, const Plan &plan,
                                       const RingResults &ring,
                                       const std::vector<HousingComparison::Result> &housing);
} // namespace fretsim::app::compare
