#pragma once
// Elastic constants of the two bodies in contact and the combined moduli that
// contact mechanics uses (Johnson, Contact Mechanics, 1985, §3-§7).

namespace fretsim::contact
{
  /// Isotropic linear elastic material. SI units: Pa.
  struct ElasticMaterial
  {
    double youngs_modulus = 200e9; ///< E [Pa]
    double poisson_ratio  = 0.3;   ///< nu [-]

    double shear_modulus() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
    /// E' = E/(1-nu^2): the body's own share of a contact modulus, a
    /// half-space of it deflects by Love's coefficients at E' [Pa].
    double plane_modulus() const { return youngs_modulus / (1.0 - poisson_ratio * poisson_ratio); }
  };

  /// The pair of bodies: `lower` carries the surface grid (the flat, the ring),
  /// `upper` is the counter-body (the ball, the housing).
  struct MaterialPair
  {
    ElasticMaterial lower;
    ElasticMaterial upper;

    /// Contact modulus E*: 1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2 [Pa].
    double contact_modulus() const;
    /// Tangential modulus G*: 1/G* = (2-nu1)/G1 + (2-nu2)/G2 [Pa]. Mindlin's
    /// initial tangential stiffness is dQ/d(delta) = 8 G* a.
    double tangential_modulus() const;
  };
} // namespace fretsim::contact
