#pragma once
// MultiLevel Multi-Integration (MLMI) of discrete convolutions on a SurfaceGrid
// (Brandt & Lubrecht, J. Comput. Phys. 90, 1990; Venner & Lubrecht, "Multilevel
// Methods in Lubrication", 2000; docs/references.md §6.1).
#include <fretsim/contact/convolution.h>
#include <fretsim/contact/surface_grid.h>

#include <functional>
#include <memory>
#include <vector>

namespace fretsim::contact
{
  struct MultilevelSettings
  {
    /// Number of coarse grids below the surface grid; 0 = automatic: the count
    /// that minimises the estimated work (corrections on every level plus the
    /// direct sum on the coarsest one).
    int levels = 0;
    /// Even order p of the Lagrange interpolation between levels (2 ... 12):
    /// the far-field kernel error is O((2h/r)^p).
    int interpolation_order = 6;
    /// Half-width m of the square local-correction window, counted in cells of
    /// each level; 0 = automatic (default_correction_width()).
    int correction_width = 0;
    /// Correction terms are dropped, smallest first, while their magnitudes
    /// add up to at most this fraction of the kernel's magnitude sum over the
    /// grid, sum_d |K(d)| (per level and parity class), so each level's result
    /// changes by at most tolerance × sum_d |K(d)| × max |load|. At 1e-6 this
    /// removes 25-45 % of the terms with no visible change in the error (tests:
    /// Boussinesq 1.1e-5 -> 1.6e-5 of max |w| at 256^2). 0 keeps every term.
    double correction_tolerance = 1e-6;
    /// OpenMP threads used by apply() and the set-up; 0 = the OpenMP default
    /// (all cores). Work is shared over outputs, or over rows when there are
    /// fewer outputs than threads.
    int threads = 0;
  };

  /// All influence coefficients at one offset (di, dj) = field minus load
  /// cell: values[output * n_loads + load]. Called concurrently from several
  /// threads, so it must not modify shared state.
  using InfluenceBlock = std::function<void(int di, int dj, double *values)>;

  /// Fast evaluation of w_o = sum_l K_ol * u_l, i.e. w_o(i) = sum_j sum_l
  /// K_ol(i - j) u_l(j), for several translation-invariant kernels on one
  /// surface grid, with the MLMI scheme:
  ///  1. each load u_l is anterpolated (transpose of order-p interpolation) to
  ///     a hierarchy of coarser grids, once for all kernels;
  ///  2. on the coarsest grid the sums are done directly;
  ///  3. going back up, each level's sums are the order-p interpolation of the
  ///     coarser level's sums plus a local correction: inside a window
  ///     |di|, |dj| <= m the exact kernel replaces the interpolated one, so the
  ///     only error left is the interpolation error of the kernel beyond m.
  /// Coarse kernels are injected: K_H(D) = (H^2/h^2) K_h(2D), evaluated from the
  /// fine influence function at any offset, including offsets beyond the fine
  /// grid (coarse grids carry ghost points). Grids of any size are handled by
  /// extending every coarse grid with p/2 ghost points per side, so every fine
  /// point has a full centred interpolation stencil; nothing is padded to a
  /// power of two. Work O(N m^2) per kernel and level, a geometric series over
  /// levels, plus O(N_coarsest^2) on the coarsest grid.
  class MultilevelSummation
  {
  public:
    /// n_outputs × n_loads kernels given as one block function.
    /// output_correction_widths (optional, one per output, 0 = use settings)
    /// lets rough kernels (e.g. stresses at the surface) have a wider window.
    MultilevelSummation(const SurfaceGrid &grid, int n_outputs, int n_loads, const InfluenceBlock &kernels,
                        const MultilevelSettings &settings,
                        const std::vector<int> &output_correction_widths = {});
    /// One kernel, one load.
    MultilevelSummation(const SurfaceGrid &grid, const InfluenceFunction &kernel,
                        const MultilevelSettings &settings = {});
    /// Several kernels applied to the same load (one output per kernel).
    MultilevelSummation(const SurfaceGrid &grid, const std::vector<InfluenceFunction> &kernels,
                        const MultilevelSettings &settings = {});
    ~MultilevelSummation();
    MultilevelSummation(MultilevelSummation &&) noexcept;
    MultilevelSummation &operator=(MultilevelSummation &&) noexcept;

    /// results[o][cell] = sum over loads of K_ol * loads[l]; arrays of
    /// grid.size() values in Field order. Results are overwritten.
    void apply(const std::vector<const double *> &loads, const std::vector<double *> &results) const;
    /// Single kernel, single load.
    void apply(const Field &load, Field &result) const;
    /// Several kernels, one load: results resized to n_outputs fields.
    void apply(const Field &load, std::vector<Field> &results) const;

    int n_outputs() const;
    int n_loads() const;
    /// Number of coarse grids actually used.
    int levels() const;
    int interpolation_order() const;
    /// Correction half-width used for an output.
    int correction_width(int output) const;
    /// Size of each grid of the hierarchy, level 0 = the surface grid
    /// (coarse grids include their ghost points).
    std::vector<std::pair<int, int>> level_sizes() const;
    /// Kernel pairs that are identically zero on every level are skipped.
    int active_kernel_count() const;
    /// Fraction of the local-correction terms kept after the tolerance
    /// (1 = the full (2m+1)^2 windows); a measure of the correction work.
    double correction_fill() const;

    /// Automatic correction half-width for interpolation order p:
    /// m = max(2p - 2, 4). The interpolated kernel at offset d mixes kernel
    /// values from d - (2p - 2) to d + (2p - 2) (the stencils of both the field
    /// and the load point), so a window of 2p - 2 keeps the non-smooth kernel
    /// near d = 0 (a spike of 4^l K(0) on level l) out of every interpolated
    /// coefficient; what is left is the smooth O((H/r)^p) error, which falls
    /// like m^-p (tests/contact/unit_multilevel_summation.cpp).
    static int default_correction_width(int interpolation_order);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace fretsim::contact
