// DC-FFT subsurface-stress evaluator (Liu, Wang & Liu, Wear 243, 2000;
// docs/references.md §6.2): linear convolution of the cell kernels with the
// three loads by zero padding to 2nx x 2ny, kernels in wrap-around order.
//
// Per call: 3 forward r2c transforms (p, qx, qy), then for every layer and
// component the three spectral products are summed and ONE inverse c2r
// transform gives that component: 3 + 6 nz transforms. The 2-D transforms are
// done as row and column passes so that the zero rows of the padded load are
// never transformed and only the ny output rows that are kept are
// back-transformed: each transform costs ~3/4 of a full 2nx x 2ny one.
//
// Kernel spectra, memory: per layer 18 (load, component) kernels, of which 15
// are distinct (reciprocity: sigma_zz from qx = sigma_xz from p, sigma_zz from
// qy = sigma_yz from p, sigma_xz from qy = sigma_yz from qx). Each kernel is
// even or odd in x and in y, so its spectrum is purely real or purely
// imaginary and even or odd in ky: one real quarter, (ny+1) x (nx+1) values,
// stores it exactly. 15 nz (nx+1)(ny+1) doubles in all: 253 MB at 512^2 with
// 8 layers. Layers whose spectra do not fit the cache budget (default
// 512 MiB: 16 layers at 512^2) are recomputed on every call (same result,
// slower), so memory stays bounded.
#include "column_transform.h"
#include "fftw_planner.h"

#include <fretsim/contact/subsurface_stress.h>

#include <fftw3.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <mutex>
#include <stdexcept>

namespace fretsim::contact
{
  namespace
  {
    constexpr int         distinct_kernels      = 15;

    /// (load, component) -> index of its distinct kernel.
    struct KernelMap
    {
      int index[3][stress_component_count];
      int load_of[distinct_kernels], component_of[distinct_kernels];

      KernelMap()
      {
        int next = 0;
        for (int l = 0; l < 3; ++l)
          for (int c = 0; c < stress_component_count; ++c)
            {
              if (l == 1 && c == zz)
                index[l][c] = index[0][xz];
              else if (l == 2 && c == zz)
                index[l][c] = index[0][yz];
              else if (l == 2 && c == xz)
                index[l][c] = index[1][yz];
              else
                {
                  load_of[next]      = l;
                  component_of[next] = c;
                  index[l][c]        = next++;
                }
            }
      }
    };
    const KernelMap kernel_map;

    template <typename T>
    struct FftwArray
    {
      T          *data = nullptr;
      std::size_t size = 0;
      FftwArray() = default;
      explicit FftwArray(std::size_t n) : data(static_cast<T *>(fftw_malloc(n * sizeof(T)))), size(n)
      {
        if (!data)
          throw std::bad_alloc();
        std::memset(static_cast<void *>(data), 0, n * sizeof(T));
      }
      FftwArray(FftwArray &&o) noexcept : data(o.data), size(o.size) { o.data = nullptr; }
      FftwArray &operator=(FftwArray &&o) noexcept
      {
        std::swap(data, o.data);
        std::swap(size, o.size);
        return *this;
      }
      ~FftwArray() { fftw_free(data); }
    };

