#pragma once
// The paper's §4 case: a ball pressed on a flat and shaken tangentially by a
// few micrometres (DESIGN.md §5 `paper_concentrated`). Contact-only: no mesh,
// no PETSc, no MPI, no SUNDIALS.
#include "scenes/scene.h"

#include <fretsim/contact/material.h>
#include <fretsim/contact/surface_grid.h>

namespace fretsim::scenes
{
  class ConcentratedContactScene : public Scene
  {
  public:
    static std::vector<app::ParameterSpec> parameter_specs();

    /// Reads and cross-checks the parameters; throws app::InputError.
    explicit ConcentratedContactScene(app::SceneParameters parameters);

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
      int    cells_x, cells_y;
      double half_width_factor;
      std::string pressure_model;          // numerical | hertz
      double normal_tolerance;
      int    normal_max_iterations;
      int    snapshots_per_cycle, snapshot_cycles;
    };

    app::SceneParameters parameters;
    Settings             settings;
  };
} // namespace fretsim::scenes
