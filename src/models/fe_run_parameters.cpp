// The schema of a ring_housing configuration's `fe` section (FE run/...):
// declared beside the mesh and reduction sections so that every reader of the
// configuration, the bearing scene's included, accepts the whole file.
#include <fretsim/models/ring_housing.h>

namespace fretsim::models
{
  namespace
  {
    constexpr double two_pi = 6.283185307179586;
  } // namespace

  std::vector<ParameterSpec> fe_run_parameter_specs()
  {
    using Spec = ParameterSpec;
    const std::string s = fe_run_section;
    std::vector<Spec> specs;
    specs.push_back(Spec::selection(s + "Analysis", "static",
                                    "static: one load case (fit, pressure, balls at rest); modes: the lowest "
                                    "eigenfrequencies and mode shapes; transient: the balls go round at the cage "
                                    "speed (Newmark, average acceleration) [-].",
                                    "static|modes|transient"));
    specs.push_back(Spec::selection(s + "Solver", "direct",
                                    "Linear solver of static solves: direct (MUMPS), cg_amg (CG + hypre "
                                    "BoomerAMG), cg_gamg (CG + GAMG with the rigid-body modes) [-]. Modal and "
                                    "transient runs factorise directly.",
                                    "direct|cg_amg|cg_gamg"));
    specs.push_back(Spec::real_range(s + "Solver tolerance", "1e-10",
                                     "Relative residual at which CG stops (iterative solvers) [-].", 0.0, 1.0, true,
                                     true));
    specs.push_back(Spec::integer_range(s + "Maximum iterations", "5000", "CG iteration limit [-].", 1, 1000000));
    specs.push_back(Spec::integer_range(s + "Modes", "10",
                                        "Elastic modes wanted by a modal analysis (rigid-body modes of a free body "
                                        "come on top) [-].",
                                        1, 200));
    Spec clamped;
    clamped.path          = s + "Supports/Clamped";
    clamped.kind          = Spec::Kind::text;
    clamped.default_value = "housing_outer";
    clamped.doc = "Comma-separated boundaries held fixed in all three directions, or none; names: " +
                  boundary_names() + " [-].";
    specs.push_back(clamped);
    specs.push_back(Spec::selection(s + "Supports/Axial faces", "free",
                                    "fixed: u_z = 0 on the side faces (plane strain, as a ring between shoulders "
                                    "that do not let it widen); free: traction-free [-].",
                                    "free|fixed"));
    Spec symmetry;
    symmetry.path          = s + "Supports/Symmetry planes";
    symmetry.kind          = Spec::Kind::boolean;
    symmetry.default_value = "false";
    symmetry.doc = "Quarter model (Divisions/Sector angle = pi/2): the cut faces are symmetry planes (u_y = 0 on "
                   "y = 0, u_x = 0 on x = 0) [-].";
    specs.push_back(symmetry);
    specs.push_back(Spec::non_negative(s + "Loads/Interference", "0",
                                       "Radial interference delta of the ring in the housing (Mesh/Bodies = "
                                       "ring_in_housing), imposed as the ring's in-plane expansion delta / R at the "
                                       "interface radius R [m]."));
    specs.push_back(Spec::selection(s + "Loads/Pressure boundary", "raceway",
                                    "Boundary that carries the uniform Pressure [-].", boundary_names()));
    specs.push_back(Spec::real_range(s + "Loads/Pressure", "0",
                                     "Uniform pressure on Pressure boundary, positive pushing into the body [Pa].",
                                     -1e12, 1e12));
    specs.push_back(Spec::integer_range(s + "Loads/Balls", "9", "Number of balls Z, equally spaced [-].", 0, 200));
    specs.push_back(Spec::non_negative(s + "Loads/Ball load", "0",
                                       "Load Q of every ball (uniform), or of the most loaded ball (radial) [N]."));
    specs.push_back(Spec::selection(s + "Loads/Load distribution", "radial",
                                    "uniform: every ball carries Ball load; radial: Stribeck's distribution of a "
                                    "radial bearing load with a half-circle load zone, Q(psi) = Q_max cos^1.5 psi for "
                                    "|psi| < 90 deg from Load direction [-].",
                                    "uniform|radial"));
    specs.push_back(Spec::real_range(s + "Loads/Load direction", "0",
                                     "Angle theta (from x towards y) of the radial load, where the most loaded ball "
                                     "sits; ball 1 starts there [rad].",
                                     -two_pi, two_pi));
    specs.push_back(Spec::real_range(s + "Loads/Contact angle", "0",
                                     "Contact angle alpha: the contact point sits on the groove arc at alpha from its "
                                     "bottom towards +z, and the ball load acts along the line from the arc centre "
                                     "through it [rad].",
                                     -1.5, 1.5));
    // A 6208 ball (D_w = 12.7 mm) on the outer raceway (f_o = 0.53) under
    // 2 kN: Hertz (Harris, elliptic contact) gives 0.30 mm × 1.32 mm.
    specs.push_back(Spec::positive(s + "Loads/Semi-axis circumferential", "3.0e-4",
                                   "Hertz semi-axis a along the circumference at Ball load; other loads scale it by "
                                   "(Q / Ball load)^(1/3) [m]."));
    specs.push_back(Spec::positive(s + "Loads/Semi-axis transverse", "1.32e-3",
                                   "Hertz semi-axis b across the groove (along its arc) at Ball load, scaled like "
                                   "a [m]."));
    // 6208 at 3000 rpm of the inner ring: Ω_cage = ω/2 (1 - D_w/d_m) with d_m = 60 mm.
    specs.push_back(Spec::real_range(s + "Transient/Cage speed", "123.8",
                                     "Angular speed of the cage, i.e. of the balls round the stationary outer ring "
                                     "[rad/s].",
                                     -1e6, 1e6));
    specs.push_back(Spec::positive(s + "Transient/Time step", "1e-4", "Newmark time step [s]."));
    specs.push_back(Spec::integer_range(s + "Transient/Steps", "50", "Number of time steps [-].", 1, 1000000));
    specs.push_back(Spec::integer_range(s + "Transient/Snapshot interval", "1",
                                        "A stress snapshot every this many steps (and at t = 0) [-].", 1, 1000000));
    specs.push_back(Spec::integer_range(s + "Sampling/Points per line", "72",
                                        "Stress sample points on each circumferential line: the ring outer surface "
                                        "in the mid-plane and the raceway's contact line (housing alone: its outer "
                                        "surface and bore), at theta = (k + 1/2) sector / n [-].",
                                        0, 100000));
    specs.push_back(Spec::integer_range(s + "Sampling/Grid circumferential", "0",
                                        "Cells around of a stress sampling grid on the ring outer surface (housing "
                                        "alone: its bore), sampled at cell centres; 0: no grid [-].",
                                        0, 100000));
    specs.push_back(Spec::integer_range(s + "Sampling/Grid axial", "0", "Cells across the width of that grid [-].",
                                        0, 100000));
    return specs;
  }
} // namespace fretsim::models