    class FftStress final : public SubsurfaceStress
    {
    public:
      FftStress(const SurfaceGrid &grid, const std::vector<double> &depths, double poisson_ratio,
                std::size_t spectrum_budget_bytes, bool measure_plans)
        : grid(grid), depths(depths), poisson_ratio(poisson_ratio), mx(2 * grid.nx), my(2 * grid.ny),
          cx(grid.nx + 1), quarter(static_cast<std::size_t>(grid.ny + 1) * cx)
      {
        const std::size_t real_size = static_cast<std::size_t>(mx) * my, complex_size = static_cast<std::size_t>(my) * cx;
        const std::size_t half_real_size = static_cast<std::size_t>(mx) * grid.ny;
        {
          FftwArray<double>       real(real_size);
          FftwArray<fftw_complex> spectrum(complex_size);
          // FFTW_MEASURE overwrites the arrays while planning: they are scratch.
          std::lock_guard<std::mutex> lock(detail::fftw_planner_mutex());
          const int      ny    = grid.ny;
          const unsigned flags = measure_plans ? FFTW_MEASURE : FFTW_ESTIMATE;
          if (!measure_plans)
            detail::forget_planner_history();
          kernel_forward = fftw_plan_dft_r2c_2d(my, mx, real.data, spectrum.data, flags);
          // ny rows of length mx -> ny rows of cx (the other my - ny rows are zero) ...
          rows_forward = fftw_plan_many_dft_r2c(1, &mx, ny, real.data, nullptr, 1, mx, spectrum.data, nullptr, 1, cx,
                                                flags);
          // ... then cx columns of length my, in place (columns, below).
          // Only rows 0..ny-1 of the result are kept.
          rows_inverse = fftw_plan_many_dft_c2r(1, &mx, ny, spectrum.data, nullptr, 1, cx, real.data, nullptr, 1, mx,
                                                flags);
        }
        if (!kernel_forward || !rows_forward || !rows_inverse)
          {
            destroy_plans();
            throw std::runtime_error("DC-FFT stress: FFTW could not plan the transforms");
          }
        {
          FftwArray<fftw_complex> spectrum(complex_size);
          columns = std::make_unique<detail::ColumnTransform>(my, cx, 1, 0, spectrum.data, measure_plans);
        }

        const std::size_t per_layer = distinct_kernels * quarter;
        cached_layers = static_cast<int>(std::min<std::size_t>(depths.size(), spectrum_budget_bytes / (per_layer * sizeof(double))));
        cached_spectra.resize(static_cast<std::size_t>(cached_layers) * per_layer);
        for (int layer = 0; layer < cached_layers; ++layer)
          compute_layer_spectra(layer, cached_spectra.data() + layer * per_layer);
        for (int l = 0; l < 3; ++l)
          {
            padded_load[l] = FftwArray<double>(half_real_size);
            load_spectrum[l] = FftwArray<fftw_complex>(complex_size);
          }
      }

      ~FftStress() override { destroy_plans(); }

      std::string name() const override { return "fft"; }

      void evaluate(const Field &pressure, const Field &shear_x, const Field &shear_y,
                    StressField &stress) const override
      {
        detail::check_stress_loads(grid, pressure, shear_x, shear_y);
        std::lock_guard<std::mutex> lock(evaluate_mutex); // work buffers are shared state
        const int nx = grid.nx, ny = grid.ny, n_layers = static_cast<int>(depths.size());
        stress.resize(n_layers, ny, nx);

        const Field *loads[3] = {&pressure, &shear_x, &shear_y};
        int          active[3], n_active = 0;
        for (int l = 0; l < 3; ++l)
          if (!detail::is_zero(*loads[l])) // a zero load adds nothing: skipping is exact
            active[n_active++] = l;
        if (n_active == 0)
          return;

        const int threads = omp_get_max_threads();
        while (static_cast<int>(work_spectrum.size()) < threads)
          {
            work_spectrum.emplace_back(static_cast<std::size_t>(my) * cx);
            work_real.emplace_back(static_cast<std::size_t>(mx) * ny);
          }

#pragma omp parallel for schedule(static)
        for (int a = 0; a < n_active; ++a)
          {
            const int l = active[a];
            double   *in = padded_load[l].data;
            for (int j = 0; j < ny; ++j)
              std::copy_n(loads[l]->data() + static_cast<std::size_t>(j) * nx, nx, in + static_cast<std::size_t>(j) * mx);
            fftw_complex *spectrum = load_spectrum[l].data;
            fftw_execute_dft_r2c(rows_forward, in, spectrum);
            std::fill_n(&spectrum[static_cast<std::size_t>(ny) * cx][0], 2 * static_cast<std::size_t>(my - ny) * cx, 0.0);
            columns->forward(spectrum);
          }

        const std::size_t per_layer = distinct_kernels * quarter;
        // Cached layers: every (layer, component) is an independent task.
        if (cached_layers > 0)
          {
#pragma omp parallel for schedule(dynamic, 1)
            for (int task = 0; task < cached_layers * stress_component_count; ++task)
              {
                const int layer = task / stress_component_count, c = task % stress_component_count;
                component(cached_spectra.data() + layer * per_layer, layer, c, active, n_active, stress);
              }
          }
        // Layers beyond the memory budget: spectra recomputed into scratch.
        if (cached_layers < n_layers)
          {
            if (scratch_spectra.size() < per_layer)
              scratch_spectra.resize(per_layer);
            for (int layer = cached_layers; layer < n_layers; ++layer)
              {
                compute_layer_spectra(layer, scratch_spectra.data());
#pragma omp parallel for schedule(dynamic, 1)
                for (int c = 0; c < stress_component_count; ++c)
                  component(scratch_spectra.data(), layer, c, active, n_active, stress);
              }
          }
      }

