#include "concentrated_scene.h"

#include "surface_grid_output.h"

#include <fretsim/support/build_info.h>
#include <fretsim/support/progress.h>
#include <fretsim/support/run_control.h>
#include <fretsim/output/results_file.h>
#include <fretsim/output/summary.h>
#include <fretsim/scenes/figures.h>

#include <fretsim/contact/bristle.h>
#include <fretsim/contact/dang_van.h>
#include <fretsim/contact/fretting_loop.h>
#include <fretsim/contact/hertz.h>
#include <fretsim/contact/mindlin.h>
#include <fretsim/contact/normal_contact.h>
#include <fretsim/contact/tangential_traction_model.h>

#include <array>
#include <atomic>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <tuple>

#include <omp.h>

namespace fretsim::scenes
{
  namespace
  {
    using Clock = std::chrono::steady_clock;

    double seconds_since(Clock::time_point start)
    {
      return std::chrono::duration<double>(Clock::now() - start).count();
    }

    double max_of(const contact::Field &field)
    {
      double result = 0.0;
      for (const double value : field)
        result = std::max(result, value);
      return result;
    }

    /// The grid's D_max below the surface: on the surface the contact's
    /// fronts (contact::ContactEdgeRisk) stand for the grid, whose cell
    /// centres sample their cusps from below.
    contact::RiskMaximum risk_below_surface(const contact::FrettingRun &run, const std::vector<double> &depths)
    {
      const contact::SurfaceGrid &grid     = run.grid();
      const std::vector<double>  &risk_max = run.risk_max();
      contact::RiskMaximum        result;
      for (std::size_t layer = 0; layer < depths.size(); ++layer)
        if (depths[layer] > 0.0)
          for (std::size_t cell = 0; cell < grid.size(); ++cell)
            {
              const double value = risk_max[layer * grid.size() + cell];
              if (std::isfinite(value) && value > result.value)
                result = {value, static_cast<int>(cell % grid.nx), static_cast<int>(cell / grid.nx),
                          static_cast<int>(layer), -1};
            }
      return result;
    }
  } // namespace

  ConcentratedContactScene::RiskConvergence::Interval ConcentratedContactScene::RiskConvergence::edge_interval() const
  {
    const auto  &e      = edge->edge;
    const double centre = e[2] + edge->edge_time_step_correction;
    const double bar    = std::max({std::abs(e[2] - e[1]), std::abs(e[1] - e[0]), 0.005 * std::abs(centre)}) +
                       2.0 * std::abs(edge->edge_time_step_correction);
    if (!edge->annulus_resolved)
      return {std::min(centre - bar, risk[2]), centre + bar};
    return {centre - bar, centre + bar};
  }

  ConcentratedContactScene::RiskConvergence::Interval ConcentratedContactScene::RiskConvergence::below_interval() const
  {
    const double centre = edge->below_grid.converged + edge->below_time_step_correction;
    const double bar    = edge->below_grid.error_estimate + 2.0 * std::abs(edge->below_time_step_correction);
    return {centre - bar, centre + bar};
  }

  ConcentratedContactScene::RiskConvergence::Interval ConcentratedContactScene::RiskConvergence::interval() const
  {
    // The larger of two uncertain limits lies between the larger lows and the
    // larger highs; and no lower than the grid's own D_max on the run's grid
    // (a surface peak the fronts do not cover, under a bulk stress say).
    const Interval on = edge_interval(), below = below_interval();
    return {std::max({on.low, below.low, risk[2]}), std::max({on.high, below.high, risk[2]})};
  }

  std::string ConcentratedContactScene::RiskConvergence::hot_spot() const
  {
    if (!edge)
      return "grid";
    const Interval on = edge_interval(), below = below_interval();
    return on.low >= below.high ? "surface" : below.low >= on.high ? "below the surface" : "surface or below";
  }

  double ConcentratedContactScene::RiskConvergence::converged() const
  {
    if (!edge)
      return grid.converged + time_step_correction;
    const Interval limit = interval();
    return 0.5 * (limit.low + limit.high);
  }

  double ConcentratedContactScene::RiskConvergence::error_estimate() const
  {
    if (!edge)
      return grid.error_estimate + 2.0 * std::abs(time_step_correction);
    const Interval limit = interval();
    return 0.5 * (limit.high - limit.low);
  }

  std::vector<app::ParameterSpec> ConcentratedContactScene::parameter_specs()
  {
    using Spec = app::ParameterSpec;
    std::vector<Spec> specs;
    for (const std::string body : {"Lower body", "Upper body"})
      {
        const std::string which = body == "Lower body" ? "the flat, on which the grid lies" : "the ball";
        specs.push_back(Spec::positive("Materials/" + body + "/Young's modulus", "200e9",
                                       "Young's modulus E of " + which + " [Pa]."));
        specs.push_back(Spec::real_range("Materials/" + body + "/Poisson ratio", "0.3",
                                         "Poisson's ratio nu of " + which + " [-].", -1, 0.5, true, true));
      }
    specs.push_back(Spec::non_negative("Materials/Lower body/Yield strength", "0",
                                       "Yield strength of the flat [Pa]: the run reports yield_margin, this over "
                                       "the largest von Mises stress (below 1 the flat yields somewhere, beyond "
                                       "the elastic analysis). 0: not given, no margin."));
    specs.push_back(Spec::positive("Geometry/Radius x", "0.05",
                                   "Combined radius of curvature of the two surfaces in x, 1/Rx = 1/R1x + 1/R2x [m]."));
    specs.push_back(Spec::positive("Geometry/Radius y", "0.05",
                                   "Combined radius of curvature of the two surfaces in y [m]. Equal to Radius x "
                                   "for a sphere on a flat."));
    specs.push_back(Spec::positive("Loading/Normal load", "1250",
                                   "Normal load P pressing the bodies together, constant in time [N]."));
    specs.push_back(Spec::non_negative("Loading/Sliding amplitude", "2.241e-6",
                                       "Amplitude of the imposed harmonic tangential displacement of the upper body "
                                       "relative to the lower one, delta(t) = amplitude sin(2 pi t / period) [m]."));
    specs.push_back(Spec::real_range("Loading/Sliding direction", "0",
                                     "Direction of the sliding, as an angle from the x axis [rad].", -7, 7));
    specs.push_back(Spec::positive("Loading/Period", "1",
                                   "Period of the sliding [s]. The contact is quasi-static, so the period only "
                                   "scales time."));
    specs.push_back(Spec::integer_range("Loading/Cycles", "8",
                                        "Number of sliding cycles. The bristle loop is steady after a few; the last "
                                        "cycle's change is reported as loop_change_last_cycle [-].", 1, 100000));
    specs.push_back(Spec::integer_range("Loading/Steps per cycle", "200",
                                        "Time steps per sliding cycle; the time step is period / steps [-].", 4,
                                        1000000));
    specs.push_back(Spec::non_negative("Friction/Friction coefficient", "0.53", "Coulomb friction coefficient mu [-]."));
    specs.push_back(Spec::selection("Friction/Traction model", "exact masing",
                                    "Tangential traction model: exact masing (the exact model's solution by Masing's "
                                    "superposition of its first loading: the elastic half-spaces at the cost of a "
                                    "quarter cycle of solves; the default), exact (elastic half-spaces, Kalker-type "
                                    "partial-slip solver every step, the reference), bristle (paper eq. 4, "
                                    "exponential bristles), elastoplastic bristle (elastic-perfectly-plastic "
                                    "bristles with a true stick zone). `fretsim compare-traction` runs them all.",
                                    "exact masing|exact|bristle|elastoplastic bristle"));
    specs.push_back(Spec::real_range("Friction/Exact solver tolerance", "1e-8",
                                     "Relative RMS traction error at which the exact partial-slip solver stops "
                                     "each step [-].", 0, 1e-2, true));
    specs.push_back(Spec::non_negative("Friction/Bristle stiffness", "0",
                                       "Tangential foundation stiffness k of the bristle model [Pa/m]; 0 calibrates "
                                       "it from Mindlin, k = 8 G* / (pi a), so the initial tangential stiffness "
                                       "equals 8 G* a."));
    specs.push_back(Spec::positive("Friction/Bristle stiffness factor", "1",
                                   "Multiplies the bristle stiffness (calibrated or given), for sensitivity "
                                   "studies [-]."));
    specs.push_back(Spec::real_range("Friction/Slip tolerance", "1e-3",
                                     "A point counts as slipping where |tau| >= (1 - tolerance) mu p [-].", 0, 1,
                                     true, true));
    for (auto &spec : bulk_stress_parameter_specs())
      specs.push_back(std::move(spec));
    for (auto &spec : numerics_parameter_specs())
      specs.push_back(std::move(spec));
    return specs;
  }

