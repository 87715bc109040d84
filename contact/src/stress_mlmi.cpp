// MLMI subsurface stresses: the rectangle kernels (rectangle_kernels.h) of all
// layers, components and loads summed by one MultilevelSummation
// (multilevel_summation.h, docs/references.md §6.1).
#include "stress_mlmi.h"

#include <fretsim/contact/multilevel_summation.h>
#include <fretsim/contact/rectangle_kernels.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace fretsim::contact
{
  namespace detail
  {
    // Why shallow layers need the wide window. On level l the injected kernel
    // is 4^l K(2^l d): a kernel whose core (width ~ depth z) is narrower than a
    // level cell turns into a spike at d = 0 of ~4^l times its neighbours
    // (at z = 0, sigma_zz = -p is a pure delta). The interpolated coefficient
    // at offset d draws on kernel values from d - (2p - 2) to d + (2p - 2), so
    // a window narrower than 2p - 2 lets that spike leak out (measured at
    // 64^2, p = 6, m = 6: 7e-2 p0 at z = 0, 6e-4 p0 at z = 0.5a). Layers whose
    // core is narrower than that reach, z < (2p - 2) h, therefore get at least
    // the 2p - 2 window; deeper kernels are smooth enough on the surface grid
    // and keep the requested one. The automatic width is already 2p - 2.
    int mlmi_layer_correction_width(double depth, double cell_size, int interpolation_order, int base_width)
    {
      const int spike_reach = MultilevelSummation::default_correction_width(interpolation_order);
      if (base_width <= 0)
        return spike_reach;
      const bool shallow = depth < (2.0 * interpolation_order - 2.0) * cell_size;
      return shallow ? std::max(base_width, spike_reach) : base_width;
    }
  } // namespace detail

  namespace
  {
    constexpr int n_loads = 3; // pressure, shear x, shear y

    class MlmiStress final : public SubsurfaceStress
    {
    public:
      MlmiStress(const SurfaceGrid &grid, const std::vector<double> &depths, double poisson_ratio,
                 const StressEvaluatorSettings &settings)
        : grid(grid)
        , n_layers(static_cast<int>(depths.size()))
        , summation(make_summation(grid, depths, poisson_ratio, settings))
      {}

      std::string name() const override { return "mlmi"; }

      void evaluate(const Field &pressure, const Field &shear_x, const Field &shear_y,
                    StressField &stress) const override
      {
        detail::check_stress_loads(grid, pressure, shear_x, shear_y);
        stress.resize(n_layers, grid.ny, grid.nx);
        // Output o = layer * 6 + component is exactly the block o of the
        // [layer][6][ny][nx] array, so the sums land in place.
        std::vector<double *> results(static_cast<std::size_t>(n_layers) * stress_component_count);
        for (std::size_t o = 0; o < results.size(); ++o)
          results[o] = stress.values.data() + o * grid.size();
        // A zero load (frictionless contact) is skipped exactly inside.
        summation.apply({pressure.data(), shear_x.data(), shear_y.data()}, results);
      }

      const MultilevelSummation &multilevel() const { return summation; }

    private:
      static MultilevelSummation make_summation(const SurfaceGrid &grid, const std::vector<double> &depths,
                                                double poisson_ratio, const StressEvaluatorSettings &settings)
      {
        MultilevelSettings ml;
        ml.levels              = settings.mlmi_levels;
        ml.interpolation_order = settings.mlmi_order;
        ml.correction_width    = settings.mlmi_correction_width;

        const int           n_outputs = static_cast<int>(depths.size()) * stress_component_count;
        std::vector<int>    widths(n_outputs);
        const double        cell = std::min(grid.hx, grid.hy);
        for (std::size_t layer = 0; layer < depths.size(); ++layer)
          for (int c = 0; c < stress_component_count; ++c)
            widths[layer * stress_component_count + c] = detail::mlmi_layer_correction_width(
              depths[layer], cell, settings.mlmi_order, settings.mlmi_correction_width);

        const double hx = grid.hx, hy = grid.hy;
        // Kernel block at cell offset (di, dj): the stresses of unit loads on
        // one cell at the field-point offset, on every layer; all three loads
        // share the corner functions.
        auto kernels = [depths, poisson_ratio, hx, hy](int di, int dj, double *values) {
          for (std::size_t layer = 0; layer < depths.size(); ++layer)
            {
              const RectangleStresses s =
                rectangle_stresses(di * hx, dj * hy, depths[layer], 0.5 * hx, 0.5 * hy, poisson_ratio);
              const StressTensor *by_load[n_loads] = {&s.pressure, &s.shear_x, &s.shear_y};
              for (int c = 0; c < stress_component_count; ++c)
                for (int l = 0; l < n_loads; ++l)
                  values[(layer * stress_component_count + c) * n_loads + l] = (*by_load[l])[c];
            }
        };
        return MultilevelSummation(grid, n_outputs, n_loads, kernels, ml, widths);
      }

      SurfaceGrid         grid;
      int                 n_layers;
      MultilevelSummation summation;
    };
  } // namespace

  std::unique_ptr<SubsurfaceStress> make_mlmi_stress(const SurfaceGrid &grid, const std::vector<double> &depths,
                                                     double poisson_ratio, const StressEvaluatorSettings &settings)
  {
    return std::make_unique<MlmiStress>(grid, depths, poisson_ratio, settings);
  }
} // namespace fretsim::contact
