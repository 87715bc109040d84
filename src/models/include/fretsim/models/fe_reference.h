#pragma once
// The bearing scene's interface solved with the full FE of ring and housing
// (docs/fe_reference.md): the two bodies condensed exactly onto the contact
// grid (interface_influence.h), the ring free and held only by the interface,
// the balls' loads given. Quasi-static: the ball pass frequency is far below
// the ring's lowest elastic frequency, so inertia only balances the loads'
// small resultant, which the ring's rigid motion takes here.
//
// Each increment solves, on the grid's cells,
//   normal:      p ≥ 0, p/k_n = d, d = δ_fit + u_r,ring − u_r,housing (the layer in series), or p = 0, d ≤ 0;
//   tangential:  the scene's bristle law (paper eq. 4) over the increment's relative slip Δs,
//                τ' = (τ + k_t Δs)/(1 + k_t |Δs|/(μ p)), |τ'| ≤ μ p — history carried from increment to increment;
//   equilibrium of the ring: the interface forces balance the balls' loads (six rigid motions as multipliers),
// the law by secant iterations (each a symmetric positive definite system on
// the loaded cells, solved by projected conjugate gradients with the
// closed grid's FFT-block inverse as preconditioner, sliding cells' bristle
// blocks inverted on their own), the contact set by
// active-set updates. The stresses below every cell on the tables' depth
// layers follow from the same tables.
#include <fretsim/models/interface_influence.h>

#include <array>
#include <memory>
#include <vector>

namespace fretsim::models
{
  struct ReferenceInterface
  {
    double friction_coefficient = 0.0; ///< μ [-]
    double normal_stiffness     = 0.0; ///< k_n of the layer [Pa/m]
    double tangential_stiffness = 0.0; ///< k_t of the bristles [Pa/m]
    double radial_interference  = 0.0; ///< δ_fit [m]
  };

  /// The balls at one instant: angles ψ_j [rad] and loads Q_j [N] on the raceway.
  struct ReferenceLoads
  {
    double              time = 0.0; ///< [s]
    std::vector<double> ball_angles, ball_loads;
  };

  struct ReferenceSettings
  {
    int    substeps  = 4;    ///< increments between two given instants (loads and angles linear in between)
    double tolerance = 1e-5; ///< law and contact set: traction change below this × μ p_max (or p_max)
    double linear_tolerance = 1e-9; ///< conjugate gradients: relative residual
    int    max_iterations   = 500;  ///< friction-law and active-set iterations per increment
    /// true: the bristle law by secant iterations (each linear solve with the
    /// law's secant, geometrically relaxed); false: by its symmetrised
    /// tangent while the law's residual shrinks, then by secant iterations.
    bool   secant_iterations = true;
    double tangent_floor     = 1e-2; ///< the tangent's stiffness kept above this × the secant's
  };

  /// The state at an instant.
  struct ReferenceState
  {
    double              time = 0.0;
    std::vector<double> pressure, shear_x, shear_y; ///< on the ring [Pa]: pushing in, along +θ, along +z
    /// [layer][6][ny][nx] in the tables' contact frame [Pa] (empty without stress tables).
    std::vector<double>   stress;
    std::array<double, 6> rigid_motion{}; ///< ring: translation x, y, z [m], rotation about x, y, z [rad]
    int iterations = 0, linear_iterations = 0; ///< over the instant's increments
  };

  class FeReference
  {
  public:
    /// `housing` null: a rigid housing. The tables must share the grid.
    /// Throws std::invalid_argument for tables that do not fit together or a
    /// law out of range.
    FeReference(const InterfaceInfluence &ring, const InterfaceInfluence *housing, const ReferenceInterface &law,
                const ReferenceSettings &settings);
    ~FeReference();
    FeReference(const FeReference &)            = delete;
    FeReference &operator=(const FeReference &) = delete;

    /// From the last state (at first: no traction, no slip, the loads of
    /// `next` reached in the increments from none) to the loads of `next`.
    /// Throws std::runtime_error if an increment does not converge.
    ReferenceState advance(const ReferenceLoads &next);

    /// The full-FE ring's stresses ([layer][6][ny][nx], as ReferenceState)
    /// under given balls and tractions on the ring (pushing in, along +θ,
    /// along +z [Pa]): e.g. another model's tractions, to tell its stresses'
    /// error from its tractions'.
    std::vector<double> ring_stress(const ReferenceLoads &loads, const std::vector<double> &pressure,
                                    const std::vector<double> &shear_x, const std::vector<double> &shear_y) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace fretsim::models
