#pragma once
// Stress recovery at given points (docs/theory.md §3: "full FE stress snapshots"):
// surface sample points or the cell centres of a contact surface grid.
//
// How: each point is located once in the cell that holds it (through the
// model's mapping, so on the curved geometry); the stress there is the FE
// field's own gradient at that point, σ = C : (ε(u_h) - ε*), with no
// smoothing or projection. Gradients are one order less accurate than the
// displacements (O(h^p)) and jump across cell faces: a point on a face
// between cells takes the cell the search finds first, the same one every
// time. The operator ∇φ_i at each point is stored, so evaluating a snapshot
// is a gather of the cell's DoF values (cheap enough for every time step of
// a transient run).
#include <fretsim/fem/elastic_model.h>
#include <fretsim/fem/surface_grid_map.h>

#include <memory>
#include <vector>

namespace fretsim::fem
{
  /// Frame of the stress components.
  enum class StressFrame
  {
    cartesian,   ///< (x, y, z): Voigt xx, yy, zz, yz, xz, xy
    cylindrical, ///< (r, θ, z) about the z axis at each point: Voigt rr, θθ, zz, θz, rz, rθ
  };

  class StressSampler
  {
  public:
    /// Locates every point (on or inside the mesh; points up to a tenth of a
    /// cell outside a curved face, as the mapped surface's chords leave them,
    /// are moved onto the cell). Throws std::invalid_argument if a point is
    /// off the mesh. Collective.
    StressSampler(const ElasticModel &model, const std::vector<Point3> &points,
                  StressFrame frame = StressFrame::cartesian);
    /// The cell centres of a contact surface grid, in the grid's order
    /// (value(i, j) at j * nx + i).
    static StressSampler on_grid(const ElasticModel &model, const CylinderGrid &grid,
                                 StressFrame frame = StressFrame::cylindrical);

    ~StressSampler();
    StressSampler(StressSampler &&) noexcept;
    StressSampler &operator=(StressSampler &&) noexcept;

    std::size_t                n_points() const;
    const std::vector<Point3> &points() const;
    StressFrame                frame() const;

    /// Stresses [Pa], row-major [n_points, 6] in the Voigt order of the frame,
    /// tension positive; the same on every rank. Collective.
    std::vector<double> evaluate(const DisplacementField &u) const;

    struct Impl;

  private:
    explicit StressSampler(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> pimpl;
  };
} // namespace fretsim::fem
