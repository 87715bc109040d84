#pragma once
// The rigid parts of a radial deep groove ball bearing as the co-simulation
// sees them (docs/theory.md §4): geometry, cage kinematics and the ball–raceway
// load–deflection law. SI units: m, N, rad, s.
//
// Balls are massless and guided by the cage: ball j sits at the cage angle
// ψ_j(t) = ψ_0 + 2π j / Z + ω_c t and is in radial equilibrium between the
// inner and the outer raceway at every instant (its own dynamics, tens of kHz
// on these contact stiffnesses, are far above the ball pass frequency). The two
// Hertz contacts in series then give one law for the ball load Q against the
// total elastic deflection δ along the line of centres (contact angle 0):
//     Q = K δ^{3/2},   K = [K_i^{-2/3} + K_o^{-2/3}]^{-3/2},
// with K_i, K_o from the exact elliptical Hertz solution of each contact
// (Harris & Kotzalas, Rolling Bearing Analysis, §6; docs/references.md §1.3).
// Contact damping is Hunt–Crossley: Q = K δ^{3/2} (1 + 3/2 α δ̇), never negative.
#include <array>
#include <cstddef>
#include <vector>

namespace fretsim::coupling
{
  struct BearingGeometry
  {
    unsigned int ball_count              = 9;
    double       ball_diameter           = 0.0127; ///< D_w [m]
    double       pitch_diameter          = 0.060;  ///< d_m [m]
    double       inner_groove_conformity = 0.52;   ///< f_i = r_i / D_w [-]
    double       outer_groove_conformity = 0.53;   ///< f_o = r_o / D_w [-]
    /// Radial internal clearance P_d: the free radial play of the inner ring
    /// in the outer ring; every ball's deflection is reduced by P_d / 2 [m].
    double radial_clearance = 0.0;
  };

  /// Load–deflection constants Q = K δ^{3/2} [N/m^{3/2}].
  struct BallContactStiffness
  {
    double inner    = 0.0; ///< ball on the inner raceway
    double outer    = 0.0; ///< ball on the outer raceway
    double combined = 0.0; ///< both in series
  };

  /// Exact elliptical Hertz constants of both contacts (ball and rings of
  /// contact modulus E*). Throws std::invalid_argument for impossible geometry
  /// (conformity ≤ 1/2, ball larger than the pitch circle).
  BallContactStiffness ball_contact_stiffness(const BearingGeometry &bearing, double contact_modulus);

  /// The Hertz ellipse of a ball on the outer raceway: its semi-axes and peak
  /// pressure grow as Q^{1/3}, so their values at 1 N give every load's.
  struct OuterContactEllipse
  {
    double semi_axis_rolling_per_newton_cube_root    = 0.0; ///< a / Q^{1/3}, along the raceway [m/N^{1/3}]
    double semi_axis_transverse_per_newton_cube_root = 0.0; ///< b / Q^{1/3}, along the groove [m/N^{1/3}]
    double peak_pressure_per_newton_cube_root        = 0.0; ///< p0 / Q^{1/3} [Pa/N^{1/3}]
    /// `count` (odd, >= 3) ball loads whose ellipses tabulate the raceway
    /// footprint: equally spaced in Q^{1/3} from a point load up to the load
    /// at which p0 reaches `peak_pressure_limit` [N]. Throws
    /// std::invalid_argument for another count.
    std::vector<double> footprint_loads(double peak_pressure_limit, unsigned int count) const;
  };
  OuterContactEllipse outer_contact_ellipse(const BearingGeometry &bearing, double contact_modulus);

  /// ISO 76's static limit of the contact pressure in a ball bearing [Pa]:
  /// the raceway footprints are tabulated up to the load that reaches it.
  inline constexpr double static_limit_peak_pressure = 4.2e9;

  /// A ball's raceway row between footprints tabulated at the ball loads
  /// `footprint_loads` (ascending): Σ_m weights[m] row[first + m] over
  /// `count` footprints, quadratic in Q^{1/3} over pieces of three (from the
  /// first), extrapolated beyond the last. One footprint (or none): that
  /// one, whatever the load.
  struct FootprintBlend
  {
    std::size_t           first = 0;
    std::size_t           count = 1;
    std::array<double, 3> weights{1.0, 0.0, 0.0};

    /// Σ_m weights[m] value(first + m): a footprint-indexed quantity at the load.
    template <class Value>
    double of(Value value) const
    {
      double sum = 0.0;
      for (std::size_t m = 0; m < count; ++m)
        sum += weights[m] * value(first + m);
      return sum;
    }
  };
  FootprintBlend footprint_blend(const std::vector<double> &footprint_loads, double load);

  /// Cage angular speed with the outer ring fixed, ω_c = ω_i (1 - D_w/d_m) / 2 [rad/s].
  double cage_speed(const BearingGeometry &bearing, double inner_ring_speed);
  /// Ball pass frequency on the outer ring, Z ω_c / 2π [Hz].
  double outer_ball_pass_frequency(const BearingGeometry &bearing, double inner_ring_speed);

  /// The balls' motion with the outer ring fixed, at inner ring speed ω_i.
  struct CageKinematics
  {
    double cage_speed          = 0.0; ///< ω_c [rad/s]
    double ball_pass_frequency = 0.0; ///< on the outer ring, Z ω_c / 2π [Hz]
  };
  CageKinematics cage_kinematics(const BearingGeometry &bearing, double inner_ring_speed);

  /// Q = K δ^{3/2} (1 + 3/2 α δ̇) for δ > 0, else 0, and never negative; with
  /// its derivatives by δ and δ̇.
  struct BallLoad
  {
    double load = 0.0, by_deflection = 0.0, by_deflection_rate = 0.0;
  };
  BallLoad ball_load(double stiffness, double damping, double deflection, double deflection_rate);
} // namespace fretsim::coupling
