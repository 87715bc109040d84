// A bulk stress of the flat superposed on the contact's stresses
// (fretting_run.h): Dang Van's D for a bulk stress alone against its closed
// form, and the superposition with the contact against the two parts.
#include <fretsim/contact/fretting_run.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace fretsim::contact;

namespace
{
  const double bending_limit = 690e6, torsion_limit = 428e6;

  /// A ball so lightly loaded that its stresses are ~1e-15 of the bulk's:
  /// the risk is the bulk stress's alone.
  FrettingCase unloaded_case()
  {
    FrettingCase c;
    c.materials            = {{200e9, 0.3}, {200e9, 0.3}};
    c.radius_x = c.radius_y = 0.0127;
    c.normal_load          = 1e-30;
    c.sliding_amplitude    = 0.0;
    c.cycles               = 3;
    c.steps_per_cycle      = 40; // a multiple of 4: the peaks are steps
    c.friction_coefficient = 0.0;
    c.traction_model       = TractionModel::bristle;
    c.bristle_stiffness    = 1e15;
    c.numerical_pressure   = false;
    c.depth_layers         = {0.0, 2e-4};
    c.dang_van             = DangVanConstants::from_fatigue_limits(bending_limit, torsion_limit);
    c.residual_stress      = ResidualStressCentre::last_cycle_mean;
    c.warmup_cycles        = 1;
    return c;
  }

  /// D_max on each depth layer (the largest over its cells).
  std::vector<double> risk_per_layer(const FrettingCase &c)
  {
    const SurfaceGrid grid = fretting_grid(c, 8, 8, 1.5);
    FrettingRun       run(c, grid);
    while (!run.finished())
      run.advance();
    std::vector<double> result(c.depth_layers.size(), 0.0);
    for (std::size_t point = 0; point < run.risk_max().size(); ++point)
      result[point / grid.size()] = std::max(result[point / grid.size()], run.risk_max()[point]);
    return result;
  }
} // namespace

// Fully reversed tension of amplitude f-1 is the bending limit by definition.
TEST(BulkStress, FullyReversedUniaxialAtTheFatigueLimitGivesRiskOne)
{
  for (int component : {0, 1})
    {
      FrettingCase c                         = unloaded_case();
      c.bulk_stress.amplitude_surface[component] = bending_limit;
      const auto risk                        = risk_per_layer(c);
      EXPECT_NEAR(risk[0], 1.0, 1e-9) << "component " << component;
    }
}

// sigma_xx = s(z) + a(z) sin(wt): centre dev(s e_xx), mesoscopic stress
// a w e_xx + s/3 I, tau = |a w| / 2, sigma_H = (s + a w) / 3; the largest D at
// w = 1 is (a/2) / (beta - alpha (s + a) / 3) on each layer.
TEST(BulkStress, StaticAndCyclicTensionWithDepthMatchTheClosedForm)
{
  FrettingCase c                     = unloaded_case();
  c.bulk_stress.static_surface[0]    = 200e6;
  c.bulk_stress.static_gradient[0]   = -5e11; // bending: -100 MPa over 0.2 mm
  c.bulk_stress.amplitude_surface[0] = 300e6;
  c.bulk_stress.amplitude_gradient[0] = -2.5e11;
  const auto constants               = DangVanConstants::from_fatigue_limits(bending_limit, torsion_limit);
  const auto risk                    = risk_per_layer(c);
  for (std::size_t layer = 0; layer < c.depth_layers.size(); ++layer)
    {
      const double z = c.depth_layers[layer];
      const double s = 200e6 - 5e11 * z, a = 300e6 - 2.5e11 * z;
      const double expected = 0.5 * a / (constants.beta - constants.alpha * (s + a) / 3.0);
      EXPECT_NEAR(risk[layer], expected, 1e-9 * expected) << "layer " << layer;
    }
}

// Fully reversed shear of amplitude t-1 is the torsion limit.
TEST(BulkStress, FullyReversedShearAtTheTorsionLimitGivesRiskOne)
{
  FrettingCase c                     = unloaded_case();
  c.bulk_stress.amplitude_surface[2] = torsion_limit;
  EXPECT_NEAR(risk_per_layer(c)[0], 1.0, 1e-9);
}

// The stresses with a bulk stress are those without it plus the bulk stress
// at the step's time, to round-off (5e-16 of the peak pressure per addition).
TEST(BulkStress, SuperposesOnTheContactStressesEveryStep)
{
  FrettingCase c            = unloaded_case();
  c.normal_load             = 500.0;
  c.sliding_amplitude       = 1e-6;
  c.friction_coefficient    = 0.5;
  c.traction_model          = TractionModel::exact;
  c.cycles                  = 1;
  c.steps_per_cycle         = 8;
  c.residual_stress         = ResidualStressCentre::running_mean;
  c.warmup_cycles           = 0;
  FrettingCase with_bulk    = c;
  with_bulk.bulk_stress.static_surface    = {100e6, -50e6, 20e6};
  with_bulk.bulk_stress.amplitude_surface = {200e6, 30e6, -40e6};
  with_bulk.bulk_stress.amplitude_gradient = {-1e11, 0.0, 2e11};
  with_bulk.bulk_stress.phase             = 0.7;
  const SurfaceGrid grid = fretting_grid(c, 16, 16, 1.5);
  FrettingRun       plain(c, grid), bulk(with_bulk, grid);
  const double      tolerance = 1e-14 * c.hertz_peak_pressure();
  while (!plain.finished())
    {
      plain.advance();
      bulk.advance();
      double worst = 0.0;
      for (int layer = 0; layer < 2; ++layer)
        {
          const StressTensor added = with_bulk.bulk_stress.at(c.depth_layers[layer], bulk.time(), c.period);
          for (int component = 0; component < stress_component_count; ++component)
            for (int j = 0; j < grid.ny; ++j)
              for (int i = 0; i < grid.nx; ++i)
                worst = std::max(worst, std::abs(bulk.stress().at(layer, component, j, i) -
                                                 plain.stress().at(layer, component, j, i) - added[component]));
        }
      EXPECT_LE(worst, tolerance) << "step " << bulk.steps_done();
    }
  EXPECT_GT(bulk.von_mises_max(), plain.von_mises_max());
}

// Pure shear tau has the von Mises stress sqrt(3) tau (the ball adds ~1e-11).
TEST(BulkStress, VonMisesOfPureShear)
{
  FrettingCase c                  = unloaded_case();
  c.bulk_stress.static_surface[2] = 100e6;
  c.cycles                        = 2;
  const SurfaceGrid grid          = fretting_grid(c, 8, 8, 1.5);
  FrettingRun       run(c, grid);
  EXPECT_NEAR(run.von_mises_max(), std::sqrt(3.0) * 100e6, 1e-9 * 100e6);
}