  std::vector<app::ParameterSpec> ConcentratedContactScene::bulk_stress_parameter_specs()
  {
    using Spec = app::ParameterSpec;
    std::vector<Spec> specs;
    const std::string intro = "of the uniform in-plane stress of the flat superposed on the contact's stresses (a "
                              "fretting-fatigue specimen's bending or tension)";
    for (const std::string component : {"xx", "yy", "xy"})
      {
        specs.push_back(Spec::real_range("Bulk stress/Static " + component, "0",
                                         "Static part of sigma_" + component + " " + intro +
                                           ", at the surface, tension positive [Pa].",
                                         -1e12, 1e12));
        specs.push_back(Spec::real_range("Bulk stress/Static gradient " + component, "0",
                                         "Change of the static sigma_" + component +
                                           " per metre of depth into the flat (bending: -2 times the surface "
                                           "value over the specimen's thickness) [Pa/m].",
                                         -1e16, 1e16));
        specs.push_back(Spec::real_range("Bulk stress/Amplitude " + component, "0",
                                         "Cyclic amplitude of sigma_" + component + " at the surface, varying as "
                                           "sin(2 pi t / period + phase) with the sliding's period [Pa].",
                                         -1e12, 1e12));
        specs.push_back(Spec::real_range("Bulk stress/Amplitude gradient " + component, "0",
                                         "Change of the amplitude of sigma_" + component +
                                           " per metre of depth [Pa/m].",
                                         -1e16, 1e16));
      }
    specs.push_back(Spec::real_range("Bulk stress/Phase", "0",
                                     "Phase of the cyclic bulk stress relative to the sliding, delta(t) = amplitude "
                                     "sin(2 pi t / period); 0: in phase, as in a rig where one actuator drives both "
                                     "[rad].",
                                     -7, 7));
    return specs;
  }

  std::vector<app::ParameterSpec> ConcentratedContactScene::numerics_parameter_specs()
  {
    using Spec = app::ParameterSpec;
    std::vector<Spec> specs;
    specs.push_back(Spec::integer_range("Grid/Cells x", "128", "Number of grid cells in x [-].", 8, 4096));
    specs.push_back(Spec::integer_range("Grid/Cells y", "128", "Number of grid cells in y [-].", 8, 4096));
    specs.push_back(Spec::real_range("Grid/Half width factor", "1.5",
                                     "Half width of the grid in each direction, in units of the Hertz semi-axis in "
                                     "that direction [-].", 1, 100, true));
    specs.push_back(fft_plans_parameter("Grid/FFT plans"));
    specs.push_back(Spec::selection("Normal contact/Pressure model", "hertz",
                                    "hertz: the analytic Hertz pressure sampled at cell centres, the exact solution "
                                    "for the scene's gap of two radii; numerical: the elastic half-space solution on "
                                    "the grid (Polonsky-Keer CG with DC-FFT), whose cells at the contact edge carry "
                                    "the grid's error into the edge's risk (paper case 1.019 instead of 1.005 on "
                                    "128^2 cells, 1.004 instead of 1.001 on 256^2).",
                                    "hertz|numerical"));
    specs.push_back(Spec::real_range("Normal contact/Tolerance", "1e-10",
                                     "Relative gap error at which the normal solver stops [-].", 0, 1e-2, true));
    specs.push_back(Spec::integer_range("Normal contact/Maximum iterations", "5000",
                                        "Iteration limit of the normal solver [-].", 1, 10000000));
    specs.push_back(Spec::selection("Stresses/Evaluator", "fft",
                                    "How the subsurface stresses of the surface loads are summed: fft (DC-FFT, "
                                    "equal to direct summation to round-off, the fastest), mlmi (multilevel "
                                    "multi-integration, error ~1e-4 p0), direct (O(N^2) reference, slow beyond "
                                    "64 x 64 cells). `fretsim bench stresses` reports error against run time.",
                                    "fft|mlmi|direct"));
    {
      auto depths = Spec::non_negative("Stresses/Depth layers", "0, 3.75e-5, 7.5e-5, 1.5e-4, 3.6e-4",
                                       "Depths z below the surface of the lower body at which the full stress "
                                       "tensor is evaluated, comma-separated; 0 is on the surface [m].");
      depths.kind       = Spec::Kind::real_list;
      depths.increasing = true;
      specs.push_back(depths);
    }
    specs.push_back(Spec::integer_range("Stresses/MLMI levels", "0",
                                        "Coarse levels of the MLMI evaluator; 0 chooses them from the grid [-].", 0,
                                        20));
    specs.push_back(Spec::integer_range("Stresses/MLMI order", "6",
                                        "Even order of the Lagrange interpolation between MLMI levels; the error "
                                        "falls with the order [-].", 2, 12));
    specs.push_back(Spec::positive("Dang Van/Bending fatigue limit", "690e6",
                                   "Fully reversed bending (or tension-compression) fatigue limit f-1 of the lower "
                                   "body's material [Pa]."));
    specs.push_back(Spec::positive("Dang Van/Torsion fatigue limit", "428e6",
                                   "Fully reversed torsion fatigue limit t-1 [Pa]; alpha = 3 (t-1/f-1 - 1/2) and "
                                   "beta = t-1, with f-1/2 <= t-1 <= f-1."));
    specs.push_back(Spec::selection("Dang Van/Residual stress", "running_mean",
                                    "Centre of the deviatoric stress path that gives the stabilised residual "
                                    "stress: running_mean (paper eq. 5, the mean over all steps so far), "
                                    "last_cycle_mean (the mean over the last complete cycle), hypersphere (Dang "
                                    "Van's minimum circumscribed hypersphere of the last complete cycle).",
                                    "running_mean|last_cycle_mean|hypersphere"));
    specs.push_back(Spec::integer_range("Dang Van/Warm-up cycles", "0",
                                        "Cycles before the maximum risk starts to accumulate; 0 counts every step, "
                                        "as the paper does (the per-cycle centres need at least 1) [-].", 0,
                                        100000));
    specs.push_back(Spec::integer_range("Output/Field snapshots per cycle", "20",
                                        "Field snapshots (pressure, shear, effective friction, slip and the "
                                        "Dang Van risk on the depth layers; with Output/Stress snapshots the "
                                        "stress tensor too) written per cycle [-].", 0, 1000000));
    specs.push_back(Spec::selection("Output/Stress snapshots", "false",
                                    "true: each field snapshot also holds the stress tensor on every depth layer "
                                    "(/fields/stress, 6 values a point: six times the risk's size, 79 of the 95 MB "
                                    "of the paper case's results.h5 with 20 snapshots, and most of its writing "
                                    "time); false: the risk only, which the figures and risk_max need.",
                                    "true|false"));
    specs.push_back(Spec::integer_range("Output/Field output cycles", "1",
                                        "Snapshots are written for this many final cycles [-].", 0, 100000));
    specs.push_back(Spec::selection("Convergence/Risk error estimate", "true",
                                    "true: after the run, the same history on grids of 2 and 4 times the cell size "
                                    "(and the coarsest at half the time step) gives risk_max_converged, the limit of "
                                    "zero cell size and time step (the contact edge's D_max where it is evaluated "
                                    "and the hot spot, else by Richardson extrapolation), and "
                                    "risk_max_error_estimate, its error bar (the reruns cost stage_times_s.risk_error_estimate). Needs "
                                    "Cells x and Cells y divisible by 4 and at least 32.",
                                    "true|false"));
    return specs;
  }

