#include <fretsim/contact/convolution.h>

#include <fftw3.h>

#include <cmath>
#include <algorithm>
#include <complex>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace fretsim::contact
{
  namespace
  {
    // The FFTW planner and fftw_destroy_plan share global state and are not
    // thread safe; fftw_execute_dft_* on existing plans is.
    std::mutex &fftw_planner_mutex()
    {
      static std::mutex mutex;
      return mutex;
    }

    struct FftwFree
    {
      void operator()(void *pointer) const { fftw_free(pointer); }
    };
    using RealBuffer    = std::unique_ptr<double[], FftwFree>;
    using ComplexBuffer = std::unique_ptr<fftw_complex[], FftwFree>;

    RealBuffer allocate_real(std::size_t n)
    {
      auto *pointer = fftw_alloc_real(n);
      if (!pointer)
        throw std::bad_alloc();
      return RealBuffer(pointer);
    }

    ComplexBuffer allocate_complex(std::size_t n)
    {
      auto *pointer = fftw_alloc_complex(n);
      if (!pointer)
        throw std::bad_alloc();
      return ComplexBuffer(pointer);
    }

    /// X asinh(Y/|X|): the part of X ln(Y + rho) that survives the corner sum
    /// (the remaining X ln|X| cancels between the two Y corners). This form has
    /// no cancellation for Y < 0 and tends to 0 as X -> 0, where X ln(Y + rho)
    /// would give 0 * (-inf).
    double x_asinh_y_over_x(double x, double y)
    {
      return x == 0.0 ? 0.0 : x * std::asinh(y / std::abs(x));
    }

    /// Love's F1(X, Y) = X ln(Y + rho) + Y ln(X + rho) up to terms that cancel
    /// in the corner sum.
    double love_f1(double x, double y) { return x_asinh_y_over_x(x, y) + x_asinh_y_over_x(y, x); }
  } // namespace

  namespace influence
  {
    double normal_displacement(double x, double y, double hx, double hy, double contact_modulus)
    {
      const double x1 = x + 0.5 * hx, x2 = x - 0.5 * hx; // x - xi1, x - xi2
      const double y1 = y + 0.5 * hy, y2 = y - 0.5 * hy;
      const double corner_sum = love_f1(x1, y1) - love_f1(x1, y2) - love_f1(x2, y1) + love_f1(x2, y2);
      return corner_sum / (M_PI * contact_modulus);
    }
  } // namespace influence

  struct SurfaceConvolution::Impl
  {
    SurfaceGrid grid;
    int         padded_nx = 0, padded_ny = 0; ///< 2 nx (nx if periodic in x), 2 ny
    int         spectrum_nx = 0;              ///< padded_nx / 2 + 1: r2c keeps half the last dimension

    /// K(di, dj) for di in [-(nx-1), nx-1], dj in [-(ny-1), ny-1], x fastest:
    /// the direct sum reads it instead of calling the std::function N^2 times.
    std::vector<double> kernel_table;
    int                 table_nx = 0;
    /// FFT of the wrap-around kernel, already divided by the padded size
    /// because FFTW's c2r is unnormalised.
    std::vector<std::complex<double>> kernel_spectrum;

    fftw_plan forward  = nullptr;
    fftw_plan backward = nullptr;

    // Work arrays for apply(). A second caller that finds them busy uses its
    // own, so apply() stays safe to call concurrently.
    mutable std::mutex    buffer_mutex;
    mutable RealBuffer    real_work;
    mutable ComplexBuffer complex_work;

    std::size_t padded_size() const { return static_cast<std::size_t>(padded_nx) * padded_ny; }
    std::size_t spectrum_size() const { return static_cast<std::size_t>(padded_ny) * spectrum_nx; }

    double kernel(int di, int dj) const
    {
      return kernel_table[static_cast<std::size_t>(dj + grid.ny - 1) * table_nx + (di + grid.nx - 1)];
    }

    void convolve(const Field &load, Field &result, double *real, fftw_complex *spectrum) const
    {
      const int nx = grid.nx, ny = grid.ny;
      std::fill(real, real + padded_size(), 0.0);
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          real[static_cast<std::size_t>(j) * padded_nx + i] = load[grid.index(i, j)];
      fftw_execute_dft_r2c(forward, real, spectrum);
      auto *values = reinterpret_cast<std::complex<double> *>(spectrum);
      for (std::size_t n = 0; n < spectrum_size(); ++n)
        values[n] *= kernel_spectrum[n];
      fftw_execute_dft_c2r(backward, spectrum, real);
      result.resize(grid.size());
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          result[grid.index(i, j)] = real[static_cast<std::size_t>(j) * padded_nx + i];
    }

    ~Impl()
    {
      std::lock_guard<std::mutex> lock(fftw_planner_mutex());
      if (forward)
        fftw_destroy_plan(forward);
      if (backward)
        fftw_destroy_plan(backward);
    }
  };

  SurfaceConvolution::SurfaceConvolution(const SurfaceGrid &grid, const InfluenceFunction &kernel, bool periodic_x)
    : impl(std::make_unique<Impl>())
  {
    if (grid.nx <= 0 || grid.ny <= 0)
      throw std::invalid_argument("SurfaceConvolution: empty grid");
    if (!kernel)
      throw std::invalid_argument("SurfaceConvolution: no influence function");

    Impl &d        = *impl;
    d.grid         = grid;
    // Periodic in x: no padding there; offsets di and di - nx then land on
    // the same slot below, with the same value for a periodic kernel.
    d.padded_nx    = periodic_x ? grid.nx : 2 * grid.nx;
    d.padded_ny    = 2 * grid.ny;
    d.spectrum_nx  = d.padded_nx / 2 + 1;
    d.table_nx     = 2 * grid.nx - 1;
    d.kernel_table.resize(static_cast<std::size_t>(d.table_nx) * (2 * grid.ny - 1));
    for (int dj = -(grid.ny - 1); dj <= grid.ny - 1; ++dj)
      for (int di = -(grid.nx - 1); di <= grid.nx - 1; ++di)
        d.kernel_table[static_cast<std::size_t>(dj + grid.ny - 1) * d.table_nx + (di + grid.nx - 1)] =
          kernel(di, dj);

    d.real_work    = allocate_real(d.padded_size());
    d.complex_work = allocate_complex(d.spectrum_size());
    {
      // FFTW's row-major n0 x n1 with n1 fastest is our [2ny][2nx].
      std::lock_guard<std::mutex> lock(fftw_planner_mutex());
      d.forward  = fftw_plan_dft_r2c_2d(d.padded_ny, d.padded_nx, d.real_work.get(), d.complex_work.get(),
                                        FFTW_ESTIMATE);
      d.backward = fftw_plan_dft_c2r_2d(d.padded_ny, d.padded_nx, d.complex_work.get(), d.real_work.get(),
                                        FFTW_ESTIMATE);
    }
    if (!d.forward || !d.backward)
      throw std::runtime_error("SurfaceConvolution: FFTW could not create the plans");

    // Wrap-around order (Liu, Wang & Liu 2000): offsets 0..n-1 at 0..n-1,
    // offsets -(n-1)..-1 at n+1..2n-1, and index n (no offset reaches it) 0.
    double *padded_kernel = d.real_work.get();
    std::fill(padded_kernel, padded_kernel + d.padded_size(), 0.0);
    auto wrap = [](int offset, int padded) { return offset >= 0 ? offset : padded + offset; };
    for (int dj = -(grid.ny - 1); dj <= grid.ny - 1; ++dj)
      for (int di = -(grid.nx - 1); di <= grid.nx - 1; ++di)
        padded_kernel[static_cast<std::size_t>(wrap(dj, d.padded_ny)) * d.padded_nx + wrap(di, d.padded_nx)] =
          d.kernel(di, dj);
    fftw_execute_dft_r2c(d.forward, padded_kernel, d.complex_work.get());
    const double normalisation = 1.0 / static_cast<double>(d.padded_size());
    const auto  *spectrum      = reinterpret_cast<const std::complex<double> *>(d.complex_work.get());
    d.kernel_spectrum.assign(spectrum, spectrum + d.spectrum_size());
    for (auto &value : d.kernel_spectrum)
      value *= normalisation;
  }

  SurfaceConvolution::~SurfaceConvolution()                                  = default;
  SurfaceConvolution::SurfaceConvolution(SurfaceConvolution &&) noexcept     = default;
  SurfaceConvolution &SurfaceConvolution::operator=(SurfaceConvolution &&) noexcept = default;

  const SurfaceGrid &SurfaceConvolution::grid() const { return impl->grid; }

  void SurfaceConvolution::apply(const Field &load, Field &result) const
  {
    const Impl &d = *impl;
    if (load.size() != d.grid.size())
      throw std::invalid_argument("SurfaceConvolution::apply: load size does not match the grid");
    if (&load == &result)
      throw std::invalid_argument("SurfaceConvolution::apply: load and result must be distinct");

    std::unique_lock<std::mutex> lock(d.buffer_mutex, std::try_to_lock);
    if (lock.owns_lock())
      {
        d.convolve(load, result, d.real_work.get(), d.complex_work.get());
        return;
      }
    // fftw_execute_dft_* with new arrays requires the same alignment as the
    // planning arrays, which fftw_alloc_* guarantees.
    RealBuffer    real     = allocate_real(d.padded_size());
    ComplexBuffer spectrum = allocate_complex(d.spectrum_size());
    d.convolve(load, result, real.get(), spectrum.get());
  }

  void SurfaceConvolution::apply_direct(const Field &load, Field &result) const
  {
    const Impl &d = *impl;
    if (load.size() != d.grid.size())
      throw std::invalid_argument("SurfaceConvolution::apply_direct: load size does not match the grid");
    if (&load == &result)
      throw std::invalid_argument("SurfaceConvolution::apply_direct: load and result must be distinct");

    const int nx = d.grid.nx, ny = d.grid.ny;
    result.assign(d.grid.size(), 0.0);
#pragma omp parallel for schedule(static) if (static_cast<long>(nx) * ny >= 4096)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        {
          double sum = 0.0;
          for (int jj = 0; jj < ny; ++jj)
            {
              const double *kernel_row = &d.kernel_table[static_cast<std::size_t>(j - jj + ny - 1) * d.table_nx];
              const double *load_row   = &load[d.grid.index(0, jj)];
              for (int ii = 0; ii < nx; ++ii)
                sum += kernel_row[i - ii + nx - 1] * load_row[ii];
            }
          result[d.grid.index(i, j)] = sum;
        }
  }
} // namespace fretsim::contact
