// MultiLevel Multi-Integration: see multilevel_summation.h and
// docs/references.md §6.1.
//
// Notation. Every level l has its own integer lattice: lattice point i of
// level l+1 sits on lattice point 2i of level l in a coarsened direction (and
// on i in a direction that is not coarsened). A level's grid is the box of
// lattice points [lo, lo + n - 1] in each direction; level 0 is the surface
// grid with lo = 0. The level-l kernel is kappa_l(d) = (area ratio) * K(s d)
// with s the number of surface cells per lattice step, so that coarse loads
// are densities (anterpolation weights sum to one).
//
// Two-grid step. With I the order-p interpolation from level l+1 to level l,
// the approximation is w ~ I K_{l+1} I^T u / r, whose kernel is
// Ktilde(i, j) = sum_{I,J} I_{iI} I_{jJ} kappa_l(2I - 2J). It depends only on
// the parity of i and on d = i - j, so the correction
// C(parity, d) = kappa_l(d) - Ktilde(parity, d), applied for |d| <= m, makes
// the two-grid result exact inside the window. Recursing on K_{l+1} I^T u
// gives the multilevel scheme.
#include <fretsim/contact/multilevel_summation.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace fretsim::contact
{
  namespace
  {
    int parity(int i) { return i & 1; } // two's complement: also right for i < 0

    /// Weights c_k, k = -p/2+1 .. p/2, interpolating the midpoint between
    /// coarse points 0 and 1 from coarse points k (Lagrange, nodes at k - 1/2
    /// relative to the midpoint). p = 6 gives (3, -25, 150, 150, -25, 3)/256.
    std::vector<double> midpoint_weights(int order)
    {
      const int           half = order / 2;
      std::vector<double> weights(order);
      for (int k = -half + 1; k <= half; ++k)
        {
          double w = 1.0;
          for (int n = -half + 1; n <= half; ++n)
            if (n != k)
              w *= (0.0 - (n - 0.5)) / ((k - 0.5) - (n - 0.5));
          weights[k + half - 1] = w;
        }
      return weights;
    }

    /// One direction of one level.
    struct Axis
    {
      int  lo = 0;          ///< lattice coordinate of array index 0
      int  n = 0;           ///< number of points
      int  scale = 1;       ///< surface cells per lattice step
      bool coarsened = false; ///< whether the next level is coarser in this direction
      int  hi() const { return lo + n - 1; }
    };

    /// Coarse range needed to interpolate every fine point of [lo, hi]:
    /// even fine points are injected from coarse i/2, odd ones use coarse
    /// (i-1)/2 + k, k = -p/2+1 .. p/2 (the ghost points).
    Axis coarsen_axis(const Axis &fine, int order)
    {
      const int half = order / 2;
      int       lo = std::numeric_limits<int>::max(), hi = std::numeric_limits<int>::min();
      for (int i = fine.lo; i <= fine.hi(); ++i)
        {
          if (i > fine.lo + 1 && i < fine.hi() - 1)
            continue; // interior points need nothing beyond the ends
          if (parity(i) == 0)
            {
              lo = std::min(lo, i / 2);
              hi = std::max(hi, i / 2);
            }
          else
            {
              const int base = (i - 1) / 2; // i odd: exact for either sign
              lo             = std::min(lo, base - half + 1);
              hi             = std::max(hi, base + half);
            }
        }
      Axis coarse;
      coarse.lo    = lo;
      coarse.n     = hi - lo + 1;
      coarse.scale = fine.scale * 2;
      return coarse;
    }

    /// (i - parity(i)) / 2 for any sign of i.
    int half_floor(int i) { return (i - parity(i)) / 2; }

    /// For a coarsened direction: the 1-D factor of Ktilde for output parity P
    /// and offset d, as a map fine offset (= 2D) -> weight.
    std::vector<std::pair<int, double>> interpolated_offsets(int P, int d, const std::vector<double> &c)
    {
      const int half = static_cast<int>(c.size()) / 2;
      auto stencil = [&](int parity_value) {
        std::vector<std::pair<int, double>> s; // (coarse offset from base, weight)
        if (parity_value == 0)
          s.emplace_back(0, 1.0);
        else
          for (int k = -half + 1; k <= half; ++k)
            s.emplace_back(k, c[k + half - 1]);
        return s;
      };
      const int q = parity(P - d);
      // base_i - base_j with base = (x - parity)/2 and i - j = d.
      const int          base_difference = (d - P + q) / 2;
      std::map<int, double> sum;
      for (const auto &[a, wa] : stencil(P))
        for (const auto &[b, wb] : stencil(q))
          sum[2 * (base_difference + a - b)] += wa * wb;
      return {sum.begin(), sum.end()};
    }

    /// target[a] += sum_t coefficients[t] * base[sources[t] + a], a < n: the
    /// local correction of one output row, the hot loop. Kept apart so the
    /// compiler vectorises it; an AVX2+FMA clone (x86-64-v3) is chosen at load
    /// time where the CPU has it, as the build itself targets generic x86-64.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
    __attribute__((target_clones("arch=x86-64-v3", "default")))
#endif
    void
    accumulate_row(int n, int terms, const double *coefficients, const int *sources, const double *base,
                   double *target)
    {
      // Eight, then four terms per sweep: target is read and written once per
      // sweep instead of once per term.
      int t = 0;
      for (; t + 8 <= terms; t += 8)
        {
          const double *c = coefficients + t;
          const double *s0 = base + sources[t], *s1 = base + sources[t + 1], *s2 = base + sources[t + 2],
                       *s3 = base + sources[t + 3], *s4 = base + sources[t + 4], *s5 = base + sources[t + 5],
                       *s6 = base + sources[t + 6], *s7 = base + sources[t + 7];
          const double c0 = c[0], c1 = c[1], c2 = c[2], c3 = c[3], c4 = c[4], c5 = c[5], c6 = c[6], c7 = c[7];
          for (int a = 0; a < n; ++a)
            target[a] += ((c0 * s0[a] + c1 * s1[a]) + (c2 * s2[a] + c3 * s3[a])) +
                         ((c4 * s4[a] + c5 * s5[a]) + (c6 * s6[a] + c7 * s7[a]));
        }
      for (; t + 4 <= terms; t += 4)
        {
          const double  c0 = coefficients[t], c1 = coefficients[t + 1], c2 = coefficients[t + 2],
                       c3 = coefficients[t + 3];
          const double *s0 = base + sources[t], *s1 = base + sources[t + 1], *s2 = base + sources[t + 2],
                       *s3 = base + sources[t + 3];
          for (int a = 0; a < n; ++a)
            target[a] += (c0 * s0[a] + c1 * s1[a]) + (c2 * s2[a] + c3 * s3[a]);
        }
      for (; t < terms; ++t)
        {
          const double  c0 = coefficients[t];
          const double *s0 = base + sources[t];
          for (int a = 0; a < n; ++a)
            target[a] += c0 * s0[a];
        }
    }
  } // namespace

  struct MultilevelSummation::Impl
  {
    SurfaceGrid grid;
    int         n_outputs = 0, n_loads = 0;
    int         order = 6;
    int         threads = 1; ///< OpenMP team size
    std::vector<double> weights; ///< midpoint interpolation weights c_k
    std::vector<int>    widths;  ///< correction half-width per output
    int                 max_width = 0;

    struct Level
    {
      Axis x, y;
      std::size_t size() const { return static_cast<std::size_t>(x.n) * y.n; }

      // Layout of the correction step (levels above the coarsest): loads are
      // copied zero-padded and split by x parity, so that row r, parity q,
      // entry B holds lattice point (x_start + 2B + q, y.lo + r - pad_y); the
      // results are built the same way from out_start. Every (output parity,
      // dx) term is then one contiguous row operation.
      int out_start = 0; ///< even lattice x of output entry 0
      int out_half  = 0; ///< output entries per parity
      int shift     = 0; ///< (out_start - x_start) / 2
      int x_start   = 0; ///< even lattice x of input entry 0
      int in_half   = 0; ///< input entries per parity
      int pad_y     = 0; ///< zero rows above and below
    };
    std::vector<Level> levels; ///< levels[0] = surface grid; levels.back() = coarsest

    /// active[o * n_loads + l]: the kernel pair is not identically zero.
    std::vector<char> active;

    /// Local correction of one kernel pair on one level, stored sparsely:
    /// for parity class k = Px + 2 Py and row dy in [-m, m], the terms
    /// begin[k (2m+1) + dy + m] .. begin[... + 1] of (dx, coefficient).
    struct Correction
    {
      std::vector<int>    begin;
      std::vector<int>    source;      ///< offset of the term's input in a padded load row
      std::vector<double> coefficient;
    };
    /// correction[l][o * n_loads + load], window half-width m = widths[o].
    std::vector<std::vector<Correction>> correction;
    double tolerance = 0.0; ///< relative size of the dropped correction terms
    std::size_t kept_terms = 0, total_terms = 0;
    /// coarsest[o * n_loads + load]: kernel on the coarsest grid,
    /// (2 ny - 1) rows × (2 nx - 1), indexed [dy + ny - 1][dx + nx - 1].
    std::vector<std::vector<double>> coarsest;

    void build_levels(const MultilevelSettings &settings);
    void build_kernels(const InfluenceBlock &kernels);

    /// Kernel block table of level l over the box |dx| <= rx, |dy| <= ry.
    std::vector<double> kernel_table(const InfluenceBlock &kernels, std::size_t level, int rx, int ry) const;

    void anterpolate(const Level &fine, const Level &coarse, const double *u, double *U) const;
    /// Row b of the order-p interpolation of the coarse-level sums W.
    void interpolate_row(const Level &coarse, const Level &fine, const double *W, int b, double *w,
                         std::vector<double> &column_mix) const;
  };

  int MultilevelSummation::default_correction_width(int interpolation_order)
  {
    return std::max(2 * interpolation_order - 2, 4);
  }

  void MultilevelSummation::Impl::build_levels(const MultilevelSettings &settings)
  {
    Level surface;
    surface.x.n = grid.nx;
    surface.y.n = grid.ny;
    levels.assign(1, surface);

    // A direction is coarsened while that makes it strictly smaller.
    auto next_level = [&](const Level &fine, Level &coarse) {
      coarse       = fine;
      Axis cx      = coarsen_axis(fine.x, order), cy = coarsen_axis(fine.y, order);
      bool shrinks = false;
      if (cx.n < fine.x.n)
        {
          coarse.x = cx;
          shrinks  = true;
        }
      if (cy.n < fine.y.n)
        {
          coarse.y = cy;
          shrinks  = true;
        }
      return shrinks;
    };

    // All possible levels, then keep the requested or the cheapest count.
    std::vector<Level> all = levels;
    for (;;)
      {
        Level coarse;
        if (!next_level(all.back(), coarse))
          break;
        all.push_back(coarse);
      }
    const int max_levels = static_cast<int>(all.size()) - 1;

    int count = settings.levels;
    if (count < 0)
      throw std::invalid_argument("MLMI: the number of levels must be >= 0 (0 = automatic), got " +
                                  std::to_string(count));
    if (count > max_levels)
      throw std::invalid_argument("MLMI: " + std::to_string(count) + " coarse levels requested but a " +
                                  std::to_string(grid.nx) + " x " + std::to_string(grid.ny) +
                                  " grid with interpolation order " + std::to_string(order) +
                                  " allows at most " + std::to_string(max_levels) +
                                  " (coarse grids stop shrinking once their p/2 ghost points dominate)");
    if (count == 0)
      {
        // Work per kernel: (2m+1)^2 per point of every corrected level, plus
        // N^2 for the direct sum on the coarsest level.
        const double stencil = std::pow(2.0 * max_width + 1.0, 2);
        double       best    = std::numeric_limits<double>::max();
        double       corrected = 0.0;
        for (int L = 0; L <= max_levels; ++L)
          {
            const double n    = static_cast<double>(all[L].size());
            const double cost = corrected + n * n;
            if (cost < best)
              {
                best  = cost;
                count = L;
              }
            corrected += n * stencil;
          }
      }
    levels.assign(all.begin(), all.begin() + count + 1);
    for (int l = 0; l < count; ++l)
      {
        Level &L     = levels[l];
        L.x.coarsened = levels[l + 1].x.scale > L.x.scale;
        L.y.coarsened = levels[l + 1].y.scale > L.y.scale;
        L.out_start   = L.x.lo - parity(L.x.lo);
        L.out_half    = (L.x.hi() - L.out_start) / 2 + 1;
        L.shift       = (max_width + 2) / 2; // 2 shift >= m + 1: inputs never run off the padding
        L.x_start     = L.out_start - 2 * L.shift;
        L.in_half     = L.out_half + 2 * L.shift;
        L.pad_y       = max_width;
      }
  }

  std::vector<double> MultilevelSummation::Impl::kernel_table(const InfluenceBlock &kernels, std::size_t level,
                                                               int rx, int ry) const
  {
    const Level       &L     = levels[level];
    const int          block = n_outputs * n_loads;
    const double       area  = static_cast<double>(L.x.scale) * L.y.scale;
    const int          wx = 2 * rx + 1, wy = 2 * ry + 1;
    std::vector<double> table(static_cast<std::size_t>(wx) * wy * block);
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads)
    for (int row = 0; row < wy; ++row)
      for (int col = 0; col < wx; ++col)
        {
          double *values = &table[(static_cast<std::size_t>(row) * wx + col) * block];
          kernels((col - rx) * L.x.scale, (row - ry) * L.y.scale, values);
          for (int k = 0; k < block; ++k)
            values[k] *= area;
        }
    return table;
  }

  void MultilevelSummation::Impl::build_kernels(const InfluenceBlock &kernels)
  {
    const int         block    = n_outputs * n_loads;
    const std::size_t n_levels = levels.size();
    active.assign(block, 0);
    correction.assign(n_levels - 1, std::vector<Correction>(block));

    // Kernel over the whole coarsest grid, for its direct sum.
    const Level              &top         = levels.back();
    const std::vector<double> top_table   = kernel_table(kernels, n_levels - 1, top.x.n - 1, top.y.n - 1);
    const std::size_t         cells       = static_cast<std::size_t>(2 * top.x.n - 1) * (2 * top.y.n - 1);
    coarsest.assign(block, {});
    for (int pair = 0; pair < block; ++pair)
      {
        std::vector<double> &K = coarsest[pair];
        K.resize(cells);
        for (std::size_t c = 0; c < cells; ++c)
          {
            K[c] = top_table[c * block + pair];
            if (K[c] != 0.0)
              active[pair] = 1;
          }
      }
    if (n_levels == 1)
      return;

    // Scale of the correction tolerance: the kernel's magnitude summed over
    // every offset the grid can see, sum_d |K(d)| = the largest |w| a unit
    // load can produce. The surface-grid window |d| <= m is summed exactly;
    // the rest comes from the coarsest table (a Riemann sum of the smooth far
    // field; its central spike 4^L K(0) lies inside the window and is left out).
    std::vector<double> magnitude(block, 0.0);
    for (int pair = 0; pair < block; ++pair)
      {
        const int m = widths[pair / n_loads];
        for (int dy = -(top.y.n - 1); dy < top.y.n; ++dy)
          for (int dx = -(top.x.n - 1); dx < top.x.n; ++dx)
            if (std::abs(dx * top.x.scale) > m || std::abs(dy * top.y.scale) > m)
              magnitude[pair] += std::fabs(
                coarsest[pair][static_cast<std::size_t>(dy + top.y.n - 1) * (2 * top.x.n - 1) + dx + top.x.n - 1]);
      }

    // Corrections of every level above the coarsest.
    for (std::size_t l = 0; l + 1 < n_levels; ++l)
      {
        const Level &L = levels[l];
        // Ktilde at offset d reaches fine offsets d ± (2p - 2) in a coarsened
        // direction.
        const int reach_x = max_width + (L.x.coarsened ? 2 * order : 0);
        const int reach_y = max_width + (L.y.coarsened ? 2 * order : 0);
        const std::vector<double> table = kernel_table(kernels, l, reach_x, reach_y);
        const int                 tw    = 2 * reach_x + 1;
        auto kappa = [&](int dx, int dy, int pair) {
          return table[((static_cast<std::size_t>(dy + reach_y)) * tw + (dx + reach_x)) * block + pair];
        };
        if (l == 0)
          for (int pair = 0; pair < block; ++pair)
            {
              const int m = widths[pair / n_loads];
              for (int dy = -m; dy <= m; ++dy)
                for (int dx = -m; dx <= m; ++dx)
                  magnitude[pair] += std::fabs(kappa(dx, dy, pair));
            }

        // 1-D factors of Ktilde per parity and offset.
        auto factors = [&](const Axis &axis, int m) {
          std::vector<std::vector<std::vector<std::pair<int, double>>>> f(2);
          for (int P = 0; P < 2; ++P)
            for (int d = -m; d <= m; ++d)
              f[P].push_back(axis.coarsened ? interpolated_offsets(P, d, weights)
                                            : std::vector<std::pair<int, double>>{{d, 1.0}});
          return f;
        };

        std::vector<std::size_t> kept(block, 0), total(block, 0);
#pragma omp parallel for schedule(dynamic) num_threads(threads)
        for (int pair = 0; pair < block; ++pair)
          {
            const int  m  = widths[pair / n_loads];
            const int  w  = 2 * m + 1;
            const auto fx = factors(L.x, m), fy = factors(L.y, m);
            // Dense correction per parity class, then the sparse copy.
            std::vector<double> C(static_cast<std::size_t>(w) * w);
            Correction         &sparse = correction[l][pair];
            sparse.begin.assign(4 * static_cast<std::size_t>(w) + 1, 0);
            for (int dy = -m; dy <= m; ++dy)
              for (int dx = -m; dx <= m; ++dx)
                if (kappa(dx, dy, pair) != 0.0)
                  active[pair] = 1;
            for (int k = 0; k < 4; ++k)
              {
                const int Px = k % 2, Py = k / 2;
                for (int dy = -m; dy <= m; ++dy)
                  for (int dx = -m; dx <= m; ++dx)
                    {
                      double interpolated = 0.0;
                      for (const auto &[ox, wx] : fx[Px][dx + m])
                        for (const auto &[oy, wy] : fy[Py][dy + m])
                          interpolated += wx * wy * kappa(ox, oy, pair);
                      C[static_cast<std::size_t>(dy + m) * w + (dx + m)] = kappa(dx, dy, pair) - interpolated;
                    }
                // Drop the smallest terms while their magnitudes add up to at
                // most tolerance × magnitude: a result on this level then
                // changes by at most that much times max |load|.
                std::vector<std::size_t> order(C.size());
                for (std::size_t t = 0; t < order.size(); ++t)
                  order[t] = t;
                std::sort(order.begin(), order.end(),
                          [&C](std::size_t a, std::size_t b) { return std::fabs(C[a]) < std::fabs(C[b]); });
                const double budget  = tolerance * magnitude[pair];
                double       dropped = 0.0;
                for (const std::size_t t : order)
                  {
                    if (dropped + std::fabs(C[t]) > budget)
                      break;
                    dropped += std::fabs(C[t]);
                    C[t] = 0.0;
                  }
                for (int dy = -m; dy <= m; ++dy)
                  {
                    for (int dx = -m; dx <= m; ++dx)
                      {
                        const double c = C[static_cast<std::size_t>(dy + m) * w + (dx + m)];
                        if (c == 0.0)
                          continue;
                        // Output lattice x = out_start + 2A + Px reads
                        // x - dx = x_start + 2B + q, B = A + shift + (Px - dx - q)/2.
                        const int q = parity(Px - dx);
                        sparse.source.push_back(q * L.in_half + L.shift + (Px - dx - q) / 2);
                        sparse.coefficient.push_back(c);
                      }
                    sparse.begin[k * w + dy + m + 1] = static_cast<int>(sparse.source.size());
                  }
              }
            kept[pair]  = sparse.source.size();
            total[pair] = 4 * C.size();
          }
        for (int pair = 0; pair < block; ++pair)
          if (active[pair])
            {
              kept_terms += kept[pair];
              total_terms += total[pair];
            }
      }
  }

  void MultilevelSummation::Impl::anterpolate(const Level &fine, const Level &coarse, const double *u,
                                              double *U) const
  {
    // Transpose of interpolate_row(), divided by 2 per coarsened direction so the
    // coarse load stays a density (its kernel carries the area ratio).
    const int half = order / 2;
    // x first: fine rows -> rows of coarse width.
    std::vector<double> rows(static_cast<std::size_t>(fine.y.n) * coarse.x.n, 0.0);
    for (int b = 0; b < fine.y.n; ++b)
      {
        const double *src = u + static_cast<std::size_t>(b) * fine.x.n;
        double       *dst = rows.data() + static_cast<std::size_t>(b) * coarse.x.n;
        if (!fine.x.coarsened)
          {
            std::copy(src, src + fine.x.n, dst);
            continue;
          }
        for (int a = 0; a < fine.x.n; ++a)
          {
            const int i = fine.x.lo + a;
            if (parity(i) == 0)
              dst[i / 2 - coarse.x.lo] += 0.5 * src[a];
            else
              {
                const int base = half_floor(i) - coarse.x.lo;
                for (int k = -half + 1; k <= half; ++k)
                  dst[base + k] += 0.5 * weights[k + half - 1] * src[a];
              }
          }
      }
    // then y, whole rows at a time.
    std::fill(U, U + coarse.size(), 0.0);
    const int nxc = coarse.x.n;
    for (int b = 0; b < fine.y.n; ++b)
      {
        const double *src = rows.data() + static_cast<std::size_t>(b) * nxc;
        const int     j   = fine.y.lo + b;
        auto          add = [&](int coarse_row, double w) {
          double *dst = U + static_cast<std::size_t>(coarse_row) * nxc;
          for (int a = 0; a < nxc; ++a)
            dst[a] += w * src[a];
        };
        if (!fine.y.coarsened)
          add(b, 1.0);
        else if (parity(j) == 0)
          add(j / 2 - coarse.y.lo, 0.5);
        else
          for (int k = -half + 1; k <= half; ++k)
            add(half_floor(j) - coarse.y.lo + k, 0.5 * weights[k + half - 1]);
      }
  }

  void MultilevelSummation::Impl::interpolate_row(const Level &coarse, const Level &fine, const double *W, int b,
                                                  double *w, std::vector<double> &column_mix) const
  {
    const int half = order / 2;
    const int nxc  = coarse.x.n;
    // y first: the coarse rows around fine row b, mixed into one row of
    // coarse width ...
    column_mix.assign(nxc, 0.0);
    const int j   = fine.y.lo + b;
    auto      add = [&](int coarse_row, double weight) {
      const double *src = W + static_cast<std::size_t>(coarse_row) * nxc;
      for (int a = 0; a < nxc; ++a)
        column_mix[a] += weight * src[a];
    };
    if (!fine.y.coarsened)
      add(b, 1.0);
    else if (parity(j) == 0)
      add(j / 2 - coarse.y.lo, 1.0);
    else
      for (int k = -half + 1; k <= half; ++k)
        add(half_floor(j) - coarse.y.lo + k, weights[k + half - 1]);
    // ... then x along it.
    const double *src = column_mix.data();
    if (!fine.x.coarsened)
      {
        std::copy(src, src + fine.x.n, w);
        return;
      }
    for (int a = 0; a < fine.x.n; ++a)
      {
        const int i = fine.x.lo + a;
        if (parity(i) == 0)
          w[a] = src[i / 2 - coarse.x.lo];
        else
          {
            const double *s   = src + (half_floor(i) - coarse.x.lo);
            double        sum = 0.0;
            for (int k = -half + 1; k <= half; ++k)
              sum += weights[k + half - 1] * s[k];
            w[a] = sum;
          }
      }
  }

  MultilevelSummation::MultilevelSummation(const SurfaceGrid &grid, int n_outputs, int n_loads,
                                           const InfluenceBlock &kernels, const MultilevelSettings &settings,
                                           const std::vector<int> &output_correction_widths)
    : impl(std::make_unique<Impl>())
  {
    if (grid.nx < 1 || grid.ny < 1)
      throw std::invalid_argument("MLMI: empty grid");
    if (n_outputs < 1 || n_loads < 1)
      throw std::invalid_argument("MLMI: need at least one output and one load");
    if (settings.interpolation_order < 2 || settings.interpolation_order > 12 ||
        settings.interpolation_order % 2 != 0)
      throw std::invalid_argument("MLMI: interpolation order must be even, 2 to 12; got " +
                                  std::to_string(settings.interpolation_order));
    if (settings.correction_width < 0)
      throw std::invalid_argument("MLMI: correction width must be >= 0 (0 = automatic)");
    if (!output_correction_widths.empty() && static_cast<int>(output_correction_widths.size()) != n_outputs)
      throw std::invalid_argument("MLMI: one correction width per output expected");

    impl->grid      = grid;
    impl->n_outputs = n_outputs;
    impl->n_loads   = n_loads;
    impl->order     = settings.interpolation_order;
    if (!(settings.correction_tolerance >= 0.0 && settings.correction_tolerance < 1.0))
      throw std::invalid_argument("MLMI: correction tolerance must lie in [0, 1)");
    impl->tolerance = settings.correction_tolerance;
    if (settings.threads < 0)
      throw std::invalid_argument("MLMI: threads must be >= 0 (0 = OpenMP default)");
    impl->threads = settings.threads;
#ifdef _OPENMP
    if (impl->threads == 0)
      impl->threads = omp_get_max_threads();
#else
    impl->threads = 1;
#endif
    impl->weights   = midpoint_weights(impl->order);
    const int base_width =
      settings.correction_width > 0 ? settings.correction_width : default_correction_width(impl->order);
    impl->widths.assign(n_outputs, base_width);
    for (int o = 0; o < static_cast<int>(output_correction_widths.size()); ++o)
      {
        if (output_correction_widths[o] < 0)
          throw std::invalid_argument("MLMI: correction width must be >= 0 (0 = automatic)");
        if (output_correction_widths[o] > 0)
          impl->widths[o] = output_correction_widths[o];
      }
    impl->max_width = *std::max_element(impl->widths.begin(), impl->widths.end());

    impl->build_levels(settings);
    impl->build_kernels(kernels);
  }

  MultilevelSummation::MultilevelSummation(const SurfaceGrid &grid, const InfluenceFunction &kernel,
                                           const MultilevelSettings &settings)
    : MultilevelSummation(
        grid, 1, 1, [&kernel](int di, int dj, double *values) { values[0] = kernel(di, dj); }, settings)
  {}

  MultilevelSummation::MultilevelSummation(const SurfaceGrid &grid, const std::vector<InfluenceFunction> &kernels,
                                           const MultilevelSettings &settings)
    : MultilevelSummation(
        grid, static_cast<int>(kernels.size()), 1,
        [&kernels](int di, int dj, double *values) {
          for (std::size_t k = 0; k < kernels.size(); ++k)
            values[k] = kernels[k](di, dj);
        },
        settings)
  {}

  MultilevelSummation::~MultilevelSummation()                                      = default;
  MultilevelSummation::MultilevelSummation(MultilevelSummation &&) noexcept        = default;
  MultilevelSummation &MultilevelSummation::operator=(MultilevelSummation &&) noexcept = default;

  int MultilevelSummation::n_outputs() const { return impl->n_outputs; }
  int MultilevelSummation::n_loads() const { return impl->n_loads; }
  int MultilevelSummation::levels() const { return static_cast<int>(impl->levels.size()) - 1; }
  int MultilevelSummation::interpolation_order() const { return impl->order; }
  int MultilevelSummation::correction_width(int output) const { return impl->widths.at(output); }
  int MultilevelSummation::active_kernel_count() const
  {
    return static_cast<int>(std::count(impl->active.begin(), impl->active.end(), 1));
  }
  double MultilevelSummation::correction_fill() const
  {
    return impl->total_terms == 0 ? 1.0 : static_cast<double>(impl->kept_terms) / impl->total_terms;
  }
  std::vector<std::pair<int, int>> MultilevelSummation::level_sizes() const
  {
    std::vector<std::pair<int, int>> sizes;
    for (const auto &L : impl->levels)
      sizes.emplace_back(L.x.n, L.y.n);
    return sizes;
  }

  void MultilevelSummation::apply(const std::vector<const double *> &loads,
                                  const std::vector<double *> &results) const
  {
    const Impl &I = *impl;
    if (static_cast<int>(loads.size()) != I.n_loads || static_cast<int>(results.size()) != I.n_outputs)
      throw std::invalid_argument("MLMI apply: expected " + std::to_string(I.n_loads) + " loads and " +
                                  std::to_string(I.n_outputs) + " results");
    const std::size_t n_levels = I.levels.size();
    const int         top      = static_cast<int>(n_levels) - 1;

    // 1. Loads on every level (anterpolated once for all kernels); a load
    //    that is zero everywhere is skipped in all sums.
    std::vector<std::vector<std::vector<double>>> U(n_levels, std::vector<std::vector<double>>(I.n_loads));
    std::vector<char>                             load_used(I.n_loads, 0);
#pragma omp parallel for schedule(static) num_threads(I.threads)
    for (int ld = 0; ld < I.n_loads; ++ld)
      {
        const double *u = loads[ld];
        load_used[ld]   = std::any_of(u, u + I.grid.size(), [](double v) { return v != 0.0; });
        if (!load_used[ld])
          continue;
        U[0][ld].assign(u, u + I.grid.size());
        for (std::size_t l = 0; l + 1 < n_levels; ++l)
          {
            U[l + 1][ld].resize(I.levels[l + 1].size());
            I.anterpolate(I.levels[l], I.levels[l + 1], U[l][ld].data(), U[l + 1][ld].data());
          }
      }

    // 2. Zero-padded, x-polyphase copies of the loads for the corrections
    //    (layout in Level).
    std::vector<std::vector<std::vector<double>>> padded(n_levels - 1, std::vector<std::vector<double>>(I.n_loads));
    for (std::size_t l = 0; l + 1 < n_levels; ++l)
      {
        const auto &L    = I.levels[l];
        const int   rows = L.y.n + 2 * L.pad_y;
        for (int ld = 0; ld < I.n_loads; ++ld)
          {
            if (!load_used[ld])
              continue;
            auto &D = padded[l][ld];
            D.assign(static_cast<std::size_t>(rows) * 2 * L.in_half, 0.0);
            for (int b = 0; b < L.y.n; ++b)
              for (int a = 0; a < L.x.n; ++a)
                {
                  const int i = L.x.lo + a - L.x_start; // >= 0
                  D[(static_cast<std::size_t>(b + L.pad_y) * 2 + parity(i)) * L.in_half + i / 2] =
                    U[l][ld][static_cast<std::size_t>(b) * L.x.n + a];
                }
          }
      }

    // 3. Per output: direct sum on the coarsest grid, then interpolate and
    //    correct level by level. Outputs are independent and shared out among
    //    the threads; with fewer outputs than threads, all threads work on one
    //    output at a time and share its rows instead. One parallel region
    //    only: a nested region costs ~0.2 ms of thread start-up each time.
    const bool over_outputs = I.n_outputs >= I.threads;

    // Row Iy of the coarsest-grid direct sum for output o.
    auto coarsest_row = [&](int o, int Iy, double *W) {
      const auto &L  = I.levels[top];
      const int   nx = L.x.n, ny = L.y.n, kw = 2 * nx - 1;
      double     *w  = W + static_cast<std::size_t>(Iy) * nx;
      std::fill(w, w + nx, 0.0);
      for (int ld = 0; ld < I.n_loads; ++ld)
        {
          const int pair = o * I.n_loads + ld;
          if (!load_used[ld] || !I.active[pair])
            continue;
          const std::vector<double> &K = I.coarsest[pair];
          const std::vector<double> &u = U[top][ld];
          for (int Jy = 0; Jy < ny; ++Jy)
            {
              const double *krow = K.data() + static_cast<std::size_t>(Iy - Jy + ny - 1) * kw + (nx - 1);
              const double *urow = u.data() + static_cast<std::size_t>(Jy) * nx;
              for (int Jx = 0; Jx < nx; ++Jx)
                {
                  const double uj = urow[Jx];
                  if (uj == 0.0)
                    continue;
                  const double *k = krow - Jx; // k[Ix] = K(Ix - Jx, Iy - Jy)
                  for (int Ix = 0; Ix < nx; ++Ix)
                    w[Ix] += uj * k[Ix];
                }
            }
        }
    };

    // Adds the local correction of level l to row b of output o's sums w;
    // row: per-thread work array.
    auto correct_row = [&](int o, std::size_t l, int b, double *w, std::vector<double> &row) {
      const auto &L = I.levels[l];
      const int   m = I.widths[o], width = 2 * m + 1;
      row.assign(2 * static_cast<std::size_t>(L.out_half), 0.0);
      const int Py = parity(L.y.lo + b);
      for (int ld = 0; ld < I.n_loads; ++ld)
        {
          const int pair = o * I.n_loads + ld;
          if (!load_used[ld] || !I.active[pair])
            continue;
          const Impl::Correction &C = I.correction[l][pair];
          for (int dy = -m; dy <= m; ++dy)
            {
              const double *in_row =
                padded[l][ld].data() + static_cast<std::size_t>(b - dy + L.pad_y) * 2 * L.in_half;
              for (int Px = 0; Px < 2; ++Px)
                {
                  const int k     = (Px + 2 * Py) * width + (dy + m);
                  const int first = C.begin[k], terms = C.begin[k + 1] - first;
                  if (terms > 0)
                    accumulate_row(L.out_half, terms, C.coefficient.data() + first, C.source.data() + first, in_row,
                                   row.data() + Px * L.out_half);
                }
            }
        }
      double *target = w + static_cast<std::size_t>(b) * L.x.n;
      for (int a = 0; a < L.x.n; ++a)
        {
          const int i = L.x.lo + a - L.out_start;
          target[a] += row[parity(i) * L.out_half + i / 2];
        }
    };

    // Work arrays of the levels above the surface, shared by the team when it
    // works on one output together.
    std::vector<std::vector<double>> shared_W(over_outputs ? 0 : n_levels);
    for (std::size_t l = 1; l < shared_W.size(); ++l)
      shared_W[l].resize(I.levels[l].size());

#pragma omp parallel num_threads(I.threads)
    {
      std::vector<double> scratch, column_mix;
      if (over_outputs)
        {
          std::vector<std::vector<double>> W(n_levels);
          for (std::size_t l = 1; l < n_levels; ++l)
            W[l].resize(I.levels[l].size());
#pragma omp for schedule(dynamic)
          for (int o = 0; o < I.n_outputs; ++o)
            {
              double *top_sums = top == 0 ? results[o] : W[top].data();
              for (int Iy = 0; Iy < I.levels[top].y.n; ++Iy)
                coarsest_row(o, Iy, top_sums);
              for (int l = top - 1; l >= 0; --l)
                {
                  double *w = l == 0 ? results[o] : W[l].data();
                  for (int b = 0; b < I.levels[l].y.n; ++b)
                    {
                      I.interpolate_row(I.levels[l + 1], I.levels[l], W[l + 1].data(), b,
                                        w + static_cast<std::size_t>(b) * I.levels[l].x.n, column_mix);
                      correct_row(o, l, b, w, scratch);
                    }
                }
            }
        }
      else
        for (int o = 0; o < I.n_outputs; ++o)
          {
            double *top_sums = top == 0 ? results[o] : shared_W[top].data();
#pragma omp for schedule(static)
            for (int Iy = 0; Iy < I.levels[top].y.n; ++Iy)
              coarsest_row(o, Iy, top_sums);
            for (int l = top - 1; l >= 0; --l)
              {
                double *w = l == 0 ? results[o] : shared_W[l].data();
                // Rows need only the coarser level: one barrier per level.
#pragma omp for schedule(static)
                for (int b = 0; b < I.levels[l].y.n; ++b)
                  {
                    I.interpolate_row(I.levels[l + 1], I.levels[l], shared_W[l + 1].data(), b,
                                      w + static_cast<std::size_t>(b) * I.levels[l].x.n, column_mix);
                    correct_row(o, l, b, w, scratch);
                  }
              }
          }
    }
  }

  void MultilevelSummation::apply(const Field &load, Field &result) const
  {
    if (impl->n_outputs != 1 || impl->n_loads != 1)
      throw std::invalid_argument("MLMI apply(load, result) needs a single kernel");
    if (load.size() != impl->grid.size())
      throw std::invalid_argument("MLMI apply: load size does not match the grid");
    result.resize(impl->grid.size());
    apply({load.data()}, {result.data()});
  }

  void MultilevelSummation::apply(const Field &load, std::vector<Field> &results) const
  {
    if (impl->n_loads != 1)
      throw std::invalid_argument("MLMI apply(load, results) needs one load");
    if (load.size() != impl->grid.size())
      throw std::invalid_argument("MLMI apply: load size does not match the grid");
    results.resize(impl->n_outputs);
    std::vector<double *> targets;
    for (auto &r : results)
      {
        r.resize(impl->grid.size());
        targets.push_back(r.data());
      }
    apply({load.data()}, targets);
  }
} // namespace fretsim::contact
