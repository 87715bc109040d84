#include <fretsim/contact/surface_grid.h>

#include <cmath>
#include <stdexcept>

namespace fretsim::contact
{
  SurfaceGrid SurfaceGrid::centred(int nx, int ny, double half_width_x, double half_width_y)
  {
    if (nx <= 0 || ny <= 0)
      throw std::invalid_argument("SurfaceGrid::centred: the number of cells must be positive");
    if (!(half_width_x > 0.0) || !(half_width_y > 0.0) || !std::isfinite(half_width_x) ||
        !std::isfinite(half_width_y))
      throw std::invalid_argument("SurfaceGrid::centred: the half widths must be positive and finite");

    SurfaceGrid grid;
    grid.nx    = nx;
    grid.ny    = ny;
    grid.hx    = 2.0 * half_width_x / nx;
    grid.hy    = 2.0 * half_width_y / ny;
    grid.x_min = -half_width_x;
    grid.y_min = -half_width_y;
    return grid;
  }

  double integrate(const SurfaceGrid &grid, const Field &field)
  {
    if (field.size() != grid.size())
      throw std::invalid_argument("integrate: field size does not match the grid");
    double sum = 0.0;
    for (const double value : field)
      sum += value;
    return sum * grid.cell_area();
  }
} // namespace fretsim::contact
