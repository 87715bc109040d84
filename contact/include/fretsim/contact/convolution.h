#pragma once
#include <fretsim/contact/surface_grid.h>

#include <functional>
#include <memory>
#include <vector>

namespace fretsim::contact
{
  /// Influence coefficient K(di, dj): response at a cell centre to a unit
  /// uniform load on a cell offset by (di, dj) cells (di = i_field - i_load).
  using InfluenceFunction = std::function<double(int di, int dj)>;
  /// Influence coefficient K(di; j, jj) translation invariant in x only:
  /// response in row j to a unit load in row jj, di cells apart in x.
  using RowPairInfluenceFunction = std::function<double(int di, int field_row, int load_row)>;

  /// Linear (non-periodic) discrete convolution w_i = sum_j K(i - j) u_j on a
  /// SurfaceGrid, evaluated with DC-FFT (Liu, Wang & Liu, Wear 243, 2000):
  /// the kernel is zero-padded to 2nx × 2ny in wrap-around order, transformed
  /// once, and the FFTW plans are reused on every call. On grids with few
  /// rows (the ring interface's 16 axial cells) the transform runs along x
  /// only and the rows are summed directly per frequency. Exact to round-off
  /// against direct summation.
  class SurfaceConvolution
  {
  public:
    /// periodic_x: the grid closes on itself in x (the unrolled cylinder);
    /// x is then not padded, and the kernel must be periodic,
    /// K(di, dj) = K(di ± nx, dj) (e.g. the nearest image's coefficient).
    /// How the convolution is evaluated; both are exact to round-off.
    enum class Method
    {
      automatic,        ///< rows_along_x for ny <= 32, else two_dimensional
      two_dimensional,  ///< 2-D DC-FFT, padded in x (unless periodic) and y
      rows_along_x      ///< FFT along x, then per x-frequency the direct sum over the ny rows
    };

    SurfaceConvolution(const SurfaceGrid &grid, const InfluenceFunction &kernel, bool periodic_x = false,
                       Method method = Method::automatic);
    /// A kernel invariant along x only (a structure's compliance on the
    /// closed circumference, whose rows differ across the width): periodic in
    /// x and rows_along_x, ny² kernel rows; K(di ± nx; j, jj) = K(di; j, jj).
    SurfaceConvolution(const SurfaceGrid &grid, const RowPairInfluenceFunction &kernel);
    ~SurfaceConvolution();
    SurfaceConvolution(SurfaceConvolution &&) noexcept;
    SurfaceConvolution &operator=(SurfaceConvolution &&) noexcept;

    /// result = K * load (DC-FFT).
    void apply(const Field &load, Field &result) const;
    /// The same in single precision (the kernel's spectra rounded to float,
    /// transforms and sums in float): within about 1e-6 of the largest
    /// |result|, for iterative solves that need the product to a few digits
    /// only.
    void apply(const std::vector<float> &load, std::vector<float> &result) const;
    /// The single precision apply shared by two threads: each calls it at
    /// once with the same arrays, its `part` (0, 1) and `wait`, a barrier
    /// across both. Thread `part` must have written the load's rows of its
    /// part (rows [0, shared_split_row()) are part 0's, the others part
    /// 1's), and on return it may read the result's rows of its part; the
    /// other rows only after a wait. Between two shared applies of one
    /// convolution the threads wait at least once. The numbers are
    /// apply()'s. result sized to the grid.
    void apply_shared(const std::vector<float> &load, std::vector<float> &result, int part,
                      const std::function<void()> &wait) const;
    /// apply_shared's first row of part 1, 0 if part 0 applies it whole
    /// (then every row is the caller's after the call).
    int shared_split_row() const;
    /// The inverse of K + shift I on the whole grid, closed in x (periodic,
    /// rows along x): per x-frequency the ny × ny block of K's spectrum plus
    /// shift, inverted, as a convolution of its own (a row-pair kernel). The
    /// interface's preconditioner (coupling/local_compliance). Throws
    /// std::logic_error for a convolution not periodic in x or not by rows,
    /// std::runtime_error if a block is singular.
    SurfaceConvolution inverse(double shift) const;
    /// result = K * load by O(N^2) direct summation: the reference.
    void apply_direct(const Field &load, Field &result) const;

    const SurfaceGrid &grid() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };

  /// Influence coefficients for uniform rectangular cells on an elastic
  /// half-space (Love 1929; docs/references.md §4.1), per unit load.
  namespace influence
  {
    /// Combined normal displacement of both bodies from unit pressure on a
    /// cell of size hx × hy, at offset (x, y) from its centre: [F1]/(pi E*).
    double normal_displacement(double x, double y, double hx, double hy, double contact_modulus);
  } // namespace influence
} // namespace fretsim::contact
