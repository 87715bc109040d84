#include "tangential_operator.h"

#include "column_transform.h"
#include "fftw_planner.h"

#include <fretsim/contact/rectangle_kernels.h>

#include <fftw3.h>

#include <algorithm>
#include <complex>
#include <mutex>
#include <new>
#include <stdexcept>

namespace fretsim::contact::detail
{
  namespace
  {
    struct FftwFree
    {
      void operator()(void *pointer) const { fftw_free(pointer); }
    };

    template <typename T>
    std::unique_ptr<T[], FftwFree> fftw_array(std::size_t n);

    template <>
    std::unique_ptr<double[], FftwFree> fftw_array<double>(std::size_t n)
    {
      double *pointer = fftw_alloc_real(n);
      if (!pointer)
        throw std::bad_alloc();
      return std::unique_ptr<double[], FftwFree>(pointer);
    }

    template <>
    std::unique_ptr<fftw_complex[], FftwFree> fftw_array<fftw_complex>(std::size_t n)
    {
      fftw_complex *pointer = fftw_alloc_complex(n);
      if (!pointer)
        throw std::bad_alloc();
      return std::unique_ptr<fftw_complex[], FftwFree>(pointer);
    }

    /// The relative displacement of the two surfaces under a unit shear on
    /// the cell at offset (x, y): the sum of both bodies' Cerruti rectangles.
    template <typename Rectangle>
    SurfaceDisplacement both_bodies(Rectangle rectangle, const MaterialPair &materials, double x, double y,
                                    double hx, double hy)
    {
      const auto &l = materials.lower, &u = materials.upper;
      const auto  a = rectangle(x, y, 0.5 * hx, 0.5 * hy, l.shear_modulus(), l.poisson_ratio);
      const auto  b = rectangle(x, y, 0.5 * hx, 0.5 * hy, u.shear_modulus(), u.poisson_ratio);
      return {a.x + b.x, a.y + b.y, a.z + b.z};
    }
  } // namespace

  double TangentialKernel::xx(int di, int dj) const
  {
    return both_bodies(rectangle_displacement_shear_x, materials, di * hx, dj * hy, hx, hy).x;
  }

  double TangentialKernel::xy(int di, int dj) const
  {
    return both_bodies(rectangle_displacement_shear_x, materials, di * hx, dj * hy, hx, hy).y;
  }

  double TangentialKernel::yy(int di, int dj) const
  {
    return both_bodies(rectangle_displacement_shear_y, materials, di * hx, dj * hy, hx, hy).y;
  }

  struct BlockConvolution::Buffers
  {
    std::size_t padded_size   = 0; ///< 2mx * 2my real values
    std::size_t spectrum_size = 0; ///< 2my * (mx + 1) complex values (r2c keeps half of x)

    std::unique_ptr<double[], FftwFree>       real_x, real_y;
    /// Both spectra in one array (x, then y), so that one column pass does both.
    std::unique_ptr<fftw_complex[], FftwFree> spectra;
    fftw_complex                             *spectrum_x = nullptr, *spectrum_y = nullptr;
    /// Real transforms of the xx, xy, yy kernels, divided by the padded size,
    /// their rows in the order the column pass leaves the spectra in.
    std::vector<double> kernel_xx, kernel_xy, kernel_yy;

    fftw_plan forward = nullptr; ///< full 2-D r2c, for the kernels
    /// The products: the input is zero outside the mx x my window and only the
    /// window of the output is read, so the 2-D transforms are done as row
    /// and column passes that skip the my zero rows on the way in and the my
    /// unread rows on the way out (3/4 of a full 2-D transform's work each).
    fftw_plan rows_forward = nullptr, rows_inverse = nullptr;
    std::unique_ptr<ColumnTransform> columns;

    ~Buffers()
    {
      std::lock_guard<std::mutex> lock(fftw_planner_mutex());
      for (fftw_plan plan : {forward, rows_forward, rows_inverse})
        if (plan)
          fftw_destroy_plan(plan);
    }
  };

