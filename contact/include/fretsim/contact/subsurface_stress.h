#pragma once
// Subsurface stresses of piecewise-constant surface loads on a SurfaceGrid
// (docs/theory.md §2.5): superposition of the closed-form uniform-rectangle kernels
// (rectangle_kernels.h) with three interchangeable evaluators:
//   "direct" O(N^2) summation per layer, the reference;
//   "mlmi"   multilevel multi-integration (Brandt & Lubrecht 1990);
//   "fft"    DC-FFT (Liu, Wang & Liu 2000), exact to round-off against direct.
#include <fretsim/contact/rectangle_kernels.h>
#include <fretsim/contact/surface_grid.h>

#include <memory>
#include <string>
#include <vector>

namespace fretsim::contact
{
  /// sigma[layer][component][j][i] in Pa for the cell-centred field points on
  /// the depth layers; components in Voigt order (StressComponent), tension
  /// positive, in the body whose surface carries the grid (docs/theory.md §6).
  struct StressField
  {
    int                 n_layers = 0, ny = 0, nx = 0;
    std::vector<double> values;

    void resize(int layers, int rows, int columns);
    std::size_t index(int layer, int component, int j, int i) const
    {
      return ((static_cast<std::size_t>(layer) * stress_component_count + component) * ny + j) * nx + i;
    }
    double &at(int layer, int component, int j, int i) { return values[index(layer, component, j, i)]; }
    double  at(int layer, int component, int j, int i) const { return values[index(layer, component, j, i)]; }
    /// The six components at one point.
    StressTensor tensor(int layer, int j, int i) const;
  };

  struct StressEvaluatorSettings
  {
    std::string method = "fft"; ///< direct | mlmi | fft
    int mlmi_levels = 0;        ///< coarse levels; 0 = automatic
    int mlmi_order  = 6;        ///< interpolation order
    int mlmi_correction_width = 0; ///< local correction half-width; 0 = automatic
    /// fft: FFTW_MEASURE plans (faster transforms after ~0.1-1 s of planning);
    /// false: FFTW_ESTIMATE, whose results do not depend on timing, so that
    /// separate processes give identical values.
    bool measure_fft_plans = true;
  };

  /// stresses(p, qx, qy) -> sigma on the depth layers. Loads are piecewise
  /// constant per cell [Pa]: pressure positive in compression, shear_x/shear_y
  /// the traction the counter-body exerts on the surface. Implementations keep
  /// their kernels and plans across calls (they are called every time step).
  class SubsurfaceStress
  {
  public:
    virtual ~SubsurfaceStress() = default;
    /// Resizes `stress` to [n_layers][6][ny][nx] and fills it. Throws
    /// std::invalid_argument if a load does not match the grid.
    virtual void        evaluate(const Field &pressure, const Field &shear_x, const Field &shear_y,
                                 StressField &stress) const = 0;
    virtual std::string name() const = 0;
  };

  namespace detail
  {
    /// The DC-FFT evaluator (stress_fft.cpp); arguments already validated.
    /// Kernel spectra of as many layers as fit the budget are cached, the
    /// others recomputed on every call.
    std::unique_ptr<SubsurfaceStress> make_fft_stress(const SurfaceGrid &grid, const std::vector<double> &depths,
                                                      double poisson_ratio,
                                                      std::size_t spectrum_budget_bytes = std::size_t(512) << 20,
                                                      bool        measure_plans         = true);
    /// Throws std::invalid_argument unless every load has one value per cell.
    void check_stress_loads(const SurfaceGrid &grid, const Field &pressure, const Field &shear_x,
                            const Field &shear_y);
    /// True if every value is exactly zero (such a load can be skipped exactly).
    bool is_zero(const Field &field);
  } // namespace detail

  /// Throws std::invalid_argument with a clear message for bad settings
  /// (unknown method, negative depth, no layers, bad grid or Poisson's ratio,
  /// MLMI levels too deep for the grid).
  std::unique_ptr<SubsurfaceStress> make_subsurface_stress(const SurfaceGrid &grid, const std::vector<double> &depths,
                                                           double poisson_ratio,
                                                           const StressEvaluatorSettings &settings);
} // namespace fretsim::contact