  // The largest arrays grow with the grid (Cells x × Cells y) times the depth
  // layers, the results with the field snapshots.
  ResourceEstimate ConcentratedContactScene::estimate_resources(const app::SceneParameters &p)
  {
    const double cells  = double(p.get_integer("Grid/Cells x")) * double(p.get_integer("Grid/Cells y"));
    const double layers = double(p.get_double_list("Stresses/Depth layers").size());
    const double steps_per_cycle = double(p.get_integer("Loading/Steps per cycle"));
    const double steps           = double(p.get_integer("Loading/Cycles")) * steps_per_cycle;
    const double snapshots =
      double(p.get_integer("Output/Field snapshots per cycle")) * double(p.get_integer("Output/Field output cycles"));
    // Per grid cell and depth layer: the stress evaluator's kernel spectra
    // (3 loads × 6 components on the 2nx × 2ny padded grid, ~580 B), the
    // stress fields (3 × 6 doubles), the Dang Van state (13 doubles) and a
    // snapshot's staging (6 doubles): ~900 B. Per cell: the normal and
    // traction solvers' fields and kernels, ~600 B. The process itself
    // (libraries) ~150 MB. The paper case's peak against this estimate:
    // 377/413 MB at 128², 0.90/1.2 GB at 256², 1.51/2.3 GB at 512².
    ResourceEstimate estimate;
    double           per_point = 900.0;
    std::string      path_note;
    if (p.get("Dang Van/Residual stress") == "hypersphere")
      {
        // The hypersphere keeps the deviatoric path of the last cycle.
        per_point += 40.0 * steps_per_cycle;
        path_note = ", the hypersphere's path of " + std::to_string(long(steps_per_cycle)) +
                    " steps per cycle (Dang Van/Residual stress)";
      }
    // The superposition keeps two fields per virgin level, a quarter cycle's
    // steps' worth of levels.
    const bool   masing       = p.get("Friction/Traction model") == "exact masing";
    const double levels       = steps_per_cycle / 4.0 + 1.0;
    double       virgin_bytes = masing ? cells * 16.0 * levels : 0.0;
    if (masing)
      {
        // The stresses of the levels and of two reversals on every layer,
        // kept while they fit the run's budget (FrettingCase::superposition_budget):
        // on the rows y >= 0 only when the history is mirror-symmetric
        // (contact::mirror_symmetric).
        bool mirrored = std::abs(std::sin(p.get_double("Loading/Sliding direction"))) <= 1e-15 &&
                        p.get("Stresses/Evaluator") != "mlmi";
        for (const char *part : {"Static xy", "Static gradient xy", "Amplitude xy", "Amplitude gradient xy"})
          mirrored = mirrored && p.get_double(std::string("Bulk stress/") + part) == 0.0;
        const double level_stresses = (levels + 2.0) * layers * 6.0 * cells * 8.0 * (mirrored ? 0.5 : 1.0);
        virgin_bytes += level_stresses <= 512.0 * 1024 * 1024 ? level_stresses : 0.0;
        path_note += ", the superposition's " + std::to_string(long(levels)) +
                     " virgin levels and their stresses (Loading/Steps per cycle / 4)";
        // A circular contact's edge risk keeps the kernel spectra of one more
        // (surface) layer.
        if (p.get_double("Geometry/Radius x") == p.get_double("Geometry/Radius y"))
          virgin_bytes += 580.0 * cells;
      }
    // The error estimate reruns the history on a quarter of the cells while
    // the run's own state is still held: 1.25 times the run.
    const double estimate_factor = p.get_bool("Convergence/Risk error estimate") ? 1.25 : 1.0;
    estimate.memory_bytes =
      150e6 + estimate_factor * (cells * (600.0 + per_point * layers) + virgin_bytes);
    estimate.memory_basis = "Grid/Cells x × Grid/Cells y = " + std::to_string(p.get_integer("Grid/Cells x")) +
                            " × " + std::to_string(p.get_integer("Grid/Cells y")) + " cells on " +
                            std::to_string(long(layers)) + " Stresses/Depth layers" + path_note;
    // results.h5: one row of 9 series per step, and per snapshot 5 surface
    // fields, the risk and (if asked for) the stress tensor on every layer;
    // figures ~5 MB.
    const double snapshot_bytes =
      8.0 * cells * (5.0 + (p.get_bool("Output/Stress snapshots") ? 7.0 : 1.0) * layers);
    estimate.disk_bytes         = 5e6 + 80.0 * (steps + 1.0) + snapshots * snapshot_bytes + 8.0 * cells * layers;
    estimate.disk_basis = std::to_string(long(snapshots)) +
                          " field snapshots (Output/Field snapshots per cycle × Output/Field output cycles) of " +
                          app::format_bytes(snapshot_bytes) + " each, and " + std::to_string(long(steps)) +
                          " steps (Loading/Cycles × Loading/Steps per cycle)";
    return estimate;
  }

  double ConcentratedContactScene::HertzSummary::equivalent_radius() const
  {
    return std::sqrt(semi_axis_x * semi_axis_y);
  }

  ConcentratedContactScene::ConcentratedContactScene(app::SceneParameters parameters_)
    : parameters(std::move(parameters_))
  {
    read_settings();
    const auto  &s               = settings;
    const double contact_modulus = s.materials.contact_modulus();
    if (s.radius_x == s.radius_y)
      {
        const auto h = contact::HertzCircular::solve(s.normal_load, s.radius_x, contact_modulus);
        hertz        = {h.contact_radius, h.contact_radius, h.peak_pressure, h.approach, true};
      }
    else
      {
        const auto h = contact::HertzElliptical::solve(s.normal_load, s.radius_x, s.radius_y, contact_modulus);
        hertz        = {h.semi_axis_x, h.semi_axis_y, h.peak_pressure, h.approach, false};
      }
    grid = contact::SurfaceGrid::centred(s.cells_x, s.cells_y, s.half_width_factor * hertz.semi_axis_x,
                                         s.half_width_factor * hertz.semi_axis_y);
    build_stress_evaluator();

    auto &c                = fretting_case;
    c.materials            = s.materials;
    c.radius_x             = s.radius_x;
    c.radius_y             = s.radius_y;
    c.normal_load          = s.normal_load;
    c.sliding_amplitude    = s.sliding_amplitude;
    c.sliding_direction    = s.sliding_direction;
    c.period               = s.period;
    c.cycles               = s.cycles;
    c.steps_per_cycle      = s.steps_per_cycle;
    c.friction_coefficient = s.friction_coefficient;
    c.traction_model       = contact::parse_traction_model(s.traction_model);
    c.bristle_stiffness =
      (s.bristle_stiffness > 0.0 ? s.bristle_stiffness : calibrated_bristle_stiffness()) * s.bristle_stiffness_factor;
    c.exact.tolerance       = s.exact_tolerance;
    c.exact.measure_fft_plans = s.stress_evaluator.measure_fft_plans;
    // The virgin levels of the Masing superposition as fine as a quarter
    // cycle's steps, uniform in the shift (the time-step study refines both).
    c.exact.masing_level_spacing = s.sliding_amplitude / (0.25 * s.steps_per_cycle);
    c.numerical_pressure    = s.pressure_model == "numerical";
    c.normal                = {s.normal_tolerance, s.normal_max_iterations};
    c.stress_evaluator      = s.stress_evaluator;
    c.depth_layers          = s.depth_layers;
    c.residual_stress       = contact::parse_residual_stress_centre(s.residual_stress);
    c.warmup_cycles         = s.warmup_cycles;
  }

