#pragma once
// A body on a unilateral Winkler foundation laid on a contact surface grid:
// the reference for the housing interface of a bearing_housing run (the
// co-simulation's p_c = k_n max(δ_fit + u_r,c, 0), coupling/ring_coupling.h),
// solved statically on the full FE model or on a reduced model.
//
// Per grid cell c (area A, centre sampled by the grid map's H, as
// SurfaceGridMap does), n_c the direction in which the pressure pushes on the
// body (-e_r on an outer surface, +e_r on a bore) and w_c = Hᵀ n_c:
//
//   penetration  d_c = δ_fit - n_c · (H u)_c          (δ_fit + u_r on an outer surface)
//   pressure     p_c = k_n max(d_c, 0)
//   equilibrium  (K - σM) u = f + Σ_c A p_c w_c
//
// u minimises the strictly convex Φ(u) = ½ uᵀ(K - σM)u - fᵀu + ½ Σ_c k_n A max(d_c, 0)²
// (reported as `energy`): the solution is unique, and a reduced model's Φ at
// its own solution can only fall towards the full one as its basis grows.
//
// Active-set iteration: with the set of penetrating cells fixed the problem
// is linear,
//   (K - σM + Σ_{c∈active} k_n A w_c w_cᵀ) u = f + Σ_{c∈active} k_n A δ_fit w_c,
// solved by a Cholesky factorisation; the cells whose d_c > 0 form the next
// set, until a solution penetrates exactly where it was assumed to (then it
// is the solution). The first set is the caller's guess, or every cell. The
// plain iteration (always moving to the new linear solution) can cycle
// between sets — it did on a small ring under two balls — so a step that
// would not lower Φ moves only as far towards the new solution as lowers Φ
// most (an exact line search of the piecewise quadratic Φ, computed from
// per-cell quantities alone; semismooth Newton with line search): Φ falls at
// every step and no state comes back. Past the iteration cap:
// std::runtime_error naming the solver.
//
// The shift σ = -(2π f_s)² (f_s = 1 Hz by default) holds what radial springs
// do not: the rotation about the axis and the axial translation. Neither
// moves any cell radially, so neither changes the pressure; radially it adds
// the stiffness (2π f_s)² M, a relative (f_s / f_1)² ~ 1e-12 of the
// foundation-supported ring's lowest frequency f_1 (~ 10⁵ Hz at k_n = 10¹⁵).
// No inertia relief (unlike ShiftedStaticSolver's option): here the
// foundation, not the ring's inertia, carries the net load, as the housing
// does in the run; relieving the load's resultant would take the very force
// the pressure has to carry out of it. Radial ball loads have no axial force
// and no moment about the axis, so the two shift-held motions are not loaded
// beyond round-off.
//
// Collective over the model's ranks; the results are the same on every rank.
// No deal.II or PETSc type appears here.
#include <fretsim/fem/elastic_model.h>
#include <fretsim/fem/surface_grid_map.h>

#include <memory>
#include <vector>

namespace fretsim::fem
{
  /// The foundation (SI).
  struct WinklerLayer
  {
    double normal_stiffness    = 0.0; ///< k_n > 0 [Pa/m]
    double radial_interference = 0.0; ///< δ_fit: > 0 interference fit, < 0 clearance [m]
  };

  struct WinklerSettings
  {
    double       shift_hz       = 1.0; ///< f_s of σ = -(2π f_s)², ≥ 0 (0: the body must be supported)
    unsigned int max_iterations = 50;  ///< linear solves before the active set is declared not converged
  };

  /// The grid side of a solution, from either model.
  struct WinklerGridSolution
  {
    std::vector<double>        pressure;    ///< p_c [Pa], per grid cell (x fastest)
    std::vector<double>        penetration; ///< d_c [m]; ≤ 0 where the cell is open
    std::vector<unsigned char> active;      ///< 1 where d_c > 0 (the converged set)
    std::size_t                active_cells = 0;
    unsigned int               iterations   = 0; ///< linear solves; the last one confirms the set
    unsigned int               factorisations = 0; ///< of them, those that factorised (a set met before reuses its factors)
    double                     energy       = 0.0; ///< Φ at the solution [J]
    double                     seconds      = 0.0; ///< the whole solve, load assembly included
    double                     factorisation_seconds = 0.0; ///< summed over the iterations

    double contact_fraction() const;
    double peak_pressure() const;
  };

  /// The full FE body. The model and map must outlive the solver.
  class WinklerFoundationSolver
  {
  public:
    /// Assembles M if the model has not yet and keeps K - σM. Throws
    /// std::invalid_argument for k_n ≤ 0, a non-finite δ_fit, a negative
    /// shift, or a map made on another model.
    WinklerFoundationSolver(ElasticModel &model, const SurfaceGridMap &map, const WinklerLayer &layer,
                            const WinklerSettings &settings = {});
    ~WinklerFoundationSolver();
    WinklerFoundationSolver(const WinklerFoundationSolver &)            = delete;
    WinklerFoundationSolver &operator=(const WinklerFoundationSolver &) = delete;

