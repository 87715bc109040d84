#pragma once
// Static solutions of a free (or supported) body through the shifted system
//
//   (K - σ M) u = f,   σ = -(2π f_s)² < 0,
//
// which is positive definite even when K is singular (a free ring: six
// rigid-body modes). For a self-equilibrated load (no work on any rigid-body
// motion) the solution has no rigid-body part, and its elastic part differs
// from the pseudo-inverse solution by a relative (f_s / f_1)², f_1 the lowest
// elastic frequency: u = Σ_k φ_k φ_kᵀ f / (ω_k² + (2π f_s)²). This is the
// system CraigBampton::full_static solves (reduction/craig_bampton.h), here
// without a reduction basis, so that a full-FE reference can be computed for
// many loads with one factorisation (MUMPS Cholesky). Collective; no PETSc
// type appears here.
//
// Inertia relief (optional, for a free body): a load that is not exactly
// self-equilibrated has a rigid-body part Φ_rᵀf (Φ_r the six rigid-body
// modes, M-orthonormal), which the shifted system answers with the rigid
// motion Φ_r Φ_rᵀf / |σ|: for σ = -(2π · 1 Hz)² a residual force of 1 N moves
// a 0.2 kg ring by 0.13 m, a million times its elastic deformation. With
// inertia relief the load is balanced by the d'Alembert force of the rigid
// acceleration it would cause, f_e = f - M Φ_r Φ_rᵀ f, and the solution
// u = (K - σM)⁻¹ f_e is the deformation alone (M-orthogonal to every rigid
// motion; the solution is projected once more after the solve, which removes
// the round-off that 1/|σ| amplifies along the rigid motions). For an exactly
// self-equilibrated load both are the same.
//
// Many loads at once: solve_each() solves them as blocks of
// right-hand sides (MUMPS's triangular solves with many columns run at
// BLAS-3 speed; one column at a time they mostly repack the factor). Each
// load gets exactly what solve(load) does, relief included, to round-off.
#include <fretsim/fem/elastic_model.h>

#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

namespace fretsim::fem
{
  class ShiftedStaticSolver
  {
  public:
    /// Assembles M if the model has not yet, forms K - σM with
    /// σ = -(2π shift_hz)² and factorises it. `shift_hz` ≥ 0; 0 solves K u = f
    /// (a supported body only). With `inertia_relief` every load is balanced
    /// by rigid-body inertia first (a free body only). The model must outlive
    /// the solver.
    ShiftedStaticSolver(ElasticModel &model, double shift_hz, bool inertia_relief = false);
    ~ShiftedStaticSolver();
    ShiftedStaticSolver(const ShiftedStaticSolver &)            = delete;
    ShiftedStaticSolver &operator=(const ShiftedStaticSolver &) = delete;

    /// Most right-hand sides solved as one block: bounds a block's memory
    /// (its loads and solutions, two dense n_dofs × 64 matrices: 1 KiB per DoF).
    static constexpr std::size_t block_columns = 64;

    /// Assembles the load vector of `load` and solves.
    DisplacementField solve(const StaticLoad &load);
    /// Every load solved in blocks of at most `columns`, and `use(i, u_i)`
    /// called for each in the loads' order, one field alive at a time.
    void solve_each(const std::vector<StaticLoad>                                  &loads,
                    const std::function<void(std::size_t, const DisplacementField &)> &use,
                    std::size_t                                                    columns = block_columns);

    double shift() const; ///< σ [1/s²]
    /// Resultant force [N] and moment about the origin [N m] of the last
    /// solved load's vector (after a list of loads, the list's last), before
    /// any inertia relief: what relief balanced.
    Vector3 last_net_force() const;
    Vector3 last_net_moment() const;
    /// Wall-clock seconds: mass assembly (0 if M was there), K - σM and its
    /// factorisation (constructor); load assembly and solve of the last
    /// solve() or solve_each() (of all the list's loads together).
    double mass_seconds() const;
    double factorisation_seconds() const;
    double last_load_seconds() const;
    double last_solve_seconds() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace fretsim::fem