  ConcentratedContactScene::~ConcentratedContactScene() = default;

  double ConcentratedContactScene::calibrated_bristle_stiffness() const
  {
    return contact::BristleTraction::mindlin_stiffness(settings.materials.tangential_modulus(),
                                                       hertz.equivalent_radius());
  }

  void ConcentratedContactScene::build_stress_evaluator()
  {
    const auto &s = settings;
    if (s.depth_layers.empty())
      parameters.reject("Stresses/Depth layers", "expected at least one depth z >= 0 [m] (0 is the surface), got none");
    try
      {
        stresses = contact::make_subsurface_stress(grid, s.depth_layers, s.materials.lower.poisson_ratio,
                                                   s.stress_evaluator);
      }
    catch (const std::invalid_argument &error)
      {
        // Settings the patterns cannot judge alone (MLMI levels too deep for
        // the grid, an odd order) come back from the evaluator.
        parameters.reject(s.stress_evaluator.method == "mlmi" ? "Stresses/MLMI levels" : "Stresses/Evaluator",
                          error.what());
      }
  }

  void ConcentratedContactScene::read_settings()
  {
    const auto &p = parameters;
    auto       &s = settings;
    s.materials.lower          = {p.get_double("Materials/Lower body/Young's modulus"),
                                  p.get_double("Materials/Lower body/Poisson ratio")};
    s.materials.upper          = {p.get_double("Materials/Upper body/Young's modulus"),
                                  p.get_double("Materials/Upper body/Poisson ratio")};
    s.radius_x                 = p.get_double("Geometry/Radius x");
    s.radius_y                 = p.get_double("Geometry/Radius y");
    s.normal_load              = p.get_double("Loading/Normal load");
    s.sliding_amplitude        = p.get_double("Loading/Sliding amplitude");
    s.sliding_direction        = p.get_double("Loading/Sliding direction");
    s.period                   = p.get_double("Loading/Period");
    s.cycles                   = static_cast<int>(p.get_integer("Loading/Cycles"));
    s.steps_per_cycle          = static_cast<int>(p.get_integer("Loading/Steps per cycle"));
    s.friction_coefficient     = p.get_double("Friction/Friction coefficient");
    s.bristle_stiffness        = p.get_double("Friction/Bristle stiffness");
    s.bristle_stiffness_factor = p.get_double("Friction/Bristle stiffness factor");
    s.slip_tolerance           = p.get_double("Friction/Slip tolerance");
    s.traction_model           = p.get("Friction/Traction model");
    s.exact_tolerance          = p.get_double("Friction/Exact solver tolerance");
    s.cells_x                  = static_cast<int>(p.get_integer("Grid/Cells x"));
    s.cells_y                  = static_cast<int>(p.get_integer("Grid/Cells y"));
    s.half_width_factor        = p.get_double("Grid/Half width factor");
    s.pressure_model           = p.get("Normal contact/Pressure model");
    s.normal_tolerance         = p.get_double("Normal contact/Tolerance");
    s.normal_max_iterations    = static_cast<int>(p.get_integer("Normal contact/Maximum iterations"));
    s.snapshots_per_cycle      = static_cast<int>(p.get_integer("Output/Field snapshots per cycle"));
    s.snapshot_cycles          = static_cast<int>(p.get_integer("Output/Field output cycles"));
    s.stress_snapshots         = p.get_bool("Output/Stress snapshots");
    s.stress_evaluator.method      = p.get("Stresses/Evaluator");
    s.stress_evaluator.measure_fft_plans = p.get("Grid/FFT plans") == "measure";
    s.yield_strength               = p.get_double("Materials/Lower body/Yield strength");
    read_bulk_stress();
    s.stress_evaluator.mlmi_levels = static_cast<int>(p.get_integer("Stresses/MLMI levels"));
    s.stress_evaluator.mlmi_order  = static_cast<int>(p.get_integer("Stresses/MLMI order"));
    s.depth_layers                 = p.get_double_list("Stresses/Depth layers");
    s.bending_fatigue_limit = p.get_double("Dang Van/Bending fatigue limit");
    s.torsion_fatigue_limit = p.get_double("Dang Van/Torsion fatigue limit");
    s.residual_stress       = p.get("Dang Van/Residual stress");
    s.warmup_cycles         = static_cast<int>(p.get_integer("Dang Van/Warm-up cycles"));
    s.estimate_risk_error   = p.get_bool("Convergence/Risk error estimate");
    if (s.estimate_risk_error)
      for (const auto &[name, cells] : {std::pair<std::string, int>{"Grid/Cells x", s.cells_x}, {"Grid/Cells y", s.cells_y}})
        if (cells % 4 != 0 || cells < 32)
          p.reject(name, "expected a multiple of 4 of at least 32 with 'Convergence/Risk error estimate' = true (the "
                         "error estimate reruns on grids of a half and a quarter of the cells), got " +
                           std::to_string(cells));
    try
      {
        fretting_case.dang_van =
          contact::DangVanConstants::from_fatigue_limits(s.bending_fatigue_limit, s.torsion_fatigue_limit);
      }
    catch (const std::invalid_argument &error)
      {
        p.reject("Dang Van/Torsion fatigue limit", error.what());
      }
    if (s.residual_stress != "running_mean" && s.cycles < 2)
      p.reject("Loading/Cycles", "expected at least 2 with 'Dang Van/Residual stress' = " + s.residual_stress +
                                   " (the first cycle only defines the centre), got " + std::to_string(s.cycles));
    if (s.warmup_cycles >= s.cycles)
      p.reject("Dang Van/Warm-up cycles", "expected fewer than 'Loading/Cycles' (" + std::to_string(s.cycles) +
                                            "), got " + std::to_string(s.warmup_cycles));
    if (s.stress_evaluator.mlmi_order % 2 != 0)
      p.reject("Stresses/MLMI order", "expected an even order from 2 to 12, got " +
                                        std::to_string(s.stress_evaluator.mlmi_order));

    if (s.snapshots_per_cycle > s.steps_per_cycle || (s.snapshots_per_cycle > 0 && s.steps_per_cycle % s.snapshots_per_cycle != 0))
      p.reject("Output/Field snapshots per cycle",
               "expected a divisor of 'Loading/Steps per cycle' (" + std::to_string(s.steps_per_cycle) + "), got " +
                 std::to_string(s.snapshots_per_cycle));
    if (s.snapshot_cycles > s.cycles)
      p.reject("Output/Field output cycles", "expected at most 'Loading/Cycles' (" + std::to_string(s.cycles) +
                                               "), got " + std::to_string(s.snapshot_cycles));
    const double total_steps = static_cast<double>(s.cycles) * s.steps_per_cycle;
    if (total_steps > 1e8)
      p.reject("Loading/Cycles", "Cycles × Steps per cycle must stay below 1e8, got " + std::to_string(total_steps));
    const double bristle_stiffness = s.bristle_stiffness * s.bristle_stiffness_factor;
    if (!std::isfinite(bristle_stiffness))
      p.reject("Friction/Bristle stiffness factor", "the scaled bristle stiffness overflows");
  }

  void ConcentratedContactScene::read_bulk_stress()
  {
    auto &bulk = fretting_case.bulk_stress;
    const std::array<std::string, 3> components{"xx", "yy", "xy"};
    for (int k = 0; k < 3; ++k)
      {
        bulk.static_surface[k]     = parameters.get_double("Bulk stress/Static " + components[k]);
        bulk.static_gradient[k]    = parameters.get_double("Bulk stress/Static gradient " + components[k]);
        bulk.amplitude_surface[k]  = parameters.get_double("Bulk stress/Amplitude " + components[k]);
        bulk.amplitude_gradient[k] = parameters.get_double("Bulk stress/Amplitude gradient " + components[k]);
      }
    bulk.phase = parameters.get_double("Bulk stress/Phase");
  }

