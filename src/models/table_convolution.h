#pragma once
// Convolutions with influence tables of a mesh that repeats every P grid
// columns, shared by the full-FE reference and the ring's stress tables.
// Internal to the models library.
#include <fretsim/contact/convolution.h>
#include <fretsim/coupling/bearing.h>
#include <fretsim/fem/surface_grid_map.h>

#include <cmath>
#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

namespace fretsim::models::detail
{
  using Vector = std::vector<double>;

  /// A convolution along the closed circumference between fields of `rows`
  /// rows per column whose kernel repeats every P columns: P columns are
  /// stacked into one, so that the kernel is translation invariant and
  /// contact::SurfaceConvolution's row-pair form applies.
  class StackedConvolution
  {
  public:
    /// kernel(ph, b, i, a): response in row a of column i to a unit load in
    /// row b of column ph < P.
    using Kernel = std::function<double(int ph, int b, int i, int a)>;

    StackedConvolution(int nx, int rows, int period, const Kernel &kernel, const Vector &diagonal = {})
      : nx(nx)
      , rows(rows)
      , period(period)
      , stacked{nx / period, rows * period, 1.0, 1.0, 0.0, 0.0}
      , convolution(stacked, row_pair(kernel, diagonal))
    {}

    /// y = K x, fields [rows][nx].
    void apply(const Vector &x, Vector &y) const { apply_with(convolution, x, y); }
    /// The inverse of K on the whole closed grid.
    contact::SurfaceConvolution inverse() const { return convolution.inverse(0.0); }
    void apply_with(const contact::SurfaceConvolution &c, const Vector &x, Vector &y) const
    {
      pack(x, packed_in);
      c.apply(packed_in, packed_out);
      unpack(packed_out, y);
    }

  private:
    contact::RowPairInfluenceFunction row_pair(const Kernel &kernel, const Vector &diagonal) const
    {
      const int NX = nx / period, n = nx, p = period, r = rows;
      return [=](int dI, int field_row, int load_row) {
        const int d      = ((dI % NX) + NX) % NX;
        const int sub_t  = field_row / r, a = field_row % r, sub_s = load_row / r, b = load_row % r;
        const int column = ((d * p + sub_t - sub_s) % n + n) % n; // relative to the load's column
        double    value  = kernel(sub_s, b, (column + sub_s) % n, a);
        if (!diagonal.empty() && d == 0 && field_row == load_row)
          value += diagonal[static_cast<std::size_t>(a)];
        return value;
      };
    }
    void pack(const Vector &x, Vector &out) const
    {
      out.resize(x.size());
      for (int a = 0; a < rows; ++a)
        for (int i = 0; i < nx; ++i)
          out[static_cast<std::size_t>(((i % period) * rows + a) * (nx / period) + i / period)] =
            x[static_cast<std::size_t>(a * nx + i)];
    }
    void unpack(const Vector &in, Vector &y) const
    {
      y.resize(in.size());
      for (int a = 0; a < rows; ++a)
        for (int i = 0; i < nx; ++i)
          y[static_cast<std::size_t>(a * nx + i)] =
            in[static_cast<std::size_t>(((i % period) * rows + a) * (nx / period) + i / period)];
    }

    int                         nx, rows, period;
    contact::SurfaceGrid        stacked;
    contact::SurfaceConvolution convolution;
    mutable Vector              packed_in, packed_out;
  };

  /// Where a ball at angle ψ sits between two column centres: the lower
  /// column and the upper one's weight.
  inline std::pair<int, double> ball_columns(const fem::CylinderGrid &grid, double angle)
  {
    const double u  = (angle * grid.radius - grid.x_min) / grid.hx - 0.5;
    const double i0 = std::floor(u);
    return {static_cast<int>(((static_cast<long>(i0) % grid.nx) + grid.nx) % grid.nx), u - i0};
  }

  /// Adds Σ over the two columns around ψ of weight × q × a ball table
  /// ([phase][layer][cell][components], shifted to the ball's column) through
  /// add(layer × cells + cell, component, value).
  template <typename Add>
  void add_ball_table(const fem::CylinderGrid &grid, int period, double psi, double q, const double *table,
                      int components, std::size_t layers, Add add)
  {
    const int         nx = grid.nx, ny = grid.ny;
    const std::size_t cells = grid.size();
    const auto [i0, w]      = ball_columns(grid, psi);
    for (int s = 0; s < 2; ++s)
      {
        const int    column = (i0 + s) % nx, ph = column % period, shift = column - ph;
        const double weight = q * (s == 0 ? 1.0 - w : w);
        if (weight == 0.0)
          continue;
        const std::size_t per_phase = layers * cells * components;
        for (std::size_t layer = 0; layer < layers; ++layer)
          for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i)
              {
                const std::size_t target = static_cast<std::size_t>(j) * nx + i;
                const std::size_t source = static_cast<std::size_t>(j) * nx + ((i - shift) % nx + nx) % nx;
                const double     *row    = table + ph * per_phase + (layer * cells + source) * components;
                for (int comp = 0; comp < components; ++comp)
                  add(layer * cells + target, comp, weight * row[comp]);
              }
      }
  }

  /// The same for a ball of load q whose tables are one per footprint
  /// ([footprint][phase][layer][cell][components]), tabulated at the ball
  /// loads `footprint_loads` (empty: one table): the footprints' tables
  /// around q, weighted as the co-simulation weighs the raceway rows
  /// (coupling::footprint_blend).
  template <typename Add>
  void add_ball_tables(const fem::CylinderGrid &grid, int period, const Vector &footprint_loads, double psi, double q,
                       const Vector &tables, int components, std::size_t layers, Add add)
  {
    const std::size_t per_footprint = static_cast<std::size_t>(period) * layers * grid.size() * components;
    const coupling::FootprintBlend blend = coupling::footprint_blend(footprint_loads, q);
    for (std::size_t m = 0; m < blend.count; ++m)
      add_ball_table(grid, period, psi, blend.weights[m] * q, tables.data() + (blend.first + m) * per_footprint,
                     components, layers, add);
  }
} // namespace fretsim::models::detail
