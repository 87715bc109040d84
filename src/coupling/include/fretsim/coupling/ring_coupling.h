#pragma once
// The coupling layer between the reduced flexible outer ring and the contact
// models (docs/theory.md §4). Displacements go from modal coordinates to contact
// points through the model file's operators (consistent: u = G T q), loads go
// back through their transposes (conservative: f_q = (G T)ᵀ (traction · area)),
// so that the work of the contact loads on the ring is the same in both
// descriptions. No FE, PETSc or SUNDIALS type appears here.
//
// How structural and local compliance are combined (nothing counted twice):
//  * housing interface: the ring's compliance at every wavelength its
//    Craig–Bampton basis resolves comes from the reduced model; the housing is
//    rigid, or flexible through its own reduced model (with_flexible_housing);
//    the contact itself is a Winkler layer of normal stiffness k_n
//    [Pa/m] (the compliance of the rough interface) and bristles of stiffness
//    k_t tangentially (paper eq. 4). Optionally (local_compliance_modulus)
//    an elastic half-space in series with the layer gives the rigid
//    housing's local elasticity, which no other model holds (LocalCompliance);
//    the ring's own stays with its reduced model (a half-space for it as
//    well would count its long wavelengths twice). The half-space also
//    gives the subsurface stresses under the interface tractions.
//  * the ring's residual flexibility (ReducedRing::residual_pressure,
//    optional): what the basis misses of the ring's static compliance on
//    the interface (R = K⁻¹ − T K_r⁻¹ Tᵀ, orthogonal to what the basis
//    holds, so adding it counts nothing twice) joins the half-space in
//    series with the layer; a ball's residual displacement of the interface
//    adds to the penetration, and reciprocally (the same table transposed)
//    the pressure's residual displacement of the raceway to each ball's
//    deflection. A flexible housing's own R_h joins it in series in the
//    same way.
//  * ball contacts: the Hertz law carries the local indentation of ball and
//    raceways; the reduced model the ring's global deformation, read as the
//    work-conjugate approach r(ψ)·q of a Hertz-distributed unit ball load.
//    Its fixed-interface modes resolve wavelengths of the order of the ring
//    wall, not the sub-millimetre indentation, which they therefore leave to Hertz.
#include <fretsim/coupling/local_compliance.h>

#include <fretsim/contact/bristle.h>
#include <fretsim/contact/surface_grid.h>

#include <algorithm>
#include <memory>
#include <vector>

namespace fretsim::coupling
{
  /// A Craig–Bampton model of the outer ring as plain arrays (see
  /// reduction/reduced_model.h for how they are made). Coordinates q ∈ R^n.
  struct ReducedRing
  {
    std::size_t         n = 0;
    std::vector<double> mass;      ///< M_r, n × n row-major
    std::vector<double> stiffness; ///< K_r, n × n row-major
    /// Lowest elastic free frequency [Hz] (sets the structural damping).
    double lowest_elastic_frequency_hz = 0.0;

    /// Interface grid unrolled on the ring outer surface of radius R: x = R θ
    /// (θ from +x towards +y), y axial; displacement operator [cell][3][n]
    /// giving (u_r outward, u_θ, u_z) [m per unit q].
    double               interface_radius = 0.0;
    contact::SurfaceGrid interface_grid;
    std::vector<double>  interface_displacement;

    /// Raceway ball operator: row k is Tᵀ f_k of a unit ball load at
    /// ψ_k = 2π k / n_angles pushing outwards; r(ψ)·q is the raceway's
    /// outward approach [m per unit q]. Interpolated linearly in ψ. One
    /// table per footprint: the Hertz ellipses of the ball loads
    /// `raceway_footprint_loads` (ascending, footprint_blend), or a single
    /// fixed footprint (no loads).
    std::vector<double> raceway_approach; ///< [footprint][n_angles][n]
    std::size_t         raceway_angles = 0;
    std::vector<double> raceway_footprint_loads; ///< [N]; empty: one fixed footprint
    std::size_t         raceway_footprints() const { return std::max<std::size_t>(1, raceway_footprint_loads.size()); }