  namespace
  {
    /// results.h5 of the concentrated scene: the grid, one series row per step
    /// and the field snapshots of the last cycles.
    class ConcentratedResults
    {
    public:
      ConcentratedResults(const std::string &file, const std::string &parameters_prm, const contact::SurfaceGrid &grid,
                          const std::vector<double> &depth_layers, double contact_radius, bool with_stress)
        : results(file, "concentrated", parameters_prm)
        , stress_fields(with_stress)
      {
        write_surface_grid(results, grid, depth_layers);
        results.set_root_attribute("contact_radius_m", contact_radius);
        for (const auto &[name, unit] : std::vector<std::pair<std::string, std::string>>{
               {"time", "s"}, {"cycle", "1"}, {"displacement_x", "m"}, {"displacement_y", "m"},
               {"tangential_force_x", "N"}, {"tangential_force_y", "N"}, {"normal_force", "N"},
               {"tangential_force_mindlin_x", "N"}, {"slip_area_fraction", "1"}})
          results.declare_series(name, unit);
        field_shape = {static_cast<std::size_t>(grid.ny), static_cast<std::size_t>(grid.nx)};
        for (const auto &[name, unit] : std::vector<std::pair<std::string, std::string>>{
               {"pressure", "Pa"}, {"shear_x", "Pa"}, {"shear_y", "Pa"}, {"effective_friction", "1"}, {"slip", "1"}})
          results.declare_field(name, unit, field_shape);
        layers = depth_layers.size();
        // The stresses and risk are dense below the surface: deflate would
        // take most of the writing time for a third off their size.
        if (stress_fields)
          {
            results.declare_field("stress", "Pa",
                                  {layers, std::size_t(contact::stress_component_count), field_shape[0], field_shape[1]},
                                  false);
            results.set_root_attribute("stress_components", "xx, yy, zz, yz, xz, xy (tension positive, lower body)");
          }
        results.declare_field("risk", "1", {layers, field_shape[0], field_shape[1]}, false);
      }

      void append_row(const std::vector<double> &row) { results.append_series_row(row); }

      void append_snapshot(double time, const contact::FrettingRun &run, double slip_tolerance)
      {
        const contact::Field effective_friction = run.traction().effective_friction();
        contact::Field       slip               = run.grid().zeros();
        for (std::size_t c = 0; c < slip.size(); ++c)
          slip[c] = run.pressure()[c] > 0.0 && effective_friction[c] >= 1.0 - slip_tolerance ? 1.0 : 0.0;
        std::vector<const std::vector<double> *> fields{&run.pressure(), &run.traction().traction_x(),
                                                        &run.traction().traction_y(), &effective_friction, &slip};
        if (stress_fields)
          fields.push_back(&run.stress().values);
        fields.push_back(&run.risk_now());
        results.append_snapshot(time, fields);
      }

      void flush() { results.flush(); }

      void close(const std::vector<double> &risk_max, bool completed, const std::string &xdmf_file)
      {
        results.write_dataset("/fields/risk_max", "1", {layers, field_shape[0], field_shape[1]}, risk_max);
        results.set_root_attribute("status", completed ? "complete" : "interrupted");
        results.flush();
        results.write_xdmf(xdmf_file);
      }

    private:
      output::ResultsFile      results;
      bool                     stress_fields;
      std::vector<std::size_t> field_shape;
      std::size_t              layers = 0;
    };
  } // namespace

  /// The reruns of the error estimate: the cases and (case, cells x, cells
  /// y) of each, worked through by threads that take the next run as they
  /// come free, each run on one core, so that its digits do not depend on how
  /// the runs share the machine.
  struct ConcentratedContactScene::RiskReruns
  {
    contact::FrettingCase coarse, finer_in_time, check, check_exact;
    std::vector<std::tuple<const contact::FrettingCase *, int, int>> runs;
    /// The model's side of the traction check is the coarsest run's history
    /// cut short: that run's D_max after check.cycles cycles, read as it
    /// passes them, goes to risk[check_slot] (no run of its own).
    std::size_t  check_source = 0, check_slot = 0;
    std::int64_t check_step   = -1; ///< -1: the check runs on its own
    double                   half_width_factor = 1.5;
    bool                     check_model       = false;
    std::vector<double>      risk;
    std::vector<double>      edge_risk; ///< the runs' D_max on the contact edge, NaN where not evaluated
    std::vector<double>      below_risk; ///< and their grid's D_max below the surface (risk_below_surface)
    std::vector<std::string> failure;
    std::atomic<std::size_t> next{0};
    std::atomic<std::size_t> working{0}; ///< threads still on the runs
    std::atomic<bool>        cancelled{false}; ///< the run was interrupted: stop
    std::vector<std::thread> threads;
    Clock::time_point        start;
    /// The history, whose virgin levels' stress evaluations the threads take
    /// between their steps (FrettingRun::defer_level_stresses): the history's
    /// core then only solves its levels' tractions, one after the other.
    std::mutex                   helped_mutex;
    const contact::FrettingRun  *helped = nullptr;

    /// Sets (or with nullptr ends, waiting for an evaluation under way) the
    /// history the threads help.
    void help(const contact::FrettingRun *history)
    {
      std::lock_guard<std::mutex> lock(helped_mutex);
      helped = history;
    }

    void work()
    {
      omp_set_num_threads(1);
      struct Leaving
      {
        std::atomic<std::size_t> &count;
        ~Leaving() { --count; }
      } leaving{working};
      for (std::size_t k = next++; k < runs.size(); k = next++)
        try
          {
            const auto &[fretting_case, cells_x, cells_y] = runs[k];
            contact::FrettingRun run(*fretting_case,
                                     contact::fretting_grid(*fretting_case, cells_x, cells_y, half_width_factor));
            while (!run.finished() && !cancelled)
              {
                {
                  std::lock_guard<std::mutex> lock(helped_mutex);
                  if (helped)
                    helped->help_with_level_stresses();
                }
                run.advance();
                if (k == check_source && run.steps_done() == check_step)
                  risk[check_slot] = run.risk_maximum().value;
              }
            risk[k] = run.risk_maximum().value;
            if (const auto edge = run.edge_risk_maximum())
              {
                edge_risk[k] = edge->value;
                below_risk[k] = risk_below_surface(run, fretting_case->depth_layers).value;
              }
          }
        catch (const std::exception &error)
          {
            failure[k] = error.what();
          }
    }

    /// Up to `count` more threads on the runs not yet taken.
    void add_threads(std::size_t count)
    {
      if (threads.empty())
        start = Clock::now();
      for (std::size_t t = 0; t < count && threads.size() < runs.size(); ++t)
        {
          ++working;
          threads.emplace_back([this] { work(); });
        }
    }

    /// Waits for every run; throws if one failed.
    void join()
    {
      for (auto &thread : threads)
        thread.join();
      threads.clear();
      for (const auto &message : failure)
        if (!message.empty())
          throw std::runtime_error("risk error estimate: " + message);
    }

    ~RiskReruns()
    {
      // The run interrupted, or an exception on its way out of run(): the
      // threads stop at their next step.
      cancelled = true;
      next      = runs.size();
      for (auto &thread : threads)
        if (thread.joinable())
          thread.join();
    }
  };

