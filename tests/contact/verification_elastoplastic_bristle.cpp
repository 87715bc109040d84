// Elastic–perfectly-plastic bristles on the paper §4 contact: the grid loop
// against the model's own closed form (Iwan/Masing), and the model
// difference to Mindlin–Deresiewicz and to the exponential bristle law.
//
// Closed form (derived here, see elastoplastic_bristle.h): with Hertz
// pressure and k = 8 G*/(pi a), u = delta/delta_t, the virgin curve is
// F(u) = mu P (3/2)(u - u^3/3) for u <= 1 (mu P beyond), delta_t = mu p0 / k =
// 3 mu P/(16 G* a) is Mindlin's; the loop follows Masing's rule
// Q = Q* -+ 2 F((delta* -+ delta)/2), exactly, for any parallel assembly of
// elastic–perfectly-plastic elements.
#include <fretsim/contact/bristle.h>
#include <fretsim/contact/elastoplastic_bristle.h>
#include <fretsim/contact/fretting_loop.h>
#include <fretsim/contact/material.h>
#include <fretsim/contact/mindlin.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

using namespace fretsim::contact;

namespace
{
  const double       mu = 0.53, load = 1250.0, radius = 0.05;
  const MaterialPair steel{{200e9, 0.3}, {200e9, 0.3}};
  const double       contact_radius = std::cbrt(3.0 * load * radius / (4.0 * steel.contact_modulus()));
  const double       peak_pressure  = 3.0 * load / (2.0 * M_PI * contact_radius * contact_radius);
  const double       stiffness =
    ElastoplasticBristleTraction::mindlin_stiffness(steel.tangential_modulus(), contact_radius);
  const MindlinLoop mindlin(mu, load, contact_radius, steel.tangential_modulus());
  const double      delta_t = mindlin.gross_slip_displacement();

  /// The closed-form virgin curve and Masing loop of the model [N].
  double virgin(double displacement)
  {
    const double u = std::min(std::abs(displacement) / delta_t, 1.0);
    return std::copysign(mu * load * 1.5 * (u - u * u * u / 3.0), displacement);
  }
  double masing(double displacement, double amplitude, bool unloading)
  {
    return unloading ? virgin(amplitude) - 2.0 * virgin(0.5 * (amplitude - displacement))
                     : -virgin(amplitude) + 2.0 * virgin(0.5 * (amplitude + displacement));
  }

  struct Loops
  {
    std::vector<double> displacement, elastoplastic, exponential;
  };

  /// Both bristle models on 128^2 cells, delta = A sin(2 pi t), two cycles.
  Loops run_loops(double amplitude, int steps_per_cycle)
  {
    const auto grid     = SurfaceGrid::centred(128, 128, 1.5 * contact_radius, 1.5 * contact_radius);
    Field      pressure = grid.zeros();
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        {
          const double r2 = (grid.x(i) * grid.x(i) + grid.y(j) * grid.y(j)) / (contact_radius * contact_radius);
          pressure[grid.index(i, j)] = peak_pressure * std::sqrt(std::max(0.0, 1.0 - r2));
        }
    ElastoplasticBristleTraction plastic(grid, stiffness);
    BristleTraction              exponential(grid, stiffness);
    Loops                        loops{{0.0}, {0.0}, {0.0}};
    double                       previous = 0.0;
    for (int step = 1; step <= 2 * steps_per_cycle; ++step)
      {
        const double displacement = amplitude * std::sin(2.0 * M_PI * step / steps_per_cycle);
        plastic.advance(pressure, mu, displacement - previous, 0.0);
        exponential.advance(pressure, mu, displacement - previous, 0.0);
        previous = displacement;
        loops.displacement.push_back(displacement);
        loops.elastoplastic.push_back(integrate(grid, plastic.traction_x()));
        loops.exponential.push_back(integrate(grid, exponential.traction_x()));
      }
    return loops;
  }

  /// Loop area of the last cycle by the trapezoidal rule [J].
  double last_cycle_area(const std::vector<double> &displacement, const std::vector<double> &force, int steps)
  {
    double    work = 0.0;
    const int end  = static_cast<int>(displacement.size()) - 1;
    for (int i = end - steps + 1; i <= end; ++i)
      work += 0.5 * (force[i] + force[i - 1]) * (displacement[i] - displacement[i - 1]);
    return std::abs(work);
  }
} // namespace