  BlockConvolution::BlockConvolution(int mx, int my, const TangentialKernel &kernel, bool measure_plans)
    : mx(mx)
    , my(my)
    , buffers(std::make_unique<Buffers>())
  {
    if (mx <= 0 || my <= 0)
      throw std::invalid_argument("BlockConvolution: empty window");
    Buffers &b      = *buffers;
    const int px = 2 * mx, py = 2 * my;
    b.padded_size   = static_cast<std::size_t>(px) * py;
    b.spectrum_size = static_cast<std::size_t>(py) * (mx + 1);
    b.real_x        = fftw_array<double>(b.padded_size);
    b.real_y        = fftw_array<double>(b.padded_size);
    b.spectra       = fftw_array<fftw_complex>(2 * b.spectrum_size);
    b.spectrum_x    = b.spectra.get();
    b.spectrum_y    = b.spectra.get() + b.spectrum_size;
    {
      // FFTW_MEASURE overwrites the arrays while planning: plan first.
      std::lock_guard<std::mutex> lock(fftw_planner_mutex());
      const unsigned flags = measure_plans ? FFTW_MEASURE : FFTW_ESTIMATE;
      if (!measure_plans)
        forget_planner_history();
      const int cx = mx + 1; // complex values of a row's r2c transform
      b.forward = fftw_plan_dft_r2c_2d(py, px, b.real_x.get(), b.spectrum_x, flags);
      // my rows of px reals -> my rows of cx (the other my rows are zero) ...
      b.rows_forward = fftw_plan_many_dft_r2c(1, &px, my, b.real_x.get(), nullptr, 1, px, b.spectrum_x, nullptr,
                                              1, cx, flags);
      // ... then cx columns of py, in place (ColumnTransform); back the same
      // way, keeping rows 0..my-1.
      b.rows_inverse = fftw_plan_many_dft_c2r(1, &px, my, b.spectrum_x, nullptr, 1, cx, b.real_x.get(), nullptr,
                                              1, px, flags);
    }
    if (!b.forward || !b.rows_forward || !b.rows_inverse)
      throw std::runtime_error("BlockConvolution: FFTW could not create the plans");
    b.columns = std::make_unique<ColumnTransform>(py, mx + 1, 2, static_cast<std::ptrdiff_t>(b.spectrum_size), b.spectra.get(),
                                                  measure_plans);

    // Wrap-around order: offsets 0..m-1 at 0..m-1, -(m-1)..-1 at m+1..2m-1,
    // index m (reached by no offset) zero.
    auto transform = [&](auto &&coefficient, std::vector<double> &result) {
      double *padded = b.real_x.get();
      std::fill(padded, padded + b.padded_size, 0.0);
      for (int jj = 0; jj < py; ++jj)
        {
          if (jj == my)
            continue;
          const int dj = jj < my ? jj : jj - py;
          for (int ii = 0; ii < px; ++ii)
            {
              if (ii == mx)
                continue;
              const int di = ii < mx ? ii : ii - px;
              padded[static_cast<std::size_t>(jj) * px + ii] = coefficient(di, dj);
            }
        }
      fftw_execute_dft_r2c(b.forward, padded, b.spectrum_x);
      // The kernel is even, so its transform is real up to round-off.
      const double scale = 1.0 / static_cast<double>(b.padded_size);
      result.resize(b.spectrum_size);
      for (int row = 0; row < py; ++row)
        {
          const std::size_t from = static_cast<std::size_t>(b.columns->frequency_of_row(row)) * (mx + 1);
          for (int column = 0; column <= mx; ++column)
            result[static_cast<std::size_t>(row) * (mx + 1) + column] = b.spectrum_x[from + column][0] * scale;
        }
    };
    transform([&](int di, int dj) { return kernel.xx(di, dj); }, b.kernel_xx);
    transform([&](int di, int dj) { return kernel.xy(di, dj); }, b.kernel_xy);
    transform([&](int di, int dj) { return kernel.yy(di, dj); }, b.kernel_yy);
    clear();
  }

  BlockConvolution::~BlockConvolution() = default;

  namespace
  {
    /// (sx, sy) = K (sx, sy) at every frequency, K the real symmetric 2 x 2
    /// kernel spectrum. In AVX2 where the processor has it, chosen when the
    /// program loads: the same IEEE operations (no fused multiply-add), so
    /// the same digits everywhere.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
    __attribute__((target_clones("avx2", "default")))
#endif
    void multiply(const double *kxx, const double *kxy, const double *kyy, std::size_t size, fftw_complex *sx,
                  fftw_complex *sy)
    {
      for (std::size_t n = 0; n < size; ++n)
        {
          const double tx_re = sx[n][0], tx_im = sx[n][1], ty_re = sy[n][0], ty_im = sy[n][1];
          sx[n][0] = kxx[n] * tx_re + kxy[n] * ty_re;
          sx[n][1] = kxx[n] * tx_im + kxy[n] * ty_im;
          sy[n][0] = kxy[n] * tx_re + kyy[n] * ty_re;
          sy[n][1] = kxy[n] * tx_im + kyy[n] * ty_im;
        }
    }
  } // namespace

  void BlockConvolution::clear()
  {
    // Only the window's rows are read by execute().
    const std::size_t read = static_cast<std::size_t>(my) * 2 * mx;
    std::fill(buffers->real_x.get(), buffers->real_x.get() + read, 0.0);
    std::fill(buffers->real_y.get(), buffers->real_y.get() + read, 0.0);
  }

  double *BlockConvolution::input_x() { return buffers->real_x.get(); }
  double *BlockConvolution::input_y() { return buffers->real_y.get(); }
  const double *BlockConvolution::output_x() const { return buffers->real_x.get(); }
  const double *BlockConvolution::output_y() const { return buffers->real_y.get(); }

  void BlockConvolution::execute()
  {
    Buffers          &b       = *buffers;
    fftw_complex     *sx      = b.spectrum_x, *sy = b.spectrum_y;
    const std::size_t cx      = static_cast<std::size_t>(mx) + 1;
    const std::size_t zero_at = static_cast<std::size_t>(my) * cx; // rows my..2my-1 of the spectrum
    for (fftw_complex *spectrum : {sx, sy})
      {
        double *real = spectrum == sx ? b.real_x.get() : b.real_y.get();
        fftw_execute_dft_r2c(b.rows_forward, real, spectrum);
        std::fill_n(&spectrum[zero_at][0], 2 * (b.spectrum_size - zero_at), 0.0);
      }
    b.columns->forward(b.spectra.get());
    multiply(b.kernel_xx.data(), b.kernel_xy.data(), b.kernel_yy.data(), b.spectrum_size, sx, sy);
    b.columns->inverse(b.spectra.get());
    for (fftw_complex *spectrum : {sx, sy})
      {
        double *real = spectrum == sx ? b.real_x.get() : b.real_y.get();
        fftw_execute_dft_c2r(b.rows_inverse, spectrum, real);
      }
  }

  int fft_friendly_size(int m)
  {
    for (int candidate = std::max(m, 1);; ++candidate)
      {
        int rest = 2 * candidate;
        for (const int prime : {2, 3, 5, 7})
          while (rest % prime == 0)
            rest /= prime;
        if (rest == 1)
          return candidate;
      }
  }
} // namespace fretsim::contact::detail
