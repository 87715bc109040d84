#pragma once
// The tangential force loop of a fretting contact under harmonic imposed
// sliding, and how far it is from the Mindlin–Deresiewicz loop.
#include <fretsim/contact/mindlin.h>

#include <vector>

namespace fretsim::contact
{
  /// Imposed relative displacement of the upper body over the lower one,
  /// delta(t) = amplitude sin(2 pi t / period), along a fixed direction.
  struct HarmonicSliding
  {
    double amplitude = 0.0; ///< [m]
    double period    = 1.0; ///< [s]
    double displacement(double time) const;
  };

  /// Figures of merit of the last complete cycle of a loop.
  struct LoopMetrics
  {
    double force_amplitude = 0.0;     ///< (max Q - min Q) / 2 [N]
    double dissipated_energy = 0.0;   ///< loop area, |closed integral of Q d(delta)| [J]
    double error_vs_reference = 0.0; ///< max |Q - Q_MD| / (mu P) over the cycle [-]
    double change_from_previous_cycle = 0.0; ///< max |Q_n - Q_{n-1}| / (mu P) [-]
  };

  /// Records (delta, Q) once per time step, steps_per_cycle steps a cycle,
  /// starting with the state at t = 0.
  class FrettingLoop
  {
  public:
    explicit FrettingLoop(int steps_per_cycle);

    void add(double displacement, double force);
    int  complete_cycles() const;

    /// Mindlin–Deresiewicz force for the displacement history: virgin loading
    /// until the first reversal, then the steady loop branch given by the
    /// direction of motion (the loop is steady from the first reversal on).
    static double reference_force(const MindlinLoop &reference, double amplitude,
                                  double displacement, double previous_displacement,
                                  bool reversed_before);

    /// Metrics of the last complete cycle. mu_P normalises the errors; the
    /// reference loop for `amplitude` gives error_vs_reference.
    LoopMetrics last_cycle(double mu_P, const MindlinLoop &reference, double amplitude) const;

  private:
    int                 steps_per_cycle;
    std::vector<double> displacements;
    std::vector<double> forces;
  };
} // namespace fretsim::contact
