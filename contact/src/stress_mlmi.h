#pragma once
// Private: the MLMI subsurface-stress evaluator (Brandt & Lubrecht 1990;
// Venner & Lubrecht 2000), built by make_subsurface_stress for method "mlmi".
#include <fretsim/contact/subsurface_stress.h>

#include <memory>
#include <vector>

namespace fretsim::contact
{
  /// All 6 components × 3 loads × n_layers rectangle kernels in one
  /// MultilevelSummation: the loads are anterpolated once per call and shared
  /// by every kernel. Throws std::invalid_argument for bad MLMI settings
  /// (order, levels too deep for the grid).
  std::unique_ptr<SubsurfaceStress> make_mlmi_stress(const SurfaceGrid &grid, const std::vector<double> &depths,
                                                     double poisson_ratio, const StressEvaluatorSettings &settings);

  namespace detail
  {
    /// Correction half-width of a layer at depth z: the automatic or
    /// requested base width, widened for shallow layers (see stress_mlmi.cpp).
    int mlmi_layer_correction_width(double depth, double cell_size, int interpolation_order, int base_width);
  } // namespace detail
} // namespace fretsim::contact
