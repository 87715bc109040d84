#pragma once
// The full FE of an axisymmetric body condensed onto its contact grid: the
// displacement of every grid cell, and the stress below every cell centre on
// given depth layers, per unit force on one cell (and, for a ring, per unit
// ball on the raceway). Static condensation is exact for a linear body, so a
// contact problem solved with these tables is the full FE's contact problem
// on that grid (docs/fe_reference.md).
//
// A body of revolution meshed with N cells around, the grid with nx columns:
// the response to a load on column i is the response to the same load on
// column i mod P shifted by the difference, P = nx / gcd(nx, N) the columns
// after which the mesh repeats on the grid. So P × 3 × ny unit loads (and P
// balls) give every cell's influence. A cell's load is spread evenly over
// s × s points of the cell and its displacement is the mean over the same
// points (consistent, so the tables are symmetric, and finite as the mesh is
// refined below the cell size, which a point force's would not be).
#include <fretsim/fem/elastic_model.h>
#include <fretsim/fem/surface_grid_map.h>

#include <algorithm>
#include <array>
#include <functional>
#include <memory>
#include <vector>

namespace fretsim::models
{
  struct InterfaceInfluence
  {
    fem::CylinderGrid   grid;
    int                 period = 1;  ///< P: columns after which the mesh repeats
    std::vector<double> depths;      ///< stress layers below the surface [m]; empty: no stress table
    /// [phase][component k][row jj][cell][3]: (u_r outward, u_θ, u_z) per N of
    /// force component k on cell (phase, jj): k = 0 the pressure's (pushing
    /// into the body), 1 along +θ, 2 along +z [m/N].
    std::vector<double> displacement;
    /// [phase][k][jj][layer][cell][6] stress per N in the contact frame of the
    /// body: xx circumferential, yy axial, zz radial (depth into the body),
    /// yz, xz, xy; tension positive [Pa/N].
    std::vector<double> stress;
    /// A unit ball at the angle of column `phase`'s centre, per footprint:
    /// [footprint][phase][cell][3] and [footprint][phase][layer][cell][6];
    /// empty for a body without a raceway.
    std::vector<double> ball_displacement, ball_stress;
    /// The ball loads whose Hertz ellipses the footprints are [N]; empty:
    /// one fixed footprint (reduction::RacewayOperators).
    std::vector<double> ball_footprint_loads;
    std::size_t         ball_footprints() const { return std::max<std::size_t>(1, ball_footprint_loads.size()); }
    unsigned long       dofs   = 0;
    unsigned int        solves = 0;
    double              seconds = 0.0;

    std::size_t cells() const { return grid.size(); }
    std::size_t layers() const { return depths.size(); }
    /// Index of (u component c) at `cell` per unit force k on (phase, jj).
    std::size_t displacement_index(int phase, int k, int jj, std::size_t cell, int c) const
    {
      return (((static_cast<std::size_t>(phase) * 3 + k) * grid.ny + jj) * cells() + cell) * 3 + c;
    }
    std::size_t stress_index(int phase, int k, int jj, std::size_t layer, std::size_t cell, int c) const
    {
      return ((((static_cast<std::size_t>(phase) * 3 + k) * grid.ny + jj) * layers() + layer) * cells() + cell) * 6 +
             c;
    }
  };

  /// The stresses below every cell centre of a grid on given depth layers
  /// ([layer][cell][6] in the tables' contact frame), as the tables take
  /// them: on a point that falls on an element face, the mean of the faces'
  /// sides. Collective.
  class InterfaceStressSampler
  {
  public:
    /// `ring`: depth into a ring from its outer surface; else outward from a bore.
    InterfaceStressSampler(const fem::ElasticModel &model, const fem::CylinderGrid &grid,
                           const std::vector<double> &depths, bool ring);
    ~InterfaceStressSampler();
    std::vector<double> evaluate(const fem::DisplacementField &u) const;

  private:
    static constexpr std::size_t samples_per_point = 8;
    struct Impl;
    std::unique_ptr<Impl> impl;
  };

  /// How a body is held for its tables.
  enum class InfluenceSupport
  {
    free_ring,   ///< a free ring on its outer surface: inertia relief (the loads' resultant balanced by rigid-body
                 ///< inertia; the tables are the deformation, without rigid motion)
    housing_bore ///< a housing held at its outside, on its bore
  };

  struct InfluenceRequest
  {
    InfluenceSupport    support = InfluenceSupport::free_ring;
    unsigned int        circumferential_cells = 0; ///< of the mesh, for P
    std::vector<double> depths;                    ///< stress layers [m]; empty: no stresses
    int                 points_per_side = 3;       ///< s
    /// Balls of unit force at an angle on the ring's raceway, one per
    /// footprint (the tables' order); empty: no ball table.
    std::function<std::vector<fem::RacewayBallLoad>(double angle)> balls;
    std::vector<double> ball_footprint_loads; ///< InterfaceInfluence's
  };

  /// The tables of `model` (its boundary ring_outer or housing_bore carries
  /// the grid). Collective; the same tables on every rank. Throws
  /// std::invalid_argument if a grid point is off the mesh.
  InterfaceInfluence interface_influence(fem::ElasticModel &model, const fem::CylinderGrid &grid,
                                         const InfluenceRequest &request);

  /// The stress Voigt order of the tables from a cylindrical one (rr, θθ, zz,
  /// θz, rz, rθ) on a ring's outer surface, depth pointing inward.
  std::array<double, 6> contact_frame_stress(const double *cylindrical);
} // namespace fretsim::models
