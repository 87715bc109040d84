#include "ring_chart.h"

#include <algorithm>
#include <cmath>

namespace fretsim::fem
{
  namespace
  {
    constexpr double two_pi = 2.0 * M_PI;

    dealii::Tensor<1, 3> periodic_in_theta()
    {
      dealii::Tensor<1, 3> periodicity;
      periodicity[1] = two_pi;
      return periodicity;
    }
  } // namespace

  RingChart::RingChart(const RingGeometry &ring_in, std::vector<double> outer_radii_in)
    : dealii::ChartManifold<3, 3, 3>(periodic_in_theta())
    , ring(ring_in)
    , outer_radii(std::move(outer_radii_in))
  {
    if (ring.has_groove())
      {
        groove_centre_radius = ring.groove_bottom_radius - ring.groove_radius;
        groove_half_width    = ring.groove_half_width();
      }
  }

  std::unique_ptr<dealii::Manifold<3, 3>> RingChart::clone() const
  {
    return std::make_unique<RingChart>(ring, outer_radii);
  }

  double RingChart::inner_radius(const double z) const
  {
    if (!ring.has_groove() || std::abs(z) >= groove_half_width)
      return ring.bore_radius;
    return groove_centre_radius + std::sqrt(ring.groove_radius * ring.groove_radius - z * z);
  }

  double RingChart::inner_radius_slope(const double z) const
  {
    if (!ring.has_groove() || std::abs(z) >= groove_half_width)
      return 0.0;
    return -z / std::sqrt(ring.groove_radius * ring.groove_radius - z * z);
  }

  dealii::Point<3> RingChart::push_forward(const dealii::Point<3> &chart) const
  {
    const double       s     = chart[0];
    const unsigned int layer = std::min(static_cast<unsigned int>(std::max(s, 0.0)), n_layers() - 1);
    const double       t     = s - layer;
    const double       r_in  = layer == 0 ? inner_radius(chart[2]) : outer_radii[layer - 1];
    const double       r     = r_in + t * (outer_radii[layer] - r_in);
    return {r * std::cos(chart[1]), r * std::sin(chart[1]), chart[2]};
  }

  dealii::Point<3> RingChart::pull_back(const dealii::Point<3> &x) const
  {
    const double r     = std::hypot(x[0], x[1]);
    double       theta = std::atan2(x[1], x[0]);
    if (theta < 0.0)
      theta += two_pi;
    const double z = x[2];

    // The layer whose radial span holds r; points slightly outside the body
    // (round-off) extrapolate from the first or last layer.
    unsigned int layer = 0;
    while (layer + 1 < n_layers() && r > outer_radii[layer])
      ++layer;
    const double r_in = layer == 0 ? inner_radius(z) : outer_radii[layer - 1];
    return {layer + (r - r_in) / (outer_radii[layer] - r_in), theta, z};
  }

  dealii::DerivativeForm<1, 3, 3> RingChart::push_forward_gradient(const dealii::Point<3> &chart) const
  {
    const double       s     = chart[0];
    const unsigned int layer = std::min(static_cast<unsigned int>(std::max(s, 0.0)), n_layers() - 1);
    const double       t     = s - layer;
    const double       r_in  = layer == 0 ? inner_radius(chart[2]) : outer_radii[layer - 1];
    const double       dr_in = layer == 0 ? inner_radius_slope(chart[2]) : 0.0;
    const double       r     = r_in + t * (outer_radii[layer] - r_in);
    const double       dr_ds = outer_radii[layer] - r_in;
    const double       dr_dz = (1.0 - t) * dr_in;
    const double       c = std::cos(chart[1]), sn = std::sin(chart[1]);

    dealii::DerivativeForm<1, 3, 3> d;
    d[0][0] = dr_ds * c;
    d[1][0] = dr_ds * sn;
    d[2][0] = 0.0;
    d[0][1] = -r * sn;
    d[1][1] = r * c;
    d[2][1] = 0.0;
    d[0][2] = dr_dz * c;
    d[1][2] = dr_dz * sn;
    d[2][2] = 1.0;
    return d;
  }
} // namespace fretsim::fem
