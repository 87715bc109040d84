#pragma once
// A ball-on-flat fretting history on one grid: the normal contact once, then
// harmonic sliding, each step advancing the tangential traction, the stresses
// on the depth layers and the Dang Van risk. The concentrated scene runs it once
// with its output, and again on coarser grids to estimate the grid error of
// D_max (grid_convergence.h).
#include <fretsim/contact/contact_edge.h>
#include <fretsim/contact/dang_van.h>
#include <fretsim/contact/masing_traction.h>
#include <fretsim/contact/material.h>
#include <fretsim/contact/normal_contact.h>
#include <fretsim/contact/partial_slip.h>
#include <fretsim/contact/subsurface_stress.h>
#include <fretsim/contact/surface_grid.h>
#include <fretsim/contact/tangential_traction_model.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <vector>

namespace fretsim::contact
{
  /// A uniform in-plane stress state of the flat (a specimen's bending or
  /// tension, as in a fretting-fatigue rig), superposed on the contact's
  /// stresses: sigma(z, t) = (static_surface + z static_gradient)
  /// + (amplitude_surface + z amplitude_gradient) sin(2 pi t / period + phase),
  /// with the sliding delta(t) = amplitude sin(2 pi t / period). Components
  /// xx, yy, xy [Pa] and their depth gradients [Pa/m], z >= 0 into the flat.
  struct BulkStress
  {
    std::array<double, 3> static_surface{}, static_gradient{};
    std::array<double, 3> amplitude_surface{}, amplitude_gradient{};
    double                phase = 0.0; ///< [rad], 0: in phase with the sliding

    bool is_zero() const;
    /// The Voigt tensor (xx, yy, zz, yz, xz, xy) at depth z [m] and time t [s].
    StressTensor at(double depth, double time, double period) const;
  };

  /// Everything that defines the history, validated by the caller.
  struct FrettingCase
  {
    MaterialPair materials;
    double       radius_x = 0.0, radius_y = 0.0; ///< combined radii of curvature [m]
    double       normal_load       = 0.0;        ///< P [N], constant
    double       sliding_amplitude = 0.0;        ///< delta(t) = amplitude sin(2 pi t / period) [m]
    double       sliding_direction = 0.0;        ///< angle from x [rad]
    double       period            = 1.0;        ///< [s]
    int          cycles = 1, steps_per_cycle = 1;
    double       friction_coefficient = 0.0;
    TractionModel       traction_model    = TractionModel::bristle;
    double              bristle_stiffness = 0.0; ///< k [Pa/m] of the bristle models, > 0
    PartialSlipSettings exact;                    ///< of the exact model
    bool                    numerical_pressure = true; ///< false: Hertz sampled at cell centres
    NormalContactSolver::Settings normal;
    StressEvaluatorSettings stress_evaluator;
    std::vector<double>     depth_layers; ///< [m], z = 0 on the surface
    DangVanConstants        dang_van;
    ResidualStressCentre    residual_stress = ResidualStressCentre::running_mean;
    int                     warmup_cycles   = 0;
    BulkStress              bulk_stress;
    /// true: with the exact masing traction the stresses of each step are
    /// composed from those of the virgin levels like the traction itself
    /// (FrettingRun), equal to a stress evaluation per step to round-off;
    /// false: a stress evaluation per step (the reference).
    bool superposed_stresses = true;
    /// Memory the superposition may keep [bytes]: the stresses of every
    /// virgin level, (amplitude / level spacing + 2) x layers x 6 x cells
    /// doubles (52 levels at 200 steps a cycle: 200 MB at 128^2 with 5
    /// layers, 800 MB at 256^2; half of it on the rows y >= 0 of a mirrored
    /// run). Above it, a stress evaluation per step.
    std::size_t superposition_budget = std::size_t(512) << 20;
    /// true: where the history is mirror-symmetric about y = 0
    /// (mirror_symmetric()), the Dang Van criterion runs on the rows y >= 0
    /// only and its fields are mirrored back; false: on every point (the
    /// reference).
    bool mirror_symmetry = true;
    /// true: with the exact masing traction on a circular contact, the risk on
    /// the contact edge too (ContactEdgeRisk, FrettingRun::edge_risk_maximum()).
    bool contact_edge_risk = true;

    /// Hertz semi-axes (a_x, a_y) of the case [m].
    std::pair<double, double> hertz_semi_axes() const;
    /// Hertz peak pressure p0 [Pa].
    double hertz_peak_pressure() const;
  };

  /// True if every stress tensor at (x, -y, z) is the mirror of that at
  /// (x, y, z) (yz and xy change sign), so that the Dang Van risk is equal at
  /// mirrored points: sliding along x (sin of the direction within round-off
  /// of 0), no bulk xy stress, a grid whose rows are symmetric about y = 0,
  /// a stress evaluator exact to round-off (fft or direct; the MLMI's
  /// interpolation error need not be symmetric) and
  /// FrettingCase::mirror_symmetry. The radii are those of x and y, so the
  /// pressure is even in y, the traction tau_x even and tau_y odd.
  bool mirror_symmetric(const FrettingCase &fretting_case, const SurfaceGrid &grid);

