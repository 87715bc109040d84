// Subsurface-stress interface, factory and the direct-summation evaluator.
#include <fretsim/contact/subsurface_stress.h>

#include "stress_mlmi.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace fretsim::contact
{
  void StressField::resize(int layers, int rows, int columns)
  {
    n_layers = layers;
    ny       = rows;
    nx       = columns;
    values.assign(static_cast<std::size_t>(layers) * stress_component_count * rows * columns, 0.0);
  }

  StressTensor StressField::tensor(int layer, int j, int i) const
  {
    StressTensor s;
    for (int c = 0; c < stress_component_count; ++c)
      s[c] = at(layer, c, j, i);
    return s;
  }

  namespace detail
  {
    void check_stress_loads(const SurfaceGrid &grid, const Field &pressure, const Field &shear_x,
                            const Field &shear_y)
    {
      const std::size_t n = grid.size();
      if (pressure.size() != n || shear_x.size() != n || shear_y.size() != n)
        {
          std::ostringstream message;
          message << "subsurface stress: loads must have one value per grid cell (" << grid.nx << " x " << grid.ny
                  << " = " << n << "); got pressure " << pressure.size() << ", shear_x " << shear_x.size()
                  << ", shear_y " << shear_y.size();
          throw std::invalid_argument(message.str());
        }
    }

    bool is_zero(const Field &field)
    {
      for (const double v : field)
        if (v != 0.0)
          return false;
      return true;
    }
  } // namespace detail

  namespace
  {
    /// O(N^2) summation per layer and component: the reference. The kernels
    /// depend only on the cell offset, so one quadrant table per layer holds
    /// them all (parity gives the other quadrants), 18 nx ny values per layer.
    class DirectStress final : public SubsurfaceStress
    {
    public:
      DirectStress(const SurfaceGrid &grid, const std::vector<double> &depths, double poisson_ratio)
        : grid(grid)
      {
        for (const double z : depths)
          tables.push_back(detail::cell_kernel_table(grid.nx, grid.ny, grid.hx, grid.hy, z, poisson_ratio));
      }

      std::string name() const override { return "direct"; }

      void evaluate(const Field &pressure, const Field &shear_x, const Field &shear_y,
                    StressField &stress) const override
      {
        detail::check_stress_loads(grid, pressure, shear_x, shear_y);
        const int nx = grid.nx, ny = grid.ny, n_layers = static_cast<int>(tables.size());
        stress.resize(n_layers, ny, nx);
        // A load that is zero everywhere (frictionless contact) contributes
        // nothing: skipping it is exact.
        const Field *loads[3] = {&pressure, &shear_x, &shear_y};
        std::vector<int> active;
        for (int l = 0; l < 3; ++l)
          if (!detail::is_zero(*loads[l]))
            active.push_back(l);

        for (int layer = 0; layer < n_layers; ++layer)
          {
            const detail::CellKernelTable &table = tables[layer];
#pragma omp parallel
            {
              // Kernel row for one (load, component, dj), laid out reversed so
              // that out[i] = sum_i' reversed[nx-1-i+i'] load[i'] runs forward:
              // reversed[t] = K(nx-1-t).
              std::vector<double> reversed(2 * static_cast<std::size_t>(nx) - 1);
#pragma omp for schedule(dynamic, 1)
              for (int j = 0; j < ny; ++j)
                for (int c = 0; c < stress_component_count; ++c)
                  {
                    double *out = &stress.at(layer, c, j, 0);
                    for (const int l : active)
                      {
                        const int px = detail::kernel_parity_x(l, c), py = detail::kernel_parity_y(l, c);
                        for (int jl = 0; jl < ny; ++jl)
                          {
                            const int     dj   = j - jl;
                            const double  sy   = dj >= 0 ? 1.0 : py;
                            const double *krow = table.row(l, c, std::abs(dj));
                            for (int t = 0; t < nx; ++t)
                              reversed[t] = sy * krow[nx - 1 - t];
                            for (int t = nx; t < 2 * nx - 1; ++t)
                              reversed[t] = sy * px * krow[t - (nx - 1)];
                            const double *load = loads[l]->data() + static_cast<std::size_t>(jl) * nx;
                            for (int i = 0; i < nx; ++i)
                              {
                                const double *k   = reversed.data() + (nx - 1 - i);
                                double        sum = 0.0;
#pragma omp simd reduction(+ : sum)
                                for (int il = 0; il < nx; ++il)
                                  sum += k[il] * load[il];
                                out[i] += sum;
                              }
                          }
                      }
                  }
            }
          }
      }

    private:
      SurfaceGrid                          grid;
      std::vector<detail::CellKernelTable> tables;
    };

    void validate(const SurfaceGrid &grid, const std::vector<double> &depths, double poisson_ratio)
    {
      if (grid.nx < 1 || grid.ny < 1 || !(grid.hx > 0.0) || !(grid.hy > 0.0) || !std::isfinite(grid.hx) ||
          !std::isfinite(grid.hy))
        throw std::invalid_argument("subsurface stress: the surface grid needs nx, ny >= 1 and positive finite "
                                    "cell sizes");
      if (depths.empty())
        throw std::invalid_argument("subsurface stress: no depth layers given; list at least one depth z >= 0 "
                                    "(z = 0 is the surface)");
      for (std::size_t k = 0; k < depths.size(); ++k)
        if (!(depths[k] >= 0.0) || !std::isfinite(depths[k]))
          {
            std::ostringstream message;
            message << "subsurface stress: depth layer " << k << " is " << depths[k]
                    << " m; depths must be finite and >= 0 (z points into the body)";
            throw std::invalid_argument(message.str());
          }
      if (!(poisson_ratio > -1.0 && poisson_ratio <= 0.5))
        throw std::invalid_argument("subsurface stress: Poisson's ratio must lie in (-1, 0.5]");
    }
  } // namespace

  std::unique_ptr<SubsurfaceStress> make_subsurface_stress(const SurfaceGrid &grid, const std::vector<double> &depths,
                                                           double poisson_ratio,
                                                           const StressEvaluatorSettings &settings)
  {
    validate(grid, depths, poisson_ratio);
    if (settings.method == "direct")
      return std::make_unique<DirectStress>(grid, depths, poisson_ratio);
    if (settings.method == "fft")
      return detail::make_fft_stress(grid, depths, poisson_ratio, std::size_t(512) << 20, settings.measure_fft_plans);
    if (settings.method == "mlmi")
      {
        if (settings.mlmi_levels < 0 || settings.mlmi_order < 1 || settings.mlmi_correction_width < 0)
          throw std::invalid_argument("subsurface stress: MLMI needs levels >= 0 (0 = automatic), order >= 1 and "
                                      "correction width >= 0 (0 = automatic)");
        return make_mlmi_stress(grid, depths, poisson_ratio, settings);
      }
    throw std::invalid_argument("subsurface stress: unknown stress evaluator '" + settings.method +
                                "'; choose direct, mlmi or fft");
  }
} // namespace fretsim::contact
