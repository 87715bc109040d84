#pragma once
// The interface's local compliance: an elastic half-space (Love's uniform
// rectangles, docs/theory.md §2.2) in series with the Winkler layer, on the
// unrolled interface grid (periodic around the circumference). Given each
// cell's structural penetration d0 (fit + the ring's u_r, from the reduced
// model), the pressure solves
//     p = k_n (d0 - C p)  where p > 0,   C the half-space compliance,
// so that the half-space's give w = C p spreads the pressure the way the
// housing's (and the ring's) local elasticity does. The layer then becomes a
// penalty: its compliance 1/k_n adds to the half-space's, and for k_n far
// above the half-space's stiffness the pressure tends to the complementarity
// solution of the half-space alone. Optionally the ring's residual
// flexibility (the part of its compliance its reduced basis misses, as
// reduce stores it) joins C: a kernel invariant around the circumference
// whose rows across the width differ, applied in the same row transforms,
// completed at the short wavelengths its FE mesh does not resolve by the
// half-space of its bodies' material.
#include <fretsim/contact/surface_grid.h>

#include <memory>
#include <vector>

namespace fretsim::coupling
{
  /// The half-space completion of a structural compliance (local_compliance.cpp):
  /// per circumferential wavenumber, where the structural compliance holds
  /// less than a half-space of `modulus` E'_s [Pa] (1/E'_s = Σ (1 - ν²)/E
  /// over the bodies it stands for), the shortfall is added, in full below
  /// `wavelength` λ_c [m] and fading out linearly in wavenumber up to 2 λ_c.
  /// modulus 0: none.
  struct HalfSpaceCompletion
  {
    double modulus    = 0.0;
    double wavelength = 0.0;
  };

  /// A housing ring's response to a pressure uniform over the whole interface
  /// (the fit's): where `compliance` C_0 > 0 [m/Pa], the half-space's mean
  /// give under a uniform unit pressure is replaced by C_0 (a constant added
  /// to every entry of the kernel changes only that mode), so that a fit's
  /// pressure follows the housing's wall rather than the half-space, whose
  /// uniform give on a closed strip depends on the grid's width alone.
  /// Lamé's thick ring in plane stress, bore b, outside c, free outside:
  /// C_0 = b/E ((c² + b²)/(c² − b²) + ν) (`lame_bore_compliance`).
  struct UniformCompliance
  {
    double compliance = 0.0;
  };

  /// Lamé's inward-positive bore displacement per unit bore pressure of a
  /// free thick ring (plane stress) [m/Pa]; throws std::invalid_argument
  /// unless 0 < bore < outside.
  double lame_bore_compliance(double bore_radius, double outer_radius, double youngs_modulus,
                              double poisson_ratio);

  class LocalCompliance
  {
  public:
    /// Newton's matrix needs the pressure sensitivity to about 1 %: on the
    /// paper's case 1e-2 took 0.54 of the sensitivity convolutions of 1e-4
    /// at as many right-hand sides; D_max on the suite's small ring moved by
    /// < 1 % [-].
    static constexpr double default_sensitivity_tolerance = 1e-2;

    /// `contact_modulus` E' [Pa]: 1/E' = Σ (1 - ν²)/E over the bodies whose
    /// local compliance the half-space stands for; 0: no half-space (then a
    /// structural compliance must be given). `layer_stiffness` k_n [Pa/m] of
    /// the layer in series. `periodic_x`: the grid's x is the whole
    /// circumference (distances wrap around). `sensitivity_tolerance`: where
    /// pressure_sensitivity's conjugate gradients stop, relative to each
    /// right-hand side's largest entry [-]. `structural_compliance`: empty,
    /// or [load row jj][cell] the inward displacement of every cell per unit
    /// pressure on cell (0, jj) [m/Pa], taken as invariant around the
    /// circumference (periodic_x), made symmetric (reciprocity) and even in
    /// x (the ring's mirror symmetry) by averaging, and completed by
    /// `completion` (with a structural compliance only). `uniform`: the
    /// housing's give under a uniform pressure (periodic_x with a half-space
    /// only); throws std::invalid_argument if the kernel would then lose
    /// positive definiteness.
    LocalCompliance(const contact::SurfaceGrid &grid, double contact_modulus, double layer_stiffness,
                    bool periodic_x, double sensitivity_tolerance = default_sensitivity_tolerance,
                    const std::vector<double> &structural_compliance = {}, const HalfSpaceCompletion &completion = {},
                    const UniformCompliance &uniform = {});
    ~LocalCompliance();

    /// Solves the contact of the layer on the half-space for the structural
    /// penetration b [m] per cell (fit + the ring's u_r, plus τ_d ḋ0 for the
    /// layer's damping): p ≥ 0, g = (C + I/k_n) p - b ≥ 0, p g = 0, the
    /// bound-constrained quadratic program of Polonsky & Keer's conjugate
    /// gradient method (without their load constraint: the approach is
    /// given). Starts from `pressure` and stops when the gap is within
    /// 1e-7 × max b of zero on the loaded cells (and no open cell
    /// penetrates by more). With a closure pressure (set_closure_pressure),
    /// Newton's method on the closure's law instead, to the same tolerance
    /// (1e-7 × max(max |b|, δ)) on every cell (the residual in double, the
    /// steps by conjugate gradients in single precision), started from `pressure` moved
    /// by the pressure changes asked for since the last solve in the
    /// combination whose approach changes make up b's change (when they
    /// do, within 10 %: Newton's update in GMRES's span). Returns the
    /// convolutions; throws std::runtime_error if it does not converge.
    int solve(const contact::Field &structural_penetration, contact::Field &pressure);

