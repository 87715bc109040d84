#pragma once
// A reduced model as the co-simulation needs it (docs/theory.md §3, §4): the
// Craig–Bampton matrices, the operators from modal coordinates q to the
// quantities on the contact surfaces, and the provenance; written to and read
// from an HDF5 model file. No HDF5 type appears here.
//
// Operators are row-major [item][component][coordinate], so that a quantity
// is x = Σ_j X[item][component][j] q_j:
//   interface grid: displacement (u_r, u_θ, u_z) at the cell centres of a
//   cylinder grid on the coupling surface (consistent map H T), and stress
//   (cylindrical Voigt rr, θθ, zz, θz, rz, rθ) at the same centres; the
//   transpose of the displacement operator takes grid tractions back to the
//   modal coordinates (f_q = (H T)ᵀ A t: conservative).
//   sample points: stress at surface points (e.g. along the raceway).
//   raceway: one row per ball position, Tᵀ f of a unit ball load there; the
//   same row gives the raceway's approach (r·q) and the generalised force of
//   a ball (Q r), so ball loads do no work the model does not store.
#include <fretsim/fem/surface_grid_map.h>
#include <fretsim/reduction/craig_bampton.h>

#include <array>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace fretsim::reduction
{
  struct GridOperators
  {
    fem::CylinderGrid   grid;
    std::vector<double> displacement; ///< [cell][3][n] [m per unit q]
    std::vector<double> stress;       ///< [cell][6][n] [Pa per unit q]
  };

  struct PointOperators
  {
    std::vector<fem::Point3> points;       ///< [m]
    std::vector<double>      displacement; ///< [point][3][n], Cartesian [m per unit q]; may be empty
    std::vector<double>      stress;       ///< [point][6][n], cylindrical Voigt [Pa per unit q]
  };

  /// The Hertz-distributed patch of a ball on the raceway: its semi-axes,
  /// and the ball load whose Hertz ellipse it is (0: a fixed footprint, the
  /// same whatever the load).
  struct BallFootprint
  {
    double semi_axis_circumferential = 0.0; ///< a [m]
    double semi_axis_transverse      = 0.0; ///< b, along the groove arc [m]
    double load                      = 0.0; ///< [N]
  };

  /// Ball loads on the raceway (co-simulation): row k is Tᵀ f_k for a unit
  /// Hertz-distributed ball load at ψ_k = 2π k / n_angles along the contact
  /// normal (outwards); r_k·q is the raceway's outward approach there [m].
  /// One table per footprint: a fixed one, or the Hertz ellipses of a few
  /// ball loads between which a run interpolates each ball's row at its load.
  struct RacewayOperators
  {
    std::vector<double> angles;   ///< ψ_k [rad], ascending, uniform from 0; empty if none
    std::vector<double> approach; ///< [footprint][angle][n] [m per unit q] (= N per unit q per N of ball load)
    std::vector<BallFootprint> footprints; ///< ascending loads, or one fixed footprint
    double                     contact_angle = 0.0; ///< [rad]
    /// Whether the footprint follows the ball load (footprints of loads > 0).
    bool follows_load() const { return !footprints.empty() && footprints.front().load > 0.0; }
    /// The footprints' loads, empty for a fixed footprint [N].
    std::vector<double> footprint_loads() const;
    /// The patch of a ball of load Q [N]: the Hertz ellipse of Q (semi-axes
    /// ∝ Q^{1/3}; Q ≤ 0: the smallest footprint), or the fixed footprint.
    BallFootprint footprint_at(double load) const;
  };

  /// Checks a footprint table: one fixed footprint (load 0), or Hertz
  /// ellipses of increasing loads > 0, both semi-axes ∝ Q^{1/3} (relative
  /// 1e-6). Throws std::invalid_argument naming the problem.
  void check_footprints(const std::vector<BallFootprint> &footprints);

  /// The part of the body's static compliance the basis misses, MacNeal's
  /// residual flexibility R = K⁻¹ − T K_r⁻¹ Tᵀ (a free ring: both with
  /// inertia relief; a housing held at its outside: plain static solves),
  /// as u_r on the interface grid, taken circulant in θ on the axisymmetric
  /// body: per unit force on the cells of the grid's first column (column
  /// angle), and for a ring per unit ball load at that angle. Empty if not
  /// computed.
  struct ResidualFlexibility
  {
    double column_angle = 0.0; ///< θ of the grid's first column [rad]
    /// [component][load row jj][cell] outward u_r per N of the traction
    /// component on cell (0, jj): 0 pressure (the force pushes into the
    /// body: inward on a ring's outer surface, outward on a housing's bore),
    /// 1 circumferential, 2 axial; a component may be empty [m/N].
    std::array<std::vector<double>, 3> traction;
    /// [footprint][cell] outward u_r per N of a ball at column_angle (the
    /// raceway operator's footprints) [m/N]; empty for a body without a
    /// raceway (the housing).
    std::vector<double> ball;
    /// Full and reduced solves it took, and their wall time [s].
    unsigned int solves  = 0;
    double       seconds = 0.0;
    bool         empty() const { return traction[0].empty(); }
    /// The pressure table as compliance: the inward displacement of every
    /// cell per unit pressure on cell (0, jj), [jj][cell] [m/Pa] (on a
    /// housing's bore, which the pressure pushes out, negative).
    std::vector<double> inward_per_pressure(double cell_area) const
    {
      std::vector<double> compliance(traction[0].size());
      for (std::size_t k = 0; k < compliance.size(); ++k)
        compliance[k] = -cell_area * traction[0][k];
      return compliance;
    }
  };

  struct ReducedModel
  {
    ReducedMatrices     matrices;
    std::vector<double> free_frequencies_hz; ///< of (K_r, M_r), rigid-body modes included
    GridOperators       interface_grid;       ///< empty grid (nx = 0) if none was asked for
    PointOperators      sample_points;
    RacewayOperators    raceway;              ///< empty angles if none was asked for (or an older file)
    ResidualFlexibility residual;             ///< empty if not computed (see `fretsim reduce`)
    ReductionTimings    timings;
    /// What the model was made from: mesh, material, boundary ids, mode
    /// counts, program version (written as string attributes).
    std::map<std::string, std::string> provenance;
    /// Hash of the inputs (configuration sections that define the body and
    /// the reduction, and the mesh file's bytes), hex.
    std::string input_hash;
  };

  /// A model file that cannot be used: unreadable, truncated, not a model
  /// file, or made from other inputs. what() names the file and the problem.
  class ModelFileError : public std::runtime_error
  {
  public:
    ModelFileError(const std::string &file, const std::string &problem);
  };

  /// Writes `path` through a temporary file and a rename, so that an
  /// interrupted write never leaves a half-written model. Call on one rank.
  void write_model_file(const std::string &path, const ReducedModel &model);

  /// Reads a model file; if `expected_hash` is not empty, refuses a file made
  /// from other inputs. Throws ModelFileError.
  ReducedModel read_model_file(const std::string &path, const std::string &expected_hash = "");

  /// Modal operators of a Craig–Bampton basis (after run()). Collective.
  GridOperators  grid_operators(const CraigBampton &basis, const fem::ElasticModel &model, fem::BoundaryId surface,
                                const fem::CylinderGrid &grid);
  PointOperators point_operators(const CraigBampton &basis, const fem::ElasticModel &model,
                                 const std::vector<fem::Point3> &points);
  /// The raceway operator of `n_angles` ball positions on the raceway of
  /// `ring` (contact angle 0), each ball a Hertz patch of each footprint
  /// (fem::RacewayBallLoad): row k of footprint f equals basis.project_load()
  /// of a unit ball at ψ_k, computed for all balls at once from the basis
  /// fields sampled at every patch point. Throws std::invalid_argument for a
  /// table check_footprints refuses, a patch that leaves the groove or a
  /// point off the mesh's raceway. Collective; the result is the same on
  /// every rank.
  RacewayOperators raceway_operators(const CraigBampton &basis, const fem::ElasticModel &model,
                                     const fem::RingGeometry &ring, unsigned int n_angles,
                                     const std::vector<BallFootprint> &footprints);
  /// A unit ball at `angle` on `ring`'s raceway with a footprint's patch.
  fem::RacewayBallLoad unit_ball(const fem::RingGeometry &ring, double angle, const BallFootprint &footprint);

  /// 64-bit FNV-1a of a text, as 16 hex digits (an input fingerprint, not a
  /// cryptographic hash).
  std::string fingerprint(const std::string &text);
} // namespace fretsim::reduction