  /// The largest finite D over the points and counted steps, and where.
  struct RiskMaximum
  {
    double       value = 0.0;
    int          i = 0, j = 0, layer = 0;
    std::int64_t step = -1; ///< 0-based step that set it
  };

  /// Seconds spent per stage so far. With superposed stresses (FrettingRun)
  /// the stresses are the virgin levels' and reversals' evaluations, and the
  /// per-step sum is done within the Dang Van pass and counted there.
  struct FrettingStageTimes
  {
    double normal_contact = 0.0, traction = 0.0, stresses = 0.0, dang_van = 0.0;
  };

  /// Call order: construct (solves the normal contact), then advance() once per
  /// step until finished(); read the fields after each advance.
  ///
  /// The half-space is linear, so the stresses of a traction composed as
  /// tau = tau_r + f ((1 - w) T_l + w T_u) (MasingTraction::Composition) are
  /// S(tau_r) + f ((1 - w) S(T_l) + w S(T_u)): with the exact masing model
  /// (and FrettingCase::superposed_stresses) the stresses of each virgin level
  /// are evaluated once, when first used, and those of a reversal's traction
  /// composed when the reversal occurs. A step then costs a few additions per
  /// value, done as the Dang Van step reads them, instead of a stress
  /// evaluation; the result differs from evaluating S(tau) by round-off only
  /// (verification_fretting_run). The memory: FrettingCase::superposition_budget.
  /// Those Dang Van steps are held back and run up to 64 at a time, each
  /// block of points through all of them while it is in cache; risk(),
  /// risk_maximum(), von_mises_max() and stage_times() run the held-back
  /// steps first, so every reading is that of the last step.
  class FrettingRun
  {
  public:
    /// Throws std::invalid_argument for settings the stress evaluator refuses,
    /// std::runtime_error if the normal contact does not converge. `stresses`,
    /// if given, is the evaluator for this grid and the case's depth layers
    /// (built beforehand to validate the settings); otherwise one is built.
    FrettingRun(const FrettingCase &fretting_case, const SurfaceGrid &grid,
                std::unique_ptr<SubsurfaceStress> stresses = nullptr);
    ~FrettingRun();

    void advance();
    bool finished() const { return step_index >= total_steps(); }

    std::int64_t total_steps() const;
    std::int64_t steps_done() const { return step_index; }
    double       time() const;
    /// Imposed sliding at the last step [m].
    double displacement() const { return current_displacement; }
    double previous_displacement() const { return last_displacement; }

    const SurfaceGrid             &grid() const { return surface; }
    const Field                   &pressure() const { return contact_pressure; }
    int                            normal_iterations() const { return normal_solver_iterations; }
    const TangentialTractionModel &traction() const { return *traction_model; }
    /// The total stress of the last step (written on the first call after a
    /// superposed step; not to be called from two threads at once).
    const StressField             &stress() const;
    /// The criterion after the last step (its pending steps are run first;
    /// not to be called from two threads at once, as stress()). When
    /// mirrored(), its points are those of the rows from mirror_first_row()
    /// on; risk_now() and risk_max() are on every point.
    const DangVanField            &risk() const;
    /// D(t) of the last step on every point, p = (layer ny + j) nx + i [-].
    const std::vector<double>     &risk_now() const;
    /// D_max on every point, as risk_now() [-].
    const std::vector<double>     &risk_max() const;
    /// Points of risk_max() that are infinite.
    std::size_t                    infinite_risk_max_count() const;
    /// The first (on ties, the first in point order over every point).
    RiskMaximum                    risk_maximum() const;
    /// D_max on the contact edge, where it is evaluated (FrettingCase::contact_edge_risk).
    std::optional<ContactEdgeRiskMaximum> edge_risk_maximum() const;
    /// True if the criterion runs on the half y >= 0 (mirror_symmetric()).
    bool                           mirrored() const { return mirror_row > 0; }
    /// First grid row the criterion runs on: ny / 2 when mirrored (the middle
    /// row included for odd ny), else 0.
    int                            mirror_first_row() const { return mirror_row; }
    const SubsurfaceStress        &stress_evaluator() const { return *stresses; }
    const FrettingStageTimes      &stage_times() const;
    long                           traction_iterations() const { return iterations_total; }
    int                            most_traction_iterations() const { return iterations_most; }
    /// The largest von Mises stress of the total stress (contact and bulk)
    /// over the points and the steps so far, the initial state included [Pa].
    double von_mises_max() const;
    /// True if the stresses are composed from the virgin levels' (class comment).
    bool stresses_superposed() const { return masing != nullptr; }

    /// With `deferred`, advance() queues the virgin levels' stress evaluations
    /// instead of running them between the serial traction solves: another
    /// thread takes them with help_with_level_stresses(), and what is still
    /// queued when a level is needed runs then. Set before the first step.
    /// The same stresses, whichever thread evaluates them.
    void defer_level_stresses(bool deferred) { level_stresses_deferred = deferred; }
    /// Runs the queued level evaluations, if any; safe from another thread
    /// while this run advances (not after it is destroyed). That thread's own
    /// OpenMP thread count applies.
    void help_with_level_stresses() const;

