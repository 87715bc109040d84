#pragma once
// Transfer between a contact surface grid and the FE model (docs/theory.md §3/§4):
// the contact module's cell-centred grid laid on a cylindrical FE surface
// (ring outer surface, housing bore), unrolled as x = arc length R·θ (θ from
// the x axis towards y) and y = z.
//
//   interpolate():  u_grid = H u            (consistent: displacements at the
//                                            cell centres)
//   nodal forces:   f = Hᵀ (A t)            (conservative: the same operator
//                                            transposed, A the cell area)
// so that the work of the grid tractions on the grid displacements equals the
// work of the nodal forces on the FE displacements, and f carries the grid's
// total force exactly (the shape functions sum to one). The grid tractions are
// cell-wise constant but sampled at cell centres: the operator is exact for
// what the contact module produces only in the limit of grid cells smaller
// than FE faces, which is how the contact grid is sized anyway.
#include <fretsim/fem/elastic_model.h>

#include <memory>
#include <cmath>
#include <vector>

namespace fretsim::fem
{
  /// A cell-centred nx × ny grid on the cylinder r = radius; same layout as
  /// contact::SurfaceGrid: value(i, j) = field[j * nx + i], x fastest.
  struct CylinderGrid
  {
    double radius = 0.0; ///< [m]
    int    nx = 0, ny = 0;
    double hx = 0.0, hy = 0.0;       ///< cell sizes: arc length, axial [m]
    double x_min = 0.0, y_min = 0.0; ///< lower-left corner: arc length from θ = 0, z [m]

    /// nx × ny cells over the whole circumference of a cylinder of `radius`
    /// and axial `width` centred on z = 0, the first column from θ = 0.
    static CylinderGrid around(double radius, double width, int nx, int ny)
    {
      return {radius, nx, ny, 2.0 * M_PI * radius / nx, width / ny, 0.0, -0.5 * width};
    }

    std::size_t size() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
    double      cell_area() const { return hx * hy; }
    double      x(int i) const { return x_min + (i + 0.5) * hx; }
    double      y(int j) const { return y_min + (j + 0.5) * hy; }
  };

  /// Per grid cell [Pa]: pressure pushing into the body, shear along +x
  /// (circumferential, +θ) and along +y (axial, +z).
  struct GridTractions
  {
    std::vector<double> pressure, shear_x, shear_y;
  };

  /// Per grid cell [m], cylindrical components at the cell centre.
  struct GridDisplacements
  {
    std::vector<double> u_r, u_theta, u_z;
  };

  class SurfaceGridMap
  {
  public:
    /// Locates every grid cell centre on `surface` (a cylinder about z of the
    /// grid's radius). Throws std::invalid_argument if a centre is not on the
    /// model's mesh. Collective.
    SurfaceGridMap(const ElasticModel &model, BoundaryId surface, const CylinderGrid &grid);
    ~SurfaceGridMap();
    SurfaceGridMap(SurfaceGridMap &&) noexcept;
    SurfaceGridMap &operator=(SurfaceGridMap &&) noexcept;

    const CylinderGrid &grid() const;

    /// u_grid = H u, the same on every rank. Collective.
    GridDisplacements interpolate(const DisplacementField &u) const;

    /// Σ over cells of A t as a Cartesian force [N].
    Vector3 total_force(const GridTractions &t) const;
    /// Σ over DoFs of f = Hᵀ (A t) per Cartesian component [N], before any
    /// support drops a part: equal to total_force() (conservation). Collective.
    Vector3 nodal_force_sum(const GridTractions &t) const;

    struct Impl;
    const Impl &impl() const { return *pimpl; }

  private:
    std::unique_ptr<Impl> pimpl;
  };
} // namespace fretsim::fem
