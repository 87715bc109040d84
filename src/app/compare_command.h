#pragma once
// `fretsim compare CONFIG`: the reduced ring of a bearing_housing co-simulation
// checked against the full FE model. At N instants of a run, the
// same loads — the balls (Hertz patches at ψ_j with force Q_j, the model's
// footprint and contact angle) and the housing's tractions on the interface
// grid — are applied to
//   * the full FE ring of the reduction configuration, solved statically with
//     the reduction's small shift, (K - σM) u = f, σ = -(2π · 1 Hz)², and
//   * the reduced model alone (the model file): q = (K_r - σM_r)⁻¹ g with
//     g = Σ_j Q_j r(ψ_j) + Σ_c A (H T)_cᵀ (-p, τ_x, τ_y)_c, r interpolated
//     linearly between the stored ball positions as the co-simulation does.
// Both with inertia relief (fem/shifted_static_solver.h): the loads'
// resultant (the ring's inertia in the run, and the O(Δψ²) resultant change of
// the interpolated ball rows) is balanced by the d'Alembert force of the rigid
// acceleration it causes, so that the 1 Hz shift does not turn a newton of
// imbalance into a rigid motion of a decimetre; the six rigid-body motions are
// the model's first six characteristic constraint modes. Then the reduced
// model's recovered displacements and stresses on the
// interface grid and at the raceway sample points are measured against the
// full ones (max-norm errors, relative to the full field's maximum), together
// with the energy-norm error of the Ritz solution and the run's own (dynamic)
// modal coordinates (rigid motion removed) against the full static solution;
// the same for the balls alone and the tractions alone (in a stiff housing the
// two nearly cancel, and the net deformation is a small difference of large
// ones); run times of both.
// The study repeats the reduced side for the model truncated to its first
// n_cc' characteristic constraint and first m' fixed-interface coordinates
// (nested subspaces: both sets are ordered by ascending eigenvalue).
//
// The interface pressure itself: at each instant the ring is also solved on
// the scene's unilateral Winkler foundation (k_n = Interface/Normal
// stiffness, δ_fit = Interface/Radial interference; p_c = k_n max(δ_fit +
// u_r,c, 0) on the interface grid, fem/winkler_foundation.h) under the run's
// ball loads alone, by the full FE ring and by every truncated model, and the
// pressure fields are compared (peak, max-norm and L2 errors, contact
// fractions, active-set solves, times). No inertia relief there: the
// foundation carries the balls' resultant, as the housing does in the run;
// the shift holds only the rotation about the axis and the axial translation,
// which move no cell radially. compare_pressure.csv holds the pressure along
// the circumference (axial mid-row) at the instant of the highest full peak.
#include <fretsim/support/parameters.h> // InputError

#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace fretsim::app
{
  struct CompareOptions
  {
    std::string config_file;      ///< bearing_housing scene file
    std::string output_directory; ///< default: results/<config name>-compare
    std::vector<std::pair<std::string, std::string>> overrides; ///< --set Section/Name=value
    bool        plots    = true;
    bool        progress = true;
  };

  /// What the comparison works on, paths resolved: the core's explicit
  /// arguments (read_compare_inputs() fills them from a scene file).
  struct CompareInputs
  {
    std::string  source;           ///< the file the inputs come from, for messages
    std::string  reduction_config; ///< ring_housing configuration of the model
    std::string  model_file;       ///< reduced model (.h5) made from it
    /// Reduction parameters over the configuration's that the model was made
    /// with (the scene's Model/Characteristic constraint modes, ...): its hash.
    std::vector<std::pair<std::string, std::string>> model_overrides;
    /// The co-simulation's results.h5. A run made with another model of the
    /// same ring (other n_cc or m, same interface grid) is accepted: its loads
    /// and pressures are compared, its own modal coordinates are not. A run
    /// with the housing's half-space or a flexible housing (as its file
    /// records) is accepted too: the ring is compared under its loads, and
    /// its pressure, another problem, is not set against the Winkler check.
    std::string  results_file;
    unsigned int instants = 4;     ///< how many snapshots to compare
    /// Steps of the full-FE transient timed against the run (0: none).
    unsigned int full_transient_steps = 20;
    /// Truncations studied: m' and n_cc' (those above the model's are left out).
    std::vector<unsigned int> fixed_interface_modes, constraint_modes;
    /// A flexible housing's reduction configuration and reduced model
    /// (Model/Housing ...; empty: the scene's housing is rigid). With a run
    /// that had it, the housing is compared too (compare_housing.h).
    std::string housing_reduction_config, housing_model_file;
    /// The housing meshed for a second full-FE transient (Compare/Full
    /// transient housing, resolved like the reduction configuration; empty:
    /// none): ring and housing joined by the layer (fem::WinklerPairNewmark).
    std::string full_transient_housing_config;
    /// The housing interface's Winkler layer, as the run had it.
    double normal_stiffness    = 1e15; ///< k_n [Pa/m], > 0
    double radial_interference = 0.0;  ///< δ_fit [m]
  };

  /// Reads the scene file (and --set overrides) and resolves the paths: the
  /// reduction configuration relative to the scene file's directory; an empty
  /// model file is results/<reduction config name>-model.h5 and an empty
  /// results file results/<scene name>/results.h5 (relative to the working
  /// directory, where `fretsim reduce` and `fretsim run` put them). Throws
  /// InputError.
  CompareInputs read_compare_inputs(const std::string &config_file,
                                    const std::vector<std::pair<std::string, std::string>> &overrides);

  /// Checks every input (InputError naming `inputs.source` and the parameter;
  /// nothing is written), then compares, prints the tables to `out` (rank 0)
  /// and writes <output_directory>/compare.csv, compare_pressure.csv and,
  /// with `plots`, compare.png. Returns the files written (on rank 0). Starts MPI unless it
  /// runs already; the full FE model is distributed over the ranks.
  std::vector<std::string> run_comparison(const CompareInputs &inputs, const std::string &output_directory,
                                          bool plots, std::ostream &out);

  /// `fretsim compare CONFIG [-o DIR] [--set ...]`.
  std::vector<std::string> run_compare_command(const CompareOptions &options, std::ostream &out);
} // namespace fretsim::app
