#include <fretsim/scenes/bearing_scene.h>

#include "surface_grid_output.h"

#include <fretsim/support/progress.h>
#include <fretsim/support/run_control.h>
#include <fretsim/output/results_file.h>
#include <fretsim/output/summary.h>
#include <fretsim/scenes/figures.h>

#include <fretsim/contact/dang_van.h>
#include <fretsim/contact/material.h>
#include <fretsim/contact/subsurface_stress.h>
#include <fretsim/coupling/cosimulation.h>
#include <fretsim/coupling/periodicity.h>
#include <fretsim/models/model_source.h>
#include <fretsim/models/reduction.h>
#include <fretsim/models/ring_stress.h>
#include <fretsim/reduction/reduced_model.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <numeric>
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

    app::ParameterSpec text(const std::string &path, const std::string &value, const std::string &doc)
    {
      app::ParameterSpec spec;
      spec.path          = path;
      spec.kind          = app::ParameterSpec::Kind::text;
      spec.default_value = value;
      spec.doc           = doc;
      return spec;
    }

    app::ParameterSpec list(app::ParameterSpec spec)
    {
      spec.kind = app::ParameterSpec::Kind::real_list;
      return spec;
    }

    app::ParameterSpec increasing(app::ParameterSpec spec)
    {
      spec.increasing = true;
      return spec;
    }
  } // namespace

  struct BearingHousingScene::Settings
  {
    models::ModelSource            ring_model;
    std::optional<models::ModelSource> housing_model; ///< none: the housing is rigid and fixed
    bool                           build_model = true;
    coupling::CosimulationSettings run;
    double                         ring_poisson_ratio = 0.3;
    std::string                    local_compliance   = "none"; ///< Interface/Local compliance
    bool                           ring_residual      = true;   ///< Interface/Ring residual flexibility
    bool                           housing_residual   = true;   ///< Interface/Housing residual flexibility
    /// E/(1 - ν²) of the ring's and the housing's materials, for the residual
    /// flexibilities' half-space completion; 0: Interface/Half-space
    /// completion off [Pa].
    double ring_completion_modulus = 0.0, housing_completion_modulus = 0.0;
    std::string                    in_step_bristle_law = "implicit Euler"; ///< Interface/In-step bristle law
    std::string                    bristle_update      = "implicit Euler"; ///< Interface/Bristle update
    std::string                    stage_predictor = "cutoff order";       ///< Integrator/Stage predictor
    int                            samples_per_ball_pass = 40;
    coupling::CageKinematics       kinematics; ///< of Loading/Inner ring speed
    /// The ring's full-FE stress tables; none: half-space stresses.
    std::optional<models::RingStressSource> ring_stress;
    contact::StressEvaluatorSettings stress_evaluator;
    std::vector<double>              depth_layers;
    contact::DangVanConstants      dang_van_constants;
    contact::DangVanSettings       dang_van;
  };

  namespace
  {
    /// The models, the bearing and its loading.
    std::vector<app::ParameterSpec> model_bearing_loading_specs()
    {
      using Spec = app::ParameterSpec;
      return {
        text("Model/Reduction configuration", "ring_6208_reduce.prm",
             "The ring_housing configuration of the outer ring's Craig-Bampton model (geometry, material, mesh, "
             "reduction), relative to this file's directory [-]."),
        text("Model/Model file", "",
             "The reduced model file; empty: results/<reduction configuration name>-model.h5 (where `fretsim reduce` "
             "writes it) [-]."),
        Spec::integer_range("Model/Characteristic constraint modes", "0",
                            "n_cc of the ring's model over its reduction configuration's (0: the configuration's): "
                            "the ring's interface shapes, which set how sharply the pressure under a ball is resolved "
                            "and D_max with it (docs/bearing.md). The model is built on first use into its own file [-].",
                            0, 5000),
        Spec::integer_range("Model/Fixed-interface modes", "0",
                            "m of the ring's model over its reduction configuration's (0: the configuration's) [-].", 0,
                            5000),
        Spec::selection("Model/Ball footprint", "load following",
                        "The balls' patch on the raceway, in the ring's model (the raceway operator and its residual "
                        "flexibility under a ball), its stress tables and `compare`/`reference`: load following, each "
                        "ball's Hertz ellipse of its current load, interpolated between the ellipses of Model/Ball "
                        "footprints loads (the model and tables get -hertz in their names); fixed, the reduction "
                        "configuration's Reduction/Ball footprint semi-axes whatever the load [-].",
                        "load following|fixed"),
        Spec::integer_range("Model/Ball footprints", "7",
                            "Load following: how many ball loads' Hertz ellipses the model and tables hold (odd: the "
                            "rows are quadratic in load^(1/3) over pieces of three), equally spaced in load^(1/3) from "
                            "a point load up to the load at which the outer contact's peak pressure reaches ISO 76's "
                            "static limit of 4.2 GPa (docs/bearing.md) [-].",
                            3, 63),
        text("Model/Housing reduction configuration", "",
             "The ring_housing configuration (Mesh/Bodies = housing, Reduction/Coupling surfaces = housing_bore) of a "
             "flexible housing's Craig-Bampton model, relative to this file's directory; the same Ring/Outer radius, "
             "Ring/Width and interface grid as the ring's. Empty: the housing is rigid and fixed, as in the paper [-]."),
        text("Model/Housing model file", "",
             "The housing's reduced model file; empty: results/<housing configuration name>-model.h5 [-]."),
        Spec::integer_range("Model/Housing characteristic constraint modes", "0",
                            "n_cc of a flexible housing's model over its reduction configuration's (0: the "
                            "configuration's): the bore's shapes, which carry the housing's tangential give (its "
                            "residual flexibility holds the normal one only; docs/bearing.md). The model is built on "
                            "first use into its own file [-].",
                            0, 5000),
        Spec::integer_range("Model/Housing fixed-interface modes", "0",
                            "m of a flexible housing's model over its reduction configuration's (0: the "
                            "configuration's) [-].",
                            0, 5000),
        Spec::selection("Model/Build if missing", "true",
                        "Build the model file with `fretsim reduce` when it is missing or was made from other inputs "
                        "(false: stop with an error) [-].",
                        "true|false"),
        Spec::integer_range("Bearing/Ball count", "9", "Z: number of balls (6208: 9) [-].", 1, 100),
        Spec::positive("Bearing/Ball diameter", "0.0127",
                       "D_w (6208: 12.7 mm); the pitch diameter is 2 x groove bottom radius - D_w and the outer groove "
                       "conformity groove radius / D_w, from the ring [m]."),
        Spec::real_range("Bearing/Inner groove conformity", "0.52", "f_i = inner groove radius / D_w [-].", 0.5, 1.0,
                         true),
        Spec::real_range("Bearing/Radial clearance", "10e-6",
                         "Radial internal clearance P_d (6208 normal clearance C0: 6-20 um) [m].", -1e-3, 1e-3),
        Spec::positive("Bearing/Young's modulus", "2.08e11", "Balls and inner ring [Pa]."),
        Spec::real_range("Bearing/Poisson ratio", "0.3", "Balls and inner ring [-].", 0.0, 0.5, true),
        Spec::non_negative("Bearing/Contact damping", "0.1",
                           "Hunt-Crossley coefficient alpha of the ball contacts, Q = K d^1.5 (1 + 1.5 alpha d') [s/m]."),
        Spec::real_range("Loading/Inner ring speed", "3000", "Inner ring speed [rpm] (the outer ring is fixed).", 0,
                         1e6),
        Spec::real_range("Loading/Inner ring displacement x", "0", "Horizontal displacement of the inner ring [m].",
                         -1e-3, 1e-3),
        Spec::real_range("Loading/Inner ring displacement y", "60e-6",
                         "Vertical (upward) displacement of the inner ring, the paper's 60 um [m].", -1e-3, 1e-3),
        Spec::non_negative("Loading/Ramp time", "2e-3",
                           "The displacement is applied with a smooth step over this time [s]."),
        Spec::real_range("Loading/First ball angle", "1.5707963267948966",
                         "Cage angle of ball 0 at t = 0, from +x towards +y (up) [rad].", -10, 10),
        Spec::real_range("Loading/Ball pass periods", "4",
                         "Simulated time in outer-ring ball pass periods 1/f_bp (6208 at 3000 rpm: 5.64 ms each; 3.55 "
                         "per inner ring revolution) [-].",
                         0.05, 1e5),
      };
    }

    /// The ring/housing interface and the ring's damping.
    std::vector<app::ParameterSpec> interface_specs()
    {
      using Spec = app::ParameterSpec;
      return {
        Spec::non_negative("Interface/Friction coefficient", "0.11", "mu between outer ring and housing [-]."),
        Spec::real_range("Interface/Normal stiffness", "1e15",
                         "k_n of the Winkler layer that carries the interface pressure p = k_n x penetration [Pa/m].",
                         1e9, 1e21),
        Spec::real_range("Interface/Tangential stiffness", "1e15", "Bristle stiffness k_t (paper eq. 4) [Pa/m].",
                         1e9, 1e21),
        Spec::non_negative("Interface/Damping time", "1e-6",
                           "Normal damping of the layer, c_n = k_n x this: damps the ring's bounce in the housing [s]."),
        Spec::non_negative("Interface/Onset pressure", "1e6",
                           "p_s: the layer closes gradually (C^1) up to the pressure 2 p_s and carries k_n x "
                           "penetration - p_s beyond; the damping acts through the same law, so that a closing cell's "
                           "pressure starts from zero. 0: sharp onset, p jumps by c_n x closing speed [Pa]."),
        Spec::non_negative("Interface/Closure pressure", "3e7",
                           "p_c: with a flexible housing the layer closes as a rough surface does, p = p_c ln(1 + "
                           "exp((d - s)/delta)), delta = p_c/k_n, s = 10 delta: the linear layer k_n (d - s) once p >> "
                           "p_c, an exponential tail below. The two bodies' conformal contact then has no edge where "
                           "Newton's iterations jump between loaded sets (D_max within 0.2 % of the sharp closure's on "
                           "the paper case; with the direct solve a fourteenth of its Newton failures: "
                           "docs/bearing.md). 0: sharp. The rigid "
                           "housing's contact closes sharply [Pa]."),
        Spec::selection("Interface/Bristles follow the closure", "true",
                        "With the closure (a flexible housing): the bristles' stiffness follows the layer's normal "
                        "stiffness, k_t (1 - exp(-p/p_c)), as an asperity's tangential stiffness follows its normal "
                        "one (Mindlin). A cell in the closure's tail does not stick as a full k_t spring that lets go "
                        "within a fraction of a nanometre of slip: on the suite's small ring 2 Newton failures in "
                        "442 steps instead of 84 in 501 (direct solve), D_max within 0.1 %; on the paper case "
                        "-0.13 % (docs/bearing.md). false: k_t at every pressure, the paper's bristle [-].",
                        "true|false"),
        Spec::selection("Interface/In-step bristle law", "implicit Euler",
                        "What the integrator sees of the bristles within a step; after every step the bristle "
                        "update (Interface/Bristle update) is committed either way. implicit Euler: that same law "
                        "(bristles and ring in one implicit step); linearised: a sticking cell a spring capped at mu "
                        "p, a sliding one at its ratio tau/p, a splitting error that the step size does not cure "
                        "(D_max -1.8 % on the paper case, -15 % on a coarse ring) and 3.5x the steps there: "
                        "docs/bearing.md [-].",
                        "linearised|implicit Euler"),
        Spec::selection("Interface/Bristle update", "implicit Euler",
                        "How the bristle law steps over a step's slip, within the step and in the update after it. "
                        "implicit Euler: the paper's, first order in the slip, so that D_max's time error is first "
                        "order in the steps (one ball pass of the paper case with a flexible housing: 0.64 % below "
                        "the converged value at the scene's settings); exponential: the law's exact answer along a "
                        "straight slip increment (there within 0.04 % in as many steps; docs/bearing.md) [-].",
                        "implicit Euler|exponential"),
        Spec::selection("Interface/Local compliance", "none",
                        "Elastic half-space in series with the layer (Love's rectangles on the interface grid, "
                        "periodic around the circumference): none (the layer alone), housing (the rigid housing's "
                        "local elasticity, which nothing else models; the ring's comes from its reduced model and its "
                        "residual flexibility), both "
                        "(housing and ring: the ring's local compliance beyond what its interface modes resolve, "
                        "counting its long wavelengths twice). Only none with a flexible housing.",
                        "none|housing|both"),
        Spec::selection("Interface/Ring residual flexibility", "true",
                      "Add the part of the ring's static compliance its reduced basis misses on the interface "
                      "(R = K^-1 - T K_r^-1 T^T, which `fretsim reduce` stores in the model file) to the local "
                      "compliance in series with the layer, and each ball's residual displacement of the interface "
                      "to its penetration: the pressure under a ball as the full FE ring gives it, whatever the "
                      "basis size (docs/bearing.md). Not with Local compliance = both, which stands for the same "
                      "compliance [-].", "true|false"),
        Spec::selection("Interface/Residual flexibility at the balls", "true",
                        "With the ring's residual flexibility: its reciprocal term too (Maxwell-Betti), the interface "
                        "pressure's residual displacement of the raceway under each ball joining that ball's "
                        "deflection, from the pressure of the interface's solve in the same evaluation (one sweep; "
                        "summary.json reports its largest value and the sweep's correction). false: only the balls' "
                        "residual displacement of the interface (docs/bearing.md) [-].",
                        "true|false"),
        Spec::selection("Interface/Housing residual flexibility", "true",
                        "With a flexible housing (Model/Housing reduction configuration): add the part of the "
                        "housing's static compliance its reduced basis misses on its bore (R_h = K^-1 - T K_r^-1 T^T, "
                        "stored by `fretsim reduce` in its model file) in series with the layer, as the ring's "
                        "(docs/bearing.md) [-].", "true|false"),
        Spec::selection("Interface/Half-space completion", "true",
                        "Complete the residual flexibilities at the short wavelengths their FE meshes lose: per "
                        "circumferential wavenumber, where the model file's residual flexibility holds less compliance "
                        "than an elastic half-space of its body's material (the exact limit at wavelengths well below "
                        "the wall thickness, which no reduced basis holds), the shortfall is added, in full below the "
                        "completion wavelength and fading out up to twice it. summary.json reports how much per "
                        "wavenumber (docs/bearing.md) [-].",
                        "true|false"),
        Spec::non_negative("Interface/Half-space completion wavelength", "0",
                           "lambda_c of the half-space completion: the wavelength around the circumference below which "
                           "the residual flexibility is completed in full. 0: the ring's thinnest wall (Outer radius "
                           "minus Groove bottom radius of its reduction configuration; 3.65 mm on the 6208) [m]."),
        Spec::positive("Interface/Housing Young's modulus", "2.08e11",
                       "E of the rigid housing's material, for its local compliance [Pa]."),
        Spec::real_range("Interface/Housing Poisson ratio", "0.3", "nu of the housing's material [-].", 0.0, 0.5,
                         true),
        Spec::non_negative("Interface/Housing outer radius", "0",
                           "The housing's wall, for a fit: with Local compliance = housing, the housing's give under a "
                           "pressure uniform around the bore is a free thick ring's of this outside radius and the "
                           "housing's material (Lame, plane stress) instead of the half-space's, whose uniform give "
                           "depends on the grid's width only; the shorter waves stay the half-space's. 0: the "
                           "half-space's (docs/bearing.md) [m]."),
        Spec::real_range("Interface/Radial interference", "0",
                         "Ring outer radius minus housing bore radius: > 0 interference fit, < 0 clearance, 0 "
                         "line-to-line (the paper: only the loaded half carries pressure) [m].",
                         -1e-3, 1e-3),
        Spec::real_range("Ring/Damping ratio", "0.02",
                         "Stiffness-proportional damping: this ratio at the lowest elastic frequency [-].", 0.0, 10.0),
      };
    }

    /// The time integrator.
    std::vector<app::ParameterSpec> integrator_specs()
    {
      using Spec = app::ParameterSpec;
      return {
        Spec::integer_range("Integrator/Order", "3", "Order of ARKODE's diagonally implicit Runge-Kutta method [-].", 2,
                            5),
        Spec::real_range("Integrator/Relative tolerance", "1e-4", "ARKODE relative tolerance [-].", 1e-12, 1e-1),
        Spec::real_range("Integrator/Displacement tolerance", "1e-11",
                         "Absolute tolerance as a displacement of the interface or raceway [m].", 1e-18, 1e-6),
        Spec::non_negative("Integrator/Maximum step", "0", "Largest step; 0: only the output interval bounds it [s]."),
        Spec::integer_range("Integrator/Maximum steps per output", "20000",
                            "The run stops with a message when one output interval needs more steps [-].", 10,
                            100000000),
        Spec::integer_range("Integrator/Maximum Newton iterations", "12",
                            "Newton iterations per stage before the step is cut. The bristles' law bends within a "
                            "step and Newton's matrix is kept over steps, so it converges linearly: with ARKODE's own "
                            "3 a third of the paper case's steps failed, with 12 a tenth to a sixth (docs/bearing.md) [-].",
                            1, 100),
        Spec::integer_range("Integrator/Maximum Newton failures per step", "10",
                            "Newton failures in one step (each retried with a smaller step and a fresh Jacobian) "
                            "before the step is given up and retried with ARKODE's own Newton start (the last "
                            "solution, 3 iterations, 10 failures) for the rest of the output interval; 10 is "
                            "ARKODE's default (docs/bearing.md) [-].",
                            1, 100),
        Spec::integer_range("Integrator/Jacobian interval", "5",
                            "Steps between fresh Jacobians of the contact forces besides those after a failed Newton "
                            "iteration (ARKODE's default 51 keeps one while the balls move the contact under it; 5: "
                            "0.7 of the time on the paper case's four ball passes, docs/bearing.md) [-].",
                            1, 1000),
        Spec::selection("Integrator/Stage predictor", "cutoff order",
                        "Newton's starting guess for each implicit stage (ARKODE's predictor): trivial (the last "
                        "step's solution), maximum order (the last step's dense output), variable order (its order "
                        "falling for later stages), cutoff order (full order in the step's first half, linear after; "
                        "a third of the trivial guess's steps on the paper case, docs/bearing.md) [-].",
                        "trivial|maximum order|variable order|cutoff order"),
        Spec::selection("Integrator/Deduce stage derivatives", "true",
                        "Take each implicit stage's derivative from Newton's converged correction instead of "
                        "evaluating the contact forces once more at the stage's solution (ARKODE's deduced implicit "
                        "right-hand side): a third fewer evaluations, each a pressure solve with the half-space, and "
                        "fewer steps on the paper case; D_max within 0.1 % (docs/bearing.md) [-].",
                        "true|false"),
        Spec::selection("Integrator/Secant updates", "true",
                        "Update the Newton matrix between a stage's Newton iterations by Broyden's secant "
                        "method, so that it follows the cells that close or open during the iteration: on the "
                        "paper case a sixth of the Newton failures and 0.9 of the run time (docs/bearing.md) [-].",
                        "true|false"),
        Spec::selection("Integrator/Balls at the iterate", "auto",
                        "Keep the balls' Hertz stiffness in Newton's matrix at the iterate rather than at the "
                        "Jacobian's state (a rank-one update per loaded ball): a ball whose load rose since the "
                        "matrix was set up is otherwise missing from it. auto: with a flexible housing, where it "
                        "cut the Newton failures by a fifth; with the rigid one it cost steps (docs/bearing.md) [-].",
                        "auto|true|false"),
        Spec::selection("Integrator/Bristles at the iterate", "false",
                        "Keep the bristles' stiffness in Newton's matrix at the iterate for the cells where it "
                        "changed most since the Jacobian (a cell that turned from sticking to sliding or back; "
                        "at most 32 cells, by Woodbury's identity). On the suite's small ring with a flexible "
                        "housing, the paper's bristles and the direct solve it removed three quarters of the "
                        "Newton failures; on the paper's 6208, where "
                        "about 200 cells change per evaluation, it did not help (docs/bearing.md) [-].",
                        "true|false"),
        Spec::selection("Integrator/Newton-Krylov", "auto",
                        "Solve Newton's linear systems with the whole Jacobian at the iterate: GMRES, each "
                        "product J v from the last evaluation's derivatives (the interface pressure's coupling "
                        "by conjugate gradients), preconditioned by Newton's matrix as set up. auto: with a "
                        "flexible housing, whose conformal contact stiffens within one Newton correction; on the "
                        "paper case it takes the Newton failures from 13 % of the steps to 0.13 % in less run "
                        "time. With the rigid housing the direct solve (docs/bearing.md) [-].",
                        "auto|true|false"),
        Spec::real_range("Integrator/Newton tolerance", "0.1",
                         "Newton stops when its update is below this fraction of the error test's tolerance "
                         "(ARKODE's nonlinear convergence coefficient). Looser is faster; with the layer alone "
                         "(Local compliance = none) keep 0.1: 0.3 already spoilt a test run [-].",
                         1e-3, 1.0),
      };
    }

    /// Output, stresses, Dang Van, and the commands that check a run.
    std::vector<app::ParameterSpec> output_risk_check_specs()
    {
      using Spec = app::ParameterSpec;
      return {
        Spec::integer_range("Output/Samples per ball pass", "40",
                            "Output times (fields, stresses, Dang Van steps) per ball pass period [-].", 4, 10000),
        Spec::selection("Stresses/Ring stresses", "full FE",
                        "The ring's stresses on the depth layers: full FE, the ring's own finite-element stresses of "
                        "the interface tractions and the balls' raceway loads, its bending between the balls "
                        "included (influence tables built once per ring, mesh and depth layers, and kept beside the "
                        "ring's model file); half-space, the interface tractions' stresses on an elastic half-space "
                        "(the paper's; it leaves out the ring's structural stress, docs/fe_reference.md) [-].",
                        "full FE|half-space"),
        text("Stresses/Ring mesh", "360x3x6x2",
             "Full FE ring stresses: the ring's mesh as 'around x radial x axial x axial land' cells (the "
             "element degree of the ring's reduction configuration), radially graded toward the interface. "
             "As many cells around as the interface grid has columns, or a divisor of them, keeps the tables "
             "small [-]."),
        Spec::real_range("Stresses/Ring mesh radial grading", "4",
                         "Full FE ring stresses: the thickest radial cell over the thinnest, the thinnest at the "
                         "interface [-].",
                         1.0, 100.0),
        Spec::selection("Stresses/Evaluator", "fft",
                        "Half-space ring stresses: the evaluator of the interface tractions' subsurface stresses: "
                        "fft (DC-FFT), mlmi, direct.",
                        "fft|mlmi|direct"),
        fft_plans_parameter("Stresses/FFT plans"),
        increasing(list(Spec::non_negative("Stresses/Depth layers", "0, 1e-4, 5e-4",
                                           "Depths below the ring's outer surface of the stress and risk layers [m]."))),
        Spec::positive("Dang Van/Bending fatigue limit", "690e6", "f-1 of the ring steel [Pa]."),
        Spec::positive("Dang Van/Torsion fatigue limit", "428e6", "t-1 of the ring steel [Pa]."),
        Spec::selection("Dang Van/Residual stress", "last_cycle_mean",
                        "Centre of the deviatoric path per ball pass cycle: running_mean (paper eq. 5), "
                        "last_cycle_mean, hypersphere.",
                        "running_mean|last_cycle_mean|hypersphere"),
        Spec::integer_range("Dang Van/Warm-up cycles", "1",
                            "Ball pass cycles (the ramp) before D_max accumulates [-].", 0, 100000),
        Spec::integer_range("Compare/Instants", "4",
                            "`fretsim compare`: instants of the last ball pass re-solved with the full FE model [-].", 1,
                            1000),
        list(Spec::real_range("Compare/Fixed-interface modes", "10, 20, 40",
                              "`fretsim compare`: fixed-interface mode counts m of the truncated models [-].", 0, 5000)),
        list(Spec::real_range("Compare/Characteristic constraint modes", "40, 80, 120",
                              "`fretsim compare`: characteristic constraint mode counts n_cc of the truncated models "
                              "[-].",
                              1, 5000)),
        Spec::integer_range("Compare/Full transient steps", "20",
                            "`fretsim compare`: steps of the full-FE transient (Newmark on the Winkler foundation, the "
                            "run's ball loads, the run's mean step) timed against the run; 0: none [-].",
                            0, 100000),
        text("Compare/Full transient housing", "",
             "`fretsim compare`: a ring_housing configuration of the housing alone (Mesh/Bodies = housing, held by its "
             "Reduction/Clamped surfaces), relative to this file: the full-FE transient is timed a second time with "
             "this housing meshed and joined to the ring by the layer (the full-FE equivalent of a run with the "
             "housing's half-space or a flexible housing); empty: the ring on the rigid foundation only [-]."),
        text("Compare/Results file", "",
             "`fretsim compare` and `fretsim reference`: the run to compare; empty: results/<this file's "
             "name>/results.h5 [-]."),
        text("Reference/Meshes", "360x3x4x6x2; 360x4x6x8x3",
             "`fretsim reference`: the full-FE meshes of ring and housing, coarse to fine, ';'-separated, each "
             "'around x radial ring x radial housing x axial x axial land' cells (the reduction configuration's "
             "geometry and material). The march's cost grows with P = grid columns / gcd(columns, cells around), "
             "the columns after which the mesh repeats on the grid: 1 for 360 around on 360 columns, 2 for 180 [-]."),
        Spec::real_range("Reference/Radial grading", "4",
                         "`fretsim reference`: radial cells in geometric progression, the thickest this many times the "
                         "thinnest at the interface [-].",
                         1.0, 1000.0),
        text("Reference/Housing", "",
             "`fretsim reference`: a ring_housing configuration of the housing (Mesh/Bodies = housing, held by its "
             "Reduction/Clamped surfaces), relative to this file: the full-FE housing; empty: a rigid housing (the "
             "layer alone between it and the ring) [-]."),
        Spec::integer_range("Reference/Substeps", "4",
                            "`fretsim reference`: quasi-static increments per output interval of the run (ball loads "
                            "and angles linear in between) [-].",
                            1, 1000),
        Spec::integer_range("Reference/Snapshots", "0",
                            "`fretsim reference`: the run's first N output times marched through; 0: all [-].", 0,
                            10000000),
        Spec::integer_range("Reference/Points per cell side", "3",
                            "`fretsim reference`: a cell's unit load is spread over s x s points, its displacement the "
                            "mean over them [-].",
                            1, 8),
      };
    }
  } // namespace

  std::vector<app::ParameterSpec> BearingHousingScene::parameter_specs()
  {
    std::vector<app::ParameterSpec> specs = model_bearing_loading_specs();
    for (auto group : {interface_specs(), integrator_specs(), output_risk_check_specs()})
      specs.insert(specs.end(), group.begin(), group.end());
    return specs;
  }

  namespace
  {
    using Settings = BearingHousingScene::Settings;
    using Material = contact::ElasticMaterial;

    Material elastic(const fem::Material &m) { return Material{m.youngs_modulus, m.poisson_ratio}; }

    /// The bearing's geometry from the ring's groove and Bearing/..., and the balls' contact stiffness.
    void read_bearing(Settings &s, const app::SceneParameters &par, const models::RingHousingRequest &body)
    {
      auto &b                   = s.run.bearing;
      b.ball_count              = static_cast<unsigned int>(par.get_integer("Bearing/Ball count"));
      b.ball_diameter           = par.get_double("Bearing/Ball diameter");
      b.pitch_diameter          = 2.0 * body.ring.groove_bottom_radius - b.ball_diameter;
      b.outer_groove_conformity = body.ring.groove_radius / b.ball_diameter;
      b.inner_groove_conformity = par.get_double("Bearing/Inner groove conformity");
      b.radial_clearance        = par.get_double("Bearing/Radial clearance");
      if (!(b.outer_groove_conformity > 0.5))
        par.reject("Bearing/Ball diameter", "the ring's groove radius must exceed half the ball diameter");
      if (!(b.pitch_diameter > b.ball_diameter))
        par.reject("Bearing/Ball diameter", "too large for the ring's groove bottom radius");
      const Material ring = elastic(body.materials.at(fem::MaterialId::ring));
      const double   contact_modulus =
        contact::MaterialPair{ring, {par.get_double("Bearing/Young's modulus"), par.get_double("Bearing/Poisson ratio")}}
          .contact_modulus();
      try
        {
          s.run.ball_stiffness = coupling::ball_contact_stiffness(b, contact_modulus).combined;
        }
      catch (const std::invalid_argument &error)
        {
          par.reject("Bearing/Ball diameter", error.what());
        }
      s.run.ball_damping = par.get_double("Bearing/Contact damping");
    }

    /// The inner ring's motion, the output times and the run's length.
    void read_loading(Settings &s, const app::SceneParameters &par)
    {
      s.run.inner_ring_speed     = par.get_double("Loading/Inner ring speed") * 2.0 * M_PI / 60.0;
      s.run.inner_displacement_x = par.get_double("Loading/Inner ring displacement x");
      s.run.inner_displacement_y = par.get_double("Loading/Inner ring displacement y");
      s.run.ramp_time            = par.get_double("Loading/Ramp time");
      s.run.first_ball_angle     = par.get_double("Loading/First ball angle");
      if (!(s.run.inner_ring_speed > 0.0))
        par.reject("Loading/Inner ring speed", "must be > 0: the balls must pass");
      s.kinematics            = coupling::cage_kinematics(s.run.bearing, s.run.inner_ring_speed);
      s.samples_per_ball_pass = static_cast<int>(par.get_integer("Output/Samples per ball pass"));
      s.run.output_interval   = 1.0 / (s.kinematics.ball_pass_frequency * s.samples_per_ball_pass);
      s.run.duration =
        std::round(par.get_double("Loading/Ball pass periods") * s.samples_per_ball_pass) * s.run.output_interval;
    }

    /// The interface law, its local compliance and the residual flexibilities.
    void read_interface(Settings &s, const app::SceneParameters &par, const Material &ring_material,
                        double ring_outer_radius, double ring_wall)
    {
      auto &interface                = s.run.interface;
      interface.friction_coefficient = par.get_double("Interface/Friction coefficient");
      interface.normal_stiffness     = par.get_double("Interface/Normal stiffness");
      interface.tangential_stiffness = par.get_double("Interface/Tangential stiffness");
      interface.normal_damping_time  = par.get_double("Interface/Damping time");
      interface.radial_interference  = par.get_double("Interface/Radial interference");
      interface.onset_pressure       = par.get_double("Interface/Onset pressure");
      interface.closure_pressure     = s.housing_model ? par.get_double("Interface/Closure pressure") : 0.0;
      interface.bristles_follow_closure = par.get_bool("Interface/Bristles follow the closure");
      s.in_step_bristle_law          = par.get("Interface/In-step bristle law");
      s.bristle_update               = par.get("Interface/Bristle update");
      interface.bristle_update       = s.bristle_update == "exponential" ? contact::BristleUpdate::exponential
                                                                          : contact::BristleUpdate::implicit_euler;
      interface.in_step_bristle_law  = s.in_step_bristle_law == "implicit Euler"
                                         ? coupling::InStepBristleLaw::implicit_euler
                                         : coupling::InStepBristleLaw::linearised;
      s.local_compliance          = par.get("Interface/Local compliance");
      const double housing_outside = par.get_double("Interface/Housing outer radius");
      if (const std::string local = s.local_compliance; local != "none")
        {
          if (s.housing_model)
            par.reject("Interface/Local compliance",
                       "none with a flexible housing (Model/Housing reduction configuration): its reduced model "
                       "carries its compliance");
          const Material housing{par.get_double("Interface/Housing Young's modulus"),
                                 par.get_double("Interface/Housing Poisson ratio")};
          interface.local_compliance_modulus =
            local == "both" ? contact::MaterialPair{ring_material, housing}.contact_modulus() : housing.plane_modulus();
          if (housing_outside > 0.0 && local == "housing")
            {
              if (!(housing_outside > ring_outer_radius))
                par.reject("Interface/Housing outer radius",
                           "0 or more than the housing's bore, the ring's outer radius " + std::to_string(ring_outer_radius) +
                             " m");
              interface.housing_uniform_compliance = coupling::lame_bore_compliance(
                ring_outer_radius, housing_outside, housing.youngs_modulus, housing.poisson_ratio);
            }
        }
      if (housing_outside > 0.0 && s.local_compliance != "housing")
        par.reject("Interface/Housing outer radius", "0 unless Local compliance = housing");
      s.ring_residual = par.get_bool("Interface/Ring residual flexibility");
      if (s.ring_residual && s.local_compliance == "both")
        par.reject("Interface/Ring residual flexibility",
                   "false with Local compliance = both: the ring's half-space and its residual flexibility stand for "
                   "the same local compliance");
      s.housing_residual               = par.get_bool("Interface/Housing residual flexibility");
      s.run.pressure_residual_at_balls = s.ring_residual && par.get_bool("Interface/Residual flexibility at the balls");
      if (par.get_bool("Interface/Half-space completion"))
        {
          s.ring_completion_modulus = ring_material.plane_modulus();
          const double wavelength   = par.get_double("Interface/Half-space completion wavelength");
          interface.half_space_completion_wavelength = wavelength > 0.0 ? wavelength : ring_wall;
        }
      s.run.damping_ratio = par.get_double("Ring/Damping ratio");
    }

    void read_integrator(Settings &s, const app::SceneParameters &par)
    {
      auto &integrator                     = s.run.integrator;
      integrator.order                     = static_cast<int>(par.get_integer("Integrator/Order"));
      integrator.relative_tolerance        = par.get_double("Integrator/Relative tolerance");
      integrator.displacement_tolerance    = par.get_double("Integrator/Displacement tolerance");
      integrator.maximum_step              = par.get_double("Integrator/Maximum step");
      integrator.maximum_steps             = par.get_integer("Integrator/Maximum steps per output");
      integrator.maximum_newton_iterations = static_cast<int>(par.get_integer("Integrator/Maximum Newton iterations"));
      integrator.newton_tolerance          = par.get_double("Integrator/Newton tolerance");
      integrator.maximum_newton_failures =
        static_cast<int>(par.get_integer("Integrator/Maximum Newton failures per step"));
      integrator.jacobian_interval = par.get_integer("Integrator/Jacobian interval");
      integrator.deduce_stage_derivative = par.get_bool("Integrator/Deduce stage derivatives");
      integrator.secant_updates          = par.get_bool("Integrator/Secant updates");
      const std::string balls = par.get("Integrator/Balls at the iterate");
      integrator.balls_at_iterate        = balls == "true" || (balls == "auto" && s.housing_model.has_value());
      integrator.bristles_at_iterate     = par.get_bool("Integrator/Bristles at the iterate");
      const std::string krylov           = par.get("Integrator/Newton-Krylov");
      integrator.newton_krylov           = krylov == "true" || (krylov == "auto" && s.housing_model.has_value());
      const std::string &predictor = s.stage_predictor = par.get("Integrator/Stage predictor");
      integrator.predictor = predictor == "trivial"          ? coupling::StagePredictor::trivial
                             : predictor == "maximum order"  ? coupling::StagePredictor::maximum_order
                             : predictor == "variable order" ? coupling::StagePredictor::variable_order
                                                             : coupling::StagePredictor::cutoff_order;
    }

    /// The ring's stress model, its depth layers and Dang Van.
    void read_stresses_and_risk(Settings &s, const app::SceneParameters &par)
    {
      s.stress_evaluator.method            = par.get("Stresses/Evaluator");
      s.stress_evaluator.measure_fft_plans = par.get("Stresses/FFT plans") == "measure";
      s.depth_layers                       = par.get_double_list("Stresses/Depth layers");
      if (s.depth_layers.empty())
        par.reject("Stresses/Depth layers", "expected at least one depth z >= 0 [m]");
      if (par.get("Stresses/Ring stresses") == "full FE")
        s.ring_stress = models::ring_stress_source(par, s.ring_model, s.depth_layers);
      try
        {
          s.dang_van_constants = contact::DangVanConstants::from_fatigue_limits(
            par.get_double("Dang Van/Bending fatigue limit"), par.get_double("Dang Van/Torsion fatigue limit"));
        }
      catch (const std::invalid_argument &error)
        {
          par.reject("Dang Van/Torsion fatigue limit", error.what());
        }
      s.dang_van.centre          = contact::parse_residual_stress_centre(par.get("Dang Van/Residual stress"));
      s.dang_van.steps_per_cycle = s.samples_per_ball_pass;
      s.dang_van.warmup_cycles   = static_cast<int>(par.get_integer("Dang Van/Warm-up cycles"));
    }
  } // namespace

  BearingHousingScene::BearingHousingScene(app::SceneParameters p)
    : parameters(std::move(p))
    , settings(std::make_unique<Settings>())
  {
    auto       &s    = *settings;
    const auto &par  = parameters;
    s.ring_model     = models::ring_model_source(par);
    s.build_model    = par.get_bool("Model/Build if missing");
    // The ring's geometry and material come from the reduction configuration.
    const auto body = models::read_ring_housing_request(models::read_ring_housing_parameters(s.ring_model.config, {}));
    if (!body.ring.has_groove())
      par.reject("Model/Reduction configuration", "the ring in '" + s.ring_model.config +
                                                    "' has no raceway groove; a ball bearing needs one");
    if (!par.get("Model/Housing reduction configuration").empty())
      {
        s.housing_model    = models::housing_model_source(par);
        const auto housing = models::read_housing_around(s.housing_model->config, body.ring, par.file(),
                                                         "Model/Housing reduction configuration");
        if (par.get_bool("Interface/Half-space completion"))
          s.housing_completion_modulus = elastic(housing.request.materials.at(fem::MaterialId::housing)).plane_modulus();
      }
    else
      for (const char *parameter : {"Model/Housing characteristic constraint modes", "Model/Housing fixed-interface modes"})
        if (par.get_integer(parameter) != 0)
          par.reject(parameter, "0 without a flexible housing (Model/Housing reduction configuration)");
    read_bearing(s, par, body);
    read_loading(s, par);
    const Material ring_material = elastic(body.materials.at(fem::MaterialId::ring));
    s.ring_poisson_ratio         = ring_material.poisson_ratio;
    read_interface(s, par, ring_material, body.ring.outer_radius,
                   body.ring.outer_radius - body.ring.groove_bottom_radius);
    read_integrator(s, par);
    read_stresses_and_risk(s, par);
  }

  BearingHousingScene::~BearingHousingScene() = default;

  BearingHousingScene::ReferenceView BearingHousingScene::reference_view() const
  {
    const Settings &s = *settings;
    ReferenceView   v;
    v.reduction_config     = s.ring_model.config;
    v.friction_coefficient = s.run.interface.friction_coefficient;
    v.normal_stiffness     = s.run.interface.normal_stiffness;
    v.tangential_stiffness = s.run.interface.tangential_stiffness;
    v.radial_interference  = s.run.interface.radial_interference;
    v.depth_layers         = s.depth_layers;
    v.dang_van_constants   = s.dang_van_constants;
    v.dang_van             = s.dang_van;
    v.local_compliance     = s.local_compliance;
    v.flexible_housing     = s.housing_model.has_value();
    return v;
  }

  namespace
  {
    /// The co-simulation's view of a model file.
    /// The parts every body's model has: matrices and the interface grid operator.
    template <typename Body>
    Body reduced_body(const reduction::ReducedModel &model)
    {
      Body body;
      body.n                      = model.matrices.size();
      body.mass                   = model.matrices.mass;
      body.stiffness              = model.matrices.stiffness;
      const auto &g               = model.interface_grid.grid;
      body.interface_radius       = g.radius;
      body.interface_grid         = {g.nx, g.ny, g.hx, g.hy, g.x_min, g.y_min};
      body.interface_displacement = model.interface_grid.displacement;
      return body;
    }

    coupling::ReducedRing reduced_ring(const reduction::ReducedModel &model)
    {
      auto ring = reduced_body<coupling::ReducedRing>(model);
      for (const double f : model.free_frequencies_hz)
        if (f >= 1.0)
          {
            ring.lowest_elastic_frequency_hz = f;
            break;
          }
      ring.raceway_angles          = model.raceway.angles.size();
      ring.raceway_approach        = model.raceway.approach;
      ring.raceway_footprint_loads = model.raceway.footprint_loads();
      return ring;
    }
  } // namespace

  namespace
  {
    using Settings = BearingHousingScene::Settings;

    /// The ring's reduced model with the housing's joined to it, as the
    /// co-simulation sees them, and the ring model file's input hash.
    struct LoadedRing
    {
      coupling::ReducedRing ring;
      std::string           input_hash;
      std::optional<models::RingStressTable> ring_stress; ///< full FE ring stresses
    };

    /// Reads the reduced models (or builds them when missing or stale) and
    /// joins their residual flexibilities and the housing's model to the ring.
    LoadedRing load_ring(const Settings &s, const app::SceneParameters &parameters, models::ModelLoader &loader)
    {
      const reduction::ReducedModel model = loader.load(s.ring_model, parameters);
      LoadedRing                    loaded{reduced_ring(model), model.input_hash, std::nullopt};
      auto                         &ring = loaded.ring;
      if (s.ring_stress)
        loaded.ring_stress.emplace(loader.load_ring_stress(*s.ring_stress, model, parameters));
      if (s.ring_residual)
        {
          if (model.residual.empty())
            parameters.reject("Interface/Ring residual flexibility",
                              "false, or a model file with the ring's residual flexibility: '" + s.ring_model.file +
                                "' has none (a free ring reduced with a raceway, an interface grid and more than six "
                                "characteristic constraint modes has)");
          ring.residual_pressure     = model.residual.inward_per_pressure(ring.interface_grid.cell_area());
          ring.residual_ball         = model.residual.ball;
          ring.residual_column_angle = model.residual.column_angle;
          ring.residual_half_space_modulus = s.ring_completion_modulus;
        }
      try
        {
          ring.check();
        }
      catch (const std::invalid_argument &error)
        {
          parameters.reject("Model/Model file", std::string(error.what()) +
                                                  " (rebuild it with `fretsim reduce`: it needs an interface grid and "
                                                  "Reduction/Raceway ball positions > 0)");
        }
      if (!s.housing_model)
        return loaded;
      const auto housing_model = loader.load(*s.housing_model, parameters);
      auto       housing       = reduced_body<coupling::ReducedHousing>(housing_model);
      if (s.housing_residual)
        {
          if (housing_model.residual.empty())
            parameters.reject("Interface/Housing residual flexibility",
                              "false, or a housing model file with its residual flexibility: '" +
                                s.housing_model->file +
                                "' has none (a housing held at Reduction/Clamped surfaces with an interface grid "
                                "on its bore has)");
          // The bore moves out under the pressure: the gap opens.
          housing.residual_pressure = housing_model.residual.inward_per_pressure(housing.interface_grid.cell_area());
          for (double &value : housing.residual_pressure)
            value = -value;
          housing.residual_half_space_modulus = s.housing_completion_modulus;
        }
      try
        {
          ring = coupling::with_flexible_housing(ring, housing);
        }
      catch (const std::invalid_argument &error)
        {
          parameters.reject("Model/Housing model file", error.what());
        }
      return loaded;
    }

    /// results.h5 with the run's attributes and its declared series and fields.
    std::unique_ptr<output::ResultsFile> open_results(const std::string &path, const Settings &s,
                                                      const app::SceneParameters &parameters,
                                                      const LoadedRing &loaded)
    {
      const auto &ring    = loaded.ring;
      const auto &grid    = ring.interface_grid;
      auto        results = std::make_unique<output::ResultsFile>(path, "bearing_housing", parameters.to_prm());
      write_surface_grid(*results, grid, s.depth_layers);
      results->set_root_attribute("interface_radius_m", ring.interface_radius);
      results->set_root_attribute("ball_pass_frequency_hz", s.kinematics.ball_pass_frequency);
      results->set_root_attribute("cage_frequency_hz", s.kinematics.cage_speed / (2.0 * M_PI));
      results->set_root_attribute("ball_count", static_cast<double>(s.run.bearing.ball_count));
      results->set_root_attribute("model_file", s.ring_model.file);
      // modal_coordinates holds the ring's coordinates, then the housing's.
      results->set_root_attribute("housing", s.housing_model ? "flexible" : "rigid");
      results->set_root_attribute("local_compliance", s.local_compliance);
      results->set_root_attribute("in_step_bristle_law", s.in_step_bristle_law);
      results->set_root_attribute("bristle_update", s.bristle_update);
      results->set_root_attribute("housing_coordinates", static_cast<double>(ring.housing_coordinates));
      if (s.housing_model)
        results->set_root_attribute("housing_model_file", s.housing_model->file);
      results->set_root_attribute("model_input_hash", loaded.input_hash);
      results->set_root_attribute("ring_stresses", s.ring_stress ? "full FE" : "half-space");
      results->set_root_attribute("stress_components",
                                  "xx (circumferential), yy (axial), zz (radial, depth into the ring), yz, xz, xy; "
                                  "tension positive, in the outer ring");
      const std::vector<std::pair<std::string, std::string>> series{
        {"interface_force_x", "N"}, {"interface_force_y", "N"}, {"ball_load_total_x", "N"}, {"ball_load_total_y", "N"},
        {"inner_ring_displacement_y", "m"}, {"contact_fraction", "1"}, {"slip_fraction", "1"}, {"risk_max_so_far", "1"}};
      for (const auto &[name, unit] : series)
        results->declare_series(name, unit);
      const std::vector<std::size_t> field{static_cast<std::size_t>(grid.ny), static_cast<std::size_t>(grid.nx)};
      results->declare_field("pressure", "Pa", field);
      results->declare_field("shear_x", "Pa", field);
      results->declare_field("shear_y", "Pa", field);
      results->declare_field("effective_friction", "1", field);
      // The ring's stresses and risk are dense: deflate took 2.4 s of a
      // 22.5 s run for 35 % off the file.
      results->declare_field("risk", "1", {s.depth_layers.size(), field[0], field[1]}, false);
      results->declare_field("stress", "Pa",
                             {s.depth_layers.size(), std::size_t(contact::stress_component_count), field[0], field[1]},
                             false);
      results->declare_field("ball_angle", "rad", {s.run.bearing.ball_count});
      results->declare_field("ball_load", "N", {s.run.bearing.ball_count});
      results->declare_field("modal_coordinates", "1", {ring.n});
      return results;
    }

    /// What the run keeps of its output times beyond results.h5.
    struct RunRecord
    {
      double stress_seconds = 0.0, dang_van_seconds = 0.0, output_seconds = 0.0;
      std::vector<std::vector<double>> pressure_history; ///< the last two ball passes
      std::vector<double>              top_pressure, times;
      double lower_half_pressure = 0.0, peak_pressure = 0.0, peak_ball_load = 0.0; ///< [Pa], [Pa], [N]
    };

    /// The ring's stresses on the run's depth layers at an output time.
    using StressModel = std::function<void(const coupling::Snapshot &, contact::StressField &)>;

    /// The full-FE ring's stresses of the tractions and the balls, or the
    /// tractions' stresses on a half-space. Throws InputError for an evaluator
    /// that cannot work on the grid.
    StressModel stress_model(const Settings &s, const LoadedRing &loaded, const app::SceneParameters &parameters)
    {
      const contact::SurfaceGrid &grid = loaded.ring.interface_grid;
      if (loaded.ring_stress)
        return [&table = *loaded.ring_stress, grid, layers = static_cast<int>(s.depth_layers.size())](
                 const coupling::Snapshot &snap, contact::StressField &field) {
          field.resize(layers, grid.ny, grid.nx);
          table.evaluate(snap.ball_angles, snap.ball_loads, *snap.pressure, *snap.shear_x, *snap.shear_y,
                         field.values);
        };
      std::shared_ptr<contact::SubsurfaceStress> half_space;
      try
        {
          half_space = contact::make_subsurface_stress(grid, s.depth_layers, s.ring_poisson_ratio, s.stress_evaluator);
        }
      catch (const std::invalid_argument &error)
        {
          parameters.reject("Stresses/Evaluator", error.what());
        }
      return [half_space](const coupling::Snapshot &snap, contact::StressField &field) {
        half_space->evaluate(*snap.pressure, *snap.shear_x, *snap.shear_y, field);
      };
    }

    /// At every output time: stresses, Dang Van, a snapshot in results.h5,
    /// the record; false once an interruption is asked for.
    class OutputStep
    {
    public:
      OutputStep(const Settings &s, const contact::SurfaceGrid &grid, const StressModel &stresses,
                 contact::DangVanField &risk, output::ResultsFile &results, app::Progress &progress)
        : s(s)
        , grid(grid)
        , top_cell(grid.index(grid.nx / 4, grid.ny / 2)) // θ = 90°: the top
        , stresses(stresses)
        , risk(risk)
        , results(results)
        , progress(progress)
      {}

      bool operator()(const coupling::Snapshot &snap)
      {
        auto start = Clock::now();
        stresses(snap, stress);
        record.stress_seconds += seconds_since(start);
        start = Clock::now();
        risk.add_step(stress);
        record.dang_van_seconds += seconds_since(start);
        start = Clock::now();
        write_snapshot(snap);
        keep(snap);
        record.output_seconds += seconds_since(start);
        progress.update(++done, snap.time);
        return !app::interrupt_requested();
      }

      RunRecord record;

    private:
      void write_snapshot(const coupling::Snapshot &snap)
      {
        double so_far = 0.0;
        for (const double d : risk.risk_max())
          so_far = std::max(so_far, d);
        results.append_series_row({snap.interface_force_x, snap.interface_force_y, snap.ball_force_x,
                                   snap.ball_force_y, snap.inner_displacement_y, snap.contact_fraction,
                                   snap.slip_fraction, so_far});
        results.append_snapshot(snap.time, {snap.pressure, snap.shear_x, snap.shear_y, &snap.effective_friction,
                                            &risk.risk(), &stress.values, &snap.ball_angles, &snap.ball_loads,
                                            &snap.q});
        results.flush();
      }

      void keep(const coupling::Snapshot &snap)
      {
        for (int j = 0; j < grid.ny; ++j)
          for (int i = grid.nx / 2 + 1; i < grid.nx; ++i) // θ in (180°, 360°): the unloaded half
            record.lower_half_pressure = std::max(record.lower_half_pressure, (*snap.pressure)[grid.index(i, j)]);
        for (const double p : *snap.pressure)
          record.peak_pressure = std::max(record.peak_pressure, p);
        for (const double q : snap.ball_loads)
          record.peak_ball_load = std::max(record.peak_ball_load, q);
        record.pressure_history.push_back(*snap.pressure);
        if (record.pressure_history.size() > static_cast<std::size_t>(2 * s.samples_per_ball_pass))
          record.pressure_history.erase(record.pressure_history.begin());
        record.top_pressure.push_back((*snap.pressure)[top_cell]);
        record.times.push_back(snap.time);
      }

      const Settings             &s;
      const contact::SurfaceGrid &grid;
      const std::size_t           top_cell;
      const StressModel          &stresses;
      contact::DangVanField      &risk;
      output::ResultsFile        &results;
      app::Progress              &progress;
      contact::StressField        stress;
      long                        done = 0;
    };

    /// Where the risk peaks, and the ball pass frequency and periodicity
    /// measured from the settled part of the run.
    struct RunMeasures
    {
      std::size_t worst = 0, worst_layer = 0;
      int         worst_i = 0, worst_j = 0;
      double      risk_max           = std::numeric_limits<double>::quiet_NaN();
      double      measured_frequency = std::numeric_limits<double>::quiet_NaN();
      double      correlation        = std::numeric_limits<double>::quiet_NaN();
      double      periodicity        = 0.0;
    };

    RunMeasures measure(const Settings &s, const contact::SurfaceGrid &grid, const contact::DangVanField &risk,
                        const RunRecord &record)
    {
      RunMeasures m;
      const auto &risk_max = risk.risk_max();
      for (std::size_t k = 0; k < risk_max.size(); ++k)
        if (risk_max[k] > risk_max[m.worst])
          m.worst = k;
      const std::size_t cells = grid.size(), worst_cell = m.worst % cells;
      m.worst_layer = m.worst / cells;
      m.worst_i     = static_cast<int>(worst_cell % grid.nx);
      m.worst_j     = static_cast<int>(worst_cell / grid.nx);
      if (!risk_max.empty())
        m.risk_max = risk_max[m.worst];
      // The settled part: a quarter ball pass after the ramp. The estimate
      // needs 2.8 ball passes of it (twice the longest lag searched).
      const double        ball_pass = s.kinematics.ball_pass_frequency;
      const double        settle    = s.run.ramp_time + 0.25 / ball_pass;
      std::vector<double> settled;
      for (std::size_t k = 0; k < record.times.size(); ++k)
        if (record.times[k] >= settle)
          settled.push_back(record.top_pressure[k]);
      try
        {
          const double period = coupling::autocorrelation_period(settled, s.run.output_interval, 0.6 / ball_pass,
                                                                  1.4 / ball_pass, &m.correlation);
          m.measured_frequency = 1.0 / period;
        }
      catch (const std::invalid_argument &)
        { // too short a run or a constant signal: no measurement
        }
      m.periodicity = coupling::periodicity_error(record.pressure_history, s.run.output_interval, 1.0 / ball_pass);
      return m;
    }

    /// How the run ended, as results.h5 and summary.json say it.
    std::string run_status(bool completed, const std::string &failure)
    {
      return completed ? "complete" : (failure.empty() ? "interrupted" : "failed");
    }

    output::Summary integrator_summary(const Settings &s, const coupling::IntegratorStatistics &stats)
    {
      output::Summary integrator;
      integrator.set("method", std::string("ARKODE ARKStep DIRK order ") + std::to_string(s.run.integrator.order));
      integrator.set("stage_predictor", s.stage_predictor);
      integrator.set("maximum_newton_iterations", static_cast<long long>(s.run.integrator.maximum_newton_iterations));
      integrator.set("jacobian_interval", static_cast<long long>(s.run.integrator.jacobian_interval));
      integrator.set("deduce_stage_derivatives", s.run.integrator.deduce_stage_derivative);
      integrator.set("secant_updates", s.run.integrator.secant_updates);
      integrator.set("balls_at_iterate", s.run.integrator.balls_at_iterate);
      integrator.set("bristles_at_iterate", s.run.integrator.bristles_at_iterate);
      integrator.set("newton_krylov", s.run.integrator.newton_krylov);
      integrator.set("steps", static_cast<long long>(stats.steps));
      integrator.set("rhs_evaluations", static_cast<long long>(stats.rhs_evaluations));
      integrator.set("newton_iterations", static_cast<long long>(stats.newton_iterations));
      integrator.set("newton_convergence_failures", static_cast<long long>(stats.newton_failures));
      integrator.set("fallbacks_to_arkode_newton_start", static_cast<long long>(stats.fallbacks));
      integrator.set("error_test_failures", static_cast<long long>(stats.error_test_failures));
      integrator.set("jacobian_evaluations", static_cast<long long>(stats.jacobian_evaluations));
      integrator.set("krylov_iterations", static_cast<long long>(stats.krylov_iterations));
      integrator.set("krylov_fresh_matrices", static_cast<long long>(stats.krylov_fresh_matrices));
      integrator.set("linear_solver_setups", static_cast<long long>(stats.linear_setups));
      integrator.set("smallest_step_s", stats.smallest_step);
      integrator.set("largest_step_s", stats.largest_step);
      return integrator;
    }

    /// The interface model's summary entries: local compliance, residual
    /// flexibilities and where their half-space completion adds compliance.
    void summarise_interface(output::Summary &summary, const Settings &s, const coupling::ReducedRing &ring,
                             const coupling::BearingCosimulation &simulation)
    {
      summary.set("local_compliance", s.local_compliance);
      summary.set("in_step_bristle_law", s.in_step_bristle_law);
      summary.set("bristle_update", s.bristle_update);
      const auto *local = simulation.local_compliance(); // the closure is the local compliance's
      summary.set("bristles_follow_closure",
                  s.run.interface.bristles_follow_closure && local && local->contact_pressure() > 0.0);
      summary.set("local_compliance_modulus_Pa", s.run.interface.local_compliance_modulus);
      summary.set("housing_uniform_compliance_m_per_Pa", s.run.interface.housing_uniform_compliance);
      summary.set("ring_residual_flexibility", s.ring_residual);
      summary.set("housing_residual_flexibility", s.housing_model && s.housing_residual);
      summary.set("residual_flexibility_at_balls", s.run.pressure_residual_at_balls && !ring.residual_ball.empty());
      summary.set("half_space_completion", ring.residual_half_space_modulus > 0.0);
      if (local && !local->completion_by_wavenumber().empty())
        { // where the residual flexibilities' FE meshes lose their bodies' local compliance
          const auto     &added = local->completion_by_wavenumber();
          output::Summary completion;
          completion.set("modulus_Pa", ring.residual_half_space_modulus);
          completion.set("wavelength_m", s.run.interface.half_space_completion_wavelength);
          const auto first = std::find_if(added.begin(), added.end(), [](double share) { return share > 0.1; });
          completion.set("longest_wavelength_over_10_percent_m",
                         first == added.end()
                           ? 0.0
                           : 2.0 * M_PI * ring.interface_radius /
                               static_cast<double>(std::max<std::ptrdiff_t>(first - added.begin(), 1)));
          completion.set("added_share_by_wavenumber", added);
          summary.set_object("half_space_completion_spectrum", completion);
        }
      const auto &stats = simulation.statistics();
      if (stats.raceway_residual_largest > 0.0)
        { // the reciprocal term's size and the sweep's correction of it
          output::Summary raceway;
          raceway.set("largest_inward_m", stats.raceway_residual_largest);
          raceway.set("largest_correction_m", stats.raceway_residual_largest_correction);
          summary.set_object("raceway_residual", raceway);
        }
    }

    /// The risk maximum's place and time, the ball pass measurement and the peaks.
    void summarise_results(output::Summary &summary, const Settings &s, const coupling::ReducedRing &ring,
                           const contact::DangVanField &risk, const RunRecord &record, const RunMeasures &m)
    {
      const double nan  = std::numeric_limits<double>::quiet_NaN();
      const auto  &grid = ring.interface_grid;
      summary.set("simulated_time_s", record.times.empty() ? 0.0 : record.times.back());
      summary.set("ball_pass_frequency_hz", s.kinematics.ball_pass_frequency);
      summary.set("ball_pass_frequency_measured_hz", m.measured_frequency);
      summary.set("ball_pass_frequency_error", m.measured_frequency / s.kinematics.ball_pass_frequency - 1.0);
      summary.set("ball_pass_autocorrelation", m.correlation);
      summary.set("periodicity_error", m.periodicity);
      summary.set("peak_pressure_Pa", record.peak_pressure);
      summary.set("peak_ball_load_N", record.peak_ball_load);
      summary.set("lower_half_peak_pressure_Pa", record.lower_half_pressure);
      summary.set("risk_max", m.risk_max);
      summary.set("risk_max_theta_deg", grid.x(m.worst_i) / ring.interface_radius * 180.0 / M_PI);
      summary.set("risk_max_axial_m", grid.y(m.worst_j));
      summary.set("risk_max_depth_m", s.depth_layers[m.worst_layer]);
      summary.set("risk_max_time_s", risk.risk_max_step().empty() || risk.risk_max_step()[m.worst] < 0
                                       ? nan
                                       : risk.risk_max_step()[m.worst] * s.run.output_interval);
      summary.set("risk_infinite_points", static_cast<long long>(risk.infinite_risk_max_count()));
      summary.set("dang_van_cycles", static_cast<long long>(risk.complete_cycles()));
    }

    /// Which stresses the risk sees and, for the full FE's, its tables.
    void summarise_stresses(output::Summary &summary, const Settings &s, const LoadedRing &loaded)
    {
      summary.set("ring_stresses", std::string(s.ring_stress ? "full FE" : "half-space"));
      if (!loaded.ring_stress)
        return;
      const auto         &t = loaded.ring_stress->tables();
      const auto         &d = s.ring_stress->divisions;
      output::Summary     tables;
      tables.set("file", s.ring_stress->file);
      tables.set("mesh", std::to_string(d.circumferential) + "x" + std::to_string(d.radial_ring) + "x" +
                           std::to_string(d.axial) + "x" + std::to_string(d.axial_land));
      tables.set("radial_grading", d.radial_grading);
      tables.set("dofs", static_cast<long long>(t.dofs));
      tables.set("period_columns", static_cast<long long>(t.period));
      tables.set("solves", static_cast<long long>(t.solves));
      tables.set("build_seconds", t.seconds);
      summary.set_object("ring_stress_tables", tables);
    }

    /// Where the wall time went, by stage, and per inner ring revolution.
    void summarise_times(output::Summary &summary, const Settings &s, const coupling::IntegratorStatistics &stats,
                         const RunRecord &record, double model_seconds, double run_seconds)
    {
      if (stats.local_compliance.solves > 0)
        { // the pressure solve's share of the contact time (half-space, residual flexibilities), in convolutions
          output::Summary local;
          local.set("pressure_solves", static_cast<long long>(stats.local_compliance.solves));
          local.set("pressure_convolutions", static_cast<long long>(stats.local_compliance.solve_convolutions));
          local.set("jacobian_sensitivities", static_cast<long long>(stats.local_compliance.sensitivities));
          local.set("jacobian_convolutions", static_cast<long long>(stats.local_compliance.sensitivity_convolutions));
          local.set("jacobian_reuses", static_cast<long long>(stats.local_compliance.sensitivity_reuses));
          local.set("jacobian_factorisations",
                    static_cast<long long>(stats.local_compliance.sensitivity_factorisations));
          local.set("jacobian_single_precision_factorisations",
                    static_cast<long long>(stats.local_compliance.sensitivity_single_precision));
          local.set("krylov_pressure_changes", static_cast<long long>(stats.local_compliance.changes));
          local.set("krylov_convolutions", static_cast<long long>(stats.local_compliance.change_convolutions));
          summary.set_object("local_compliance_solver", local);
        }
      output::Summary stage_times;
      stage_times.set("model", model_seconds);
      stage_times.set("integrator", stats.integrator_seconds);
      stage_times.set("contact", stats.contact_seconds);
      stage_times.set("stresses", record.stress_seconds);
      stage_times.set("dang_van", record.dang_van_seconds);
      stage_times.set("output", record.output_seconds);
      stage_times.set("run", run_seconds);
      summary.set_object("stage_times_s", stage_times);
      const double revolution = 2.0 * M_PI / s.run.inner_ring_speed;
      summary.set("seconds_per_inner_ring_revolution", record.times.empty() || record.times.back() <= 0.0
                                                         ? std::numeric_limits<double>::quiet_NaN()
                                                         : run_seconds * revolution / record.times.back());
    }
  } // namespace

  void BearingHousingScene::prepare()
  {
    models::ModelLoader loader(settings->build_model, true);
    load_ring(*settings, parameters, loader);
    loader.finish();
  }

  RunReport BearingHousingScene::run(const RunOptions &options)
  {
    const auto &s         = *settings;
    const auto  run_start = Clock::now();
    RunReport   report;
    namespace fs = std::filesystem;

    // 1. The reduced models: read them, or build them when missing or stale.
    models::ModelLoader loader(s.build_model, options.progress);
    const LoadedRing    loaded = load_ring(s, parameters, loader);
    loader.finish(); // the models are built: the run needs no MPI
    const double model_seconds = seconds_since(run_start);
    const auto  &ring          = loaded.ring;
    const auto  &grid          = ring.interface_grid;

    // 2. Stages that can fail on the model's data, before anything is written.
    const StressModel             stresses = stress_model(s, loaded, parameters);
    coupling::BearingCosimulation simulation(ring, s.run);
    contact::DangVanField         risk(s.depth_layers.size() * grid.size(), s.dang_van_constants, s.dang_van);

    // 3. Output.
    fs::create_directories(options.output_directory);
    report.results_file = (fs::path(options.output_directory) / "results.h5").string();
    report.summary_file = (fs::path(options.output_directory) / "summary.json").string();
    auto results = open_results(report.results_file, s, parameters, loaded);

    // 4. The run: at every output time stresses, Dang Van, a snapshot.
    app::Progress progress("bearing_housing", std::lround(s.run.duration / s.run.output_interval) + 1,
                           options.progress);
    OutputStep  output_step(s, grid, stresses, risk, *results, progress);
    const auto  integrate_start = Clock::now();
    std::string failure;
    try
      {
        report.completed = simulation.run([&](const coupling::Snapshot &snap) { return output_step(snap); });
      }
    catch (const std::runtime_error &error)
      {
        failure          = error.what();
        report.completed = false;
      }
    progress.finish();
    const double     run_seconds = seconds_since(integrate_start);
    const auto      &stats       = simulation.statistics();
    RunRecord       &record      = output_step.record;

    // 5. Risk maximum, ball pass frequency, periodicity; the end of results.h5.
    const RunMeasures measures = measure(s, grid, risk, record);
    if (!risk.risk_max().empty())
      results->write_dataset("/fields/risk_max", "1", {s.depth_layers.size(), static_cast<std::size_t>(grid.ny),
                                                       static_cast<std::size_t>(grid.nx)},
                             risk.risk_max());
    // What `fretsim compare` sets a full-FE transient against: the run's
    // integrator steps and the wall time they took (integration, contact,
    // stresses, Dang Van and output of the steps).
    results->set_root_attribute("integrator_steps", static_cast<double>(stats.steps));
    results->set_root_attribute("run_seconds", run_seconds);
    results->set_root_attribute("inner_ring_frequency_hz", s.run.inner_ring_speed / (2.0 * M_PI));
    results->set_root_attribute("status", run_status(report.completed, failure));
    results->flush();
    const auto output_start = Clock::now();
    results->write_xdmf((fs::path(options.output_directory) / "results.xdmf").string());
    results.reset();
    record.output_seconds += seconds_since(output_start);

    // 6. summary.json, the report and the figures.
    output::Summary summary;
    summary.set("scene", std::string("bearing_housing"));
    summary.set("status", run_status(report.completed, failure));
    if (!failure.empty())
      summary.set("error", failure);
    summary.set("model_file", s.ring_model.file);
    summary.set("model_built", loader.built());
    summary.set("reduced_coordinates", static_cast<long long>(ring.n));
    summary.set("housing", std::string(s.housing_model ? "flexible" : "rigid"));
    summary.set("housing_coordinates", static_cast<long long>(ring.housing_coordinates));
    summary.set("interface_grid_cells", static_cast<long long>(grid.size()));
    summarise_interface(summary, s, ring, simulation);
    summarise_stresses(summary, s, loaded);
    summary.set("ball_count", static_cast<long long>(s.run.bearing.ball_count));
    summary.set("pitch_diameter_m", s.run.bearing.pitch_diameter);
    summary.set("ball_contact_stiffness_N_per_m1.5", s.run.ball_stiffness);
    summary.set("ball_footprint", std::string(ring.raceway_footprint_loads.empty() ? "fixed" : "load following"));
    summary.set("ball_footprint_loads_N", ring.raceway_footprint_loads);
    summarise_results(summary, s, ring, risk, record, measures);
    summary.set_object("integrator", integrator_summary(s, stats));
    summarise_times(summary, s, stats, record, model_seconds, run_seconds);
    summary.set("wall_time_s", seconds_since(run_start));
    summary.write(report.summary_file);

    report.numbers = {{"risk_max", measures.risk_max},
                      {"wall_time_s", seconds_since(run_start)},
                      {"ball_pass_frequency_error",
                       measures.measured_frequency / s.kinematics.ball_pass_frequency - 1.0},
                      {"peak_pressure_Pa", record.peak_pressure},
                      {"lower_half_peak_pressure_Pa", record.lower_half_pressure}};
    if (options.plots)
      report.figures = run_plot_script("plot_bearing_housing.py", {options.output_directory});
    if (!failure.empty())
      throw std::runtime_error(failure + " (results.h5 holds the steps done so far)");
    return report;
  }

  ResourceEstimate BearingHousingScene::estimate_resources(const app::SceneParameters &parameters)
  {
    const auto &par = parameters;
    // The interface grid (n_x × n_y = G cells) of each body's reduction configuration.
    const auto grid = [](const models::ModelSource &source) {
      const auto reduction = models::read_ring_housing_parameters(source.config, source.overrides);
      return std::pair{reduction.get_integer("Reduction/Interface grid circumferential cells"),
                       reduction.get_integer("Reduction/Interface grid axial cells")};
    };
    const auto grid_cells = [&](const models::ModelSource &source) {
      const auto [nx, ny] = grid(source);
      return double(nx) * double(ny);
    };
    const auto [ring_nx, ring_ny] = grid(models::ring_model_source(par));
    const double cells       = double(ring_nx) * double(ring_ny);
    const double layers      = double(par.get_double_list("Stresses/Depth layers").size());
    const double samples     = std::round(par.get_double("Loading/Ball pass periods") *
                                          double(par.get_integer("Output/Samples per ball pass"))) + 1.0;
    double       dense_cells = par.get_bool("Interface/Ring residual flexibility") ? cells * cells : 0.0;
    if (!par.get("Model/Housing reduction configuration").empty() &&
        par.get_bool("Interface/Housing residual flexibility"))
      dense_cells += std::pow(grid_cells(models::housing_model_source(par)), 2);

    // A residual flexibility is a dense G × G matrix, held with its
    // factorisation and the compliance it joins (3 copies); per cell and
    // layer the stress evaluator, stress fields and Dang Van state (~900 B,
    // as the concentrated scene); the pressure history (one field per
    // output); the process, reduced model and integrator ~300 MB.
    // The full-FE ring stresses: per layer the tables (three traction
    // components on each cell of P columns' rows, six stresses at every
    // cell) and their convolution kernel (6 n_y rows square, per wavenumber).
    double stress_tables = 0.0;
    if (par.get("Stresses/Ring stresses") == "full FE")
      {
        const long   nx     = ring_nx;
        const double ny     = double(ring_ny);
        const auto   counts = app::parse_cell_counts(par.get("Stresses/Ring mesh"), 4);
        const double period    = counts.empty() ? double(nx) : double(nx / std::gcd(nx, counts[0]));
        stress_tables = layers * (period * 3.0 * ny * cells * 6.0 * 8.0 +
                                  std::pow(6.0 * ny * period, 2) * (double(nx) / period / 2.0 + 1.0) * 16.0);
      }
    ResourceEstimate estimate;
    estimate.memory_bytes =
      300e6 + 24.0 * dense_cells + cells * (600.0 + 900.0 * layers + 8.0 * samples) + stress_tables;
    estimate.memory_basis = "the interface grid of " + std::to_string(long(cells)) +
                            " cells (Reduction/Interface grid ... cells of Model/Reduction configuration) on " +
                            std::to_string(long(layers)) + " Stresses/Depth layers" +
                            (dense_cells > 0.0 ? ", with its residual flexibility (a dense cells × cells matrix)" : "") +
                            (stress_tables > 0.0 ? ", the ring's stress tables" : "");
    // Per output: 4 interface fields, the risk and six stress components on
    // every layer, balls and modes.
    const double sample_bytes = 8.0 * cells * (4.0 + 7.0 * layers) + 8.0 * 1000.0;
    estimate.disk_bytes       = 5e6 + samples * sample_bytes + 8.0 * cells * layers;
    estimate.disk_basis = std::to_string(long(samples)) +
                          " outputs (Loading/Ball pass periods × Output/Samples per ball pass) of " +
                          app::format_bytes(sample_bytes) + " each";
    return estimate;
  }
} // namespace fretsim::scenes
