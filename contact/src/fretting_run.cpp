#include <fretsim/contact/fretting_run.h>

#include <fretsim/contact/fretting_loop.h>
#include <fretsim/contact/hertz.h>
#include <fretsim/contact/masing_traction.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <type_traits>

#include <omp.h>

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

    // The superposition needs the level table to stay within the budget: the
    // history reaches the virgin shift amplitude (the first quarter cycle; a
    // branch from a reversal at +-amplitude halves the shift of at most
    // 2 amplitude), so amplitude / spacing + 1 levels besides level 0.
    const double spacing = setup.exact.masing_level_spacing;
    if (setup.superposed_stresses && spacing > 0.0)
      if (const MasingTraction *model = masing_traction(*traction_model))
        {
          const double levels = std::ceil(std::abs(setup.sliding_amplitude) / spacing) + 2.0;
          const double bytes  = levels * static_cast<double>(total_stress.values.size()) * sizeof(double);
          if (bytes <= static_cast<double>(setup.superposition_budget))
            masing = model;
        }
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

    // The composition of the traction before the step (that of a reversal
    // the step may start).
    const MasingTraction::Composition before = masing ? masing->composition() : MasingTraction::Composition{};
    auto start = Clock::now();
    traction_model->advance(contact_pressure, setup.friction_coefficient, slip * std::cos(setup.sliding_direction),
                            slip * std::sin(setup.sliding_direction));
    times.traction += seconds_since(start);
    iterations_total += traction_model->last_iterations();
    iterations_most = std::max(iterations_most, traction_model->last_iterations());

    start = Clock::now();
    if (masing)
      {
        const MasingTraction::Composition &recipe = masing->composition();
        if (recipe.reversal >= 0 && reversal_stress.count(recipe.reversal) == 0)
          // A new reversal: its traction is the one before this step.
          compose_shear(before, reversal_stress[recipe.reversal]);
        for (auto kept = reversal_stress.begin(); kept != reversal_stress.end();)
          kept = masing->holds_reversal(kept->first) ? std::next(kept) : reversal_stress.erase(kept);
        add_superposed_stresses(recipe);
      }
    else
      {
        stresses->evaluate(no_load, traction_model->traction_x(), traction_model->traction_y(), shear_stress);
        add_stresses(&shear_stress);
      }
    times.stresses += seconds_since(start);

    start = Clock::now();
    dang_van->add_step(total_stress);
    times.dang_van += seconds_since(start);
  }

  const StressField &FrettingRun::level_stresses(std::size_t level)
  {
    if (virgin_stress.size() <= level)
      virgin_stress.resize(level + 1);
    StressField &field = virgin_stress[level];
    if (field.values.empty())
      stresses->evaluate(no_load, masing->virgin_level_x(level), masing->virgin_level_y(level), field);
    return field;
  }

  void FrettingRun::compose_shear(const MasingTraction::Composition &recipe, StressField &out)
  {
    const double *lower = level_stresses(recipe.lower).values.data();
    const double *upper = level_stresses(recipe.upper).values.data();
    const double *base  = recipe.reversal >= 0 ? reversal_stress.at(recipe.reversal).values.data() : nullptr;
    out.resize(total_stress.n_layers, total_stress.ny, total_stress.nx);
    double           *result = out.values.data();
    const double      f = recipe.factor, w = recipe.weight;
    const std::int64_t size = static_cast<std::int64_t>(out.values.size());
    // As MasingTraction composes the traction, value by value.
#pragma omp parallel for simd schedule(static) if (size > 65536)
    for (std::int64_t k = 0; k < size; ++k)
      result[k] = (base ? base[k] : 0.0) + f * ((1.0 - w) * lower[k] + w * upper[k]);
  }

  void FrettingRun::add_stresses(const StressField *shear)
  {
    add_shear(shear ? shear->values.data() : nullptr, nullptr, 0.0, nullptr, nullptr, 0.0);
  }

  void FrettingRun::add_superposed_stresses(const MasingTraction::Composition &recipe)
  {
    const double *lower = level_stresses(recipe.lower).values.data();
    const double *upper = level_stresses(recipe.upper).values.data();
    const double *base  = recipe.reversal >= 0 ? reversal_stress.at(recipe.reversal).values.data() : nullptr;
    add_shear(nullptr, base, recipe.factor, lower, upper, recipe.weight);
  }

  void FrettingRun::add_shear(const double *shear, const double *base, double factor, const double *lower,
                              const double *upper, double weight)
  {
    const std::size_t per_layer = surface.size();
    const std::size_t layers    = setup.depth_layers.size();
    const bool        bulk      = !setup.bulk_stress.is_zero();
    std::vector<std::array<double, stress_component_count>> add(layers);
    for (std::size_t layer = 0; layer < layers; ++layer)
      {
        const StressTensor bulk_here =
          bulk ? setup.bulk_stress.at(setup.depth_layers[layer], time(), setup.period) : StressTensor{};
        for (int component = 0; component < stress_component_count; ++component)
          add[layer][component] = bulk_here[component];
      }
    const double *pressure_part = pressure_stress.values.data();
    double       *total         = total_stress.values.data();
    // The largest 6 J2 = 2 sigma_vM^2 (von_mises_max: sqrt is monotone, so
    // its root is the largest root). A maximum does not depend on the order:
    // neither the threads' split nor the vector lanes change it.
    double largest = largest_six_j2;
    // The shear given, composed as the traction is, or none: a branch-free
    // loop for each, so that it vectorises.
    enum Part { none, given, levels, levels_and_base };
    const auto sum = [&](auto part, std::size_t first, const double *plus, std::size_t begin, std::size_t end,
                         double &worst) {
      // Locals, not the closure's references, which the stores might alias.
      const std::size_t stride = per_layer;
      const double     *p = pressure_part, *given_shear = shear, *from = base, *low = lower, *high = upper;
      double           *out = total;
      const double      f = factor, w = weight;
      double            local = worst;
#pragma omp simd reduction(max : local)
      for (std::size_t cell = begin; cell < end; ++cell)
        {
          double sigma[stress_component_count];
          for (int component = 0; component < stress_component_count; ++component)
            {
              const std::size_t k = first + component * stride + cell;
              constexpr Part    kind = decltype(part)::value;
              double            value = 0.0;
              // As MasingTraction composes the traction, value by value.
              if constexpr (kind == levels_and_base)
                value = from[k] + f * ((1.0 - w) * low[k] + w * high[k]);
              else if constexpr (kind == levels)
                value = 0.0 + f * ((1.0 - w) * low[k] + w * high[k]);
              else if constexpr (kind == given)
                value = given_shear[k];
              sigma[component] = p[k] + value + plus[component];
              out[k]           = sigma[component];
            }
          const double xx = sigma[0], yy = sigma[1], zz = sigma[2], yz = sigma[3], xz = sigma[4], xy = sigma[5];
          const double j2_times_6 = (xx - yy) * (xx - yy) + (yy - zz) * (yy - zz) + (zz - xx) * (zz - xx) +
                                    6.0 * (yz * yz + xz * xz + xy * xy);
          local = std::max(local, j2_times_6);
        }
      worst = std::max(worst, local);
    };
    // One parallel region for all layers, each thread a contiguous share of
    // every layer.
#pragma omp parallel if (layers * per_layer > 4096)
    {
      const std::size_t threads = static_cast<std::size_t>(omp_get_num_threads());
      const std::size_t thread  = static_cast<std::size_t>(omp_get_thread_num());
      const std::size_t begin = per_layer * thread / threads, end = per_layer * (thread + 1) / threads;
      double            mine  = largest;
      for (std::size_t layer = 0; layer < layers; ++layer)
        {
          const std::size_t first = layer * stress_component_count * per_layer;
          const double *plus = add[layer].data();
          if (lower && base)
            sum(std::integral_constant<Part, levels_and_base>{}, first, plus, begin, end, mine);
          else if (lower)
            sum(std::integral_constant<Part, levels>{}, first, plus, begin, end, mine);
          else if (shear)
            sum(std::integral_constant<Part, given>{}, first, plus, begin, end, mine);
          else
            sum(std::integral_constant<Part, none>{}, first, plus, begin, end, mine);
        }
#pragma omp critical(fretting_run_von_mises)
      largest = std::max(largest, mine);
    }
    largest_six_j2 = largest;
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
