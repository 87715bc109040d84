#pragma once
// Exact elastic quasi-static partial slip ("shift", transient rolling-free
// tangential contact) on the SurfaceGrid, the detailed reference model of
// docs/theory.md §2.4 in the manner of Kalker's CONTACT.
//
// Problem solved per load step n (cell-centred, piecewise-constant tractions):
//
//   unknown  tau_i   the tangential traction the upper body exerts on the lower
//                    body at cell i [Pa] (the sign convention of BristleTraction:
//                    for an imposed shift in +x the traction on the lower body
//                    points in +x);
//   given    p_i     pressure [Pa], mu the friction coefficient, g_i = mu p_i;
//            d_i     the imposed increment of the rigid shift: the relative
//                    displacement of remote points of the upper body over the
//                    lower body since step n-1 [m] (uniform, or per cell);
//   micro-slip increment of the upper surface particle over the lower one
//            s_i = d_i - (w_i^n - w_i^{n-1}),   w = C tau   [m],
//   with C the combined Cerruti compliance of both bodies (below);
//   conditions
//            |tau_i| <= g_i everywhere, tau_i = 0 where g_i = 0,
//            stick:  |tau_i| <  g_i  =>  s_i = 0,
//            slip:   |tau_i| =  g_i  =>  s_i = lambda_i tau_i / g_i, lambda_i >= 0
//                    (the traction on the lower body points along the slip of
//                    the upper surface over it: it opposes the lower body's own
//                    motion relative to the upper one).
//
// These are the optimality conditions of the convex problem
//     minimise 1/2 tau^T C tau - tau^T (d + C tau^{n-1})  over |tau_i| <= g_i,
// a quadratic program with one disc constraint per cell (not a box): the
// solution exists, is unique, and the micro-slip is the negative gradient.
//
// Compliance. u = C tau is the relative tangential surface displacement of the
// lower body over the upper one, the sum of both bodies' Cerruti
// uniform-rectangle coefficients (docs/references.md §4.1):
//     C_xx = C_xx^lower + C_xx^upper  (u_x from tau_x), C_yy likewise, and the
//     cross term C_xy = C_yx = -nu/(2 pi G)[rho] per body (u_y from tau_x),
//     which is non-zero for nu != 0 and is included.
// Normal-tangential coupling: the relative normal displacement from the shear
// traction, and the relative tangential displacement from the pressure, are
// proportional to (1-2nu1)/G1 - (1-2nu2)/G2 (Dundurs' beta). For equal
// materials they vanish exactly and the decoupled solution is exact. For
// dissimilar materials they are neglected (Goodman's approximation): the
// pressure is taken as given (not altered by the shear) and the pressure does
// not drive tangential slip. The error is of order beta mu, small for steel on
// steel-like pairs.
//
// Algorithm: an active-set projected conjugate-gradient iteration of the
// Polonsky–Keer kind generalised to disc constraints (cf. Kalker's TangCG and
// the active-set nonlinear CG of Zhao, Vollebregt & Oosterlee, 2014):
//   * stick cells (|tau| < g) carry both traction components as unknowns;
//     slip cells (|tau| = g) only the rotation of the traction along the
//     circle: their search direction is restricted to the tangent of the
//     circle, the step is retracted back onto it, and the curvature of the
//     circle enters the line search as the stiffness lambda_i / g_i (the exact
//     second derivative of the energy along the circle at a KKT point);
//   * stick cells whose traction leaves the disc are projected onto it and
//     become slip cells; slip cells whose micro-slip points into the disc
//     (lambda_i < 0, slip reversal) are released into the stick set; every
//     active-set change restarts the conjugate directions (Polak–Ribière+
//     otherwise);
//   * products with C by DC-FFT (FFTW plans and the three kernel transforms
//     created once per window size and reused), on the bounding window of the
//     loaded cells rather than the whole grid; C tau of the new iterate is
//     updated from C d by linearity when the retraction correction is below
//     1 % of the step (second order), and recomputed exactly before
//     convergence is accepted, so about 1.2 products per iteration;
//   * each step is warm-started from the previous step's tractions (and their
//     displacement C tau^{n-1}, kept from the last step).
// Convergence: the RMS traction error over the loaded cells, relative to the
// RMS traction, is below `tolerance`. The traction error of a stick cell is
// |s_i| / C_xx(0,0) (the traction that would cancel its micro-slip); of a slip
// cell the smaller of |s_t| / C_xx(0,0) and g_i |s_t| / |s| (s_t: the
// micro-slip component along the circle, i.e. the misalignment of tau with
// the slip); the active set is consistent (no slip cell with lambda_i < 0).
// Measured on the paper case (40 steps a cycle): tolerance 1e-8 leaves a loop
// error of 1e-9 muP against a 1e-12 solve, 1e-6 leaves 1e-7 muP.
//
// Force control (advance_to_force) wraps displacement control in a Broyden
// iteration on the uniform shift increment, each solve warm-started.
//
// Call order: construct, then advance() / advance_to_force() once per load
// step in time order; reset() returns to the unloaded, untouched state.

#include <fretsim/contact/material.h>
#include <fretsim/contact/surface_grid.h>

#include <cstddef>
#include <memory>
#include <vector>

