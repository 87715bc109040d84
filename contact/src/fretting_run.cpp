#include <fretsim/contact/fretting_run.h>

#include <fretsim/contact/fretting_loop.h>
#include <fretsim/contact/hertz.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace fretsim::contact
{
  namespace
  {
    using Clock = std::chrono::steady_clock;

    double seconds_since(Clock::time_point start)
    {
      return std::chrono::duration<double>(Clock::now() - start).count();
    }

    Field initial_gap(const FrettingCase &c, const SurfaceGrid &grid)
    {
      Field gap = grid.zeros();
      for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i)
          gap[grid.index(i, j)] =
            grid.x(i) * grid.x(i) / (2.0 * c.radius_x) + grid.y(j) * grid.y(j) / (2.0 * c.radius_y);
      return gap;
    }

    Field hertz_pressure(const FrettingCase &c, const SurfaceGrid &grid)
    {
      const auto [ax, ay] = c.hertz_semi_axes();
      const double p0     = c.hertz_peak_pressure();
      Field        pressure = grid.zeros();
      for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i)
          {
            const double ex = grid.x(i) / ax, ey = grid.y(j) / ay;
            pressure[grid.index(i, j)] = p0 * std::sqrt(std::max(0.0, 1.0 - ex * ex - ey * ey));
          }
      return pressure;
    }
  } // namespace

  bool BulkStress::is_zero() const
  {
    for (const auto *part : {&static_surface, &static_gradient, &amplitude_surface, &amplitude_gradient})
      for (const double value : *part)
        if (value != 0.0)
          return false;
    return true;
  }

  StressTensor BulkStress::at(double depth, double time, double period) const
  {
    const double wave = std::sin(2.0 * M_PI * time / period + phase);
    const auto   component = [&](int k) {
      return static_surface[k] + depth * static_gradient[k] + (amplitude_surface[k] + depth * amplitude_gradient[k]) * wave;
    };
    StressTensor tensor;
    tensor.xx = component(0);
    tensor.yy = component(1);
    tensor.xy = component(2);
    return tensor;
  }

  std::pair<double, double> FrettingCase::hertz_semi_axes() const
  {
    if (radius_x == radius_y)
      {
        const auto h = HertzCircular::solve(normal_load, radius_x, materials.contact_modulus());
        return {h.contact_radius, h.contact_radius};
      }
    const auto h = HertzElliptical::solve(normal_load, radius_x, radius_y, materials.contact_modulus());
    return {h.semi_axis_x, h.semi_axis_y};
  }

  double FrettingCase::hertz_peak_pressure() const
  {
    const auto [ax, ay] = hertz_semi_axes();
    return 3.0 * normal_load / (2.0 * M_PI * ax * ay);
  }

  SurfaceGrid fretting_grid(const FrettingCase &fretting_case, int cells_x, int cells_y, double half_width_factor)
  {
    const auto [ax, ay] = fretting_case.hertz_semi_axes();
    return SurfaceGrid::centred(cells_x, cells_y, half_width_factor * ax, half_width_factor * ay);
  }

  FrettingRun::FrettingRun(const FrettingCase &fretting_case, const SurfaceGrid &grid,
                           std::unique_ptr<SubsurfaceStress> evaluator)
    : setup(fretting_case)
    , surface(grid)
    , stresses(std::move(evaluator))
    , no_load(grid.zeros())
  {
    const auto start = Clock::now();
    if (setup.numerical_pressure)
      {
        const NormalContactSolver solver(surface, setup.materials.contact_modulus(), setup.normal);
        auto                      result = solver.solve(initial_gap(setup, surface), setup.normal_load);
        contact_pressure                 = std::move(result.pressure);
        normal_solver_iterations         = result.iterations;
      }
    else
      contact_pressure = hertz_pressure(setup, surface);
    times.normal_contact = seconds_since(start);

    if (!stresses)
      stresses = make_subsurface_stress(surface, setup.depth_layers, setup.materials.lower.poisson_ratio,
                                        setup.stress_evaluator);
    // The pressure's stresses once: the half-space is linear, so each step
    // only adds those of the current shear.
    const auto stress_start = Clock::now();
    stresses->evaluate(contact_pressure, no_load, no_load, pressure_stress);
    total_stress = pressure_stress;
    add_stresses(nullptr);
    times.stresses += seconds_since(stress_start);

    traction_model = make_tangential_traction_model(setup.traction_model, surface, setup.materials,
                                                    setup.bristle_stiffness, setup.exact);
    DangVanSettings settings;
    settings.centre          = setup.residual_stress;
    settings.steps_per_cycle = setup.steps_per_cycle;
    settings.warmup_cycles   = setup.warmup_cycles;
    dang_van = std::make_unique<DangVanField>(setup.depth_layers.size() * surface.size(), setup.dang_van, settings);
  }

  FrettingRun::~FrettingRun() = default;

  std::int64_t FrettingRun::total_steps() const
  {
    return static_cast<std::int64_t>(setup.cycles) * setup.steps_per_cycle;
  }

  double FrettingRun::time() const
  {
    return step_index * setup.period / setup.steps_per_cycle;
  }

  void FrettingRun::advance()
  {
    ++step_index;
    last_displacement    = current_displacement;
    current_displacement = HarmonicSliding{setup.sliding_amplitude, setup.period}.displacement(time());
    const double slip    = current_displacement - last_displacement;

    auto start = Clock::now();
    traction_model->advance(contact_pressure, setup.friction_coefficient, slip * std::cos(setup.sliding_direction),
                            slip * std::sin(setup.sliding_direction));
    times.traction += seconds_since(start);
    iterations_total += traction_model->last_iterations();
    iterations_most = std::max(iterations_most, traction_model->last_iterations());

    start = Clock::now();
    stresses->evaluate(no_load, traction_model->traction_x(), traction_model->traction_y(), shear_stress);
    add_stresses(&shear_stress);
    times.stresses += seconds_since(start);

    start = Clock::now();
    dang_van->add_step(total_stress);
    times.dang_van += seconds_since(start);
  }

  void FrettingRun::add_stresses(const StressField *shear)
  {
    const std::size_t per_layer = surface.size();
    const bool        bulk      = !setup.bulk_stress.is_zero();
    for (std::size_t layer = 0; layer < setup.depth_layers.size(); ++layer)
      {
        const StressTensor bulk_here =
          bulk ? setup.bulk_stress.at(setup.depth_layers[layer], time(), setup.period) : StressTensor{};
        for (int component = 0; component < stress_component_count; ++component)
          {
            const std::size_t first = (layer * stress_component_count + component) * per_layer;
            const double      add   = bulk_here[component];
            for (std::size_t k = first; k < first + per_layer; ++k)
              total_stress.values[k] = pressure_stress.values[k] + (shear ? shear->values[k] : 0.0) + add;
          }
        // von Mises: sqrt(3 J2) of the total stress.
        const auto at = [&](int component, std::size_t cell) {
          return total_stress.values[(layer * stress_component_count + component) * per_layer + cell];
        };
        for (std::size_t cell = 0; cell < per_layer; ++cell)
          {
            const double xx = at(0, cell), yy = at(1, cell), zz = at(2, cell);
            const double yz = at(3, cell), xz = at(4, cell), xy = at(5, cell);
            const double j2_times_6 = (xx - yy) * (xx - yy) + (yy - zz) * (yy - zz) + (zz - xx) * (zz - xx) +
                                      6.0 * (yz * yz + xz * xz + xy * xy);
            von_mises_largest = std::max(von_mises_largest, std::sqrt(0.5 * j2_times_6));
          }
      }
  }

  RiskMaximum FrettingRun::risk_maximum() const
  {
    const std::vector<double> &risk_max = dang_van->risk_max();
    RiskMaximum                result;
    std::size_t                worst = risk_max.size();
    for (std::size_t point = 0; point < risk_max.size(); ++point)
      if (std::isfinite(risk_max[point]) && (worst == risk_max.size() || risk_max[point] > risk_max[worst]))
        worst = point;
    if (worst == risk_max.size())
      return result;
    const std::size_t cell = worst % surface.size();
    result.value           = risk_max[worst];
    result.layer           = static_cast<int>(worst / surface.size());
    result.i               = static_cast<int>(cell % surface.nx);
    result.j               = static_cast<int>(cell / surface.nx);
    result.step            = dang_van->risk_max_step()[worst];
    return result;
  }

  RiskMaximum fretting_risk_maximum(const FrettingCase &fretting_case, const SurfaceGrid &grid)
  {
    FrettingRun run(fretting_case, grid);
    while (!run.finished())
      run.advance();
    return run.risk_maximum();
  }
} // namespace fretsim::contact