    private:
      void destroy_plans()
      {
        std::lock_guard<std::mutex> lock(detail::fftw_planner_mutex());
        for (fftw_plan *plan : {&kernel_forward, &rows_forward, &rows_inverse})
          if (*plan)
            {
              fftw_destroy_plan(*plan);
              *plan = nullptr;
            }
      }

      /// Sum of the spectral products of the active loads with the kernels of
      /// component c, one inverse transform, the first ny x nx values kept.
      void component(const double *spectra, int layer, int c, const int *active, int n_active,
                     StressField &stress) const
      {
        const int     thread = omp_get_thread_num();
        fftw_complex *sum    = work_spectrum[thread].data;
        double       *real   = work_real[thread].data;
        // Each kernel spectrum is s K with K real and s one of +-1, +-i (its
        // parity type and the mirror sign of rows ky > my/2).
        const double *kernel[3];
        const fftw_complex *load[3];
        double              sign_real[3], sign_imag[3], mirror_sign[3];
        for (int a = 0; a < n_active; ++a)
          {
            const int l    = active[a];
            kernel[a]      = spectra + kernel_map.index[l][c] * quarter;
            load[a]        = load_spectrum[l].data;
            const bool imaginary = detail::kernel_parity_x(l, c) * detail::kernel_parity_y(l, c) < 0;
            sign_real[a]   = imaginary ? 0.0 : 1.0;
            sign_imag[a]   = imaginary ? 1.0 : 0.0;
            mirror_sign[a] = detail::kernel_parity_y(l, c);
          }
        switch (n_active)
          {
            case 1: spectral_sum<1>(kernel, load, sign_real, sign_imag, mirror_sign, sum); break;
            case 2: spectral_sum<2>(kernel, load, sign_real, sign_imag, mirror_sign, sum); break;
            default: spectral_sum<3>(kernel, load, sign_real, sign_imag, mirror_sign, sum); break;
          }
        columns->inverse(sum);
        fftw_execute_dft_c2r(rows_inverse, sum, real);
        const int nx = grid.nx, ny = grid.ny;
        for (int j = 0; j < ny; ++j)
          std::copy_n(real + static_cast<std::size_t>(j) * mx, nx, &stress.at(layer, c, j, 0));
      }

      /// sum = sum over the N loads of (kernel spectrum) x (load spectrum), in
      /// one pass so the accumulator is written once (memory bound).
      template <int N>
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
      __attribute__((target_clones("avx2", "default")))
#endif
      void spectral_sum(const double *const *kernel, const fftw_complex *const *load, const double *sign_real,
                        const double *sign_imag, const double *mirror_sign, fftw_complex *sum) const
      {
        for (int r = 0; r < my; ++r)
          {
            // Row r of the spectra holds frequency ky (ColumnTransform's
            // order); ky > my/2 is the stored row my - ky times the y parity.
            const int         ky       = columns->frequency_of_row(r);
            const bool        mirrored = ky > my / 2;
            const std::size_t row      = static_cast<std::size_t>(mirrored ? my - ky : ky) * cx;
            const double     *k[N];
            const double     *in[N];
            double            cr[N], ci[N];
            for (int a = 0; a < N; ++a)
              {
                k[a]            = kernel[a] + row;
                in[a]           = &load[a][static_cast<std::size_t>(r) * cx][0];
                const double sg = mirrored ? mirror_sign[a] : 1.0;
                cr[a]           = sg * sign_real[a];
                ci[a]           = sg * sign_imag[a];
              }
            double *out = &sum[static_cast<std::size_t>(r) * cx][0];
            for (int kx = 0; kx < cx; ++kx)
              {
                double re = 0.0, im = 0.0;
                for (int a = 0; a < N; ++a)
                  {
                    const double lr = in[a][2 * kx], li = in[a][2 * kx + 1], kv = k[a][kx];
                    re += kv * (cr[a] * lr - ci[a] * li);
                    im += kv * (cr[a] * li + ci[a] * lr);
                  }
                out[2 * kx]     = re;
                out[2 * kx + 1] = im;
              }
          }
      }

