#pragma once
// The paper's §4 case: a ball pressed on a flat and shaken tangentially by a
// few micrometres (docs/theory.md §5 `paper_concentrated`). Contact-only: no mesh,
// no PETSc, no MPI, no SUNDIALS.
#include <fretsim/scenes/scene.h>

#include <fretsim/output/summary.h>

#include <fretsim/contact/fretting_loop.h>
#include <fretsim/contact/fretting_run.h>
#include <fretsim/contact/grid_convergence.h>
#include <fretsim/contact/material.h>
#include <fretsim/contact/mindlin.h>
#include <fretsim/contact/subsurface_stress.h>
#include <fretsim/contact/surface_grid.h>

#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <string>

namespace fretsim::scenes
{
  class ConcentratedContactScene : public Scene
  {
  public:
    static std::vector<app::ParameterSpec> parameter_specs();
    /// Memory and disk of a run, from the parameters alone (builds nothing).
    static ResourceEstimate estimate_resources(const app::SceneParameters &parameters);

    /// Reads and cross-checks the parameters and builds what the run needs
    /// that can fail on bad input (grid, stress evaluator); throws
    /// app::InputError and touches nothing on disk.
    explicit ConcentratedContactScene(app::SceneParameters parameters);
    ~ConcentratedContactScene() override;

    /// Normal contact once, then harmonic sliding cycles; results.h5 grows
    /// step by step; then D_max on coarser grids for its converged value and
    /// error bar; summary.json and figures at the end.
    RunReport run(const RunOptions &options) override;

  private:
    static std::vector<app::ParameterSpec> numerics_parameter_specs();
    static std::vector<app::ParameterSpec> bulk_stress_parameter_specs();

    struct Settings
    {
      contact::MaterialPair materials;
      double radius_x, radius_y;           // combined radii of curvature [m]
      double normal_load;                  // [N]
      double sliding_amplitude;            // [m]
      double sliding_direction;            // angle from x [rad]
      double period;                       // [s]
      int    cycles, steps_per_cycle;
      double friction_coefficient;
      double bristle_stiffness;            // 0: Mindlin calibration [Pa/m]
      double bristle_stiffness_factor;
      double slip_tolerance;
      std::string traction_model;          // bristle | elastoplastic bristle | exact
      double exact_tolerance;
      int    cells_x, cells_y;
      double half_width_factor;
      std::string pressure_model;          // numerical | hertz
      double normal_tolerance;
      int    normal_max_iterations;
      int    snapshots_per_cycle, snapshot_cycles;
      bool   stress_snapshots = false;
      contact::StressEvaluatorSettings stress_evaluator;
      std::vector<double>              depth_layers; // [m], z = 0 on the surface
      double      bending_fatigue_limit, torsion_fatigue_limit; // f-1, t-1 [Pa]
      std::string residual_stress;                              // Dang Van centre
      int         warmup_cycles;
      bool        estimate_risk_error; // D_max on coarser grids for its converged value
      double      yield_strength;      // of the flat [Pa]; 0: not given
    };

    /// What the sliding cycles leave besides the fields: the force loop, the
    /// Mindlin reference, the contact radius of the numerical pressure.
    struct History
    {
      contact::FrettingLoop               loop;
      std::optional<contact::MindlinLoop> mindlin;
      double                              contact_radius = 0.0; // [m]
      double                              slip_area_fraction_max = 0.0; // over the steps after the first

      bool                                completed      = false;
    };

    /// D_max on grids of 4h, 2h, h and its extrapolation.
    struct RiskConvergence
    {
      std::array<int, 3>          cells{};         // cells in x, coarsest first
      std::array<double, 3>       risk{};          // D_max on each
      double                      time_step_correction = 0.0;
      contact::RichardsonEstimate grid;
      // The traction model against the incremental exact solver on the
      // coarsest grid over the first (at most two) cycles; absent for exact.
      std::optional<std::array<double, 2>> model_and_exact_risk;
      int                                  traction_check_cycles = 0;