  ConcentratedContactScene::History ConcentratedContactScene::simulate(contact::FrettingRun &run,
                                                                       const RunOptions    &options,
                                                                       const std::string   &results_file,
                                                                       const RiskReruns    *reruns) const
  {
    const auto     &s = settings;
    const auto     &grid_ = run.grid();
    History         history{contact::FrettingLoop(s.steps_per_cycle), std::nullopt, 0.0};
    const double    mu_P = s.friction_coefficient * s.normal_load;
    const double    tangential_modulus = s.materials.tangential_modulus();
    if (mu_P > 0.0)
      history.mindlin.emplace(s.friction_coefficient, s.normal_load, hertz.equivalent_radius(), tangential_modulus);

    double contact_area = 0.0;
    for (const double value : run.pressure())
      contact_area += value > 0.0 ? grid_.cell_area() : 0.0;
    history.contact_radius = std::sqrt(contact_area / M_PI);
    std::optional<ConcentratedResults> results;
    if (options.files)
      results.emplace(results_file, parameters.to_prm(), grid_, s.depth_layers, history.contact_radius,
                      s.stress_snapshots);

    const double direction_x = std::cos(s.sliding_direction), direction_y = std::sin(s.sliding_direction);
    const int    snapshot_interval   = s.snapshots_per_cycle > 0 ? s.steps_per_cycle / s.snapshots_per_cycle : 0;
    const long   first_snapshot_step = static_cast<long>(s.cycles - s.snapshot_cycles) * s.steps_per_cycle + 1;
    const double time_step           = s.period / s.steps_per_cycle;
    // One series row; returns the force along the sliding for the loop.
    auto write_row = [&](long step, double displacement, double reference_force) {
      const double force_x = contact::integrate(grid_, run.traction().traction_x());
      const double force_y = contact::integrate(grid_, run.traction().traction_y());
      const double slip_fraction =
        contact::slip_area_fraction(run.traction().effective_friction(), run.pressure(), s.slip_tolerance);
      history.slip_area_fraction_max = std::max(history.slip_area_fraction_max, step > 0 ? slip_fraction : 0.0);
      if (results)
        results->append_row({step * time_step, static_cast<double>((step + s.steps_per_cycle - 1) / s.steps_per_cycle),
                          displacement * direction_x, displacement * direction_y, force_x, force_y, s.normal_load,
                          reference_force * direction_x, slip_fraction});
      return force_x * direction_x + force_y * direction_y;
    };

    app::Progress progress("concentrated contact", run.total_steps(), options.progress);
    history.loop.add(0.0, write_row(0, 0.0, 0.0));
    if (results)
      results->flush();
    // The run's threads: the cores the reruns leave, so that no core has two
    // threads (an OpenMP thread waiting for work spins for a while, taking
    // the core from a rerun).
    const int cores = omp_get_max_threads();
    while (!run.finished() && !app::interrupt_requested())
      {
        if (reruns)
          omp_set_num_threads(std::max(1, cores - static_cast<int>(reruns->working.load())));
        run.advance();
        const long step            = run.steps_done();
        const bool reversed_before = (step - 1) * time_step >= 0.25 * s.period * (1.0 - 1e-12);
        const double reference_force =
          history.mindlin ? contact::FrettingLoop::reference_force(*history.mindlin, s.sliding_amplitude,
                                                                   run.displacement(), run.previous_displacement(),
                                                                   reversed_before) :
                            0.0;
        history.loop.add(run.displacement(), write_row(step, run.displacement(), reference_force));
        if (results && snapshot_interval > 0 && step >= first_snapshot_step && step % snapshot_interval == 0)
          results->append_snapshot(run.time(), run, s.slip_tolerance);
        if (results)
          results->flush();
        progress.update(step, run.time());
      }
    if (reruns)
      omp_set_num_threads(cores);
    progress.finish();
    history.completed = run.finished();
    if (results)
      results->close(run.risk_max(), history.completed,
                     (std::filesystem::path(options.output_directory) / "results.xdmf").string());
    return history;
  }

  std::unique_ptr<ConcentratedContactScene::RiskReruns> ConcentratedContactScene::risk_reruns() const
  {
    // The same history on the grids of 2 and 4 times the spacing (the grid's
    // half-widths are kept), and on the coarsest grid with half the time step
    // for the time error; with a model other than exact, the model and the
    // incremental exact solver over the same first cycles on the coarsest grid.
    const auto &s      = settings;
    auto        reruns = std::make_unique<RiskReruns>();
    auto       &r      = *reruns;
    // Short runs: FFTW's estimated plans (measuring costs more than these runs
    // save, and estimated plans give the same digits in every process).
    r.coarse                                    = fretting_case;
    r.coarse.exact.measure_fft_plans            = false;
    r.coarse.stress_evaluator.measure_fft_plans = false;
    r.finer_in_time = r.coarse;
    r.finer_in_time.steps_per_cycle *= 2;
    // The masing traction's virgin levels are as fine as the steps: refined with them.
    r.finer_in_time.exact.masing_level_spacing /= 2.0;
    // Both models over the same short history: the running-mean risk peaks in
    // the first cycle, and the comparison needs only the same history.
    r.check               = r.coarse;
    r.check.cycles        = std::min(r.check.cycles, 2);
    r.check.warmup_cycles = std::min(r.check.warmup_cycles, r.check.cycles - 1);
    r.check_exact                = r.check;
    r.check_exact.traction_model = contact::TractionModel::exact;

    const int quarter_x = s.cells_x / 4, quarter_y = s.cells_y / 4;
    // The longest first: the threads that take them finish together.
    r.runs = {{&r.coarse, s.cells_x / 2, s.cells_y / 2}, {&r.finer_in_time, quarter_x, quarter_y},
              {&r.coarse, quarter_x, quarter_y}};
    r.check_model = fretting_case.traction_model != contact::TractionModel::exact;
    if (r.check_model)
      {
        r.runs.emplace_back(&r.check_exact, quarter_x, quarter_y);
        // The check's model run is the coarsest run's first cycles when both
        // count D_max from the same step: D_max only grows, and a run's steps
        // do not depend on how many follow, so its value is the same to the
        // last digit.
        if (r.check.warmup_cycles == r.coarse.warmup_cycles)
          {
            r.check_source = 2;
            r.check_slot   = 4;
            r.check_step   = static_cast<std::int64_t>(r.check.cycles) * r.check.steps_per_cycle;
          }
        else
          r.runs.emplace_back(&r.check, quarter_x, quarter_y);
      }
    r.half_width_factor = s.half_width_factor;
    r.risk.assign(r.check_model ? 5 : 3, 0.0); // [3]: the check's exact run, [4]: its model's D_max
    r.edge_risk.assign(r.risk.size(), std::numeric_limits<double>::quiet_NaN());
    r.below_risk = r.edge_risk;
    r.failure.assign(r.runs.size(), std::string());
    return reruns;
  }

  ConcentratedContactScene::RiskConvergence
  ConcentratedContactScene::risk_convergence(const RiskReruns &r, const contact::FrettingRun &finest) const
  {
    const auto     &s = settings;
    RiskConvergence convergence;
    convergence.cells = {s.cells_x / 4, s.cells_x / 2, s.cells_x};
    convergence.risk  = {r.risk[2], r.risk[0], finest.risk_maximum().value};
    if (const auto edge = finest.edge_risk_maximum();
        edge && std::isfinite(r.edge_risk[0]) && std::isfinite(r.edge_risk[1]) && std::isfinite(r.edge_risk[2]))
      {
        RiskConvergence::EdgeStudy study;
        study.below_maximum             = risk_below_surface(finest, fretting_case.depth_layers);
        study.edge                      = {r.edge_risk[2], r.edge_risk[0], edge->value};
        study.below                     = {r.below_risk[2], r.below_risk[0], study.below_maximum.value};
        study.edge_time_step_correction = r.edge_risk[1] - r.edge_risk[2];
        study.below_time_step_correction = r.below_risk[1] - r.below_risk[2];
        study.below_grid = contact::richardson_estimate(study.below[2], study.below[1], study.below[0]);
        study.annulus_resolved =
          edge->on_edge || edge->slip_annulus >= 2.0 * std::max(finest.grid().hx, finest.grid().hy);
        convergence.edge = study;
      }
    // First order in the time step: the limit lies as far beyond the half
    // step as the half step lies beyond the full one.
    convergence.time_step_correction = r.risk[1] - r.risk[2];
    convergence.grid = contact::richardson_estimate(convergence.risk[2], convergence.risk[1], convergence.risk[0]);
    if (r.check_model)
      {
        convergence.model_and_exact_risk  = std::array<double, 2>{r.risk[4], r.risk[3]};
        convergence.traction_check_cycles = r.check.cycles;
      }
    return convergence;
  }