namespace fretsim::contact
{
  struct PartialSlipSettings
  {
    /// Relative RMS traction error (see the file comment).
    double tolerance = 1e-8;
    /// Conjugate-gradient iterations per displacement-controlled solve.
    int max_iterations = 10000;
    /// Force control: |Q - Q_target| <= force_tolerance mu P.
    double force_tolerance = 1e-9;
    /// Force control: displacement-controlled solves per step.
    int max_force_iterations = 60;
    /// FFTW_MEASURE plans (faster transforms, ~0.1-1 s planning once per window
    /// size and process) instead of FFTW_ESTIMATE.
    bool measure_fft_plans = true;
    /// Masing superposition (masing_traction.h): the virgin traction is solved
    /// at multiples of this shift [m] and interpolated in between; 0 solves it
    /// at the shifts the history asks for.
    double masing_level_spacing = 0.0;
    /// Displacement control with a uniform shift continuing along the last
    /// step's: start from the last tractions extrapolated linearly in the
    /// shift (projected onto the discs) instead of the last tractions. The
    /// same solution to the tolerance, in fewer iterations on a monotone
    /// loading (MasingTraction's virgin levels use it).
    bool extrapolated_start = false;
  };

  /// What one load step did.
  struct PartialSlipStep
  {
    int         iterations = 0;       ///< CG iterations of the step (all force iterations)
    int         convolutions = 0;     ///< products with C (each 2 forward + 2 inverse FFTs)
    int         force_iterations = 0; ///< displacement solves (1 in displacement control)
    double      residual = 0.0;       ///< final relative residual
    double      shift_x_increment = 0.0; ///< imposed or (force control) found [m]; uniform part
    double      shift_y_increment = 0.0;
    double      force_x = 0.0; ///< sum of tau_x times cell area [N], on the lower body
    double      force_y = 0.0;
    double      dissipation = 0.0; ///< frictional work of the step, sum tau.s A [J] (>= 0)
    std::size_t stick_cells = 0;
    std::size_t slip_cells = 0;
  };

  /// The combined tangential compliance u = C tau of both bodies (docs/references.md
  /// §4.1) on a SurfaceGrid, by DC-FFT with the 2 x 2 block kernel: two forward
  /// and two inverse real FFTs per product. Exposed for tests and for callers
  /// that need the elastic tangential displacement of a traction field.
  class TangentialCompliance
  {
  public:
    TangentialCompliance(const SurfaceGrid &grid, const MaterialPair &materials, bool measure_fft_plans = false);
    ~TangentialCompliance();
    TangentialCompliance(TangentialCompliance &&) noexcept;
    TangentialCompliance &operator=(TangentialCompliance &&) noexcept;

    /// Influence coefficients [m/Pa] for a field cell offset (di, dj) from
    /// the loaded cell: xx = u_x from tau_x, xy = u_x from tau_y = u_y from tau_x.
    double kernel_xx(int di, int dj) const;
    double kernel_xy(int di, int dj) const;
    double kernel_yy(int di, int dj) const;

    /// (u_x, u_y) = C (tau_x, tau_y) on the whole grid [m], by DC-FFT.
    void apply(const Field &tau_x, const Field &tau_y, Field &u_x, Field &u_y) const;
    /// The same by O(N^2) direct summation: the reference.
    void apply_direct(const Field &tau_x, const Field &tau_y, Field &u_x, Field &u_y) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };

  /// The exact elastic partial-slip solver (see the file comment).
  class PartialSlipSolver
  {
  public:
    PartialSlipSolver(const SurfaceGrid &grid, const MaterialPair &materials, PartialSlipSettings settings);
    PartialSlipSolver(const SurfaceGrid &grid, const MaterialPair &materials)
      : PartialSlipSolver(grid, materials, PartialSlipSettings{}) {}
    ~PartialSlipSolver();
    PartialSlipSolver(PartialSlipSolver &&) noexcept;
    PartialSlipSolver &operator=(PartialSlipSolver &&) noexcept;

    /// Displacement control: one load step with the rigid shift increment
    /// (shift_x, shift_y) [m] of the upper body's remote points over the lower
    /// body's. pressure [Pa] per cell (it may change from step to step).
    /// Throws std::runtime_error if the iteration does not converge.
    const PartialSlipStep &advance(const Field &pressure, double friction_coefficient, double shift_x,
                                   double shift_y);
    /// The same with a shift increment per cell (e.g. a small rigid rotation).
    const PartialSlipStep &advance(const Field &pressure, double friction_coefficient, const Field &shift_x,
                                   const Field &shift_y);
    /// Force control: one load step to the total tangential force (force_x,
    /// force_y) [N] on the lower body; the uniform shift increment is the
    /// unknown (found by a Broyden iteration on displacement-controlled solves,
    /// each warm-started). Requires |Q| < mu sum(p A) (no gross slip: there the
    /// shift is undetermined); throws std::invalid_argument otherwise.
    const PartialSlipStep &advance_to_force(const Field &pressure, double friction_coefficient, double force_x,
                                            double force_y);

    /// Back to zero traction and zero shift history.
    void reset();

    const Field &traction_x() const; ///< [Pa], on the lower body
    const Field &traction_y() const; ///< [Pa]
    /// Micro-slip increment of the last step, upper surface over lower [m];
    /// zero on stick cells (to the tolerance) and outside the contact.
    const Field &slip_increment_x() const;
    const Field &slip_increment_y() const;
    /// Per cell: 1 where the last step left the cell slipping (|tau| = mu p),
    /// 0 where it sticks or carries no load. Exact: the solver's active set.
    const std::vector<unsigned char> &slip_mask() const;
    /// |tau| / (mu p) per cell, 0 outside the contact, 1 on slip cells.
    Field effective_friction() const;
    /// Slipping cells / loaded cells of the last step.
    double slip_area_fraction() const;
    /// Accumulated uniform shift [m] since construction or reset().
    double shift_x() const;
    double shift_y() const;

    const PartialSlipStep &last_step() const;
    const SurfaceGrid     &grid() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace fretsim::contact
