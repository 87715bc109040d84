#pragma once
// Private to the contact library: the combined Cerruti tangential compliance
// of two half-spaces as a 2 x 2 block DC-FFT convolution on a window of
// mx x my cells (partial_slip.h explains the physics).
#include <fretsim/contact/material.h>

#include <cstddef>
#include <memory>
#include <vector>

namespace fretsim::contact::detail
{
  /// Influence coefficients [m/Pa] of the relative tangential displacement of
  /// the two bodies at a cell centre offset (di, dj) cells from a cell loaded
  /// by a unit uniform shear traction: the sum over both bodies of the
  /// uniform-rectangle Cerruti coefficients (docs/references.md §4.1). The upper
  /// body carries the opposite traction; reflecting it in z = 0 leaves the
  /// in-plane displacements unchanged, so both bodies' coefficients add.
  struct TangentialKernel
  {
    double       hx = 0.0, hy = 0.0;
    MaterialPair materials;

    double xx(int di, int dj) const; ///< u_x from tau_x
    double xy(int di, int dj) const; ///< u_x from tau_y = u_y from tau_x (even in (di, dj))
    double yy(int di, int dj) const; ///< u_y from tau_y
  };

  /// (u_x, u_y) = C (tau_x, tau_y) on a window of mx x my cells by DC-FFT
  /// (Liu, Wang & Liu 2000): the three kernels, zero-padded to 2mx x 2my in
  /// wrap-around order, are transformed once. The kernels are even under
  /// (di, dj) -> (-di, -dj), so their transforms are real and a product costs
  /// two forward and two inverse real FFTs plus 2 x 2 real multiplies.
  ///
  /// Use: clear(), write the tractions into input_x()/input_y() at
  /// padded_index(i, j) (window coordinates, 0 <= i < mx, 0 <= j < my),
  /// execute(), read the displacements from output_x()/output_y() at the same
  /// indices (only the window's: the rest of the padded arrays is scratch).
  class BlockConvolution
  {
  public:
    BlockConvolution(int mx, int my, const TangentialKernel &kernel, bool measure_plans);
    ~BlockConvolution();
    BlockConvolution(const BlockConvolution &) = delete;
    BlockConvolution &operator=(const BlockConvolution &) = delete;

    int         window_x() const { return mx; }
    int         window_y() const { return my; }
    std::size_t padded_index(int i, int j) const { return static_cast<std::size_t>(j) * (2 * mx) + i; }

    void    clear();
    double *input_x();
    double *input_y();
    void    execute();
    const double *output_x() const;
    const double *output_y() const;

  private:
    struct Buffers;
    int                      mx, my;
    std::unique_ptr<Buffers> buffers;
  };

  /// Smallest m' >= m such that 2 m' has no prime factor above 7 (fast FFTW sizes).
  int fft_friendly_size(int m);
} // namespace fretsim::contact::detail
