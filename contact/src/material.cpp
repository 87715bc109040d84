#include <fretsim/contact/material.h>

namespace fretsim::contact
{
  double MaterialPair::contact_modulus() const
  {
    return 1.0 / (1.0 / lower.plane_modulus() + 1.0 / upper.plane_modulus());
  }

  double MaterialPair::tangential_modulus() const
  {
    const double compliance = (2.0 - lower.poisson_ratio) / lower.shear_modulus() +
                              (2.0 - upper.poisson_ratio) / upper.shear_modulus();
    return 1.0 / compliance;
  }
} // namespace fretsim::contact
