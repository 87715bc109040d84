#pragma once
// Private to the contact library: the complex DFTs down the columns of
// row-major blocks, the column pass of a 2-D transform done as rows then
// columns.
//
// FFTW's estimated plan for n-point transforms at a stride of a row loops
// over the columns one by one through a copy buffer (2.5x slower than the
// plan FFTW_MEASURE finds, at n = 180). Split as n = n1 n2 (Cooley–Tukey,
// decimation in time), each pass is a short transform that FFTW runs with
// one codelet across all columns at once, and the plans stay estimated, so
// that every process takes the same operations and gives the same digits:
//   forward: n1-point transforms at a stride of n2 rows, row r = n2 k1 + j2
//            scaled by exp(-2 pi i k1 j2 / n), n2-point transforms over each
//            group of n2 rows; frequency k1 + n1 k2 ends in row n2 k1 + k2
//            (frequency_of_row), which a pointwise product does not mind;
//   inverse: the same passes backwards, from that order to natural order.
#include <fftw3.h>

#include <cstddef>
#include <vector>

namespace fretsim::contact::detail
{
  class ColumnTransform
  {
  public:
    /// In place on `blocks` blocks of rows x columns complex values, row
    /// major, `block_distance` complex values apart; planned on `scratch`
    /// (which FFTW_MEASURE overwrites). Takes the planner lock.
    ColumnTransform(int rows, int columns, int blocks, std::ptrdiff_t block_distance, fftw_complex *scratch,
                    bool measure_plans);
    ~ColumnTransform();
    ColumnTransform(const ColumnTransform &)            = delete;
    ColumnTransform &operator=(const ColumnTransform &) = delete;

    /// On `data` (laid out as the scratch array, from fftw_malloc like it):
    /// natural row order in, the rows in the order of frequency_of_row out.
    /// Thread safe.
    void forward(fftw_complex *data) const;
    /// The inverse (unnormalised) of forward(): its row order in, natural out.
    void inverse(fftw_complex *data) const;
    /// The frequency (0..rows-1) that forward() leaves in row `row`.
    int frequency_of_row(int row) const { return row / n2 + n1 * (row % n2); }

  private:
    void scale_rows(fftw_complex *data, double sign) const;

    int               n1 = 1, n2 = 1, columns = 0, blocks = 0;
    std::ptrdiff_t    block_distance = 0;
    fftw_plan         first_forward = nullptr, second_forward = nullptr;
    fftw_plan         second_inverse = nullptr, first_inverse = nullptr;
    /// exp(-2 pi i k1 j2 / n) for row n2 k1 + j2.
    std::vector<double> twiddle_re, twiddle_im;
  };
} // namespace fretsim::contact::detail
