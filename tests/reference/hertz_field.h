#pragma once
// The circular Hertz pressure p0 sqrt(1 - r^2/a^2) sampled at a grid's cell
// centres (docs/references.md §1.1), for tests that need a load on a grid.
#include <fretsim/contact/surface_grid.h>

#include <algorithm>
#include <cmath>

namespace fretsim::reference
{
  inline contact::Field hertz_pressure_field(const contact::SurfaceGrid &g, double a, double p0)
  {
    contact::Field p = g.zeros();
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i)
        p[g.index(i, j)] = p0 * std::sqrt(std::max(0.0, 1.0 - (g.x(i) * g.x(i) + g.y(j) * g.y(j)) / (a * a)));
    return p;
  }
} // namespace fretsim::reference