  RunReport ConcentratedContactScene::run(const RunOptions &options)
  {
    const auto run_start = Clock::now();
    RunReport  report;
    if (options.files)
      {
        std::filesystem::create_directories(options.output_directory);
        report.results_file = (std::filesystem::path(options.output_directory) / "results.h5").string();
        report.summary_file = (std::filesystem::path(options.output_directory) / "summary.json").string();
      }

    // The grid and time-step error of D_max comes from coarser runs of the
    // same history, independent of this run's: with two cores or more one
    // thread starts on them now and takes the core the history leaves idle
    // (its traction solves are serial), more join when the history is done.
    // A single thread (a map's point) runs them after the history.
    const std::size_t           cores = static_cast<std::size_t>(std::max(1, omp_get_max_threads()));
    std::unique_ptr<RiskReruns> reruns;
    if (settings.estimate_risk_error)
      {
        reruns = risk_reruns();
        if (cores > 1)
          reruns->add_threads(1);
      }
    // 1. Normal contact, on the grid of the run.
    contact::FrettingRun run(fretting_case, grid, std::move(stresses));
    // The reruns' thread evaluates the history's level stresses; it stops
    // before the history goes (a throw included).
    struct StopHelping
    {
      RiskReruns *reruns;
      ~StopHelping()
      {
        if (reruns)
          reruns->help(nullptr);
      }
    } stop_helping{reruns && cores > 1 ? reruns.get() : nullptr};
    if (stop_helping.reruns)
      {
        run.defer_level_stresses(true);
        reruns->help(&run);
      }
    // 2. The sliding cycles: traction, stresses and Dang Van every step,
    //    results.h5 growing step by step.
    const History history = simulate(run, options, report.results_file, reruns.get());
    if (stop_helping.reruns)
      {
        reruns->help(nullptr);
        stop_helping.reruns = nullptr;
      }
    report.completed      = history.completed;
    // 3. The error estimate's reruns finished, on every core.
    std::optional<RiskConvergence> convergence;
    double                         convergence_seconds = 0.0;
    if (reruns)
      {
        if (report.completed)
          {
            reruns->add_threads(cores);
            reruns->join();
            convergence_seconds = seconds_since(reruns->start);
            convergence         = risk_convergence(*reruns, run);
          }
        reruns.reset();
      }
    // 4. Summary and figures.
    const output::Summary summary =
      make_summary(run, history, convergence, convergence_seconds, seconds_since(run_start));
    report.numbers = key_numbers(run, history, convergence, seconds_since(run_start));
    report.labels["regime"] = regime(history);
    if (!options.files)
      return report;
    summary.write(report.summary_file);
    if (options.plots)
      report.figures = make_figures(options.output_directory);
    return report;
  }

  output::Summary ConcentratedContactScene::make_summary(const contact::FrettingRun            &run,
                                                         const History                         &history,
                                                         const std::optional<RiskConvergence>  &convergence,
                                                         double convergence_seconds, double wall_seconds) const
  {
    const auto     &s   = settings;
    const double    nan = std::numeric_limits<double>::quiet_NaN();
    const long long steps_done = run.steps_done();
    output::Summary summary;
    summary.set("scene", std::string("concentrated"));
    summary.set("config_file", parameters.file());
    summary.set("version", std::string(FRETSIM_VERSION));
    summary.set("status", std::string(history.completed ? "complete" : "interrupted"));
    summary.set("contact_radius_m", history.contact_radius);
    summary.set("hertz_contact_radius_m", hertz.equivalent_radius());
    summary.set("hertz_semi_axis_x_m", hertz.semi_axis_x);
    summary.set("hertz_semi_axis_y_m", hertz.semi_axis_y);
    summary.set("peak_pressure_Pa", max_of(run.pressure()));
    summary.set("hertz_peak_pressure_Pa", hertz.peak_pressure);
    summary.set("pressure_model", s.pressure_model);
    summary.set("normal_solver_iterations", static_cast<long long>(run.normal_iterations()));
    summary.set("traction_model", s.traction_model);
    summary.set("traction_seconds_per_step", steps_done > 0 ? run.stage_times().traction / steps_done : nan);
    if (run.traction().kind() == contact::TractionModel::exact || run.traction().kind() == contact::TractionModel::exact_masing)
      {
        summary.set("traction_iterations_per_step",
                    steps_done > 0 ? double(run.traction_iterations()) / steps_done : nan);
        summary.set("traction_iterations_max", static_cast<long long>(run.most_traction_iterations()));
      }
    summary.set("bristle_stiffness_Pa_per_m", fretting_case.bristle_stiffness);
    summary.set("mindlin_calibrated_stiffness_Pa_per_m", calibrated_bristle_stiffness());
    summary.set("stress_evaluator", run.stress_evaluator().name());
    summary.set("stress_evaluations", static_cast<long long>(steps_done + 1));
    add_risk(summary, run, convergence);
    summary.set("von_mises_max_Pa", run.von_mises_max());
    if (s.yield_strength > 0.0)
      {
        summary.set("yield_strength_Pa", s.yield_strength);
        summary.set("yield_margin", s.yield_strength / run.von_mises_max());
      }
    if (!fretting_case.bulk_stress.is_zero())
      summary.set("bulk_stress", std::string("superposed (Bulk stress section)"));
    summary.set("sliding_amplitude_m", s.sliding_amplitude);
    summary.set("cycles", static_cast<long long>(history.loop.complete_cycles()));
    summary.set("steps", steps_done);
    add_loop(summary, history);

    output::Summary stage_times;
    stage_times.set("normal_contact", run.stage_times().normal_contact);
    stage_times.set("traction", run.stage_times().traction);
    stage_times.set("stresses", run.stage_times().stresses);
    stage_times.set("dang_van", run.stage_times().dang_van);
    stage_times.set("risk_error_estimate", convergence_seconds);
    stage_times.set("total", wall_seconds);
    summary.set_object("stage_times_s", stage_times);
    summary.set("wall_time_s", wall_seconds);
    return summary;
  }