    struct Solution
    {
      WinklerGridSolution grid;
      DisplacementField   displacement;
    };

    /// Solves for `load` (the body's own loads, e.g. balls). `initial_active`:
    /// a first guess of the contact set, one entry per grid cell, or empty
    /// (every cell). Collective.
    Solution solve(const StaticLoad &load, const std::vector<unsigned char> &initial_active = {});

    double shift() const;         ///< σ [1/s²]
    double setup_seconds() const; ///< mass (if assembled here) and K - σM

  private:
    friend class WinklerNewmark;
    struct Impl;
    std::unique_ptr<Impl> impl;
  };

  /// The full FE body's transient on the foundation: what a bearing_housing
  /// run does on the reduced model, done on the full one (without the
  /// bristles' tangential tractions), to measure what the reduction saves.
  /// Newmark's average acceleration in NewmarkIntegrator's displacement–
  /// velocity form (transient.h), the foundation force G(u) = Σ_c A p_c w_c
  /// taken at both ends of the step like the loads (the trapezoidal rule):
  ///   (K + 4M/Δt²) u₊ - G(u₊) = M(4u/Δt² + 4v/Δt) - K u + G(u) + f + f₊,
  ///   v₊ = 2(u₊ - u)/Δt - v.
  /// Each step is WinklerFoundationSolver's problem with σ = -4/Δt² and the
  /// right-hand side's known part as a load, solved by the same active-set
  /// iteration from the previous step's set; the factorisation is kept while
  /// the set does not change (each new set costs one MUMPS factorisation).
  /// While no cell opens or closes the system is linear and the rule keeps
  /// energy() exactly under a constant load; under a constant load the
  /// static solution is a fixed point (up to the start's 1 Hz shift, ~1e-12).
  class WinklerNewmark
  {
  public:
    /// Starts at rest from the static solution on the foundation under
    /// `initial_load` (WinklerFoundationSolver, 1 Hz shift). The model, map
    /// and the loads' referenced objects must outlive the integrator.
    /// Collective. Throws std::invalid_argument for a time step that is not
    /// finite and > 0, and what WinklerFoundationSolver throws.
    /// `initial_active`: a guess of the start's contact set (as for
    /// WinklerFoundationSolver::solve; empty: every cell).
    WinklerNewmark(ElasticModel &model, const SurfaceGridMap &map, const WinklerLayer &layer, double time_step,
                   const StaticLoad &initial_load, double start_time = 0.0,
                   const std::vector<unsigned char> &initial_active = {});
    ~WinklerNewmark();
    WinklerNewmark(const WinklerNewmark &)            = delete;
    WinklerNewmark &operator=(const WinklerNewmark &) = delete;

    /// One step to time() + Δt under `load`, the load at the new time (its
    /// referenced objects must live until the next step). Returns the
    /// foundation at the new time (`seconds`: this step). Collective.
    const WinklerGridSolution &advance(const StaticLoad &load);

    double                     time() const;
    double                     time_step() const;
    /// At time(); its `energy` is the foundation's ½ Σ k_n A max(d, 0)² alone.
    const WinklerGridSolution &foundation() const;
    DisplacementField          displacement() const;
    /// ½vᵀMv + ½uᵀKu + ½ Σ k_n A max(d, 0)² - fᵀu at time() [J]. Collective.
    double       energy() const;
    unsigned long n_dofs() const; ///< of the model
    unsigned int steps() const;
    unsigned int solves() const;         ///< linear solves over the steps
    unsigned int factorisations() const; ///< MUMPS factorisations over the steps
    double       factorisation_seconds() const; ///< their wall time, part of step_seconds()
    double       step_seconds() const;   ///< wall time of the steps so far (not the static start)

  private:
    struct Impl;
    std::unique_ptr<Impl> pimpl;
  };

