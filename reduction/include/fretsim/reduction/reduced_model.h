#pragma once
// A reduced model as the co-simulation needs it (DESIGN.md §3, §4): the
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
#include <fretsim/fem/surface_grid_map.h>
#include <fretsim/reduction/craig_bampton.h>

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

  struct ReducedModel
  {
    ReducedMatrices     matrices;
    std::vector<double> free_frequencies_hz; ///< of (K_r, M_r), rigid-body modes included
    GridOperators       interface_grid;       ///< empty grid (nx = 0) if none was asked for
    PointOperators      sample_points;
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

  /// 64-bit FNV-1a of a text, as 16 hex digits (an input fingerprint, not a
  /// cryptographic hash).
  std::string fingerprint(const std::string &text);
} // namespace fretsim::reduction
