#pragma once
// A ball-on-flat fretting history on one grid: the normal contact once, then
// harmonic sliding, each step advancing the tangential traction, the stresses
// on the depth layers and the Dang Van risk. The concentrated scene runs it once
// with its output, and again on coarser grids to estimate the grid error of
// D_max (grid_convergence.h).
#include <fretsim/contact/dang_van.h>
#include <fretsim/contact/material.h>
#include <fretsim/contact/normal_contact.h>
#include <fretsim/contact/partial_slip.h>
#include <fretsim/contact/subsurface_stress.h>
#include <fretsim/contact/surface_grid.h>
#include <fretsim/contact/tangential_traction_model.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace fretsim::contact
{
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

    /// Hertz semi-axes (a_x, a_y) of the case [m].
    std::pair<double, double> hertz_semi_axes() const;
    /// Hertz peak pressure p0 [Pa].
    double hertz_peak_pressure() const;
  };

  /// The largest finite D over the points and counted steps, and where.
  struct RiskMaximum
  {
    double       value = 0.0;
    int          i = 0, j = 0, layer = 0;
    std::int64_t step = -1; ///< 0-based step that set it
  };

  /// Seconds spent per stage so far.
  struct FrettingStageTimes
  {
    double normal_contact = 0.0, traction = 0.0, stresses = 0.0, dang_van = 0.0;
  };

  /// Call order: construct (solves the normal contact), then advance() once per
  /// step until finished(); read the fields after each advance.
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
    const StressField             &stress() const { return total_stress; }
    const DangVanField            &risk() const { return *dang_van; }
    RiskMaximum                    risk_maximum() const;
    const SubsurfaceStress        &stress_evaluator() const { return *stresses; }
    const FrettingStageTimes      &stage_times() const { return times; }
    long                           traction_iterations() const { return iterations_total; }
    int                            most_traction_iterations() const { return iterations_most; }

  private:
    FrettingCase                             setup;
    SurfaceGrid                              surface;
    Field                                    contact_pressure;
    int                                      normal_solver_iterations = 0;
    std::unique_ptr<SubsurfaceStress>        stresses;
    std::unique_ptr<TangentialTractionModel> traction_model;
    std::unique_ptr<DangVanField>            dang_van;
    StressField                              pressure_stress, shear_stress, total_stress;
    Field                                    no_load;
    std::int64_t                             step_index           = 0;
    double                                   current_displacement = 0.0, last_displacement = 0.0;
    FrettingStageTimes                       times;
    long                                     iterations_total = 0;
    int                                      iterations_most  = 0;
  };

  /// The grid of the case: n_x × n_y cells over half_width_factor times the
  /// Hertz semi-axis in each direction.
  SurfaceGrid fretting_grid(const FrettingCase &fretting_case, int cells_x, int cells_y, double half_width_factor);

  /// Runs the whole history on `grid` and returns D_max.
  RiskMaximum fretting_risk_maximum(const FrettingCase &fretting_case, const SurfaceGrid &grid);
} // namespace fretsim::contact