  private:
    /// total = pressure + shear (if given) + bulk stress at the current time.
    void add_stresses(const StressField *shear);
    /// The Dang Van steps of the superposed steps held back so far, all at
    /// once (DangVanField::add_steps): each step's stresses composed by its
    /// recipe (see the class), summed block by block as the criterion reads
    /// them, with the von Mises maximum.
    void run_pending_steps() const;
    /// Points a layer of the superposition's parts: the criterion's rows.
    std::size_t superposed_plane() const;
    /// The rows from mirror_row on of `full` (every row if not mirrored),
    /// layer by layer and component by component, into `out`.
    void superposed_part(const StressField &full, double *out) const;
    void superposed_part(const StressField &full, std::vector<double> &out) const;
    /// `half` (the criterion's points) mirrored onto every point into `full`.
    void mirror_onto(const std::vector<double> &half, std::vector<double> &full) const;
    /// `field` on every point: itself, or mirrored into `whole` (kept while
    /// `whole_step` is the criterion's step count).
    const std::vector<double> &whole_field(const std::vector<double> &field, std::vector<double> &whole,
                                           std::int64_t &whole_step) const;
    /// The bulk stress on each layer at the current time (Voigt).
    std::vector<std::array<double, stress_component_count>> bulk_parts() const;
    /// Level k's stresses once they are evaluated: runs its queued evaluation
    /// here, or waits for the thread that took it.
    const double *ready_level(std::size_t level) const;
    /// Evaluates level k's stresses from its tractions into the store.
    void evaluate_level(std::size_t level, const Field &tau_x, const Field &tau_y, StressField &scratch) const;
    /// Asks for the stresses of virgin level k (superposed_part): evaluated
    /// now, or queued (defer_level_stresses); nullptr while queued or
    /// running (ready_level waits for them).
    const double *level_stresses(std::size_t level);
    /// out = S(p) + S(tau_r) + f ((1 - w) S(T_l) + w S(T_u)) for `recipe`, the
    /// pressure's stresses included (and kept so in reversal_stress), as superposed_part.
    void compose_shear(const MasingTraction::Composition &recipe, std::vector<double> &out);

    FrettingCase                             setup;
    SurfaceGrid                              surface;
    Field                                    contact_pressure;
    int                                      normal_solver_iterations = 0;
    std::unique_ptr<SubsurfaceStress>        stresses;
    std::unique_ptr<TangentialTractionModel> traction_model;
    std::unique_ptr<DangVanField>            dang_van;
    std::unique_ptr<ContactEdgeRisk>         edge;            ///< the contact edge's risk, where evaluated
    const MasingTraction                    *edge_traction = nullptr; ///< its traction
    int                                      mirror_row = 0; ///< mirror_first_row()
    mutable std::vector<double>              mirrored_now, mirrored_max; ///< risk_now(), risk_max() when mirrored
    mutable std::int64_t                     mirrored_now_step = -1, mirrored_max_step = -1; ///< of the step they are of
    StressField                              pressure_stress, shear_stress;
    mutable StressField                      total_stress;
    mutable bool                             total_written = true; ///< false: stress() writes it
    MasingTraction::Composition              total_recipe;         ///< of the step total_stress is of
    const MasingTraction                    *masing = nullptr; ///< set: superposed stresses
    struct LevelStore;
    std::unique_ptr<LevelStore>              virgin_stress;   ///< the levels' stresses
    bool                                     level_stresses_deferred = false;
    std::map<std::int64_t, std::vector<double>> reversal_stress; ///< by reversal id, the pressure's included (superposed_part)
    std::vector<double>                      pressure_part;   ///< superposed_part of pressure_stress
    /// A superposed step whose Dang Van step is still to run: its recipe and
    /// bulk stress per layer.
    struct PendingStep
    {
      MasingTraction::Composition                             recipe;
      std::vector<std::array<double, stress_component_count>> bulk;
    };
    mutable std::vector<PendingStep>         pending;
    mutable double                           largest_six_j2 = 0.0; ///< of the total stress, 6 J2 = 2 sigma_vM^2
    Field                                    no_load;
    std::int64_t                             step_index           = 0;
    double                                   current_displacement = 0.0, last_displacement = 0.0;
    mutable FrettingStageTimes               times;
    long                                     iterations_total = 0;
    int                                      iterations_most  = 0;
  };

  /// The grid of the case: n_x × n_y cells over half_width_factor times the
  /// Hertz semi-axis in each direction.
  SurfaceGrid fretting_grid(const FrettingCase &fretting_case, int cells_x, int cells_y, double half_width_factor);

  /// Runs the whole history on `grid` and returns D_max.
  RiskMaximum fretting_risk_maximum(const FrettingCase &fretting_case, const SurfaceGrid &grid);
} // namespace fretsim::contact
