#pragma once
#include <fretsim/contact/surface_grid.h>

namespace fretsim::contact
{
  struct BristleStep
  {
    double x, y; ///< traction [Pa]
  };

  /// How a step of paper eq. 4, dτ = k ds − k |ds| τ/(μp), is taken over a
  /// slip increment ds at constant μp. implicit_euler (the paper's):
  /// τ' = (τ + k ds) / (1 + λ), λ = k |ds|/(μp), first order in |ds|: a
  /// bristle sheared by λ = 6 in one step reaches 0.86 of the μp it tends to
  /// (the equation's own answer 1 − e⁻⁶ = 0.998). exponential: the equation's
  /// exact solution along a straight increment, τ' = e^(−λ) τ + k φ(λ) ds,
  /// φ(λ) = (1 − e^(−λ))/λ: the same steady sliding and sticking, and a
  /// step's answer that does not depend on how the increment is divided.
  enum class BristleUpdate
  {
    implicit_euler,
    exponential
  };

  /// One step of paper eq. 4 at one cell: from the traction (tau_x, tau_y)
  /// [Pa], stiffness k [Pa/m], Coulomb limit mu p [Pa] and the slip increment
  /// (ds_x, ds_y) [m], by `update`, clamped to |tau'| <= mu p; 0 where mu p =
  /// 0. BristleTraction advances every cell with it; a coupled solver
  /// evaluates it at trial states.
  BristleStep bristle_step(double tau_x, double tau_y, double stiffness, double mu_p, double slip_x, double slip_y,
                           BristleUpdate update = BristleUpdate::implicit_euler);

  /// bristle_step's derivatives at one cell, for a solver that couples the law
  /// to the bodies' motion: ∂τ'/∂ds (not symmetric), ∂τ'/∂p and ∂τ'/∂k (for
  /// a stiffness that depends on the pressure).
  struct BristleStepDerivatives
  {
    double by_slip[2][2]   = {{0.0, 0.0}, {0.0, 0.0}}; ///< ∂τ'_i/∂ds_j [Pa/m]
    double by_pressure[2]  = {0.0, 0.0};               ///< ∂τ'_i/∂p [-]
    double by_stiffness[2] = {0.0, 0.0};               ///< ∂τ'_i/∂k [m]
  };

  /// bristle_step with the limit μ p from `friction_coefficient` and
  /// `pressure`, and its derivatives (zero where μ p = 0). At ds = 0, where
  /// every step starts, |ds| has no derivative: with `sliding_on` (the cell's
  /// traction is near μ p) the one-sided derivative along τ is taken, since the
  /// cell most likely slides on; otherwise the spring's, k I / D.
  BristleStep bristle_step(double tau_x, double tau_y, double stiffness, double friction_coefficient,
                           double pressure, double slip_x, double slip_y, bool sliding_on,
                           BristleStepDerivatives &derivatives,
                           BristleUpdate update = BristleUpdate::implicit_euler);

  /// Tangential traction by the bristle (elastic-foundation, LuGre-type) model
  /// of the paper, eq. 4 (docs/theory.md §2.3): at every cell
  ///     dtau/dt = k v - k |v| tau / (mu p),
  /// advanced with implicit Euler over a slip increment ds = v dt:
  ///     tau^{n+1} = (tau^n + k ds) / (1 + k |ds| / (mu p)).
  /// |tau^{n+1}| <= mu p holds for any step size and stiffness; where mu p
  /// drops below |tau| the traction is clamped to the Coulomb limit.
  class BristleTraction
  {
  public:
    /// stiffness: tangential foundation stiffness k [Pa/m].
    /// slip_tolerance: a cell counts as slipping where |tau| >= (1 - eps) mu p.
    BristleTraction(const SurfaceGrid &grid, double stiffness, double slip_tolerance = 1e-3);

    /// Mindlin calibration (docs/theory.md §2.3): k = 8 G* / (pi a) makes the initial
    /// tangential stiffness k pi a^2 equal Mindlin's 8 G* a [Pa/m].
    static double mindlin_stiffness(double tangential_modulus, double contact_radius);

    /// One implicit Euler step with the same relative slip increment (dx, dy)
    /// [m] at every cell (rigid sliding of the two bodies).
    void advance(const Field &pressure, double friction_coefficient, double slip_x, double slip_y);
    /// One step with a slip increment per cell [m] (conformal contacts).
    void advance(const Field &pressure, double friction_coefficient, const Field &slip_x,
                 const Field &slip_y);

    void reset();

    const Field &traction_x() const { return tau_x; } ///< [Pa], on the lower body
    const Field &traction_y() const { return tau_y; } ///< [Pa]
    double       stiffness() const { return k; }

    /// |tau| / (mu p) per cell, 0 outside the contact: the paper's "effective
    /// friction" map normalised by mu.
    Field effective_friction(const Field &pressure, double friction_coefficient) const;
    /// Fraction of the loaded area that slips.
    double slip_area_fraction(const Field &pressure, double friction_coefficient) const;

  private:
    void advance_cell(std::size_t c, double mu_p, double slip_x, double slip_y);

    SurfaceGrid grid;
    double      k;
    double      slip_tolerance;
    Field       tau_x;
    Field       tau_y;
  };

  /// |tau| / (mu p) per cell, capped at 1; 1 on loaded frictionless cells
  /// (they slip freely), 0 outside the contact. Shared by the bristle models.
  Field effective_friction(const Field &traction_x, const Field &traction_y, const Field &pressure,
                           double friction_coefficient);

  /// Fraction of the loaded cells (p > 0) whose effective friction is at
  /// least 1 - slip_tolerance.
  double slip_area_fraction(const Field &effective_friction, const Field &pressure, double slip_tolerance);
} // namespace fretsim::contact