      /// The 15 distinct kernel spectra of one layer as real quarters, scaled
      /// by 1/(mx my) so that the unnormalised inverse transform is exact.
      void compute_layer_spectra(int layer, double *out) const
      {
        const int nx = grid.nx, ny = grid.ny;
        const detail::CellKernelTable table =
          detail::cell_kernel_table(nx, ny, grid.hx, grid.hy, depths[layer], poisson_ratio);
        const double scale = 1.0 / (static_cast<double>(mx) * my);
#pragma omp parallel
        {
          FftwArray<double>       padded(static_cast<std::size_t>(mx) * my);
          FftwArray<fftw_complex> spectrum(static_cast<std::size_t>(my) * cx);
#pragma omp for schedule(dynamic, 1)
          for (int u = 0; u < distinct_kernels; ++u)
            {
              const int l = kernel_map.load_of[u], c = kernel_map.component_of[u];
              const int px = detail::kernel_parity_x(l, c), py = detail::kernel_parity_y(l, c);
              // Wrap-around order: index d >= 0 holds offset d, index m - d
              // offset -d; index n (offset +-n) stays 0, which keeps the
              // padded kernel exactly even or odd.
              for (int dj = 0; dj < ny; ++dj)
                {
                  const double *row = table.row(l, c, dj);
                  for (int sy = 0; sy < (dj == 0 ? 1 : 2); ++sy)
                    {
                      const int    jy  = sy == 0 ? dj : my - dj;
                      const double fy  = sy == 0 ? 1.0 : py;
                      double      *dst = padded.data + static_cast<std::size_t>(jy) * mx;
                      dst[0]           = fy * row[0];
                      for (int di = 1; di < nx; ++di)
                        {
                          dst[di]      = fy * row[di];
                          dst[mx - di] = fy * px * row[di];
                        }
                    }
                }
              fftw_execute_dft_r2c(kernel_forward, padded.data, spectrum.data);
              const bool imaginary = px * py < 0;
              double    *dst       = out + u * quarter;
              for (int ky = 0; ky <= ny; ++ky)
                for (int kx = 0; kx < cx; ++kx)
                  dst[static_cast<std::size_t>(ky) * cx + kx] =
                    scale * spectrum.data[static_cast<std::size_t>(ky) * cx + kx][imaginary ? 1 : 0];
            }
        }
      }

      SurfaceGrid         grid;
      std::vector<double> depths;
      double              poisson_ratio;
      int                 mx, my, cx; ///< padded sizes and r2c width mx/2 + 1
      std::size_t         quarter;    ///< (my/2 + 1) * cx reals per kernel spectrum
      fftw_plan           kernel_forward = nullptr; ///< full 2-D r2c, for the kernel spectra
      fftw_plan           rows_forward = nullptr, rows_inverse = nullptr;
      /// The column passes, two short transforms each (column_transform.h).
      std::unique_ptr<detail::ColumnTransform> columns;
      int                 cached_layers = 0;
      std::vector<double> cached_spectra;

      mutable std::mutex                           evaluate_mutex;
      mutable FftwArray<double>                    padded_load[3];
      mutable FftwArray<fftw_complex>              load_spectrum[3];
      mutable std::vector<FftwArray<fftw_complex>> work_spectrum;
      mutable std::vector<FftwArray<double>>       work_real;
      mutable std::vector<double>                  scratch_spectra;
    };
  } // namespace

  namespace detail
  {
    std::unique_ptr<SubsurfaceStress> make_fft_stress(const SurfaceGrid &grid, const std::vector<double> &depths,
                                                      double poisson_ratio, std::size_t spectrum_budget_bytes,
                                                      bool measure_plans)
    {
      return std::make_unique<FftStress>(grid, depths, poisson_ratio, spectrum_budget_bytes, measure_plans);
    }
  } // namespace detail
} // namespace fretsim::contact
