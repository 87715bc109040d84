#pragma once
// Dang Van multiaxial fatigue criterion evaluated incrementally on a field of
// material points (docs/theory.md §2.6; docs/references.md §5). Per point and step:
//   Sigma          macroscopic stress [Pa], tension positive, Voigt xx,yy,zz,yz,xz,xy
//   S_c            centre of the deviatoric load path (see ResidualStressCentre)
//   rho* = -S_c    stabilised mesoscopic residual stress (deviatoric)
//   sigma          = Sigma + rho*, the mesoscopic stress
//   tau            = (sigma_1 - sigma_3) / 2, Tresca shear of sigma
//   sigma_H        = tr Sigma / 3 (residual stresses are deviatoric)
//   D(t)           = tau / (beta - alpha sigma_H), D_max = max over t of D(t)
// D >= 1 predicts crack initiation. Where beta - alpha sigma_H <= 0 the point is
// flagged and D = +infinity (no division is made).
#include <fretsim/contact/subsurface_stress.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace fretsim::contact
{
  /// Material constants of D = tau / (beta - alpha sigma_H).
  struct DangVanConstants
  {
    double alpha = 0.0; ///< hydrostatic sensitivity [-], >= 0
    double beta  = 0.0; ///< shear fatigue limit [Pa], > 0

    /// From the fully reversed fatigue limits in bending/tension f_-1 and in
    /// torsion t_-1 [Pa]: alpha = 3 (t_-1/f_-1 - 1/2), beta = t_-1
    /// (690 and 428 MPa give alpha = 0.360870, beta = 428 MPa).
    /// Throws std::invalid_argument unless both are positive and finite and
    /// 1/2 <= t_-1/f_-1 <= 1. Below 1/2, alpha < 0 would make hydrostatic
    /// tension raise the allowable shear, which no metal shows; 1/2 itself
    /// (alpha = 0, the Tresca limit) is allowed. Above 1 the torsion limit
    /// would exceed the bending limit (beyond even brittle cast irons, t/f ~ 1):
    /// almost certainly the two arguments swapped.
    static DangVanConstants from_fatigue_limits(double bending_limit, double torsion_limit);
  };

  /// How the residual-stress centre S_c of the deviatoric path is obtained.
  enum class ResidualStressCentre
  {
    /// Paper eq. 5: the running mean M_n = M_{n-1} + (Sigma_n - M_{n-1})/n over
    /// all steps so far, including the current one; S_c = dev(M_n). O(1)
    /// memory, no cycle needed. Converges to the cycle mean like 1/n, but its
    /// first cycle can overshoot the settled D (fully reversed torsion at the
    /// limit: 1.21 instead of 1; bending at f_-1/2: +1.8 %). D_max keeps that
    /// unless warmup_cycles excludes it.
    running_mean,
    /// dev of the mean of Sigma over the steps of the last complete cycle.
    /// Steps of cycle k >= 2 are evaluated with the centre of cycle k-1; the
    /// steps of cycle 1 with the running mean of cycle 1 so far. O(1) memory.
    last_cycle_mean,
    /// Dang Van's own definition (Papadopoulos 1997): the centre of the
    /// smallest ball enclosing the deviatoric path of the last complete cycle,
    /// in the 5-D deviatoric space with the norm sqrt(s:s). Used like
    /// last_cycle_mean (cycle k evaluated with the centre of cycle k-1; cycle 1
    /// with its running mean). Keeps the current cycle's path: 5 doubles per
    /// point per step of the cycle (49k points x 64 steps: 126 MB). end_cycle()
    /// then solves one ball per point, exactly up to round-off: 2-10 us a point
    /// on one core for a fully 5-D path of 32-200 steps (about the cost of
    /// 40-150 steps); proportional paths are cheaper.
    hypersphere
  };

  /// "running_mean" | "last_cycle_mean" | "hypersphere"; anything else throws
  /// std::invalid_argument naming the accepted values.
  ResidualStressCentre parse_residual_stress_centre(const std::string &name);
  std::string          to_string(ResidualStressCentre centre);

  struct DangVanSettings
  {
    ResidualStressCentre centre = ResidualStressCentre::running_mean;
    /// > 0: a cycle ends automatically after this many steps (and end_cycle()
    /// may still end one early). 0: cycles end only when end_cycle() is called.
    int steps_per_cycle = 0;
    /// D_max (and its step) accumulate only once this many cycles are
    /// complete. The two per-cycle centres have no centre before the first
    /// cycle is complete, so for them at least 1 applies whatever is set here;
    /// for running_mean 0 (the default) counts every step, as the paper does.
    int warmup_cycles = 0;
  };

  /// The criterion on n_points material points, advanced one time step at a
  /// time. Call order: add_step() per time step, end_cycle() when a load cycle
  /// ends (unless steps_per_cycle does it), read risk()/risk_max() at any time.
  /// State is a struct of arrays; a step allocates nothing (the hypersphere
  /// centre's path store grows during the first cycle unless steps_per_cycle
  /// is set, in which case it is reserved up front).
  class DangVanField
  {
  public:
    /// Throws std::invalid_argument for n_points == 0, beta <= 0, alpha < 0,
    /// non-finite constants, or negative steps_per_cycle / warmup_cycles.
    DangVanField(std::size_t n_points, const DangVanConstants &constants, const DangVanSettings &settings = {});

    /// One time step from a subsurface stress field. Point index
    /// p = (layer * ny + j) * nx + i, the layout of results.h5 /fields/risk.
    /// Throws std::invalid_argument (state unchanged) if n_layers*ny*nx differs
    /// from n_points or a value is not finite.
    void add_step(const StressField &stress);
    /// One time step from n_points consecutive Voigt tensors [Pa]:
    /// voigt[6 p + c], c in xx, yy, zz, yz, xz, xy. Same checks.
    void add_step(const double *voigt, std::size_t point_count);

    /// Fills the six components of `count` points of one layer, starting at
    /// point `first` of the layer: component c of point first + k into
    /// out[c][k] (c in xx, yy, zz, yz, xz, xy) [Pa].
    using BlockSource =
      std::function<void(std::size_t layer, std::size_t first, std::size_t count, double *const *out)>;
    /// Most points a BlockSource is asked for at once.
    static constexpr std::size_t block_size = 256;
    /// One time step from stresses made block by block while the criterion
    /// reads them (no stress field in memory): `plane` points a layer,
    /// n_points / plane layers, point p = layer plane + i as above. `source`
    /// is called concurrently for disjoint blocks. Throws std::invalid_argument
    /// if plane does not divide n_points (state unchanged) or, after the step
    /// (which then counts), if a value was not finite.
    void add_step(std::size_t plane, const BlockSource &source);

    /// Fills the six components of a block as BlockSource does, for step
    /// `step` (0-based) of a batch.
    using StepBlockSource = std::function<void(std::size_t step, std::size_t layer, std::size_t first,
                                               std::size_t count, double *const *out)>;
    /// `steps` time steps at once, equal to as many add_step(plane, source)
    /// calls with source(k, ...) for step k, value for value; cycle ends
    /// (DangVanSettings::steps_per_cycle) fall where they would. Each block of
    /// points goes through all the steps while its state and stresses are in
    /// cache, instead of every step streaming the whole field through memory.
    /// risk() and infinite_risk_count() are the last step's. The stresses
    /// must not depend on the criterion's state. A non-finite value throws
    /// std::invalid_argument after the batch (which then counts).
    void add_steps(std::size_t plane, std::size_t steps, const StepBlockSource &source);

    /// Ends the current load cycle. Throws std::logic_error if no step was
    /// added since the last cycle ended.
    void end_cycle();
    /// Forget D_max and its steps (e.g. after a warm-up the caller defines).
    void reset_maximum();
    /// Back to the state right after construction.
    void reset();

    std::size_t          n_points() const { return n; }
    std::int64_t         step_count() const { return steps; }
    int                  complete_cycles() const { return cycles; }
    int                  steps_in_current_cycle() const { return cycle_steps; }
    /// True once D_max accumulates (warm-up over, a centre available).
    bool                 maximum_active() const;
    const DangVanSettings  &settings() const { return options; }
    const DangVanConstants &constants() const { return material; }

    /// D(t) of the last step [-]; +infinity where beta - alpha sigma_H <= 0.
    const std::vector<double> &risk() const { return risk_now; }
    /// D_max over the counted steps [-]; 0 where no step was counted yet.
    const std::vector<double> &risk_max() const { return risk_peak; }
    /// 0-based index of the step that set D_max (the first, on ties); -1 if none.
    const std::vector<std::int64_t> &risk_max_step() const { return risk_peak_step; }
    /// Points with beta - alpha sigma_H <= 0 at the last step.
    std::size_t infinite_risk_count() const { return infinite_now; }
    /// Points whose D_max is infinite.
    std::size_t infinite_risk_max_count() const;
    /// Bytes held by the per-point state (and the hypersphere path store).
    std::size_t memory_bytes() const;

  private:
    /// One step; component c of point q of layer l at
    /// values[l layer_stride + c component_stride + q point_stride], `plane`
    /// points a layer.
    /// With `source`, the values come from it instead (values unused).
    /// Returns the number of non-finite values met (only counted with a source).
    std::size_t advance(const double *values, std::size_t component_stride, std::size_t point_stride,
                        std::size_t layer_stride, std::size_t plane, std::size_t layers,
                        const BlockSource *source = nullptr);
    /// `count` steps from a StepBlockSource (first_step: the batch index of
    /// the first), none past a cycle end; risk() written at the last of them
    /// if `last`. Returns the number of non-finite values met.
    std::size_t advance_segment(std::size_t plane, std::size_t layers, const StepBlockSource &source,
                                std::size_t first_step, std::size_t count, bool last);
    void check_finite(const double *values, std::size_t count) const;

    std::size_t      n;
    DangVanConstants material;
    DangVanSettings  options;

    std::int64_t steps       = 0;
    int          cycles      = 0;
    int          cycle_steps = 0;
    std::size_t  infinite_now = 0;

    // Deviatoric coordinates (detail::deviator_coordinates), [5][n] each.
    std::vector<double> mean;   ///< running mean (all steps, or the current cycle)
    std::vector<double> centre; ///< centre of the last complete cycle
    std::vector<double> path;   ///< hypersphere: [step of cycle][n][5]

    std::vector<double>       risk_now, risk_peak;
    std::vector<std::int64_t> risk_peak_step;
  };

  /// Principal values of a symmetric stress tensor, largest first [Pa].
  /// Trigonometric (Lode-angle) closed form; where two principal values are
  /// within 0.2 % of the spread, where that form loses digits, cyclic Jacobi
  /// rotations instead. Agrees with Eigen's iterative solver to 1e-14 of the
  /// largest |principal value|, repeated values included.
  std::array<double, 3> principal_stresses(const StressTensor &stress);
  /// Tresca shear (sigma_1 - sigma_3) / 2 [Pa]. Where principal_stresses uses
  /// the trigonometric form, this solves the same cubic by Newton's method
  /// (no trigonometric calls, vectorisable), equal to the trigonometric form
  /// to round-off (unit_dang_van); near-repeated values by Jacobi as there.
  double tresca_shear(const StressTensor &stress);

  /// Where a field of D_max values is largest among its finite entries (the
  /// first, on ties); values.size() if none is finite.
  std::size_t largest_finite_point(const std::vector<double> &values);

  namespace detail
  {
    constexpr int deviator_dimension = 5;
    /// Coordinates u of dev(stress) in an orthonormal basis of the symmetric
    /// traceless tensors, so that |u|^2 = s:s (= 2 J2):
    /// u = ((2 s_zz - s_xx - s_yy)/sqrt6, (s_xx - s_yy)/sqrt2, sqrt2 s_yz, sqrt2 s_xz, sqrt2 s_xy).
    std::array<double, deviator_dimension> deviator_coordinates(const StressTensor &stress);
    /// The traceless tensor with coordinates u (inverse of the above).
    StressTensor deviator_from_coordinates(const std::array<double, deviator_dimension> &u);
    /// Tresca shear of the traceless tensor with coordinates u [Pa].
    double tresca_shear_of_deviator(const double *u);
    /// sin(acos(x)/3 + pi/3) for x in [-1, 1], by Newton's method on the
    /// cubic (dang_van.cpp): the Tresca shear of a deviator of norm |u| and
    /// Lode invariant x is |u| lode_tresca_factor(x) / sqrt2.
    double lode_tresca_factor(double x);

    /// Smallest ball enclosing `count` points of R^5 stored row-major
    /// (points[5 k + d]). Writes its centre; returns its radius, the largest
    /// distance from the centre to a point, so the ball always encloses them.
    /// Exact up to round-off (see dang_van.cpp). Throws for count == 0.
    double minimum_enclosing_ball(const double *points, std::size_t count, double *centre);

    /// Reference principal values from Eigen's iterative (tridiagonal QR)
    /// SelfAdjointEigenSolver, largest first: for tests and cross-checks.
    std::array<double, 3> principal_stresses_reference(const StressTensor &stress);
  } // namespace detail
} // namespace fretsim::contact
