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