    /// The layer's closure (default: sharp, the complementarity above).
    /// With a closure pressure p_c > 0 [Pa] the layer closes as a rough
    /// surface's asperities do (Greenwood–Williamson, exponential heights):
    ///     p = p_c ln(1 + e^((d - s)/δ)),   δ = p_c/k_n,  s = 10 δ,
    /// d the layer's compression b - C p: the linear layer p = k_n (d - s)
    /// once p ≫ p_c, an exponential tail below (p_c e^-10 at d = 0, so that
    /// surfaces that just touch carry next to nothing). Every cell then
    /// carries a pressure and p(b) is smooth: a conformal contact, whose
    /// edge has cells with both p and the gap near zero, no longer jumps
    /// between loaded sets under Newton's iterations (docs/bearing.md,
    /// Flexible housing). Cells below p_c e^-30 are set to zero.
    void set_closure_pressure(double closure_pressure);
    /// Where the layer is compressed (d > 0): p_c e^-10 with a closure
    /// pressure, else 0 [Pa]. Cells above it are in contact.
    double contact_pressure() const;

    /// Loaded sets up to this many cells get the sensitivity by a dense
    /// Cholesky factorisation of C_AA + I/k_n (≈ 0.1 s at 1 200 cells), larger
    /// ones by conjugate gradients [-].
    static constexpr std::size_t default_direct_sensitivity_cells = 4000;
    /// Sets that limit (0: always conjugate gradients).
    void set_direct_sensitivity_cells(std::size_t cells);

    /// Whether the factorisation (up to the direct limit) may work in single
    /// precision: about twice as fast, its error about the operator's
    /// condition times float's epsilon (1e-6 on a half-space's contact
    /// patch of 300 cells, condition 23, against the 1e-2 Newton's matrix
    /// needs); default double. A factorisation that fails, or whose
    /// estimated condition times float's epsilon exceeds 1e-4 (a structural
    /// compliance without a half-space or its completion can be
    /// ill-conditioned), is redone in double.
    void set_single_precision_factorisation(bool single);

    /// (C_AA + I/k_n)⁻¹ R over the loaded cells A, i.e. ∂p_A/∂b_A applied to
    /// R: `rhs` and `result` are [cells of A][columns] row-major. With a
    /// closure pressure, (C_AA + I/k_n + D_A)⁻¹ R at the last solve, D the
    /// closure's compliance (1/k_n)/(e^(p/p_c) - 1) per cell: exactly on the
    /// cells where D is at most ten times a cell's own compliance, each of
    /// the others from what the first move it (within 3 % of the response). Up to
    /// default_direct_sensitivity_cells loaded cells, exact (a Cholesky factorisation);
    /// beyond, conjugate gradients to the sensitivity tolerance, and R must
    /// be the same rows per cell from call to call (the interface operator):
    /// while A differs from the last computed set in at most 2 % of its
    /// cells, the last answer is returned (for Newton's matrix only; not
    /// with a closure pressure, whose operator depends on p).
    /// Returns whether the answer came from a single precision factorisation
    /// (set_single_precision_factorisation): accurate to about 1e-6, not to
    /// rounding.
    bool pressure_sensitivity(const std::vector<std::size_t> &loaded, const double *rhs,
                              std::size_t columns, std::vector<double> &result);

    /// The pressure's change under a change of the approach at `pressure`,
    /// the last solve's: (C + I/k_n + D)_AA Δp = Δb on the cells A carrying
    /// pressure (D the closure's compliance there), zero elsewhere; by the
    /// solve's preconditioned conjugate gradients (single precision) to
    /// `relative_tolerance` of the largest Δb. The Jacobian's sensitivity applied to one vector,
    /// at the state of the last solve rather than the last Jacobian.
    void pressure_change(const contact::Field &pressure, const contact::Field &approach_change,
                         contact::Field &change, double relative_tolerance);

    /// Work done so far, in convolutions (the cost of both calls).
    struct Statistics
    {
      std::size_t solves = 0, solve_convolutions = 0;
      std::size_t sensitivities = 0, sensitivity_convolutions = 0;
      std::size_t sensitivity_reuses = 0; ///< sensitivities answered from the last one (loaded set within 2 %)
      std::size_t sensitivity_factorisations = 0; ///< sensitivities solved by a Cholesky factorisation
      std::size_t sensitivity_single_precision = 0; ///< of those, in single precision
      std::size_t changes = 0, change_convolutions = 0; ///< pressure_change
    };
    const Statistics &statistics() const;

    /// How far the structural compliance was from symmetric and even:
    /// max |R - R_sym| / max |R| before the averaging (0 without one) [-].
    double structural_asymmetry() const;

    /// The half-space completion per circumferential wavenumber k = 0 …
    /// nx/2: the compliance it added over the half-space's own (trace of
    /// the ny × ny blocks; 0 where the structural compliance held at least
    /// the half-space's or k is below the completion's band, 1 where it
    /// held none) [-]; empty without one.
    const std::vector<double> &completion_by_wavenumber() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace fretsim::coupling