    /// The residual flexibility (what a basis misses of its body's static
    /// compliance; reduction::ResidualFlexibility), in the interface's
    /// terms; empty: none. `residual_pressure` [load row jj][cell]: how far
    /// the interface's gap opens at every cell per unit pressure on cell
    /// (0, jj) [m/Pa] (LocalCompliance's structural compliance): the ring's
    /// inward displacement, plus with a flexible housing its bore's outward
    /// one; `residual_ball` [footprint][cell] (the ring's, per raceway
    /// footprint; empty: none, and then
    /// `residual_pressure` may be the housing's alone): the outward u_r per N
    /// of a ball at `residual_column_angle` [m/N], shifted around with each
    /// ball.
    std::vector<double> residual_pressure, residual_ball;
    double              residual_column_angle = 0.0;
    /// E'_s [Pa], 1/E'_s = Σ (1 - ν²)/E over the bodies whose residual
    /// flexibility `residual_pressure` holds: it is completed to their
    /// half-space where its FE mesh loses the short wavelengths
    /// (LocalCompliance); 0: taken as it is.
    double residual_half_space_modulus = 0.0;

    /// Coordinates of a flexible housing appended after the ring's own
    /// (with_flexible_housing); 0: the housing is rigid and fixed.
    std::size_t housing_coordinates = 0;

    /// Throws std::invalid_argument if the arrays do not fit together.
    void check() const;
  };

  /// field += Σ_b Q_b R(θ − ψ_b): a ball residual table `table`
  /// [footprint][cell] (per N of a ball at `column_angle` [rad];
  /// ReducedRing::residual_ball) shifted to each ball at ψ_b with load Q_b,
  /// linear between the grid's columns (x = radius θ), and between the
  /// footprints of `footprint_loads` at Q_b (footprint_blend; empty: one
  /// table). The co-simulation's and compare's one way to place it.
  void add_ball_residual(const contact::SurfaceGrid &grid, double radius, const std::vector<double> &table,
                         const std::vector<double> &footprint_loads, double column_angle,
                         const std::vector<double> &angles, const std::vector<double> &loads,
                         std::vector<double> &field);

  /// Its reciprocal (Maxwell–Betti): how far the interface pressure
  /// `pressure` [Pa per cell] moves the raceway inward under each ball at
  /// `angles` with `loads` (which pick its footprint) through the same
  /// table, Σ_c R(θ_c − ψ_b) p_c A [m]; the exact transpose of
  /// add_ball_residual.
  std::vector<double> pressure_residual_at_balls(const contact::SurfaceGrid &grid, double radius,
                                                 const std::vector<double> &table,
                                                 const std::vector<double> &footprint_loads, double column_angle,
                                                 const std::vector<double> &angles, const std::vector<double> &loads,
                                                 const contact::Field &pressure);

  /// A Craig–Bampton model of the housing (held at its outside), reduced on
  /// its bore: coordinates q_h ∈ R^n, the bore's displacement on the same grid
  /// as the ring's outer surface, [cell][3][n] (u_r outward, u_θ, u_z).
  struct ReducedHousing
  {
    std::size_t          n = 0;
    std::vector<double>  mass, stiffness; ///< n × n row-major
    double               interface_radius = 0.0;
    contact::SurfaceGrid interface_grid;
    std::vector<double>  interface_displacement;
    /// Its residual flexibility (optional): the bore's outward displacement
    /// of every cell per unit pressure on cell (0, jj), [jj][cell] [m/Pa].
    std::vector<double> residual_pressure;
    double              residual_half_space_modulus = 0.0; ///< as ReducedRing's [Pa]
  };

