#include "scenes/concentrated_scene.h"

#include "scenes/surface_grid_output.h"

#include "app/build_info.h"
#include "app/progress.h"
#include "app/run_control.h"
#include "output/results_file.h"
#include "output/summary.h"
#include "scenes/figures.h"

#include <fretsim/contact/bristle.h>
#include <fretsim/contact/dang_van.h>
#include <fretsim/contact/fretting_loop.h>
#include <fretsim/contact/hertz.h>
#include <fretsim/contact/mindlin.h>
#include <fretsim/contact/normal_contact.h>
#include <fretsim/contact/tangential_traction_model.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>

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
  } // namespace

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
    specs.push_back(Spec::selection("Friction/Traction model", "bristle",
                                    "Tangential traction model: bristle (paper eq. 4, exponential bristles, the "
                                    "fast model), elastoplastic bristle (elastic-perfectly-plastic bristles with a "
                                    "true stick zone), exact (elastic half-spaces, Kalker-type partial-slip "
                                    "solver, the reference; `fretsim compare-traction` runs all three).",
                                    "bristle|elastoplastic bristle|exact"));
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
    specs.push_back(Spec::integer_range("Grid/Cells x", "128", "Number of grid cells in x [-].", 8, 4096));
    specs.push_back(Spec::integer_range("Grid/Cells y", "128", "Number of grid cells in y [-].", 8, 4096));
    specs.push_back(Spec::real_range("Grid/Half width factor", "1.5",
                                     "Half width of the grid in each direction, in units of the Hertz semi-axis in "
                                     "that direction [-].", 1, 100, true));
    specs.push_back(Spec::selection("Normal contact/Pressure model", "numerical",
                                    "numerical: elastic half-space solution on the grid (Polonsky-Keer CG with "
                                    "DC-FFT); hertz: the analytic Hertz pressure sampled at cell centres.",
                                    "numerical|hertz"));
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
      depths.kind = Spec::Kind::real_list;
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
                                        "Field snapshots (pressure, shear, effective friction, slip, the "
                                        "stress tensor and the Dang Van risk on the depth layers) written per "
                                        "cycle [-].", 0, 1000000));
    specs.push_back(Spec::integer_range("Output/Field output cycles", "1",
                                        "Snapshots are written for this many final cycles [-].", 0, 100000));
    return specs;
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
  }

  ConcentratedContactScene::~ConcentratedContactScene() = default;

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
    s.stress_evaluator.method      = p.get("Stresses/Evaluator");
    s.stress_evaluator.mlmi_levels = static_cast<int>(p.get_integer("Stresses/MLMI levels"));
    s.stress_evaluator.mlmi_order  = static_cast<int>(p.get_integer("Stresses/MLMI order"));
    s.depth_layers                 = p.get_double_list("Stresses/Depth layers");
    s.bending_fatigue_limit = p.get_double("Dang Van/Bending fatigue limit");
    s.torsion_fatigue_limit = p.get_double("Dang Van/Torsion fatigue limit");
    s.residual_stress       = p.get("Dang Van/Residual stress");
    s.warmup_cycles         = static_cast<int>(p.get_integer("Dang Van/Warm-up cycles"));
    try
      {
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

  RunReport ConcentratedContactScene::run(const RunOptions &options)
  {
    const auto  run_start = Clock::now();
    const auto &s         = settings;
    RunReport   report;
    output::Summary stage_times;

    const double contact_modulus    = s.materials.contact_modulus();
    const double tangential_modulus = s.materials.tangential_modulus();

    // 1. Normal contact: pressure, constant during the sliding.
    auto           stage_start = Clock::now();
    contact::Field pressure    = grid.zeros();
    int            normal_iterations = 0;
    if (s.pressure_model == "numerical")
      {
        contact::Field initial_gap = grid.zeros();
        for (int j = 0; j < grid.ny; ++j)
          for (int i = 0; i < grid.nx; ++i)
            initial_gap[grid.index(i, j)] = grid.x(i) * grid.x(i) / (2.0 * s.radius_x) +
                                            grid.y(j) * grid.y(j) / (2.0 * s.radius_y);
        const contact::NormalContactSolver solver(grid, contact_modulus,
                                                  {s.normal_tolerance, s.normal_max_iterations});
        const auto result = solver.solve(initial_gap, s.normal_load);
        pressure          = result.pressure;
        normal_iterations = result.iterations;
      }
    else
      {
        for (int j = 0; j < grid.ny; ++j)
          for (int i = 0; i < grid.nx; ++i)
            {
              const double ex = grid.x(i) / hertz.semi_axis_x, ey = grid.y(j) / hertz.semi_axis_y;
              pressure[grid.index(i, j)] = hertz.peak_pressure * std::sqrt(std::max(0.0, 1.0 - ex * ex - ey * ey));
            }
      }
    double contact_area = 0.0;
    for (const double value : pressure)
      contact_area += value > 0.0 ? grid.cell_area() : 0.0;
    const double contact_radius = std::sqrt(contact_area / M_PI);
    stage_times.set("normal_contact", seconds_since(stage_start));

    // 2. Subsurface stresses of the pressure, which stays constant: the
    //    stresses are linear in the loads, so each instant only adds those of
    //    the current shear traction.
    stage_start = Clock::now();
    const contact::Field no_load = grid.zeros();
    contact::StressField pressure_stress, shear_stress, stress;
    stresses->evaluate(pressure, no_load, no_load, pressure_stress);
    const double seconds_of_pressure_stress = seconds_since(stage_start);
    double       stress_seconds             = seconds_of_pressure_stress;
    long         stress_evaluations         = 1;
    auto   evaluate_stress = [&](const contact::Field &shear_x, const contact::Field &shear_y) {
      const auto start = Clock::now();
      stresses->evaluate(no_load, shear_x, shear_y, shear_stress);
      stress = pressure_stress;
      for (std::size_t k = 0; k < stress.values.size(); ++k)
        stress.values[k] += shear_stress.values[k];
      stress_seconds += seconds_since(start);
      ++stress_evaluations;
    };

    // 3. Dang Van risk on every depth layer, fed the stress of every step.
    contact::DangVanSettings dang_van_settings;
    dang_van_settings.centre          = contact::parse_residual_stress_centre(s.residual_stress);
    dang_van_settings.steps_per_cycle = s.steps_per_cycle;
    dang_van_settings.warmup_cycles   = s.warmup_cycles;
    contact::DangVanField risk(s.depth_layers.size() * grid.size(),
                               contact::DangVanConstants::from_fatigue_limits(s.bending_fatigue_limit,
                                                                              s.torsion_fatigue_limit),
                               dang_van_settings);
    double dang_van_seconds = 0.0;
    auto   update_risk      = [&] {
      const auto start = Clock::now();
      risk.add_step(stress);
      dang_van_seconds += seconds_since(start);
    };

    // 4. Bristle traction under harmonic sliding, with the Mindlin–Deresiewicz
    //    loop alongside for the same displacement history.
    const double calibrated_stiffness =
      contact::BristleTraction::mindlin_stiffness(tangential_modulus, hertz.equivalent_radius());
    const double stiffness =
      (s.bristle_stiffness > 0.0 ? s.bristle_stiffness : calibrated_stiffness) * s.bristle_stiffness_factor;
    contact::PartialSlipSettings exact_settings;
    exact_settings.tolerance = s.exact_tolerance;
    const auto traction_model = contact::make_tangential_traction_model(
      contact::parse_traction_model(s.traction_model), grid, s.materials, stiffness, exact_settings);
    auto &bristles = *traction_model;
    double traction_seconds = 0.0;
    long   traction_iterations = 0, most_traction_iterations = 0;
    const contact::HarmonicSliding sliding{s.sliding_amplitude, s.period};
    const double mu_P = s.friction_coefficient * s.normal_load;
    std::optional<contact::MindlinLoop> mindlin;
    if (mu_P > 0.0)
      mindlin.emplace(s.friction_coefficient, s.normal_load, hertz.equivalent_radius(), tangential_modulus);
    contact::FrettingLoop loop(s.steps_per_cycle);

    std::filesystem::create_directories(options.output_directory);
    report.results_file = (std::filesystem::path(options.output_directory) / "results.h5").string();
    report.summary_file = (std::filesystem::path(options.output_directory) / "summary.json").string();
    // Held by pointer so it can be closed before the plotting script reads it
    // (HDF5 locks a file that is open for writing).
    auto results_owner =
      std::make_unique<output::ResultsFile>(report.results_file, "concentrated", parameters.to_prm());
    auto &results = *results_owner;
    write_surface_grid(results, grid, s.depth_layers);
    results.set_root_attribute("contact_radius_m", contact_radius);
    for (const auto &[name, unit] : std::vector<std::pair<std::string, std::string>>{
           {"time", "s"}, {"cycle", "1"}, {"displacement_x", "m"}, {"displacement_y", "m"},
           {"tangential_force_x", "N"}, {"tangential_force_y", "N"}, {"normal_force", "N"},
           {"tangential_force_mindlin_x", "N"}, {"slip_area_fraction", "1"}})
      results.declare_series(name, unit);
    const std::vector<std::size_t> field_shape{static_cast<std::size_t>(grid.ny), static_cast<std::size_t>(grid.nx)};
    results.declare_field("pressure", "Pa", field_shape);
    results.declare_field("shear_x", "Pa", field_shape);
    results.declare_field("shear_y", "Pa", field_shape);
    results.declare_field("effective_friction", "1", field_shape);
    results.declare_field("slip", "1", field_shape);
    results.declare_field("stress", "Pa", {s.depth_layers.size(), std::size_t(contact::stress_component_count),
                                           field_shape[0], field_shape[1]});
    results.set_root_attribute("stress_components", "xx, yy, zz, yz, xz, xy (tension positive, lower body)");
    results.declare_field("risk", "1", {s.depth_layers.size(), field_shape[0], field_shape[1]});

    const double direction_x = std::cos(s.sliding_direction), direction_y = std::sin(s.sliding_direction);
    const long   total_steps = static_cast<long>(s.cycles) * s.steps_per_cycle;
    const double time_step   = s.period / s.steps_per_cycle;
    const int    snapshot_interval = s.snapshots_per_cycle > 0 ? s.steps_per_cycle / s.snapshots_per_cycle : 0;
    const long   first_snapshot_step = static_cast<long>(s.cycles - s.snapshot_cycles) * s.steps_per_cycle + 1;

    // The scene's slip tolerance, the same for every traction model.
    auto slip_area_fraction = [&] {
      return contact::slip_area_fraction(bristles.effective_friction(), pressure, s.slip_tolerance);
    };
    auto write_row = [&](long step, double displacement, double reference_force) {
      const double force_x = contact::integrate(grid, bristles.traction_x());
      const double force_y = contact::integrate(grid, bristles.traction_y());
      const long   cycle   = (step + s.steps_per_cycle - 1) / s.steps_per_cycle;
      results.append_series_row({step * time_step, static_cast<double>(cycle), displacement * direction_x,
                                 displacement * direction_y, force_x, force_y, s.normal_load,
                                 reference_force * direction_x,
                                 slip_area_fraction()});
      return force_x * direction_x + force_y * direction_y;
    };
    auto write_snapshot = [&](double time) {
      const contact::Field effective_friction = bristles.effective_friction();
      contact::Field       slip               = grid.zeros();
      for (std::size_t c = 0; c < slip.size(); ++c)
        slip[c] = pressure[c] > 0.0 && effective_friction[c] >= 1.0 - s.slip_tolerance ? 1.0 : 0.0;
      results.append_snapshot(time, {&pressure, &bristles.traction_x(), &bristles.traction_y(),
                                     &effective_friction, &slip, &stress.values, &risk.risk()});
    };

    stage_start = Clock::now();
    app::Progress progress("concentrated contact", total_steps, options.progress);
    loop.add(0.0, write_row(0, 0.0, 0.0));
    results.flush();
    double previous_displacement = 0.0;
    long   steps_done            = 0;
    for (long step = 1; step <= total_steps; ++step)
      {
        if (app::interrupt_requested())
          break;
        const double time         = step * time_step;
        const double displacement = sliding.displacement(time);
        const double slip         = displacement - previous_displacement;
        const auto traction_start = Clock::now();
        bristles.advance(pressure, s.friction_coefficient, slip * direction_x, slip * direction_y);
        traction_seconds += seconds_since(traction_start);
        traction_iterations += bristles.last_iterations();
        most_traction_iterations = std::max<long>(most_traction_iterations, bristles.last_iterations());
        const bool   reversed_before = (step - 1) * time_step >= 0.25 * s.period * (1.0 - 1e-12);
        const double reference_force =
          mindlin ? contact::FrettingLoop::reference_force(*mindlin, s.sliding_amplitude, displacement,
                                                           previous_displacement, reversed_before) :
                    0.0;
        loop.add(displacement, write_row(step, displacement, reference_force));
        evaluate_stress(bristles.traction_x(), bristles.traction_y());
        update_risk();
        if (snapshot_interval > 0 && step >= first_snapshot_step && step % snapshot_interval == 0)
          write_snapshot(time);
        results.flush();
        previous_displacement = displacement;
        steps_done            = step;
        progress.update(step, time);
      }
    progress.finish();
    stage_times.set("traction", traction_seconds);
    stage_times.set("output", seconds_since(stage_start) - (stress_seconds - seconds_of_pressure_stress) -
                                dang_van_seconds - traction_seconds);
    stage_times.set("stresses", stress_seconds);
    stage_times.set("dang_van", dang_van_seconds);

    // The maximum risk and where it sits.
    const std::vector<double> &risk_max = risk.risk_max();
    results.write_dataset("/fields/risk_max", "1", {s.depth_layers.size(), field_shape[0], field_shape[1]}, risk_max);
    std::size_t worst = 0;
    for (std::size_t point = 0; point < risk_max.size(); ++point)
      if (std::isfinite(risk_max[point]) && !(risk_max[point] <= risk_max[worst]))
        worst = point;
    const std::size_t worst_layer = worst / grid.size(), worst_cell = worst % grid.size();
    const int         worst_i = static_cast<int>(worst_cell % grid.nx), worst_j = static_cast<int>(worst_cell / grid.nx);
    const std::size_t infinite_max = risk.infinite_risk_max_count();
    if (infinite_max > 0)
      std::cerr << "fretsim: warning: " << infinite_max << " of " << risk_max.size()
                << " points reached beta - alpha sigma_H <= 0 (hydrostatic tension beyond the Dang Van line): "
                   "their risk is infinite in /fields/risk_max and left out of risk_max\n";
    report.completed = steps_done == total_steps;

    // 5. Summary of the run.
    const double    nan = std::numeric_limits<double>::quiet_NaN();
    output::Summary summary;
    summary.set("scene", std::string("concentrated"));
    summary.set("config_file", parameters.file());
    summary.set("version", std::string(FRETSIM_VERSION));
    summary.set("status", std::string(report.completed ? "complete" : "interrupted"));
    summary.set("contact_radius_m", contact_radius);
    summary.set("hertz_contact_radius_m", hertz.equivalent_radius());
    summary.set("hertz_semi_axis_x_m", hertz.semi_axis_x);
    summary.set("hertz_semi_axis_y_m", hertz.semi_axis_y);
    summary.set("peak_pressure_Pa", max_of(pressure));
    summary.set("hertz_peak_pressure_Pa", hertz.peak_pressure);
    summary.set("pressure_model", s.pressure_model);
    summary.set("normal_solver_iterations", static_cast<long long>(normal_iterations));
    summary.set("traction_model", s.traction_model);
    summary.set("traction_seconds_per_step", steps_done > 0 ? traction_seconds / steps_done : nan);
    if (bristles.kind() == contact::TractionModel::exact)
      {
        summary.set("traction_iterations_per_step", steps_done > 0 ? double(traction_iterations) / steps_done : nan);
        summary.set("traction_iterations_max", static_cast<long long>(most_traction_iterations));
      }
    summary.set("bristle_stiffness_Pa_per_m", stiffness);
    summary.set("mindlin_calibrated_stiffness_Pa_per_m", calibrated_stiffness);
    summary.set("stress_evaluator", stresses->name());
    summary.set("stress_evaluations", static_cast<long long>(stress_evaluations));
    summary.set("risk_max", risk_max.empty() ? nan : risk_max[worst]);
    summary.set("risk_max_location_m", std::vector<double>{grid.x(worst_i), grid.y(worst_j), s.depth_layers[worst_layer]});
    summary.set("risk_max_depth_m", s.depth_layers[worst_layer]);
    summary.set("risk_max_time_s", (risk.risk_max_step()[worst] + 1) * time_step);
    summary.set("risk_infinite_points", static_cast<long long>(infinite_max));
    summary.set("residual_stress_centre", s.residual_stress);
    summary.set("sliding_amplitude_m", s.sliding_amplitude);
    summary.set("cycles", static_cast<long long>(loop.complete_cycles()));
    summary.set("steps", static_cast<long long>(steps_done));
    if (mindlin)
      {
        summary.set("gross_slip_displacement_m", mindlin->gross_slip_displacement());
        summary.set("regime", std::string(s.sliding_amplitude < mindlin->gross_slip_displacement() ? "partial slip" : "gross slip"));
        summary.set("mindlin_reference", std::string(hertz.circular ? "exact (circular contact)" :
                                                       "approximate (elliptical contact, equivalent radius sqrt(ab))"));
      }
    if (loop.complete_cycles() >= 1 && mindlin)
      {
        const auto metrics = loop.last_cycle(mu_P, *mindlin, s.sliding_amplitude);
        summary.set("tangential_force_amplitude_N", metrics.force_amplitude);
        summary.set("dissipated_energy_per_cycle_J", metrics.dissipated_energy);
        summary.set("loop_error_vs_mindlin", metrics.error_vs_reference);
        summary.set("loop_change_last_cycle", metrics.change_from_previous_cycle);
        summary.set("mindlin_tangential_force_amplitude_N", mindlin->force_amplitude(s.sliding_amplitude));
        summary.set("mindlin_dissipated_energy_per_cycle_J", mindlin->dissipated_energy(s.sliding_amplitude));
      }
    else
      {
        // mu = 0 transmits no tangential force; an interrupted first cycle has no loop.
        summary.set("tangential_force_amplitude_N", mu_P > 0.0 ? nan : 0.0);
        summary.set("dissipated_energy_per_cycle_J", mu_P > 0.0 ? nan : 0.0);
        summary.set("loop_error_vs_mindlin", nan);
      }

    results.set_root_attribute("status", report.completed ? "complete" : "interrupted");
    results.flush();
    const std::string xdmf_file = (std::filesystem::path(options.output_directory) / "results.xdmf").string();
    results.write_xdmf(xdmf_file);
    results_owner.reset();
    stage_times.set("total", seconds_since(run_start));
    summary.set_object("stage_times_s", stage_times);
    summary.set("wall_time_s", seconds_since(run_start));
    summary.write(report.summary_file);

    report.numbers = {{"wall_time_s", seconds_since(run_start)},
                      {"traction_seconds", traction_seconds},
                      {"risk_max", risk_max.empty() ? nan : risk_max[worst]},
                      {"risk_max_x_m", grid.x(worst_i)},
                      {"risk_max_y_m", grid.y(worst_j)},
                      {"risk_max_depth_m", s.depth_layers[worst_layer]},
                      {"friction_force_limit_N", mu_P},
                      {"contact_radius_m", contact_radius}};
    if (loop.complete_cycles() >= 1 && mindlin)
      {
        const auto metrics = loop.last_cycle(mu_P, *mindlin, s.sliding_amplitude);
        report.numbers["dissipated_energy_per_cycle_J"] = metrics.dissipated_energy;
        report.numbers["tangential_force_amplitude_N"]  = metrics.force_amplitude;
        report.numbers["loop_error_vs_mindlin"]         = metrics.error_vs_reference;
      }

    if (options.plots)
      report.figures = make_figures(options.output_directory);
    return report;
  }
} // namespace fretsim::scenes
