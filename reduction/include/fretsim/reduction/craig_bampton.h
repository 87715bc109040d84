#pragma once
// Craig–Bampton reduction of an FE body (docs/theory.md §3), with the interface
// reduced by characteristic constraint modes.
//
// The FE DoFs split into boundary b (the nodes of the coupling surfaces) and
// interior i. The basis is
//
//   u = T q,   T = [ V      0 ]   q = [ q_c ]   V: n_b × n_cc characteristic constraint modes
//                  [ Ψ V    Φ ]       [ η   ]   Φ: n_i × m fixed-interface modes
//
// with the constraint modes Ψ = -K_ii⁻¹ K_ib (static condensation: an
// interior load reaches the boundary coordinates exactly), Φ the lowest
// modes of K_ii φ = ω² M_ii φ, mass-normalised, and V the lowest eigenvectors
// of the Guyan-condensed interface problem
//
//   S v = λ M_G v,   S = K_bb + K_bi Ψ,   M_G = [I; Ψ]ᵀ M [I; Ψ],
//
// M_G-normalised. Without interface reduction (n_cc = 0) V is the identity:
// classic Craig–Bampton with one constraint mode per boundary DoF.
//
// How the n_cc interface modes are found without forming Ψ for every boundary
// DoF (thousands of solves): Krylov–Schur (SLEPc) on the operator
// v ↦ [(K - σM)⁻¹ M [v; Ψv]]_b, which for σ = 0 is exactly S⁻¹ M_G (the bb
// block of K⁻¹ is S⁻¹, and the interior part of K⁻¹ drops out), with σ < 0
// small so that a free body's K is invertible. Each application costs two
// solves with factorisations done once (K_ii and K - σM, MUMPS). A Rayleigh–Ritz step with the exact S and M_G
// in the space found then gives the characteristic constraint modes of the
// Guyan problem itself; the small shift only steers the search.
//
// Reduced matrices M_r = Tᵀ M T, K_r = Tᵀ K T. No PETSc or SLEPc type appears
// here; all calls are collective over the model's ranks.
#include <fretsim/fem/elastic_model.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace fretsim::reduction
{
  struct ReductionSettings
  {
    /// Surfaces whose nodes are boundary DoFs (e.g. ring_outer, raceway).
    std::vector<fem::BoundaryId> coupling_surfaces;
    /// m: fixed-interface normal modes kept.
    unsigned int n_fixed_interface_modes = 40;
    /// n_cc: characteristic constraint modes kept; 0 keeps one constraint
    /// mode per boundary DoF (no interface reduction, small models only).
    unsigned int n_characteristic_constraint_modes = 60;
    /// The steering shift σ = -(2π f)² of the interface search [Hz]; 0 picks
    /// f = f_1/50, f_1 the lowest fixed-interface frequency: small enough that
    /// the search's eigenvectors differ from the Guyan ones by ~ (f/f_1)² (the
    /// Rayleigh–Ritz step removes that to second order), large enough that the
    /// six rigid-body modes (λ = 0) do not drown the rest of the spectrum.
    double interface_shift_hz = 0.0;
    /// The shift of the static solves (full_static, reduced_static) [Hz]: a
    /// free body's K is singular; (f/f_1)² is the relative change it makes.
    double static_shift_hz = 1.0;
    /// Relative residual of the eigen-solves.
    double eigen_tolerance = 1e-10;
    /// Called with a stage name and the fraction done (0..1), on every rank.
    std::function<void(const std::string &stage, double fraction)> progress;
  };

  /// Wall-clock seconds of each stage.
  struct ReductionTimings
  {
    double partition               = 0.0; ///< index sets and sub-matrices
    double factorisation           = 0.0; ///< K_ii and K - σM (MUMPS)
    double fixed_interface_modes   = 0.0;
    double interface_modes         = 0.0; ///< characteristic constraint modes
    double constraint_modes        = 0.0; ///< Ψ V
    double reduced_matrices        = 0.0;
    double total                   = 0.0;
  };

  /// The reduced model in plain arrays (the same on every rank). Coordinates:
  /// the n_c constraint coordinates q_c first, then the m modal coordinates η.
  struct ReducedMatrices
  {
    unsigned int        n_constraint = 0; ///< n_cc, or n_b without interface reduction
    unsigned int        n_modal      = 0; ///< m
    std::vector<double> mass;             ///< M_r, row-major n × n [kg, kg·m ... per basis scaling]
    std::vector<double> stiffness;        ///< K_r, row-major n × n
    /// Fixed-interface frequencies ω_j / 2π of Φ, ascending [Hz].
    std::vector<double> fixed_interface_frequencies_hz;
    /// Guyan interface eigenvalues λ of V as frequencies sqrt(λ)/2π, ascending
    /// (near 0 for rigid-body motions) [Hz]; empty without interface reduction.
    std::vector<double> interface_frequencies_hz;
    /// max |A - Aᵀ| / max |A| of Tᵀ K T and Tᵀ M T before symmetrisation.
    double stiffness_asymmetry = 0.0, mass_asymmetry = 0.0;
    unsigned long n_boundary_dofs = 0, n_interior_dofs = 0;

    unsigned int size() const { return n_constraint + n_modal; }
  };

  class CraigBampton
  {
  public:
    /// Keeps a reference to the model (which must outlive this object).
    CraigBampton(fem::ElasticModel &model, ReductionSettings settings);
    ~CraigBampton();

    /// Partition, factorise, fixed-interface modes, interface modes,
    /// constraint modes, reduced matrices. Throws std::invalid_argument for
    /// settings the model cannot meet (no boundary DoFs, too many modes).
    ReducedMatrices run();

    const ReductionTimings &timings() const;
    /// Number of reduced coordinates (columns of T) after run().
    std::size_t size() const;

    /// Column j of T as a displacement field on the full mesh (after run()).
    fem::DisplacementField basis_field(unsigned int j) const;
    /// Tᵀ f for the load vector of `load` [N per unit coordinate].
    std::vector<double> project_load(const fem::StaticLoad &load) const;
    /// Full-FE static solution of (K - σ_s M) u = f with σ_s = -(2π static_shift_hz)²
    /// (a free body stays solvable; a self-equilibrated load has no rigid
    /// part), by the factorised K - σM; and the reduced one, T q with
    /// (K_r - σ_s M_r) q = Tᵀ f. Both as fields, for comparisons.
    fem::DisplacementField full_static(const fem::StaticLoad &load) const;
    fem::DisplacementField reduced_static(const fem::StaticLoad &load, const ReducedMatrices &reduced) const;
    /// T q as a field.
    fem::DisplacementField expand(const std::vector<double> &q) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };

  /// Generalised eigenvalues of (K_r, M_r) as frequencies sqrt(max(λ,0))/2π,
  /// ascending, rigid-body modes included (≈ 0) [Hz].
  std::vector<double> reduced_frequencies_hz(const ReducedMatrices &reduced);
} // namespace fretsim::reduction