  /// The ring and a flexible housing as one system for the co-simulation:
  /// coordinates [q, q_h], mass and stiffness block-diagonal, and the
  /// interface operator the two surfaces' relative displacement,
  /// [G T | −G_h T_h] per cell row. The interface contact then sees the gap
  /// between the two surfaces, and its tractions return to both bodies, equal
  /// and opposite, through the same rows (still consistent and conservative).
  /// The balls act on the ring's columns only. The two bodies' residual
  /// flexibilities, both opening the gap under the pressure, add in series
  /// (and so do the compliances of their half-space completions).
  /// Throws std::invalid_argument if the two interface grids or radii differ.
  ReducedRing with_flexible_housing(const ReducedRing &ring, const ReducedHousing &housing);

  /// What the integrator sees of the bristles within a step (InterfaceContact).
  enum class InStepBristleLaw
  {
    linearised,    ///< a sticking cell a spring capped at μp, a sliding one at its ratio τ/p
    implicit_euler ///< the update's own law: bristles and structure solved together
  };

  /// Housing interface contact settings (SI).
  struct InterfaceSettings
  {
    double normal_stiffness     = 1e16; ///< k_n of the Winkler layer [Pa/m]
    double normal_damping_time  = 0.0;  ///< c_n = k_n × this [s]
    double tangential_stiffness = 1e16; ///< bristle stiffness k_t [Pa/m]
    double friction_coefficient = 0.11; ///< μ [-]
    /// Radial interference of the fit (ring outer radius minus housing bore),
    /// negative for a clearance [m].
    double radial_interference = 0.0;
    /// p_s: the layer closes gradually over the first 2 p_s / k_n of
    /// penetration (InterfaceContact); 0: a sharp onset [Pa].
    double onset_pressure = 0.0;
    /// E' [Pa] of the elastic half-space in series with the layer: the
    /// interface's local compliance (LocalCompliance), 1/E' = Σ (1 - ν²)/E
    /// over the bodies it stands for; 0: none, the layer alone.
    double local_compliance_modulus = 0.0;
    /// With the half-space: the housing's give under a uniform bore pressure
    /// (UniformCompliance, e.g. lame_bore_compliance); 0: the half-space's
    /// own [m/Pa].
    double housing_uniform_compliance = 0.0;
    /// p_c [Pa]: without a half-space (the layer in series with the bodies'
    /// residual flexibilities alone, as with a flexible housing) the layer
    /// closes exponentially on this pressure scale
    /// (LocalCompliance::set_closure_pressure); 0: sharply.
    double closure_pressure = 0.0;
    /// With the closure: the bristles' stiffness follows the layer's normal
    /// stiffness, k_t (1 − e^(−p/p_c)), as an asperity's tangential
    /// stiffness follows its normal one (Mindlin); false: k_t at every
    /// pressure.
    bool bristles_follow_closure = true;
    /// λ_c [m] of the residual flexibility's half-space completion
    /// (ReducedRing::residual_half_space_modulus; HalfSpaceCompletion):
    /// in full below it, fading out up to 2 λ_c.
    double half_space_completion_wavelength = 0.0;
    /// Where the half-space's pressure sensitivity in Newton's matrix stops,
    /// relative to each right-hand side (LocalCompliance) [-].
    double sensitivity_tolerance = LocalCompliance::default_sensitivity_tolerance;
    InStepBristleLaw in_step_bristle_law = InStepBristleLaw::implicit_euler;
    /// How the bristle law steps over a slip increment, within the step and in
    /// the update after it (contact::BristleUpdate): the paper's implicit
    /// Euler or the law's exact exponential.
    contact::BristleUpdate bristle_update = contact::BristleUpdate::implicit_euler;
  };

  /// Loads and their derivatives at a trial state, added into caller arrays:
  /// force [n], and if not null, ∂force/∂q and ∂force/∂q̇ [n × n, row-major].
  struct ForceOutput
  {
    double *force         = nullptr;
    double *by_position   = nullptr;
    double *by_velocity   = nullptr;
  };

