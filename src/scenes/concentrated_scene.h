#pragma once
// The paper's §4 case: a ball pressed on a flat and shaken tangentially by a
// few micrometres (DESIGN.md §5 `paper_concentrated`). Contact-only: no mesh,
// no PETSc, no MPI, no SUNDIALS.
#include "scenes/scene.h"

#include <fretsim/contact/material.h>
#include <fretsim/contact/subsurface_stress.h>
#include <fretsim/contact/surface_grid.h>

#include <memory>

namespace fretsim::scenes
{
  class ConcentratedContactScene : public Scene
  {
  public:
    static std::vector<app::ParameterSpec> parameter_specs();

    /// Reads and cross-checks the parameters and builds what the run needs
    /// that can fail on bad input (grid, stress evaluator); throws
    /// app::InputError and touches nothing on disk.
    explicit ConcentratedContactScene(app::SceneParameters parameters);
    ~ConcentratedContactScene() override;

    /// Normal contact once, then harmonic sliding cycles with bristle traction;
    /// results.h5 grows step by step, summary.json and figures at the end.
    RunReport run(const RunOptions &options) override;

  private:
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
      contact::StressEvaluatorSettings stress_evaluator;
      std::vector<double>              depth_layers; // [m], z = 0 on the surface
      double      bending_fatigue_limit, torsion_fatigue_limit; // f-1, t-1 [Pa]
      std::string residual_stress;                              // Dang Van centre
      int         warmup_cycles;
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
    void build_stress_evaluator();

    app::SceneParameters parameters;
    Settings             settings;
    HertzSummary         hertz;
    contact::SurfaceGrid grid;
    std::unique_ptr<contact::SubsurfaceStress> stresses;
  };
} // namespace fretsim::scenes
