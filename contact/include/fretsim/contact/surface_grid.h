#pragma once
#include <cstddef>
#include <vector>

namespace fretsim::contact
{
  /// A surface field on a SurfaceGrid: one value per cell, row-major with x
  /// fastest, i.e. value(i, j) = field[j * nx + i], matching [ny][nx] in HDF5.
  using Field = std::vector<double>;

  /// Uniform rectangular grid of nx × ny cells; values live at cell centres and
  /// loads are piecewise constant over a cell (docs/theory.md §2.1). Lengths in m.
  struct SurfaceGrid
  {
    int    nx = 0;
    int    ny = 0;
    double hx = 0.0; ///< cell size in x [m]
    double hy = 0.0; ///< cell size in y [m]
    double x_min = 0.0; ///< left edge of the grid [m]
    double y_min = 0.0; ///< lower edge of the grid [m]

    /// A grid of nx × ny cells covering [-half_width_x, half_width_x] ×
    /// [-half_width_y, half_width_y].
    static SurfaceGrid centred(int nx, int ny, double half_width_x, double half_width_y);

    std::size_t size() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
    double      cell_area() const { return hx * hy; }
    double      x(int i) const { return x_min + (i + 0.5) * hx; }
    double      y(int j) const { return y_min + (j + 0.5) * hy; }
    std::size_t index(int i, int j) const { return static_cast<std::size_t>(j) * nx + i; }
    Field       zeros() const { return Field(size(), 0.0); }
  };

  /// Sum over cells of value × cell area (a force, when the field is a traction).
  double integrate(const SurfaceGrid &grid, const Field &field);
} // namespace fretsim::contact