  /// Ring and housing both meshed, joined by the layer between the ring's
  /// outer surface and the housing bore on one grid: the full-FE transient of
  /// a run whose housing gives way (the half-space or a flexible housing), to
  /// measure what the reduction saves where WinklerNewmark's rigid foundation
  /// would leave the housing's compliance out. Per grid cell the layer's
  /// penetration is the gap closed by both surfaces,
  ///   d_c = δ_fit - n_c·(H u)_c - n'_c·(H' u')_c = δ_fit + u_r,c - u'_r,c,
  /// (n_c = -e_r on the ring's outer surface, n'_c = +e_r on the bore) and
  /// p_c = k_n max(d_c, 0) pushes on both, equal and opposite. With w_c the
  /// cell's weights on both bodies' DoFs, the layer adds k_n A w_c w_cᵀ to the
  /// joint matrix [K + 4M/Δt², 0; 0, K' + 4M'/Δt²], which couples the two
  /// bodies' DoFs of a cell; the steps are WinklerNewmark's (Newmark's
  /// average acceleration, the layer at both ends of the step, the active-set
  /// iteration from the last step's set, one MUMPS Cholesky factorisation of
  /// the joint system per new set). The housing's loads are the layer alone;
  /// it is held by its own supports (a housing held nowhere is singular).
  /// No bristle tractions: a lower bound on a full-FE co-simulation.
  class WinklerPairNewmark
  {
  public:
    /// Starts at rest from the joint static solution under `initial_ring_load`
    /// (both bodies with the 1 Hz shift, which holds the free ring's rigid
    /// motions as in WinklerFoundationSolver). The maps must be on the two
    /// models, on grids of the same size, with opposite pressure directions
    /// (an outer surface and a bore); the models on the same ranks.
    /// Everything passed must outlive the integrator. Collective. Throws
    /// std::invalid_argument for mismatched maps, a time step that is not
    /// finite and > 0, or a layer check_layer rejects; std::runtime_error if
    /// a layer cell's DoF is constrained other than to zero.
    /// `initial_active`: a guess of the start's contact set (empty: every cell).
    WinklerPairNewmark(ElasticModel &ring, const SurfaceGridMap &ring_map, ElasticModel &housing,
                       const SurfaceGridMap &housing_map, const WinklerLayer &layer, double time_step,
                       const StaticLoad &initial_ring_load, double start_time = 0.0,
                       const std::vector<unsigned char> &initial_active = {});
    ~WinklerPairNewmark();
    WinklerPairNewmark(const WinklerPairNewmark &)            = delete;
    WinklerPairNewmark &operator=(const WinklerPairNewmark &) = delete;

    /// One step to time() + Δt under the ring's `load` at the new time (its
    /// referenced objects must live until the next step). Collective.
    const WinklerGridSolution &advance(const StaticLoad &ring_load);

    double                     time() const;
    double                     time_step() const;
    /// At time(); `energy` is the layer's ½ Σ k_n A max(d, 0)² alone.
    const WinklerGridSolution &foundation() const;
    /// The static start's layer (its `seconds`: the start's solve).
    const WinklerGridSolution &start() const;
    DisplacementField          ring_displacement() const;
    DisplacementField          housing_displacement() const;
    /// Σ over both bodies of ½vᵀMv + ½uᵀKu, plus the layer's energy, minus
    /// the ring load's fᵀu at time() [J]. Collective.
    double        energy() const;
    unsigned long n_dofs() const; ///< of the joint system
    unsigned int  steps() const;
    unsigned int  solves() const;         ///< linear solves over the steps
    unsigned int  factorisations() const; ///< joint factorisations over the steps
    double        factorisation_seconds() const; ///< their wall time, part of step_seconds()
    double        step_seconds() const;   ///< wall time of the steps so far (not the static start)

  private:
    struct Impl;
    std::unique_ptr<Impl> pimpl;
  };

  /// The same problem on a reduced model u = T q (plain arrays, dense
  /// Cholesky): (K_r - σM_r + Σ_{c∈active} k_n A g_c g_cᵀ) q = g + Σ_{c∈active} k_n A δ_fit g_c,
  /// with g_c the row giving the cell's outward motion into the foundation
  /// (d_c = δ_fit + g_c·q; for a ring's outer surface the u_r row of the
  /// interface grid operator H T) and g the generalised load Tᵀf.
  class ReducedWinklerSolver
  {
  public:
    /// `shifted`: K_r - σM_r, n × n row-major (symmetric positive definite);
    /// `penetration_rows`: [cell][n] row-major [m per unit q]; `cell_area` [m²].
    /// Throws std::invalid_argument for inconsistent sizes, k_n ≤ 0 or a
    /// non-finite δ_fit.
    ReducedWinklerSolver(std::size_t n, const std::vector<double> &shifted, const std::vector<double> &penetration_rows,
                         double cell_area, const WinklerLayer &layer, unsigned int max_iterations = 50);
    ~ReducedWinklerSolver();
    ReducedWinklerSolver(ReducedWinklerSolver &&) noexcept;
    ReducedWinklerSolver &operator=(ReducedWinklerSolver &&) noexcept;

    struct Solution
    {
      WinklerGridSolution grid;
      std::vector<double> q;
    };

    /// `generalised_load`: g [n]; `initial_active` as for the full solver.
    Solution solve(const std::vector<double> &generalised_load,
                   const std::vector<unsigned char> &initial_active = {}) const;

    std::size_t n() const;
    std::size_t n_cells() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace fretsim::fem