TEST(ElastoplasticBristleLoop, FollowsTheIwanMasingClosedForm)
{
  // The grid sum of the cell-centred Hertz pressure differs from P by the
  // quadrature error of the sqrt edge (measured 2e-4 P at 128^2); the return
  // mapping itself is exact for any step, so 40 steps a cycle suffice.
  const int steps = 40;
  for (const double amplitude : {0.3073 * delta_t, 0.8 * delta_t, 1.5 * delta_t})
    {
      const auto loops = run_loops(amplitude, steps);
      double     error = 0.0;
      std::vector<double> closed_form{0.0};
      for (std::size_t i = 1; i < loops.displacement.size(); ++i)
        {
          const bool   reversed  = i > static_cast<std::size_t>(steps / 4);
          const bool   unloading = loops.displacement[i] < loops.displacement[i - 1];
          const double expected  = reversed ? masing(loops.displacement[i], amplitude, unloading)
                                            : virgin(loops.displacement[i]);
          closed_form.push_back(expected);
          error = std::max(error, std::abs(loops.elastoplastic[i] - expected) / (mu * load));
        }
      const double area_ratio = last_cycle_area(loops.displacement, loops.elastoplastic, steps) /
                                last_cycle_area(loops.displacement, closed_form, steps);
      std::printf("delta* = %.2f delta_t: grid vs closed form %.2e mu P, loop area ratio %.5f\n",
                  amplitude / delta_t, error, area_ratio);
      EXPECT_LT(error, 2e-3);
      EXPECT_NEAR(area_ratio, 1.0, 1e-2);
    }
}

TEST(ElastoplasticBristleLoop, AgainstMindlinDeresiewiczAndTheExponentialLaw)
{
  // Same initial stiffness 8 G* a and the same delta_t as Mindlin, but the
  // bristles have no elastic coupling: slip starts where mu p is smallest
  // (the edge) rather than where the elastic shear concentrates, so the loop
  // is thinner. Closed-form model differences (continuum, derived here):
  //   delta*/delta_t   max|Q - Q_MD|/muP   W/W_MD   Q*/Q*_MD
  //   0.1              0.0033              0.195    1.023
  //   0.3073 (paper)   0.0230              0.564    1.054
  //   0.5              0.0411              0.859    1.064
  //   0.8              0.0567              1.193    1.037
  // Measured on 128^2 with 200 steps a cycle: the same to 1e-4 in the loop.
  // The exponential law, same grid and steps: loop error 0.016, 0.093, 0.19,
  // 0.34 and W/W_MD 7.0, 5.3, 4.1, 2.6. At small amplitude W ~ u^4 here against
  // u^3 for Mindlin: elastic–plastic bristles under-dissipate, exponential
  // ones over-dissipate.
  struct Expected
  {
    double ratio, loop_error, energy_ratio, energy_tolerance;
  };
  const int steps = 200; // the exponential law needs small steps (implicit Euler)
  // Energy tolerances: 2 % (grid and trapezoidal rule on 200 steps,
  // measured within 0.4 %), except at 0.1 delta_t where the slip annulus
  // (0.005 a) is a fifth of a cell and the grid overstates the energy
  // (measured 0.235 against 0.195).
  for (const Expected &e : {Expected{0.1, 0.0033, 0.195, 0.25}, Expected{0.3073, 0.0230, 0.564, 0.02},
                            Expected{0.5, 0.0411, 0.859, 0.02}, Expected{0.8, 0.0567, 1.193, 0.02}})
    {
      const double amplitude = e.ratio * delta_t;
      const auto   loops     = run_loops(amplitude, steps);
      FrettingLoop plastic(steps), exponential(steps);
      for (std::size_t i = 0; i < loops.displacement.size(); ++i)
        {
          plastic.add(loops.displacement[i], loops.elastoplastic[i]);
          exponential.add(loops.displacement[i], loops.exponential[i]);
        }
      const auto   p = plastic.last_cycle(mu * load, mindlin, amplitude);
      const auto   x = exponential.last_cycle(mu * load, mindlin, amplitude);
      const double w = mindlin.dissipated_energy(amplitude);
      std::printf("delta* = %.4f delta_t: max |Q - Q_MD|/muP elastoplastic %.4f, exponential %.4f; W/W_MD "
                  "elastoplastic %.3f, exponential %.3f; Q*/Q*_MD elastoplastic %.4f, exponential %.4f\n",
                  e.ratio, p.error_vs_reference, x.error_vs_reference, p.dissipated_energy / w,
                  x.dissipated_energy / w, p.force_amplitude / mindlin.force_amplitude(amplitude),
                  x.force_amplitude / mindlin.force_amplitude(amplitude));
      // Grid and step: 2e-3 muP in the loop (see above), and the trapezoidal
      // rule on 200 steps (-0.02 %) plus the grid in the energy.
      EXPECT_NEAR(p.error_vs_reference, e.loop_error, 2e-3);
      EXPECT_NEAR(p.dissipated_energy / w, e.energy_ratio, e.energy_tolerance * e.energy_ratio);
      // The point of the model: closer to Mindlin than the exponential law
      // in the loop and, in partial slip, in the energy.
      EXPECT_LT(p.error_vs_reference, x.error_vs_reference);
      EXPECT_LT(std::abs(std::log(p.dissipated_energy / w)), std::abs(std::log(x.dissipated_energy / w)));
    }
}
