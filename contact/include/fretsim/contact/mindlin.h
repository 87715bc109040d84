#pragma once
// Cattaneo–Mindlin partial slip and the Mindlin–Deresiewicz fretting loop for
// two elastic spheres under constant normal load (Johnson 1985 §7.2-7.3;
// docs/references.md §2). Displacement-controlled form: given the imposed
// tangential displacement history, the tangential force Q.

namespace fretsim::contact
{
  class MindlinLoop
  {
  public:
    /// friction_coefficient mu, normal_load P [N], contact_radius a [m],
    /// tangential_modulus G* [Pa] with 1/G* = (2-nu1)/G1 + (2-nu2)/G2.
    MindlinLoop(double friction_coefficient, double normal_load, double contact_radius,
                double tangential_modulus);

    /// Displacement at the onset of gross slip: delta_t = 3 mu P / (16 G* a) [m].
    double gross_slip_displacement() const { return delta_t; }

    /// Virgin loading from zero: Q(delta) = mu P (1 - (1 - delta/delta_t)^{3/2}).
    double virgin_force(double displacement) const;
    /// Stick radius under monotonic loading to Q: c = a (1 - Q/(mu P))^{1/3}.
    double stick_radius(double tangential_force) const;
    /// Force amplitude Q* of the steady loop for displacement amplitude delta*.
    double force_amplitude(double displacement_amplitude) const;
    /// Steady loop for amplitude delta*: Q on the unloading branch (displacement
    /// decreasing from +delta*) or on the reloading branch.
    double loop_force(double displacement, double displacement_amplitude, bool unloading) const;
    /// Energy dissipated per steady cycle of amplitude delta* [J]; includes the
    /// gross-slip part 4 mu P (delta* - delta_t) above delta_t.
    double dissipated_energy(double displacement_amplitude) const;

  private:
    double mu_P;
    double delta_t;
  };
} // namespace fretsim::contact
