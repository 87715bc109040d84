#pragma once
// Exact geometry of ring and housing: a chart (s, θ, z) ↦ x of the whole body.
// The radial chart coordinate s runs through the layers (ring wall, housing
// wall), layer k covering s ∈ [k, k+1]; inside a layer the radius varies
// linearly in s between the layer's inner surface (for the ring: the bore
// profile with its circular groove arc, a function of z) and its outer
// cylinder. Because every new vertex and every mapping support point is placed
// through this chart, refinement and MappingQ follow the groove arc and the
// cylinders exactly, which the convergence rates of the FE tests rely on.
#include <fretsim/fem/mesh.h>

#include <deal.II/grid/manifold.h>

#include <vector>

namespace fretsim::fem
{
  class RingChart : public dealii::ChartManifold<3, 3, 3>
  {
  public:
    /// `ring` gives the inner profile of layer 0; `outer_radii[k]` is the
    /// outer radius of layer k. A plain inner surface: ring.groove_radius = 0.
    RingChart(const RingGeometry &ring, std::vector<double> outer_radii);

    std::unique_ptr<dealii::Manifold<3, 3>> clone() const override;

    dealii::Point<3> pull_back(const dealii::Point<3> &x) const override;
    dealii::Point<3> push_forward(const dealii::Point<3> &chart) const override;
    dealii::DerivativeForm<1, 3, 3> push_forward_gradient(const dealii::Point<3> &chart) const override;

    /// Radius of the inner surface of layer 0 at axial position z, and dr/dz.
    double inner_radius(double z) const;
    double inner_radius_slope(double z) const;

    unsigned int n_layers() const { return static_cast<unsigned int>(outer_radii.size()); }

  private:
    RingGeometry        ring;
    std::vector<double> outer_radii;
    double              groove_centre_radius = 0.0;
    double              groove_half_width    = 0.0;
  };
} // namespace fretsim::fem