  void ConcentratedContactScene::add_risk(output::Summary &summary, const contact::FrettingRun &run,
                                          const std::optional<RiskConvergence> &convergence) const
  {
    const auto  &s      = settings;
    const auto   worst  = run.risk_maximum();
    const double x      = run.grid().x(worst.i), y = run.grid().y(worst.j), z = s.depth_layers[worst.layer];
    summary.set("risk_max", worst.value);
    summary.set("risk_max_location_m", std::vector<double>{x, y, z});
    summary.set("risk_max_depth_m", z);
    summary.set("risk_max_time_s", (worst.step + 1) * s.period / s.steps_per_cycle);
    const std::size_t infinite_max = run.infinite_risk_max_count();
    if (infinite_max > 0)
      std::cerr << "fretsim: warning: " << infinite_max << " of " << run.risk_max().size()
                << " points reached beta - alpha sigma_H <= 0 (hydrostatic tension beyond the Dang Van line): "
                   "their risk is infinite in /fields/risk_max and left out of risk_max\n";
    summary.set("risk_infinite_points", static_cast<long long>(infinite_max));
    summary.set("risk_mirrored", run.mirrored());
    summary.set("residual_stress_centre", s.residual_stress);
    const auto edge = run.edge_risk_maximum();
    if (edge)
      {
        summary.set("risk_max_edge", edge->value);
        summary.set("risk_max_edge_location_m", std::vector<double>{edge->x, edge->y, 0.0});
        summary.set("risk_max_edge_time_s", (edge->step + 1) * s.period / s.steps_per_cycle);
      }
    if (!convergence)
      return;
    const auto &c = *convergence;
    summary.set("risk_max_converged", c.converged());
    summary.set("risk_max_error_estimate", c.error_estimate());
    std::vector<double> where{x, y, z};
    if (c.edge)
      {
        const auto &below = c.edge->below_maximum;
        where = c.edge_interval().high >= c.below_interval().high ?
                  std::vector<double>{edge->x, edge->y, 0.0} :
                  std::vector<double>{run.grid().x(below.i), run.grid().y(below.j), s.depth_layers[below.layer]};
      }
    summary.set("risk_max_converged_location_m", where);
    output::Summary study;
    study.set("method",
              std::string(c.edge ?
                            "the larger of two limits: on the surface the D_max of the contact's fronts (its edge "
                            "and the stick zone's largest boundary; the square-root shapes in closed form, the rest "
                            "from the grid) on the finest grid, bar: its larger change over grids of 4h, 2h and h, "
                            "at least 0.5 %; below the surface the grid's D_max by Richardson extrapolation at "
                            "order 1/2; each plus its time step's first-order correction from the coarsest grid at "
                            "half the step, bar: twice that correction" :
                            "Richardson extrapolation over grids of 4h, 2h and h at the square-root edge's order "
                            "1/2, bar: the larger grid difference carried to the limit; plus the time step's "
                            "first-order correction from the coarsest grid at half the step, bar: twice that "
                            "correction"));
    study.set("hot_spot", c.hot_spot());
    study.set("cells_x", std::vector<double>(c.cells.begin(), c.cells.end()));
    study.set("risk_max", std::vector<double>(c.risk.begin(), c.risk.end()));
    study.set("grid_limit", c.grid.converged);
    study.set("grid_error_estimate", c.grid.error_estimate);
    study.set("observed_order", c.grid.observed_order);
    study.set("asymptotic", c.grid.asymptotic);
    study.set("time_step_correction", c.time_step_correction);
    if (c.edge)
      {
        study.set("surface_risk_max", std::vector<double>(c.edge->edge.begin(), c.edge->edge.end()));
        study.set("surface_time_step_correction", c.edge->edge_time_step_correction);
        study.set("surface_limit", std::vector<double>{c.edge_interval().low, c.edge_interval().high});
        study.set("below_surface_risk_max", std::vector<double>(c.edge->below.begin(), c.edge->below.end()));
        study.set("below_surface_time_step_correction", c.edge->below_time_step_correction);
        study.set("below_surface_limit", std::vector<double>{c.below_interval().low, c.below_interval().high});
      }
    summary.set_object("risk_convergence", study);
    if (c.model_and_exact_risk)
      {
        const auto [model, exact] = *c.model_and_exact_risk;
        summary.set("traction_model_error_estimate", exact > 0.0 ? std::abs(model - exact) / exact : 0.0);
        output::Summary check;
        check.set("method", std::string("D_max of the traction model and of the incremental exact solver over the "
                                        "same first cycles on the coarsest grid; relative difference"));
        check.set("cells_x", static_cast<long long>(c.cells[0]));
        check.set("cycles_compared", static_cast<long long>(c.traction_check_cycles));
        check.set("risk_max_model", model);
        check.set("risk_max_exact", exact);
        summary.set_object("traction_model_check", check);
      }
    else if (s.traction_model == "exact")
      summary.set("traction_model_error_estimate", 0.0);
  }

  void ConcentratedContactScene::add_loop(output::Summary &summary, const History &history) const
  {
    const auto  &s    = settings;
    const double nan  = std::numeric_limits<double>::quiet_NaN();
    const double mu_P = s.friction_coefficient * s.normal_load;
    if (history.mindlin)
      {
        const double gross_slip = history.mindlin->gross_slip_displacement();
        summary.set("gross_slip_displacement_m", gross_slip);
        summary.set("mindlin_reference", std::string(hertz.circular ? "exact (circular contact)" :
                                                       "approximate (elliptical contact, equivalent radius sqrt(ab))"));
      }
    summary.set("regime", regime(history));
    summary.set("slip_area_fraction_max", history.slip_area_fraction_max);
    if (history.loop.complete_cycles() >= 1 && history.mindlin)
      {
        const auto metrics = history.loop.last_cycle(mu_P, *history.mindlin, s.sliding_amplitude);
        summary.set("tangential_force_amplitude_N", metrics.force_amplitude);
        summary.set("dissipated_energy_per_cycle_J", metrics.dissipated_energy);
        summary.set("loop_error_vs_mindlin", metrics.error_vs_reference);
        summary.set("loop_change_last_cycle", metrics.change_from_previous_cycle);
        summary.set("mindlin_tangential_force_amplitude_N", history.mindlin->force_amplitude(s.sliding_amplitude));
        summary.set("mindlin_dissipated_energy_per_cycle_J", history.mindlin->dissipated_energy(s.sliding_amplitude));
      }
    else
      {
        // mu = 0 transmits no tangential force; an interrupted first cycle has no loop.
        summary.set("tangential_force_amplitude_N", mu_P > 0.0 ? nan : 0.0);
        summary.set("dissipated_energy_per_cycle_J", mu_P > 0.0 ? nan : 0.0);
        summary.set("loop_error_vs_mindlin", nan);
      }
  }

  std::string ConcentratedContactScene::regime(const History &history)
  {
    // Every loaded cell slipping at some step is gross slip; the margin
    // covers the sum's round-off.
    if (history.slip_area_fraction_max <= 0.0)
      return "stick";
    return history.slip_area_fraction_max >= 1.0 - 1e-9 ? "gross slip" : "partial slip";
  }

  std::map<std::string, double> ConcentratedContactScene::key_numbers(const contact::FrettingRun &run,
                                                                      const History &history,
                                                                      const std::optional<RiskConvergence> &convergence,
                                                                      double wall_seconds) const
  {
    const auto  &s     = settings;
    const auto   worst = run.risk_maximum();
    std::map<std::string, double> numbers{{"wall_time_s", wall_seconds},
                                          {"traction_seconds", run.stage_times().traction},
                                          {"risk_max", worst.value},
                                          {"risk_max_x_m", run.grid().x(worst.i)},
                                          {"risk_max_y_m", run.grid().y(worst.j)},
                                          {"risk_max_depth_m", s.depth_layers[worst.layer]},
                                          {"friction_force_limit_N", s.friction_coefficient * s.normal_load},
                                          {"contact_radius_m", history.contact_radius},
                                          {"peak_pressure_Pa", max_of(run.pressure())},
                                          {"slip_area_fraction_max", history.slip_area_fraction_max},
                                          {"von_mises_max_Pa", run.von_mises_max()}};
    if (s.yield_strength > 0.0)
      numbers["yield_margin"] = s.yield_strength / run.von_mises_max();
    if (convergence)
      {
        numbers["risk_max_converged"]      = convergence->converged();
        numbers["risk_max_error_estimate"] = convergence->error_estimate();
      }
    if (history.loop.complete_cycles() >= 1 && history.mindlin)
      {
        const auto metrics = history.loop.last_cycle(s.friction_coefficient * s.normal_load, *history.mindlin,
                                                     s.sliding_amplitude);
        numbers["dissipated_energy_per_cycle_J"] = metrics.dissipated_energy;
        numbers["tangential_force_amplitude_N"]  = metrics.force_amplitude;
        numbers["loop_error_vs_mindlin"]         = metrics.error_vs_reference;
      }
    return numbers;
  }
} // namespace fretsim::scenes