  /// The ring outer surface against the rigid housing bore on the interface
  /// grid: penetration d = δ_fit + u_r, pressure p = max(k_n g(d) + c_n g'(d) ḋ, 0)
  /// where d > 0, with the closure g(d) = d²/(4 d_s) on (0, 2 d_s) and d - d_s
  /// beyond, d_s = p_s / k_n (C¹; a rough layer's gradual closure, on the
  /// scale of p_s = 1 MPa in the scene). The damping acts through the same
  /// law, so a cell closing at speed starts from zero pressure: with the
  /// plain max(k_n d + c_n ḋ, 0) (p_s = 0) the pressure jumps by c_n ḋ at
  /// closure, and Newton's method failed on those jumps. Tangential traction
  /// from the bristle model (paper eq. 4), advanced by implicit Euler in the
  /// slip since the last accepted step:
  ///     τ(q) = (τ_n + k ds(q)) / (1 + k |ds(q)| / (μ p(q))),
  ///     ds = -(u_t(q) - u_t,n)   (the housing's shift relative to the ring),
  /// or by the law's exact exponential step (InterfaceSettings::bristle_update),
  /// k = k_t, or k_t (1 − e^(−p/p_c)) under the layer's closure
  /// (InterfaceSettings::bristles_follow_closure).
  /// accept() applies exactly this update after every accepted step. Within a
  /// step (add_forces) the integrator sees, by InterfaceSettings::
  /// in_step_bristle_law, either the same law (implicit_euler, the default:
  /// the structure and the bristles in one implicit step, so what the step
  /// balanced is what is committed; its ∂τ/∂ds is not symmetric, and at
  /// ds = 0, where every cell starts its step, a cell near μp takes the
  /// derivative of sliding on), or (linearised) an approximation: a sticking
  /// cell is a linear spring τ_n + k ds capped at μp, a sliding cell
  /// (|τ_n| ≥ 0.9 μ p_n) keeps its ratio τ/p and direction. The linearised
  /// step is stiffer than the law near saturation and a sliding cell's
  /// traction does not grow towards μp within it; the committed update then
  /// differs from what the step balanced, a splitting error that does not
  /// vanish with the step size (D_max −1.8 % on the paper case, −15 % on the
  /// suite's small ring: docs/bearing.md), and the kicks it leaves cost steps.
  class InterfaceContact
  {
  public:
    InterfaceContact(const ReducedRing &ring, const InterfaceSettings &settings);
    ~InterfaceContact();

    /// Tractions at (q, q̇) and their generalised force (and derivatives).
    void add_forces(const double *q, const double *velocity, const ForceOutput &out);
    /// Stores the bristle state at the accepted (q, q̇).
    void accept(const double *q, const double *velocity);

    /// The ball loads [N] at their angles [rad] for the next add_forces or
    /// accept: with the ring's residual flexibility, each ball's residual
    /// u_r under the interface adds to the structural penetration (quasi-
    /// static, like the residual itself). Newton's matrix leaves out its
    /// derivative through the ball loads (see docs/bearing.md).
    void set_ball_loads(const std::vector<double> &angles, const std::vector<double> &loads);

    /// The pressure of the last add_forces call (trial state) [Pa].
    const contact::Field &trial_pressure() const;
    /// Fields at the last accepted state [Pa] (pressure positive; shear_x
    /// circumferential, shear_y axial: the housing's traction on the ring).
    const contact::Field &pressure() const;
    const contact::Field &shear_x() const;
    const contact::Field &shear_y() const;
    /// |τ| / p (the paper's effective friction coefficient), 0 without contact.
    contact::Field effective_friction() const;
    /// Loaded cells / all cells, and slipping cells (|τ| ≥ (1 - 1e-3) μ p) / loaded;
    /// with the layer's closure a cell is loaded where the layer is
    /// compressed (LocalCompliance::contact_pressure).
    double contact_fraction() const;
    double slip_fraction() const;
    /// Resultant of the housing's tractions on the ring in the Cartesian x, y
    /// directions [N] (last accepted state).
    void resultant(double &force_x, double &force_y) const;
    /// The half-space in series with the layer, or null without one.
    const LocalCompliance *local_compliance() const;

