#pragma once
// The 6208 outer ring of the paper's §5 scene (raceway groove f_o = 0.53,
// bearing steel) at a chosen mesh size, for the reduction tests.
#include <fretsim/fem/elastic_model.h>
#include <fretsim/fem/mesh.h>

#include <memory>

namespace fretsim::reduction_testing
{
  inline const fem::Material bearing_steel{208e9, 0.3, 7850.0};

  inline fem::RingGeometry ring_6208_geometry()
  {
    fem::RingGeometry g;
    g.bore_radius          = 0.0341;
    g.outer_radius         = 0.040;
    g.width                = 0.018;
    g.groove_radius        = 0.006731;
    g.groove_bottom_radius = 0.03635;
    return g;
  }

  /// A ball pressing on the 6208 raceway with the footprint the reduction
  /// configuration uses for its raceway operator (0.3 × 1.3 mm semi-axes).
  inline fem::RacewayBallLoad raceway_ball_6208(double angle, double force)
  {
    fem::RacewayBallLoad b;
    b.ring                      = ring_6208_geometry();
    b.angle                     = angle;
    b.force                     = force;
    b.semi_axis_circumferential = 0.3e-3;
    b.semi_axis_transverse      = 1.3e-3;
    return b;
  }

  inline std::shared_ptr<const fem::Mesh> ring_6208(unsigned int circumferential, unsigned int radial,
                                                    unsigned int axial, unsigned int axial_land)
  {
    const fem::RingGeometry g = ring_6208_geometry();
    fem::MeshDivisions d;
    d.circumferential = circumferential;
    d.radial_ring     = radial;
    d.axial           = axial;
    d.axial_land      = axial_land;
    return std::make_shared<const fem::Mesh>(fem::Mesh::ring(g, d));
  }
} // namespace fretsim::reduction_testing
