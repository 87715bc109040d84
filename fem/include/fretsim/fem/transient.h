#pragma once
// Transient response under moving loads (docs/theory.md §3): Newmark's average
// acceleration rule (β = 1/4, γ = 1/2, the trapezoidal rule), unconditionally
// stable and without numerical damping, so that an undamped free vibration
// keeps its energy ½vᵀMv + ½uᵀKu exactly up to the solver's round-off.
// Written in displacement–velocity form, which needs no initial acceleration
// (M is singular on constrained DoFs):
//   (K + 4M/Δt²) u₊ = M (4u/Δt² + 4v/Δt) - K u + f + f₊,   v₊ = 2(u₊ - u)/Δt - v.
// The effective matrix is factorised once (MUMPS Cholesky) and every step is
// one pair of triangular solves.
#include <fretsim/fem/elastic_model.h>
#include <fretsim/fem/surface_grid_map.h>

#include <memory>
#include <vector>

namespace fretsim::fem
{
  /// A Hertz (semi-ellipsoidal) pressure patch p = p₀ √(1 - (ξ/a)² - (η/b)²),
  /// p₀ = 3P/(2πab), such as a ball presses into a raceway, centred at (x, y)
  /// of a contact surface grid (x = arc length, wrapped around the circumference).
  struct HertzPatch
  {
    double x = 0.0, y = 0.0; ///< centre: arc length from θ = 0, axial position [m]
    double a = 0.0;          ///< semi-axis along x (circumferential) [m]
    double b = 0.0;          ///< semi-axis along y (axial) [m]
    double force = 0.0;      ///< total normal force P [N]
  };

  /// The patches as grid pressures (cell-centre values, scaled so that each
  /// patch's Σ A p is exactly P even when it covers few cells). Applied through
  /// a SurfaceGridMap (f = Hᵀ A t) the nodal forces carry P exactly as well.
  GridTractions hertz_patch_tractions(const CylinderGrid &grid, const std::vector<HertzPatch> &patches);

  class NewmarkIntegrator
  {
  public:
    /// Starts at time `start_time` from `initial_displacement` (nullptr: zero)
    /// at rest, under `initial_load` (the load at the start time). The model
    /// must outlive the integrator. Collective.
    NewmarkIntegrator(ElasticModel &model, double time_step, const StaticLoad &initial_load,
                      const DisplacementField *initial_displacement = nullptr, double start_time = 0.0);
    ~NewmarkIntegrator();

    /// One step to time() + Δt under `load`, the load at the new time. Collective.
    void advance(const StaticLoad &load);

    double            time() const;
    double            time_step() const;
    DisplacementField displacement() const;
    double            kinetic_energy() const; ///< ½ vᵀ M v [J]
    double            strain_energy() const;  ///< ½ uᵀ K u [J]
    double            factorisation_seconds() const;
    double            step_seconds() const; ///< total over the steps so far

  private:
    struct Impl;
    std::unique_ptr<Impl> pimpl;
  };
} // namespace fretsim::fem
