#pragma once
// The names the commands on a ring_housing configuration (mesh, fe, reduce)
// share with the command line; the configuration itself is models/'s.
#include <fretsim/models/ring_housing.h>

namespace fretsim::app
{
  using models::ring_housing_parameter_specs;
  using models::ring_housing_scene;
  using models::RingHousingCommandOptions;
} // namespace fretsim::app
