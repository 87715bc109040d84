#pragma once
// Static solves of a Craig–Bampton model from its file, with inertia relief
// (the reduced counterpart of fem::ShiftedStaticSolver's), on the whole model
// or a truncation of it; and MacNeal's residual flexibility of the basis,
// which `reduce` stores for the co-simulation and `compare` checks against
// the full FE.
#include <fretsim/fem/elastic_model.h>
#include <fretsim/fem/surface_grid_map.h>
#include <fretsim/reduction/reduced_model.h>

#include <cstddef>
#include <functional>
#include <vector>

namespace fretsim::fem
{
  class ShiftedStaticSolver;
  class SurfaceGridMap;
} // namespace fretsim::fem

namespace fretsim::models
{
  /// The rigid-body motions of a free body: the model's first six
  /// constraint coordinates.
  constexpr std::size_t rigid_modes = 6;

  /// Whether the model's first six constraint coordinates are the rigid-body
  /// motions (a free ring reduced with more than six characteristic
  /// constraint modes: Guyan eigenvalue 0, below fem::ModalSettings' rigid-body
  /// cutoff), which inertia relief needs.
  bool starts_with_rigid_motions(const reduction::ReducedMatrices &matrices);

  /// The model restricted to the coordinates of one truncation (m', n_cc'):
  /// the sub-blocks of K_r and M_r and the matching operator columns.
  struct Truncation
  {
    unsigned int        fixed_interface = 0, constraint = 0;
    std::size_t         n = 0;
    bool                whole_model = false;
    std::vector<double> shifted;           ///< K_r - σ M_r, n × n
    std::vector<double> grid_displacement; ///< [cell][3][n]
    std::vector<double> grid_stress;       ///< [cell][6][n]
    std::vector<double> raceway_stress;    ///< [raceway point][6][n]
    std::vector<double> approach;          ///< [footprint][angle][n]
    std::size_t         n_angles = 0;
    std::vector<double> footprint_loads;   ///< the footprints' ball loads [N]; empty: one fixed footprint
    /// Inertia relief: the first six constraint coordinates are the
    /// rigid-body motions R; M_r R [n][6] and the factor of Rᵀ M_r R [6][6].
    std::vector<double> mass_rigid, rigid_factor;
  };

  /// The coordinates of the first `constraint` constraint modes and the first
  /// `fixed_interface` fixed-interface modes; σ the static shift [rad²/s²]
  /// (negative); `raceway_points`: sample points whose stress rows to keep.
  Truncation truncate(const reduction::ReducedModel &model, unsigned int fixed_interface, unsigned int constraint,
                      const std::vector<std::size_t> &raceway_points, double sigma);
  /// The whole model, without raceway sample points.
  Truncation whole_model(const reduction::ReducedModel &model, double sigma);

  /// In-place Cholesky factor (lower) of a symmetric positive definite
  /// row-major matrix, and the solve with it. Throws std::runtime_error if
  /// the matrix is not positive definite.
  void                cholesky(std::vector<double> &a, std::size_t n);
  std::vector<double> cholesky_solve(const std::vector<double> &l, std::size_t n, std::vector<double> b);

  /// q = (K_r - σM_r)⁻¹ g_e, g_e the inertia-relieved generalised load g,
  /// without rigid-body motion (M_r-orthogonal to it).
  std::vector<double> relieved_static(const Truncation &t, std::vector<double> g);

  /// q without its rigid-body motion: q - R (Rᵀ M_r R)⁻¹ Rᵀ M_r q.
  void remove_rigid_motion(const Truncation &t, std::vector<double> &q);

  /// y = A q for a row-major [rows][n] operator.
  std::vector<double> apply(const std::vector<double> &op, std::size_t n, const std::vector<double> &q);

  /// row += factor r(ψ) of a ball of load `load` [N], r interpolated
  /// linearly between the stored positions ψ_k = 2πk/n and between the
  /// footprints at that load with the co-simulation's weights
  /// (coupling::BallContacts).
  void add_ball_row(const Truncation &t, double angle, double load, double factor, std::vector<double> &row);
  /// row += factor r(ψ) of footprint `footprint` alone.
  void add_footprint_row(const Truncation &t, std::size_t footprint, double angle, double factor,
                         std::vector<double> &row);

  /// MacNeal's residual flexibility of the model's basis on its interface
  /// grid (reduction::ResidualFlexibility): unit forces of the first
  /// `components` traction components (1: pressure only; 3: all) on each cell
  /// of the grid's first column, and a unit ball at its angle with each of
  /// the raceway operator's `footprints` (`ring` its raceway; none: no
  /// ball), each solved by the full FE (`solver`, sampled by `map`) and by the
  /// whole model; R is the difference. The body is a free ring on its outer
  /// surface (`solver` and the reduced solves with inertia relief, the
  /// pressure pushing inward) or a housing held at its outside on its bore
  /// (`housing_bore`: plain static solves, the pressure pushing outward).
  /// Collective.
  reduction::ResidualFlexibility residual_flexibility(fem::ShiftedStaticSolver &solver,
                                                      const fem::SurfaceGridMap &map, const Truncation &whole,
                                                      const fem::CylinderGrid &grid, const fem::RingGeometry &ring,
                                                      const std::vector<reduction::BallFootprint> &footprints,
                                                      int components, bool housing_bore = false);
  /// The residual flexibility (residual_flexibility()) applied to tractions
  /// on the grid and to ball loads (the ring's; none without its ball table):
  /// the outward u_r per cell [m]. Taken circulant in θ, the body being
  /// axisymmetric; the mesh's divisions need not be the grid's columns, and
  /// that difference is the approximation's error: a load on column i0 acts
  /// as the first column's, shifted by i0, and a ball between columns as the
  /// table interpolated. Components without a table are left out. `compare`'s
  /// check of what the co-simulation adds: reduced + R against the full FE.
  std::vector<double> residual_u_r(const reduction::ResidualFlexibility &residual,
                                   const std::vector<double> &footprint_loads, const fem::CylinderGrid &grid,
                                   const fem::GridTractions &tractions, const std::vector<double> &ball_angles,
                                   const std::vector<double> &ball_loads);

  /// The whole model on a Winkler layer (stiffness k_n, interference
  /// `fit`, the outward u_r rows of its interface operator) with its
  /// residual flexibility in series (coupling::LocalCompliance) under the
  /// generalised load g of balls at `ball_angles` with `ball_loads`, whose
  /// residual u_r under the layer adds to the penetration: what the
  /// co-simulation's interface solves, statically. Newton on q with the
  /// pressure's sensitivity; stops when the force balance is within 1e-6 of
  /// the load (the pressure solve's own stop is 1e-7 of the penetration).
  struct ResidualWinklerSolution
  {
    std::vector<double> pressure; ///< [cell] [Pa]
    int                 iterations = 0;
    double              seconds    = 0.0;
    double              peak() const;
    double              contact_fraction() const;
  };
  ResidualWinklerSolution winkler_with_residual(const Truncation &whole, const reduction::ResidualFlexibility &residual,
                                                const fem::CylinderGrid &grid, double normal_stiffness, double fit,
                                                const std::vector<double> &ball_angles,
                                                const std::vector<double> &ball_loads);
} // namespace fretsim::models
