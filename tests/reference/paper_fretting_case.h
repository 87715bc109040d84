#pragma once
// The paper's ball-on-flat case (steel on steel, R 50 mm, 1250 N, μ 0.53,
// 2.241 µm) with the exact traction on a few cycles of 40 steps and four
// depth layers: small enough for a test, the paper's physics otherwise.
#include <fretsim/contact/fretting_run.h>

namespace fretsim::reference
{
  inline contact::FrettingCase paper_fretting_case(int cycles)
  {
    contact::FrettingCase c;
    c.materials            = {{200e9, 0.3}, {200e9, 0.3}};
    c.radius_x = c.radius_y = 0.05;
    c.normal_load          = 1250.0;
    c.sliding_amplitude    = 2.241e-6;
    c.cycles               = cycles;
    c.steps_per_cycle      = 40;
    c.friction_coefficient = 0.53;
    c.traction_model       = contact::TractionModel::exact_masing;
    c.exact.masing_level_spacing = c.sliding_amplitude / (0.25 * c.steps_per_cycle);
    c.depth_layers         = {0.0, 3.75e-5, 1.5e-4, 3.6e-4};
    c.dang_van             = contact::DangVanConstants::from_fatigue_limits(690e6, 428e6);
    c.stress_evaluator.measure_fft_plans = false;
    c.exact.measure_fft_plans            = false;
    return c;
  }
} // namespace fretsim::reference
