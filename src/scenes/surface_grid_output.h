#pragma once
// The results file's /grid of a scene whose fields live on a contact grid.
#include <fretsim/output/results_file.h>

#include <fretsim/contact/surface_grid.h>

#include <vector>

namespace fretsim::scenes
{
  /// /grid/x, /grid/y: the grid's cell centres; /grid/z: the depth layers [m].
  inline void write_surface_grid(output::ResultsFile &results, const contact::SurfaceGrid &grid,
                                 const std::vector<double> &depths)
  {
    std::vector<double> x(grid.nx), y(grid.ny);
    for (int i = 0; i < grid.nx; ++i)
      x[i] = grid.x(i);
    for (int j = 0; j < grid.ny; ++j)
      y[j] = grid.y(j);
    results.write_grid(x, y, depths);
  }
} // namespace fretsim::scenes