    /// Keep every evaluation's per-cell derivatives (a Jacobian's), so that
    /// add_derivative can follow the last evaluation.
    void keep_derivatives();
    /// out += (∂F/∂q) dq + (∂F/∂q̇) dv at the last evaluation (keep_derivatives):
    /// the interface force's derivative along one direction, its pressure
    /// coupling solved on the loaded cells (LocalCompliance::pressure_change).
    void add_derivative(const double *dq, const double *dv, double *out);

    /// From now on every evaluation keeps each cell's bristle stiffness
    /// ∂τ/∂ds (S_c), and each Jacobian's.
    void track_slip_stiffness();
    /// The cells whose S_c at the last evaluation differs from the last
    /// Jacobian's by more than a quarter of the tangential stiffness, the
    /// largest changes first, at most slip_stiffness_changes_kept: their
    /// tangential rows ([cell][2][n]: ∂F/∂q changed by -Σ A G_tᵀ ΔS_c G_t)
    /// and A ΔS_c ([cell][2][2] row-major, A the cell's area). Empty unless
    /// tracked.
    void slip_stiffness_changes(std::vector<double> &rows, std::vector<double> &changes) const;
    static constexpr std::size_t slip_stiffness_changes_kept = 32;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };

  /// Massless cage-guided balls between the rigid inner ring and the flexible
  /// outer raceway (see bearing.h): the deflection of ball j at ψ_j is
  ///     δ_j = e · n(ψ_j) - r(ψ_j) · q - P_d / 2 + w_j,
  /// e the inner ring's displacement, n the outward unit radius, w_j the
  /// raceway's residual inward displacement (set_raceway_residual, 0 unless
  /// set); the load Q_j acts on the ring as Q_j r(ψ_j) (generalised). r is
  /// interpolated linearly between the stored angles, the same weights both
  /// ways; with footprints that follow the load, between the footprints'
  /// rows at Q_j (footprint_blend), Q_j and its row solved together.
  /// Newton's matrix leaves out the row's change with Q_j.
  class BallContacts
  {
  public:
    BallContacts(const ReducedRing &ring, unsigned int ball_count, double stiffness, double damping,
                 double radial_clearance);
    ~BallContacts();

    /// angles ψ_j [rad] and their rate (the cage speed) [rad/s]; inner ring
    /// displacement (e_x, e_y) [m] and velocity [m/s].
    void add_forces(const std::vector<double> &angles, double cage_speed, const double inner_displacement[2],
                    const double inner_velocity[2], const double *q, const double *velocity,
                    const ForceOutput &out);
    /// w_j [m] per ball from now on (pressure_residual_at_balls): held
    /// fixed within add_forces, so no derivative of it enters the Jacobian.
    void set_raceway_residual(const std::vector<double> &inward);
    /// Ball loads [N] of the last add_forces call.
    const std::vector<double> &loads() const;

    /// The balls' part of the force's derivatives at the last add_forces
    /// call, ball by ball: ∂F/∂q = -Σ_j r_j (k_j r_j + c_j Ω s_j)ᵀ and
    /// ∂F/∂q̇ = -Σ_j c_j r_j r_jᵀ, r_j the raceway row under ball j, s_j its
    /// slope dr/dψ, k_j = ∂Q_j/∂δ_j and c_j = ∂Q_j/∂δ̇_j (both 0 for an
    /// unloaded ball), Ω the cage speed.
    struct Linearisation
    {
      std::vector<double> rows, slopes;                      ///< [ball][n]
      std::vector<double> by_deflection, by_deflection_rate; ///< k_j [N/m], c_j [N s/m]
      double              cage_speed = 0.0;                  ///< Ω [rad/s]
      /// out += (∂F/∂q) dq + (∂F/∂q̇) dv [n] (the derivatives above along one direction).
      void add_derivative(const double *dq, const double *dv, double *out) const;
    };
    const Linearisation &linearisation() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace fretsim::coupling
