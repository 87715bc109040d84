#include "column_transform.h"

#include "fftw_planner.h"

#include <cmath>
#include <mutex>
#include <stdexcept>

namespace fretsim::contact::detail
{
  ColumnTransform::ColumnTransform(int rows, int columns_, int blocks_, std::ptrdiff_t block_distance_,
                                   fftw_complex *scratch, bool measure_plans)
    : columns(columns_)
    , blocks(blocks_)
    , block_distance(block_distance_)
  {
    if (rows <= 0 || columns <= 0 || blocks <= 0)
      throw std::invalid_argument("ColumnTransform: empty blocks");
    // The divisor nearest below sqrt(n): two short passes (12 x 15 at 180).
    for (int divisor = 1; divisor * divisor <= rows; ++divisor)
      if (rows % divisor == 0)
        n1 = divisor;
    n2 = rows / n1;

    twiddle_re.resize(rows);
    twiddle_im.resize(rows);
    for (int k1 = 0; k1 < n1; ++k1)
      for (int j2 = 0; j2 < n2; ++j2)
        {
          // The exponent reduced mod n, so that the angle is exact before cos and sin.
          const double angle = -2.0 * M_PI * static_cast<double>((k1 * j2) % rows) / rows;
          twiddle_re[n2 * k1 + j2] = std::cos(angle);
          twiddle_im[n2 * k1 + j2] = std::sin(angle);
        }

    const int    distance = static_cast<int>(block_distance);
    const int    row      = columns;
    fftw_iodim   first{n1, n2 * row, n2 * row};
    fftw_iodim   first_loops[3]{{columns, 1, 1}, {n2, row, row}, {blocks, distance, distance}};
    fftw_iodim   second{n2, row, row};
    fftw_iodim   second_loops[3]{{columns, 1, 1}, {n1, n2 * row, n2 * row}, {blocks, distance, distance}};
    std::lock_guard<std::mutex> lock(fftw_planner_mutex());
    const unsigned flags = measure_plans ? FFTW_MEASURE : FFTW_ESTIMATE;
    if (!measure_plans)
      forget_planner_history();
    first_forward  = fftw_plan_guru_dft(1, &first, 3, first_loops, scratch, scratch, FFTW_FORWARD, flags);
    second_forward = fftw_plan_guru_dft(1, &second, 3, second_loops, scratch, scratch, FFTW_FORWARD, flags);
    second_inverse = fftw_plan_guru_dft(1, &second, 3, second_loops, scratch, scratch, FFTW_BACKWARD, flags);
    first_inverse  = fftw_plan_guru_dft(1, &first, 3, first_loops, scratch, scratch, FFTW_BACKWARD, flags);
    if (!first_forward || !second_forward || !second_inverse || !first_inverse)
      {
        for (fftw_plan plan : {first_forward, second_forward, second_inverse, first_inverse})
          if (plan)
            fftw_destroy_plan(plan);
        throw std::runtime_error("ColumnTransform: FFTW could not create the plans");
      }
  }

  ColumnTransform::~ColumnTransform()
  {
    std::lock_guard<std::mutex> lock(fftw_planner_mutex());
    for (fftw_plan plan : {first_forward, second_forward, second_inverse, first_inverse})
      fftw_destroy_plan(plan);
  }

// In AVX2 where the processor has it, chosen when the program loads: the same
// IEEE operations (no fused multiply-add), so the same digits everywhere.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
  __attribute__((target_clones("avx2", "default")))
#endif
  void ColumnTransform::scale_rows(fftw_complex *data, double sign) const
  {
    const int rows = n1 * n2;
    for (int block = 0; block < blocks; ++block)
      for (int r = 0; r < rows; ++r)
        {
          const double wr = twiddle_re[r], wi = sign * twiddle_im[r];
          if (wr == 1.0 && wi == 0.0)
            continue; // k1 = 0 or j2 = 0
          double *values = &data[block * block_distance + static_cast<std::ptrdiff_t>(r) * columns][0];
          for (int c = 0; c < 2 * columns; c += 2)
            {
              const double re = values[c], im = values[c + 1];
              values[c]       = re * wr - im * wi;
              values[c + 1]   = re * wi + im * wr;
            }
        }
  }

  void ColumnTransform::forward(fftw_complex *data) const
  {
    fftw_execute_dft(first_forward, data, data);
    scale_rows(data, 1.0);
    fftw_execute_dft(second_forward, data, data);
  }

  void ColumnTransform::inverse(fftw_complex *data) const
  {
    fftw_execute_dft(second_inverse, data, data);
    scale_rows(data, -1.0);
    fftw_execute_dft(first_inverse, data, data);
  }
} // namespace fretsim::contact::detail
