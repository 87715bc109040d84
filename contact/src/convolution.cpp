#include <fretsim/contact/convolution.h>

#include "fftw_planner.h"

#include <Eigen/Dense>
#include <fftw3.h>
#include <omp.h>

#include <cmath>
#include <algorithm>
#include <array>
#include <complex>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace fretsim::contact
{
  std::mutex &detail::fftw_planner_mutex()
  {
    static std::mutex mutex;
    return mutex;
  }

  void detail::forget_planner_history() { fftw_forget_wisdom(); }

  namespace
  {
    struct FftwFree
    {
      void operator()(void *pointer) const { fftw_free(pointer); }
    };
    using RealBuffer    = std::unique_ptr<double[], FftwFree>;
    using ComplexBuffer = std::unique_ptr<fftw_complex[], FftwFree>;
    struct FftwfFree
    {
      void operator()(void *pointer) const { fftwf_free(pointer); }
    };
    using SingleRealBuffer    = std::unique_ptr<float[], FftwfFree>;
    using SingleComplexBuffer = std::unique_ptr<fftwf_complex[], FftwfFree>;

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

    /// Which kernel row couples field row j to load row jj: j·field + jj·load
    /// + offset. Translation invariant in y, the row of the offset dj = j - jj
    /// (field 1, load -1, offset ny - 1: 2ny - 1 rows); a row-pair kernel,
    /// the pair itself (field ny, load 1, offset 0: ny² rows).
    struct KernelRows
    {
      int field = 1, load = -1, offset = 0;
      int operator()(int j, int jj) const { return j * field + jj * load + offset; }
    };

    /// The row sums of SurfaceConvolution's rows_along_x, on interleaved
    /// (re, im) spectra of `values` doubles per row: out_j = Σ_jj K_(j,jj) u_jj
    /// over jj < ny, K_(j,jj) the row pair(j, jj) of `kernel_rows`.
    ///
    /// A kernel even in x (Love's: the ring interface's hot path) has real
    /// spectra, one value per frequency, each spread over its frequency's
    /// (re, im) by a shuffle: half the bytes of a (re, im) kernel, which
    /// bounds this loop (its rows come from the cache, not registers). Eight
    /// doubles at a time in GCC's vector extension, so that the sums stay in
    /// registers (summing whole rows into the result re-reads and re-writes
    /// it ny times: half as fast). Compiled also for AVX2, chosen at run
    /// time: the same operations on wider registers and no FMA contraction,
    /// so the same result to the last bit.
    __attribute__((target_clones("avx2", "default"))) void
    sum_rows_real_kernel(const double *kernel_rows, const KernelRows &pair, const double *load, double *out, int ny,
                         std::size_t values, int first_row, int end_row)
    {
      // four doubles: one AVX or two SSE registers; loads need no alignment
      using Quad          = double __attribute__((vector_size(32)));
      using UnalignedQuad = double __attribute__((vector_size(32), aligned(8)));
      using Lanes         = long long __attribute__((vector_size(32)));
      constexpr std::size_t block = 8;
      const std::size_t     whole = values - values % block, frequencies = values / 2;
      const auto load_row   = [values](auto *rows, int r) { return rows + static_cast<std::size_t>(r) * values; };
      const auto kernel_row = [&](int j, int jj) {
        return kernel_rows + static_cast<std::size_t>(pair(j, jj)) * frequencies;
      };
      for (int j = first_row; j < end_row; ++j)
        {
          double *row_out = load_row(out, j);
          for (std::size_t first = 0; first < whole; first += block)
            {
              Quad low = {}, high = {};
              for (int jj = 0; jj < ny; ++jj)
                {
                  const Quad  k = *reinterpret_cast<const UnalignedQuad *>(kernel_row(j, jj) + first / 2);
                  const auto *u = reinterpret_cast<const UnalignedQuad *>(load_row(load, jj) + first);
                  low += __builtin_shuffle(k, Lanes{0, 0, 1, 1}) * Quad(u[0]);
                  high += __builtin_shuffle(k, Lanes{2, 2, 3, 3}) * Quad(u[1]);
                }
              *reinterpret_cast<UnalignedQuad *>(row_out + first)     = low;
              *reinterpret_cast<UnalignedQuad *>(row_out + first + 4) = high;
            }
          for (std::size_t n = whole; n < values; ++n)
            {
              double sum = 0.0;
              for (int jj = 0; jj < ny; ++jj)
                sum += kernel_row(j, jj)[n / 2] * load_row(load, jj)[n];
              row_out[n] = sum;
            }
        }
    }

    /// Any other kernel: complex spectra, complex products (in double or
    /// single precision).
    template <typename Real>
    void sum_rows_complex_kernel(const Real *kernel_rows, const KernelRows &pair, const Real *load, Real *out, int ny,
                                 std::size_t values, int first_row, int end_row)
    {
      const auto row = [values](auto *rows, int r) { return rows + static_cast<std::size_t>(r) * values; };
      for (int j = first_row; j < end_row; ++j)
        for (std::size_t n = 0; n < values; n += 2)
          {
            Real re = 0, im = 0;
            for (int jj = 0; jj < ny; ++jj)
              {
                const Real *k = row(kernel_rows, pair(j, jj)) + n, *u = row(load, jj) + n;
                re += k[0] * u[0] - k[1] * u[1];
                im += k[0] * u[1] + k[1] * u[0];
              }
            row(out, j)[n]     = re;
            row(out, j)[n + 1] = im;
          }
    }

    /// sum_rows_real_kernel in single precision: eight floats at a time,
    /// each kernel value spread over its frequency's (re, im).
    __attribute__((target_clones("avx2", "default"))) void
    sum_rows_real_kernel_single(const float *kernel_rows, const KernelRows &pair, const float *load, float *out,
                                int ny, std::size_t values, int first_row, int end_row)
    {
      using Oct          = float __attribute__((vector_size(32)));
      using UnalignedOct = float __attribute__((vector_size(32), aligned(4)));
      using Lanes        = int __attribute__((vector_size(32)));
      constexpr std::size_t block = 16;
      const std::size_t     whole = values - values % block, frequencies = values / 2;
      const auto kernel_row = [&](int j, int jj) {
        return kernel_rows + static_cast<std::size_t>(pair(j, jj)) * frequencies;
      };
      for (int j = first_row; j < end_row; ++j)
        {
          float *row_out = out + static_cast<std::size_t>(j) * values;
          for (std::size_t first = 0; first < whole; first += block)
            {
              Oct low = {}, high = {};
              for (int jj = 0; jj < ny; ++jj)
                {
                  const Oct   k = *reinterpret_cast<const UnalignedOct *>(kernel_row(j, jj) + first / 2);
                  const auto *u = reinterpret_cast<const UnalignedOct *>(load + static_cast<std::size_t>(jj) * values + first);
                  low += __builtin_shuffle(k, Lanes{0, 0, 1, 1, 2, 2, 3, 3}) * Oct(u[0]);
                  high += __builtin_shuffle(k, Lanes{4, 4, 5, 5, 6, 6, 7, 7}) * Oct(u[1]);
                }
              *reinterpret_cast<UnalignedOct *>(row_out + first)     = low;
              *reinterpret_cast<UnalignedOct *>(row_out + first + 8) = high;
            }
          for (std::size_t n = whole; n < values; ++n)
            {
              float sum = 0.0f;
              for (int jj = 0; jj < ny; ++jj)
                sum += kernel_row(j, jj)[n / 2] * load[static_cast<std::size_t>(jj) * values + n];
              row_out[n] = sum;
            }
        }
    }

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

  /// Two ways to the same linear convolution, chosen by the grid's shape:
  /// - 2-D DC-FFT (Liu, Wang & Liu 2000), the kernel padded to
  ///   padded_nx × 2ny;
  /// - for few rows (ny ≤ direct_rows_limit, e.g. the ring interface's 16
  ///   axial cells) transforms along x only and, per x-frequency, the exact
  ///   sum over the ny rows: w^(k, j) = Σ_jj K^(k, j - jj) u^(k, jj). No
  ///   padding in y, half as many row transforms and no column transforms;
  ///   ny² products per frequency against two 2ny-point FFTs, so it pays
  ///   only for small ny.
  struct SurfaceConvolution::Impl
  {
    /// bench_normal_contact, BM_ConvolutionRingInterface (Love's kernel on
    /// 360 cells closed in x): rows along x 1.5x as fast as the 2-D plan at
    /// 16 and 24 rows, 1.1x at 32.
    static constexpr int direct_rows_limit = 32;

    SurfaceGrid grid;
    bool        direct_rows = false;
    int         padded_nx = 0, padded_ny = 0; ///< 2 nx (nx if periodic in x); 2 ny (ny with direct_rows)
    int         spectrum_nx = 0;              ///< padded_nx / 2 + 1: r2c keeps half the last dimension

    /// K for di in [-(nx-1), nx-1], x fastest, one row per kernel row
    /// (`pair`: per row offset dj = -(ny-1)..ny-1, or per row pair): the
    /// direct sum reads it instead of calling the std::function N^2 times.
    std::vector<double> kernel_table;
    int                 table_nx = 0;
    KernelRows          pair;
    int                 kernel_rows = 0;
    /// 2-D: FFT of the wrap-around kernel [padded_ny][spectrum_nx]. Rows:
    /// FFT along x of each kernel row [kernel_rows][spectrum_nx].
    /// Both already divided by the transform's size (FFTW's c2r is
    /// unnormalised).
    std::vector<std::complex<double>> kernel_spectrum;
    /// Rows, kernel even in x (Love's normal kernel): the spectra are real,
    /// [kernel_rows][spectrum_nx].
    std::vector<double> real_row_spectrum;
    bool                real_rows = false;

    fftw_plan forward  = nullptr;
    fftw_plan backward = nullptr;
    /// Rows along x: the rows in two parts [0, split_row) and [split_row, ny),
    /// each with its own pair of plans, so that two threads share every
    /// phase of a convolution (the ring interface's pressure solves call it
    /// one after another from one thread, where the other waited). Every
    /// row goes through the same plan whatever the thread count: the same
    /// numbers on one thread as on two. 0: one part (a part's first row would
    /// not be aligned as FFTW planned it, or too few rows).
    int                      split_row = 0;
    std::array<fftw_plan, 2> part_forward{}, part_backward{};
    /// Whether the two parts run on two threads: only from a row sum of
    /// nx ny² = 2^19 products up. The ring interface's 360 × 16 (2^16.5) is
    /// ~70 µs of work, and the three barriers of its threads cost more than
    /// they saved: one ball pass of the paper case took 0.81 of the time on
    /// one thread (2 cores AMD EPYC busy with other work; 3 alternated
    /// pairs, the same numbers bitwise).
    bool                     parallel_parts = false;
    static constexpr long    parallel_row_work = 1L << 19;

    struct Workspace
    {
      RealBuffer    real;
      ComplexBuffer spectrum, result_spectrum; ///< result_spectrum: rows only
    };
    /// The work arrays of apply(), one set per concurrent caller (the
    /// Jacobian's sensitivities convolve on every thread): a caller takes
    /// the first free set, allocated on first use; one that finds all busy
    /// allocates its own for the call. apply() stays safe to call
    /// concurrently.
    struct WorkspaceSlot
    {
      std::mutex mutex;
      Workspace  workspace;
    };
    static constexpr std::size_t    workspace_slots = 4;
    mutable std::array<WorkspaceSlot, workspace_slots> workspaces;

    /// Single precision: the spectra above rounded to float (real, or
    /// interleaved (re, im)), the plans and the work arrays, as above; set up
    /// on the first single precision apply (setup_single), which most
    /// convolutions never ask for.
    mutable std::once_flag     single_ready;
    mutable std::vector<float> single_spectrum;
    mutable fftwf_plan         single_forward = nullptr, single_backward = nullptr;
    /// Rows along x: the two parts' plans as in double (split_row), here
    /// also for apply_shared's two threads; the same plans on one thread.
    mutable std::array<fftwf_plan, 2> single_part_forward{}, single_part_backward{};
    mutable bool                      single_split = false;
    struct SingleWorkspace
    {
      SingleRealBuffer    real;
      SingleComplexBuffer spectrum, result_spectrum;
    };
    struct SingleSlot
    {
      std::mutex      mutex;
      SingleWorkspace workspace;
    };
    mutable std::array<SingleSlot, workspace_slots> single_workspaces;
    /// apply_shared's work arrays (both threads on one set).
    mutable SingleWorkspace shared_workspace;

    SingleWorkspace allocate_single_workspace() const
    {
      SingleWorkspace w;
      w.real.reset(fftwf_alloc_real(padded_size()));
      w.spectrum.reset(fftwf_alloc_complex(spectrum_size()));
      w.result_spectrum.reset(fftwf_alloc_complex(spectrum_size()));
      if (!w.real || !w.spectrum || !w.result_spectrum)
        throw std::bad_alloc();
      return w;
    }

    /// convolve() in single precision, either method.
    void convolve_single(const std::vector<float> &load, std::vector<float> &result, const SingleWorkspace &w) const
    {
      if (single_split)
        {
          result.resize(grid.size());
          for (int part = 0; part < 2; ++part)
            forward_single_part(load, w, part);
          for (int part = 0; part < 2; ++part)
            backward_single_part(result, w, part);
          return;
        }
      float *real = w.real.get();
      pad(load, real);
      fftwf_execute_dft_r2c(single_forward, real, w.spectrum.get());
      const auto *in = reinterpret_cast<const float *>(w.spectrum.get());
      auto       *out = reinterpret_cast<float *>(w.result_spectrum.get());
      if (!direct_rows)
        for (std::size_t n = 0; n < 2 * spectrum_size(); n += 2)
          {
            out[n]     = single_spectrum[n] * in[n] - single_spectrum[n + 1] * in[n + 1];
            out[n + 1] = single_spectrum[n] * in[n + 1] + single_spectrum[n + 1] * in[n];
          }
      else
        sum_rows_single(w, 0, grid.ny);
      fftwf_execute_dft_c2r(single_backward, w.result_spectrum.get(), real);
      unpad(real, result);
    }

    /// Rows along x in single precision, rows [first, end) of a part.
    std::pair<int, int> single_part_rows(int part) const
    {
      return part == 0 ? std::pair<int, int>{0, split_row} : std::pair<int, int>{split_row, grid.ny};
    }
    /// A part's rows of the load transformed.
    void forward_single_part(const std::vector<float> &load, const SingleWorkspace &w, int part) const
    {
      const auto [first, end] = single_part_rows(part);
      float *real = w.real.get();
      for (int j = first; j < end; ++j)
        {
          float *row = real + static_cast<std::size_t>(j) * padded_nx;
          std::fill(row + grid.nx, row + padded_nx, 0.0f);
          std::copy_n(load.begin() + static_cast<std::ptrdiff_t>(grid.index(0, j)), grid.nx, row);
        }
      fftwf_execute_dft_r2c(single_part_forward[part], real + static_cast<std::size_t>(first) * padded_nx,
                            w.spectrum.get() + static_cast<std::size_t>(first) * spectrum_nx);
    }
    /// A part's rows of the result: their sums over every row's transform, back.
    void backward_single_part(std::vector<float> &result, const SingleWorkspace &w, int part) const
    {
      const auto [first, end] = single_part_rows(part);
      float *real = w.real.get();
      sum_rows_single(w, first, end);
      fftwf_execute_dft_c2r(single_part_backward[part], w.result_spectrum.get() + static_cast<std::size_t>(first) * spectrum_nx,
                            real + static_cast<std::size_t>(first) * padded_nx);
      for (int j = first; j < end; ++j)
        std::copy_n(real + static_cast<std::size_t>(j) * padded_nx, grid.nx,
                    result.begin() + static_cast<std::ptrdiff_t>(grid.index(0, j)));
    }
    /// sum_rows in single precision.
    void sum_rows_single(const SingleWorkspace &w, int first_row, int end_row) const
    {
      const auto *in = reinterpret_cast<const float *>(w.spectrum.get());
      auto       *out = reinterpret_cast<float *>(w.result_spectrum.get());
      const auto  values = 2 * static_cast<std::size_t>(spectrum_nx);
      if (real_rows)
        sum_rows_real_kernel_single(single_spectrum.data(), pair, in, out, grid.ny, values, first_row, end_row);
      else
        sum_rows_complex_kernel(single_spectrum.data(), pair, in, out, grid.ny, values, first_row, end_row);
    }

    /// The load into a transform's padded array (zeros elsewhere), and the
    /// result out of it.
    template <typename Real>
    void pad(const std::vector<Real> &load, Real *real) const
    {
      std::fill(real, real + padded_size(), Real(0));
      for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i)
          real[static_cast<std::size_t>(j) * padded_nx + i] = load[grid.index(i, j)];
    }
    template <typename Real>
    void unpad(const Real *real, std::vector<Real> &result) const
    {
      result.resize(grid.size());
      for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i)
          result[grid.index(i, j)] = real[static_cast<std::size_t>(j) * padded_nx + i];
    }

    std::size_t padded_size() const { return static_cast<std::size_t>(padded_nx) * padded_ny; }
    std::size_t spectrum_size() const { return static_cast<std::size_t>(padded_ny) * spectrum_nx; }

    Workspace allocate_workspace() const
    {
      Workspace w;
      w.real     = allocate_real(padded_size());
      w.spectrum = allocate_complex(spectrum_size());
      if (direct_rows)
        w.result_spectrum = allocate_complex(spectrum_size());
      return w;
    }

    /// The table's row r at offset di.
    double kernel(int di, int r) const
    {
      return kernel_table[static_cast<std::size_t>(r) * table_nx + (di + grid.nx - 1)];
    }

    /// Plans, the kernel's table and its spectra; `fill(table)` fills the
    /// table [kernel_rows][table_nx] (pair and kernel_rows set).
    void setup(const SurfaceGrid &g, bool periodic_x, Method method, const std::function<void(std::vector<double> &)> &fill);
    /// The single precision copies of the spectra, plans and first work arrays.
    void setup_single() const;

    void convolve(const Field &load, Field &result, const Workspace &w) const
    {
      result.resize(grid.size());
      if (direct_rows)
        {
          convolve_rows(load, result, w);
          return;
        }
      double *real = w.real.get();
      pad(load, real);
      fftw_execute_dft_r2c(forward, real, w.spectrum.get());
      auto *values = reinterpret_cast<std::complex<double> *>(w.spectrum.get());
      for (std::size_t n = 0; n < spectrum_size(); ++n)
        values[n] *= kernel_spectrum[n];
      fftw_execute_dft_c2r(backward, w.spectrum.get(), real);
      unpad(real, result);
    }

    /// Rows along x, part by part: forward transforms, the sums over rows
    /// (which need every row's transform), backward transforms. Within a
    /// caller's own parallel region (the Jacobian's sensitivities) the
    /// region below runs on that one thread.
    void convolve_rows(const Field &load, Field &result, const Workspace &w) const
    {
      const int nx = grid.nx, ny = grid.ny, parts = split_row > 0 ? 2 : 1;
      double   *real = w.real.get();
      auto     *spectrum = w.spectrum.get(), *result_spectrum = w.result_spectrum.get();
      const auto rows   = [&](int part) {
        return parts == 1 ? std::pair<int, int>{0, ny}
                          : (part == 0 ? std::pair<int, int>{0, split_row} : std::pair<int, int>{split_row, ny});
      };
      const auto plan = [&](const std::array<fftw_plan, 2> &of_part, fftw_plan whole, int part) {
        return parts == 1 ? whole : of_part[part];
      };
#pragma omp parallel num_threads(parts) if (parts > 1 && parallel_parts && omp_get_max_threads() > 1)
      {
#pragma omp for schedule(static)
        for (int part = 0; part < parts; ++part)
          {
            const auto [first, end] = rows(part);
            for (int j = first; j < end; ++j)
              {
                double *row = real + static_cast<std::size_t>(j) * padded_nx;
                std::fill(row + nx, row + padded_nx, 0.0);
                for (int i = 0; i < nx; ++i)
                  row[i] = load[grid.index(i, j)];
              }
            fftw_execute_dft_r2c(plan(part_forward, forward, part), real + static_cast<std::size_t>(first) * padded_nx,
                                 spectrum + static_cast<std::size_t>(first) * spectrum_nx);
          }
#pragma omp for schedule(static)
        for (int part = 0; part < parts; ++part)
          {
            const auto [first, end] = rows(part);
            sum_rows(w, first, end);
          }
#pragma omp for schedule(static)
        for (int part = 0; part < parts; ++part)
          {
            const auto [first, end] = rows(part);
            fftw_execute_dft_c2r(plan(part_backward, backward, part),
                                 result_spectrum + static_cast<std::size_t>(first) * spectrum_nx,
                                 real + static_cast<std::size_t>(first) * padded_nx);
            for (int j = first; j < end; ++j)
              for (int i = 0; i < nx; ++i)
                result[grid.index(i, j)] = real[static_cast<std::size_t>(j) * padded_nx + i];
          }
      }
    }

    /// w^(·, j) = Σ_jj K^(·, j - jj) u^(·, jj) over the row spectra, for the
    /// output rows j in [first_row, end_row).
    void sum_rows(const Workspace &w, int first_row, int end_row) const
    {
      const auto *load = reinterpret_cast<const double *>(w.spectrum.get());
      auto       *out  = reinterpret_cast<double *>(w.result_spectrum.get());
      const auto  values = 2 * static_cast<std::size_t>(spectrum_nx);
      if (real_rows)
        sum_rows_real_kernel(real_row_spectrum.data(), pair, load, out, grid.ny, values, first_row, end_row);
      else
        sum_rows_complex_kernel(reinterpret_cast<const double *>(kernel_spectrum.data()), pair, load, out, grid.ny,
                                values, first_row, end_row);
    }

    ~Impl()
    {
      std::lock_guard<std::mutex> lock(detail::fftw_planner_mutex());
      for (fftw_plan plan : {forward, backward, part_forward[0], part_forward[1], part_backward[0], part_backward[1]})
        if (plan)
          fftw_destroy_plan(plan);
      for (fftwf_plan plan : {single_forward, single_backward, single_part_forward[0], single_part_forward[1],
                              single_part_backward[0], single_part_backward[1]})
        if (plan)
          fftwf_destroy_plan(plan);
    }
  };

  SurfaceConvolution::SurfaceConvolution(const SurfaceGrid &grid, const InfluenceFunction &kernel, bool periodic_x,
                                         Method method)
    : impl(std::make_unique<Impl>())
  {
    if (grid.nx <= 0 || grid.ny <= 0)
      throw std::invalid_argument("SurfaceConvolution: empty grid");
    if (!kernel)
      throw std::invalid_argument("SurfaceConvolution: no influence function");
    impl->pair        = {1, -1, grid.ny - 1};
    impl->kernel_rows = 2 * grid.ny - 1;
    impl->setup(grid, periodic_x, method, [&](std::vector<double> &table) {
      const int table_nx = 2 * grid.nx - 1;
      for (int dj = -(grid.ny - 1); dj <= grid.ny - 1; ++dj)
        for (int di = -(grid.nx - 1); di <= grid.nx - 1; ++di)
          table[static_cast<std::size_t>(dj + grid.ny - 1) * table_nx + (di + grid.nx - 1)] = kernel(di, dj);
    });
  }

  SurfaceConvolution::SurfaceConvolution(const SurfaceGrid &grid, const RowPairInfluenceFunction &kernel)
    : impl(std::make_unique<Impl>())
  {
    if (grid.nx <= 0 || grid.ny <= 0)
      throw std::invalid_argument("SurfaceConvolution: empty grid");
    if (!kernel)
      throw std::invalid_argument("SurfaceConvolution: no influence function");
    impl->pair        = {grid.ny, 1, 0};
    impl->kernel_rows = grid.ny * grid.ny;
    impl->setup(grid, true, Method::rows_along_x, [&](std::vector<double> &table) {
      const int table_nx = 2 * grid.nx - 1;
      for (int j = 0; j < grid.ny; ++j)
        for (int jj = 0; jj < grid.ny; ++jj)
          for (int di = -(grid.nx - 1); di <= grid.nx - 1; ++di)
            table[static_cast<std::size_t>(j * grid.ny + jj) * table_nx + (di + grid.nx - 1)] = kernel(di, j, jj);
    });
  }

  void SurfaceConvolution::Impl::setup(const SurfaceGrid &g, bool periodic_x, Method method,
                                       const std::function<void(std::vector<double> &)> &fill)
  {
    Impl &d        = *this;
    const SurfaceGrid &grid = g;
    d.grid         = grid;
    d.direct_rows  = method == Method::rows_along_x ||
                    (method == Method::automatic && grid.ny <= Impl::direct_rows_limit);
    // Periodic in x: no padding there; offsets di and di - nx then land on
    // the same slot below, with the same value for a periodic kernel.
    d.padded_nx    = periodic_x ? grid.nx : 2 * grid.nx;
    d.padded_ny    = d.direct_rows ? grid.ny : 2 * grid.ny;
    d.spectrum_nx  = d.padded_nx / 2 + 1;
    d.table_nx     = 2 * grid.nx - 1;
    d.kernel_table.resize(static_cast<std::size_t>(d.table_nx) * d.kernel_rows);
    fill(d.kernel_table);

    Impl::Workspace &planning = d.workspaces[0].workspace;
    planning               = d.allocate_workspace();
    double       *real     = planning.real.get();
    fftw_complex *spectrum = planning.spectrum.get();
    {
      std::lock_guard<std::mutex> lock(detail::fftw_planner_mutex());
      detail::forget_planner_history();
      if (d.direct_rows)
        { // ny transforms of padded_nx points, rows padded_nx (real) and
          // spectrum_nx (complex) apart
          d.forward  = fftw_plan_many_dft_r2c(1, &d.padded_nx, grid.ny, real, nullptr, 1, d.padded_nx, spectrum,
                                              nullptr, 1, d.spectrum_nx, FFTW_ESTIMATE);
          d.backward = fftw_plan_many_dft_c2r(1, &d.padded_nx, grid.ny, planning.result_spectrum.get(), nullptr,
                                              1, d.spectrum_nx, real, nullptr, 1, d.padded_nx, FFTW_ESTIMATE);
          // Executing a plan on other arrays needs them aligned as the
          // planning ones (fftw_alignment_of): the second part's first rows.
          const int  split   = grid.ny / 2;
          const auto aligned = [](double *pointer, double *planned) {
            return fftw_alignment_of(pointer) == fftw_alignment_of(planned);
          };
          const auto complex_row = [&](fftw_complex *rows, int r) {
            return reinterpret_cast<double *>(rows + static_cast<std::size_t>(r) * d.spectrum_nx);
          };
          if (split >= 1 && aligned(real + static_cast<std::size_t>(split) * d.padded_nx, real) &&
              aligned(complex_row(spectrum, split), complex_row(spectrum, 0)) &&
              aligned(complex_row(planning.result_spectrum.get(), split),
                      complex_row(planning.result_spectrum.get(), 0)))
            {
              d.split_row      = split;
              d.parallel_parts = static_cast<long>(grid.nx) * grid.ny * grid.ny >= parallel_row_work;
              for (int part = 0; part < 2; ++part)
                {
                  const int count     = part == 0 ? split : grid.ny - split;
                  d.part_forward[part] = fftw_plan_many_dft_r2c(1, &d.padded_nx, count, real, nullptr, 1, d.padded_nx,
                                                                spectrum, nullptr, 1, d.spectrum_nx, FFTW_ESTIMATE);
                  d.part_backward[part] =
                    fftw_plan_many_dft_c2r(1, &d.padded_nx, count, planning.result_spectrum.get(), nullptr, 1,
                                           d.spectrum_nx, real, nullptr, 1, d.padded_nx, FFTW_ESTIMATE);
                  if (!d.part_forward[part] || !d.part_backward[part])
                    throw std::runtime_error("SurfaceConvolution: FFTW could not create the plans");
                }
            }
        }
      else
        { // FFTW's row-major n0 x n1 with n1 fastest is our [2ny][padded_nx].
          d.forward  = fftw_plan_dft_r2c_2d(d.padded_ny, d.padded_nx, real, spectrum, FFTW_ESTIMATE);
          d.backward = fftw_plan_dft_c2r_2d(d.padded_ny, d.padded_nx, spectrum, real, FFTW_ESTIMATE);
        }
    }
    if (!d.forward || !d.backward)
      throw std::runtime_error("SurfaceConvolution: FFTW could not create the plans");

    // Wrap-around order (Liu, Wang & Liu 2000): offsets 0..n-1 at 0..n-1,
    // offsets -(n-1)..-1 at n+1..2n-1, and index n (no offset reaches it) 0.
    auto wrap = [](int offset, int padded) { return offset >= 0 ? offset : padded + offset; };
    const double normalisation = 1.0 / static_cast<double>(d.direct_rows ? d.padded_nx : d.padded_size());
    const auto   transformed   = [&](std::size_t first, std::size_t count) {
      const auto *values = reinterpret_cast<const std::complex<double> *>(spectrum) + first;
      for (std::size_t n = 0; n < count; ++n)
        d.kernel_spectrum.push_back(values[n] * normalisation);
    };
    if (d.direct_rows)
      { // the kernel rows, ny at a time through the same plan
        for (int first = 0; first < d.kernel_rows; first += grid.ny)
          {
            std::fill(real, real + d.padded_size(), 0.0);
            const int count = std::min(grid.ny, d.kernel_rows - first);
            for (int r = 0; r < count; ++r)
              for (int di = -(grid.nx - 1); di <= grid.nx - 1; ++di)
                real[static_cast<std::size_t>(r) * d.padded_nx + wrap(di, d.padded_nx)] = d.kernel(di, first + r);
            fftw_execute_dft_r2c(d.forward, real, spectrum);
            transformed(0, static_cast<std::size_t>(count) * d.spectrum_nx);
          }
        // Even in x to round-off: drop the imaginary parts' rounding noise
        // and halve the products.
        double largest = 0.0, largest_imaginary = 0.0;
        for (const auto &value : d.kernel_spectrum)
          {
            largest           = std::max(largest, std::abs(value));
            largest_imaginary = std::max(largest_imaginary, std::abs(value.imag()));
          }
        d.real_rows = largest_imaginary <= 1e-13 * largest;
        if (d.real_rows)
          {
            for (const auto &value : d.kernel_spectrum)
              d.real_row_spectrum.push_back(value.real());
            d.kernel_spectrum = {};
          }
      }
    else
      {
        std::fill(real, real + d.padded_size(), 0.0);
        for (int dj = -(grid.ny - 1); dj <= grid.ny - 1; ++dj)
          for (int di = -(grid.nx - 1); di <= grid.nx - 1; ++di)
            real[static_cast<std::size_t>(wrap(dj, d.padded_ny)) * d.padded_nx + wrap(di, d.padded_nx)] =
              d.kernel(di, dj + grid.ny - 1);
        fftw_execute_dft_r2c(d.forward, real, spectrum);
        transformed(0, d.spectrum_size());
      }
  }

  void SurfaceConvolution::Impl::setup_single() const
  {
    if (real_rows)
      single_spectrum.assign(real_row_spectrum.begin(), real_row_spectrum.end());
    else
      for (const auto &value : kernel_spectrum)
        {
          single_spectrum.push_back(static_cast<float>(value.real()));
          single_spectrum.push_back(static_cast<float>(value.imag()));
        }
    SingleWorkspace             planning = allocate_single_workspace();
    std::lock_guard<std::mutex> lock(detail::fftw_planner_mutex());
    fftwf_forget_wisdom(); // as for the double plans: the same plan whatever was planned before
    if (direct_rows)
      {
        single_forward  = fftwf_plan_many_dft_r2c(1, &padded_nx, grid.ny, planning.real.get(), nullptr, 1, padded_nx,
                                                  planning.spectrum.get(), nullptr, 1, spectrum_nx, FFTW_ESTIMATE);
        single_backward = fftwf_plan_many_dft_c2r(1, &padded_nx, grid.ny, planning.result_spectrum.get(), nullptr, 1,
                                                  spectrum_nx, planning.real.get(), nullptr, 1, padded_nx, FFTW_ESTIMATE);
        // The double's parts, if the second part's rows are aligned as
        // FFTW planned the first's in float too.
        const auto aligned = [](float *pointer, float *planned) {
          return fftwf_alignment_of(pointer) == fftwf_alignment_of(planned);
        };
        const auto complex_row = [&](fftwf_complex *rows, int r) {
          return reinterpret_cast<float *>(rows + static_cast<std::size_t>(r) * spectrum_nx);
        };
        float *real = planning.real.get();
        if (split_row > 0 && aligned(real + static_cast<std::size_t>(split_row) * padded_nx, real) &&
            aligned(complex_row(planning.spectrum.get(), split_row), complex_row(planning.spectrum.get(), 0)) &&
            aligned(complex_row(planning.result_spectrum.get(), split_row),
                    complex_row(planning.result_spectrum.get(), 0)))
          {
            for (int part = 0; part < 2; ++part)
              {
                const int count = part == 0 ? split_row : grid.ny - split_row;
                single_part_forward[part] =
                  fftwf_plan_many_dft_r2c(1, &padded_nx, count, real, nullptr, 1, padded_nx, planning.spectrum.get(),
                                          nullptr, 1, spectrum_nx, FFTW_ESTIMATE);
                single_part_backward[part] =
                  fftwf_plan_many_dft_c2r(1, &padded_nx, count, planning.result_spectrum.get(), nullptr, 1,
                                          spectrum_nx, real, nullptr, 1, padded_nx, FFTW_ESTIMATE);
                if (!single_part_forward[part] || !single_part_backward[part])
                  throw std::runtime_error("SurfaceConvolution: FFTW could not create the single precision plans");
              }
            single_split = true;
          }
      }
    else
      {
        single_forward  = fftwf_plan_dft_r2c_2d(padded_ny, padded_nx, planning.real.get(), planning.spectrum.get(),
                                                FFTW_ESTIMATE);
        single_backward = fftwf_plan_dft_c2r_2d(padded_ny, padded_nx, planning.result_spectrum.get(),
                                                planning.real.get(), FFTW_ESTIMATE);
      }
    if (!single_forward || !single_backward)
      throw std::runtime_error("SurfaceConvolution: FFTW could not create the single precision plans");
    single_workspaces[0].workspace = std::move(planning);
    shared_workspace               = allocate_single_workspace();
  }

  SurfaceConvolution::~SurfaceConvolution()                                  = default;
  SurfaceConvolution::SurfaceConvolution(SurfaceConvolution &&) noexcept     = default;
  SurfaceConvolution &SurfaceConvolution::operator=(SurfaceConvolution &&) noexcept = default;

  const SurfaceGrid &SurfaceConvolution::grid() const { return impl->grid; }

  namespace
  {
    template <typename Value>
    void check_arguments(const SurfaceGrid &grid, const std::vector<Value> &load, const std::vector<Value> &result)
    {
      if (load.size() != grid.size())
        throw std::invalid_argument("SurfaceConvolution::apply: load size does not match the grid");
      if (&load == &result)
        throw std::invalid_argument("SurfaceConvolution::apply: load and result must be distinct");
    }

    /// `convolve` on the first free work arrays of `slots` (allocated on
    /// first use), or on arrays of its own when all are busy. (FFTW's
    /// execution on new arrays needs the planning arrays' alignment, which
    /// fftw_alloc_* guarantees.)
    template <typename Slots, typename Allocate, typename Convolve>
    void in_free_slot(Slots &slots, const Allocate &allocate, const Convolve &convolve)
    {
      for (auto &slot : slots)
        {
          std::unique_lock<std::mutex> lock(slot.mutex, std::try_to_lock);
          if (!lock.owns_lock())
            continue;
          if (!slot.workspace.real)
            slot.workspace = allocate();
          convolve(slot.workspace);
          return;
        }
      convolve(allocate());
    }
  } // namespace

  void SurfaceConvolution::apply(const Field &load, Field &result) const
  {
    const Impl &d = *impl;
    check_arguments(d.grid, load, result);
    in_free_slot(
      d.workspaces, [&] { return d.allocate_workspace(); },
      [&](const Impl::Workspace &w) { d.convolve(load, result, w); });
  }

  void SurfaceConvolution::apply(const std::vector<float> &load, std::vector<float> &result) const
  {
    const Impl &d = *impl;
    check_arguments(d.grid, load, result);
    std::call_once(d.single_ready, [&d] { d.setup_single(); });
    in_free_slot(
      d.single_workspaces, [&] { return d.allocate_single_workspace(); },
      [&](const Impl::SingleWorkspace &w) { d.convolve_single(load, result, w); });
  }

  void SurfaceConvolution::apply_shared(const std::vector<float> &load, std::vector<float> &result, int part,
                                        const std::function<void()> &wait) const
  {
    const Impl &d = *impl;
    check_arguments(d.grid, load, result);
    if (result.size() != d.grid.size() || (part != 0 && part != 1))
      throw std::invalid_argument("SurfaceConvolution::apply_shared: result not sized to the grid, or part not 0 or 1");
    std::call_once(d.single_ready, [&d] { d.setup_single(); });
    if (!d.single_split)
      { // one part: the first thread applies it whole
        wait();
        if (part == 0)
          d.convolve_single(load, result, d.shared_workspace);
        wait();
        return;
      }
    d.forward_single_part(load, d.shared_workspace, part);
    wait(); // every row's transform, before the sums over rows
    d.backward_single_part(result, d.shared_workspace, part);
  }

  int SurfaceConvolution::shared_split_row() const
  {
    const Impl &d = *impl;
    std::call_once(d.single_ready, [&d] { d.setup_single(); });
    return d.single_split ? d.split_row : 0;
  }

  SurfaceConvolution SurfaceConvolution::inverse(double shift) const
  {
    const Impl &d = *impl;
    if (!d.direct_rows || d.padded_nx != d.grid.nx)
      throw std::logic_error("SurfaceConvolution::inverse: only for a convolution closed in x, by rows");
    const int nx = d.grid.nx, ny = d.grid.ny, frequencies = d.spectrum_nx;
    // K's spectrum as applied (the stored spectra carry FFTW's 1/nx).
    const auto spectrum = [&](int row, int k) -> std::complex<double> {
      const std::size_t at = static_cast<std::size_t>(row) * frequencies + k;
      return static_cast<double>(nx) * (d.real_rows ? std::complex<double>(d.real_row_spectrum[at], 0.0)
                                                     : d.kernel_spectrum[at]);
    };
    // The inverse's spectrum per frequency, [pair][frequency].
    std::vector<std::complex<double>> inverse_spectrum(static_cast<std::size_t>(ny) * ny * frequencies);
    Eigen::MatrixXcd                  block(ny, ny);
    for (int k = 0; k < frequencies; ++k)
      {
        for (int j = 0; j < ny; ++j)
          for (int jj = 0; jj < ny; ++jj)
            block(j, jj) = spectrum(d.pair(j, jj), k) + (j == jj ? shift : 0.0);
        const Eigen::FullPivLU<Eigen::MatrixXcd> lu(block);
        if (!lu.isInvertible())
          throw std::runtime_error("SurfaceConvolution::inverse: a frequency's block is singular");
        const Eigen::MatrixXcd inverse = lu.inverse();
        for (int j = 0; j < ny; ++j)
          for (int jj = 0; jj < ny; ++jj)
            inverse_spectrum[(static_cast<std::size_t>(j) * ny + jj) * frequencies + k] = inverse(j, jj);
      }
    // Back to offsets: the real signal of a half spectrum (X[nx - k] =
    // conj X[k]), x[n] = (1/nx) Σ_k X[k] e^{2πikn/nx}.
    std::vector<double> table(static_cast<std::size_t>(ny) * ny * nx);
    for (std::size_t pair = 0; pair < static_cast<std::size_t>(ny) * ny; ++pair)
      for (int n = 0; n < nx; ++n)
        {
          double sum = 0.0;
          for (int k = 0; k < frequencies; ++k)
            {
              const bool   mirrored = k > 0 && 2 * k != nx; // its conjugate at nx - k is not stored
              const double phase    = 2.0 * M_PI * static_cast<double>((static_cast<long>(k) * n) % nx) / nx;
              const auto  &value    = inverse_spectrum[pair * frequencies + k];
              sum += (mirrored ? 2.0 : 1.0) * (value.real() * std::cos(phase) - value.imag() * std::sin(phase));
            }
          table[pair * nx + n] = sum / nx;
        }
    return SurfaceConvolution(d.grid, RowPairInfluenceFunction([nx, ny, table = std::move(table)](int di, int j, int jj) {
                                const int wrapped = ((di % nx) + nx) % nx;
                                return table[(static_cast<std::size_t>(j) * ny + jj) * nx + wrapped];
                              }));
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
              const double *kernel_row = &d.kernel_table[static_cast<std::size_t>(d.pair(j, jj)) * d.table_nx];
              const double *load_row   = &load[d.grid.index(0, jj)];
              for (int ii = 0; ii < nx; ++ii)
                sum += kernel_row[i - ii + nx - 1] * load_row[ii];
            }
          result[d.grid.index(i, j)] = sum;
        }
  }
} // namespace fretsim::contact