      // Where the contact's fronts are evaluated (contact::ContactEdgeRisk):
      // their D_max on the same grids, coarsest first, and the grid's D_max
      // below the surface, each with its time-step correction.
      struct EdgeStudy
      {
        std::array<double, 3>       edge{}, below{};
        double                      edge_time_step_correction = 0.0, below_time_step_correction = 0.0;
        contact::RichardsonEstimate below_grid;
        contact::RiskMaximum        below_maximum; ///< on the finest grid, where
        /// False when the fronts' maximum lies in a slip annulus narrower than
        /// two of the finest grid's cells: its remainder is then not resolved,
        /// and the grid's D_max (which samples the peak from below) bounds the
        /// limit from below instead.
        bool annulus_resolved = true;
      };
      std::optional<EdgeStudy> edge;

      struct Interval
      {
        double low = 0.0, high = 0.0;
      };
      /// The fronts' limit: their D_max on the finest grid plus the time-step
      /// correction, give or take its larger grid change (it converges at
      /// about first order, not monotonically), at least 0.5 % (the scatter
      /// seen between 64^2 and finer grids), and twice the correction.
      Interval edge_interval() const;
      /// The grid's limit below the surface: Richardson at order 1/2.
      Interval below_interval() const;
      /// "surface" or "below the surface" when one interval lies above the
      /// other, else "surface or below"; "grid" without the fronts.
      std::string hot_spot() const;
      /// With the fronts: the interval the larger of the two limits lies in,
      /// raised to the grid's own D_max on the run's grid where that is higher.
      Interval interval() const;
      /// The limit of zero cell size and time step: with the fronts, the middle
      /// of interval(); else the grid's Richardson limit plus the time-step
      /// correction.
      double converged() const;
      /// Its bar: half that interval, or the grid's bar and twice the
      /// time-step correction (the coarsest grid underestimates the time-step
      /// error by about a fifth: paper case 2.3e-3 at 32 cells against 2.9e-3 at 128).
      double error_estimate() const;
    };

    /// The Hertz solution the grid, the bristle calibration and the Mindlin
    /// reference are built on; circular when Rx == Ry.
    struct HertzSummary
    {
      double semi_axis_x, semi_axis_y, peak_pressure, approach;
      bool   circular;
      double equivalent_radius() const;
    };

    void read_settings();
    void read_bulk_stress(); // into fretting_case
    void build_stress_evaluator();
    double calibrated_bristle_stiffness() const;

    /// The reruns of the error estimate (concentrated_scene.cpp), ready to start.
    struct RiskReruns;
    /// The history; its threads leave the cores to `reruns` (if given) while they work.
    History simulate(contact::FrettingRun &run, const RunOptions &options, const std::string &results_file,
                     const RiskReruns *reruns) const;
    std::unique_ptr<RiskReruns> risk_reruns() const;
    /// D_max's convergence from the finished reruns and the run's own D_max.
    RiskConvergence risk_convergence(const RiskReruns &reruns, const contact::FrettingRun &finest) const;
    output::Summary make_summary(const contact::FrettingRun &run, const History &history,
                                 const std::optional<RiskConvergence> &convergence, double convergence_seconds,
                                 double wall_seconds) const;
    void add_risk(output::Summary &summary, const contact::FrettingRun &run,
                  const std::optional<RiskConvergence> &convergence) const;
    void add_loop(output::Summary &summary, const History &history) const;
    std::map<std::string, double> key_numbers(const contact::FrettingRun &run, const History &history,
                                              const std::optional<RiskConvergence> &convergence,
                                              double wall_seconds) const;
    /// stick | partial slip | gross slip, from the slip the run computed.
    static std::string regime(const History &history);

    app::SceneParameters parameters;
    Settings             settings;
    HertzSummary         hertz;
    contact::FrettingCase fretting_case; // the validated settings the runs use
    contact::SurfaceGrid grid;
    std::unique_ptr<contact::SubsurfaceStress> stresses;
  };
} // namespace fretsim::scenes
