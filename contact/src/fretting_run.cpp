#include <fretsim/contact/fretting_run.h>

#include <fretsim/contact/fretting_loop.h>
#include <fretsim/contact/hertz.h>
#include <fretsim/contact/masing_traction.h>
#include <fretsim/contact/mindlin.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <new>
#include <type_traits>
#include <utility>

#if __has_include(<sys/mman.h>)
#include <sys/mman.h>
#endif

#include <omp.h>

namespace fretsim::contact
{
  namespace
  {
    using Clock = std::chrono::steady_clock;

    /// Superposed steps held back before their Dang Van steps run together:
    /// enough that a block's state and the levels' stresses it reads are
    /// reused from cache, few enough that the records stay small.
    constexpr std::size_t pending_steps_at_most = 64;

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

  bool mirror_symmetric(const FrettingCase &c, const SurfaceGrid &grid)
  {
    if (!c.mirror_symmetry || grid.ny < 2 || c.stress_evaluator.method == "mlmi")
      return false;
    // sin(pi) is 1.2e-16, not 0: sliding at 180 degrees counts as along x.
    if (std::abs(std::sin(c.sliding_direction)) > 1e-15)
      return false;
    const BulkStress &bulk = c.bulk_stress;
    for (const auto *part : {&bulk.static_surface, &bulk.static_gradient, &bulk.amplitude_surface, &bulk.amplitude_gradient})
      if ((*part)[2] != 0.0)
        return false;
    for (int j = 0; j < grid.ny; ++j)
      if (std::abs(grid.y(j) + grid.y(grid.ny - 1 - j)) > 1e-12 * grid.hy)
        return false;
    return true;
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
      {
        const auto [ax, ay] = setup.hertz_semi_axes();
        contact_pressure    = sampled_hertz_pressure(surface, ax, ay, setup.hertz_peak_pressure());
      }
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
    // On a mirror-symmetric history the risk at (x, -y) equals that at
    // (x, y): the criterion runs on the rows y >= 0 only.
    mirror_row = mirror_symmetric(setup, surface) ? surface.ny / 2 : 0;
    dang_van   = std::make_unique<DangVanField>(setup.depth_layers.size() * (surface.ny - mirror_row) * surface.nx,
                                                setup.dang_van, settings);

    if (setup.contact_edge_risk && setup.radius_x == setup.radius_y && setup.sliding_amplitude != 0.0 &&
        setup.exact.masing_level_spacing > 0.0)
      if (const MasingTraction *model = masing_traction(*traction_model))
        {
          const auto [a, a_y] = setup.hertz_semi_axes();
          if (ContactEdgeRisk::fits(surface, a))
            {
              ContactEdgeCase edge_case;
              edge_case.contact_radius       = a;
              edge_case.peak_pressure        = setup.hertz_peak_pressure();
              edge_case.friction_coefficient = setup.friction_coefficient;
              if (setup.friction_coefficient > 0.0)
                edge_case.gross_slip_shift =
                  MindlinLoop(setup.friction_coefficient, setup.normal_load, a, setup.materials.tangential_modulus())
                    .gross_slip_displacement();
              edge_case.level_spacing     = setup.exact.masing_level_spacing;
              // The virgin loading's largest shift is the amplitude, and no
              // branch of Masing's rule reaches beyond it.
              const double amplitude = std::abs(setup.sliding_amplitude);
              if (amplitude < edge_case.gross_slip_shift)
                edge_case.stick_radius = a * std::sqrt(1.0 - amplitude / edge_case.gross_slip_shift);
              // The virgin levels point along the first shift: for a negative
              // amplitude, opposite to the sliding direction.
              edge_case.sliding_angle = setup.sliding_direction + (setup.sliding_amplitude < 0.0 ? M_PI : 0.0);
              edge_case.poisson_ratio     = setup.materials.lower.poisson_ratio;
              edge_case.dang_van          = setup.dang_van;
              edge_case.dang_van_settings = settings;
              edge_case.stress_evaluator  = setup.stress_evaluator;
              edge_case.stress_evaluator.method = "fft"; // the surface only: exact to round-off and fast
              edge          = std::make_unique<ContactEdgeRisk>(edge_case, surface, contact_pressure);
              edge_traction = model;
            }
        }

    // The superposition needs the level table to stay within the budget: the
    // history reaches the virgin shift amplitude (the first quarter cycle; a
    // branch from a reversal at +-amplitude halves the shift of at most
    // 2 amplitude), so amplitude / spacing + 1 levels besides level 0.
    const double spacing = setup.exact.masing_level_spacing;
    if (setup.superposed_stresses && spacing > 0.0)
      if (const MasingTraction *model = masing_traction(*traction_model))
        {
          const double levels = std::ceil(std::abs(setup.sliding_amplitude) / spacing) + 2.0;
          // Mirrored, the parts are kept on the criterion's rows only: half
          // the memory the kernel zeroes on first touch, half the copies.
          const std::size_t size  = setup.depth_layers.size() * stress_component_count * superposed_plane();
          const double      bytes = levels * static_cast<double>(size) * sizeof(double);
          if (bytes <= static_cast<double>(setup.superposition_budget))
            {
              masing        = model;
              virgin_stress = std::make_unique<LevelStore>(static_cast<std::size_t>(levels), size);
              superposed_part(pressure_stress, pressure_part);
            }
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
    const MasingTraction::Composition before = masing          ? masing->composition() :
                                               edge_traction ? edge_traction->composition() :
                                                               MasingTraction::Composition{};
    auto start = Clock::now();
    traction_model->advance(contact_pressure, setup.friction_coefficient, slip * std::cos(setup.sliding_direction),
                            slip * std::sin(setup.sliding_direction));
    times.traction += seconds_since(start);
    iterations_total += traction_model->last_iterations();
    iterations_most = std::max(iterations_most, traction_model->last_iterations());
    if (edge)
      {
        start = Clock::now();
        const StressTensor bulk = setup.bulk_stress.at(0.0, time(), setup.period);
        std::array<double, stress_component_count> surface_bulk;
        for (int component = 0; component < stress_component_count; ++component)
          surface_bulk[component] = bulk[component];
        edge->add_step(*edge_traction, before, surface_bulk);
        times.dang_van += seconds_since(start);
      }

    start = Clock::now();
    if (masing)
      {
        const MasingTraction::Composition &recipe = masing->composition();
        if (recipe.reversal >= 0 && reversal_stress.count(recipe.reversal) == 0)
          // A new reversal: its traction is the one before this step.
          compose_shear(before, reversal_stress[recipe.reversal]);
        // A reversal Masing's memory dropped goes once no held-back step needs it.
        const auto needed = [&](std::int64_t id) {
          return masing->holds_reversal(id) ||
                 std::any_of(pending.begin(), pending.end(), [id](const PendingStep &p) { return p.recipe.reversal == id; });
        };
        for (auto kept = reversal_stress.begin(); kept != reversal_stress.end();)
          kept = needed(kept->first) ? std::next(kept) : reversal_stress.erase(kept);
        // The levels' stresses the step needs, evaluated before the sum.
        level_stresses(recipe.lower);
        level_stresses(recipe.upper);
        times.stresses += seconds_since(start);
        // The sum, von Mises and Dang Van of the step are held back and run
        // with the next ones (run_pending_steps): a block of points then goes
        // through many steps while it is in cache.
        pending.push_back({recipe, bulk_parts()});
        total_recipe  = recipe;
        total_written = false;
        if (pending.size() >= pending_steps_at_most || finished())
          run_pending_steps();
        return;
      }
    stresses->evaluate(no_load, traction_model->traction_x(), traction_model->traction_y(), shear_stress);
    add_stresses(&shear_stress);
    times.stresses += seconds_since(start);

    start = Clock::now();
    if (mirrored())
      {
        const std::size_t per_layer = surface.size(), first_point = std::size_t(mirror_row) * surface.nx;
        const double     *total     = total_stress.values.data();
        dang_van->add_step((surface.ny - mirror_row) * surface.nx,
                           [&](std::size_t layer, std::size_t first, std::size_t count, double *const *out) {
                             for (int component = 0; component < stress_component_count; ++component)
                               std::copy_n(total + (layer * stress_component_count + component) * per_layer +
                                             first_point + first,
                                           count, out[component]);
                           });
      }
    else
      dang_van->add_step(total_stress);
    times.dang_van += seconds_since(start);
  }

  /// One block for the stresses of all levels the history can reach, in
  /// transparent huge pages where the system offers them: 200 MB in 4 KiB
  /// pages would cost ~50000 page faults, a noticeable part of the run.
  /// Levels past the estimate (not expected) go to separate fields.
  struct FrettingRun::LevelStore
  {
    struct Free
    {
      void operator()(double *pointer) const { std::free(pointer); }
    };
    /// A level's evaluation: not asked for, queued (defer_level_stresses),
    /// taken by a thread, done.
    enum class State : unsigned char
    {
      none,
      queued,
      taken,
      ready
    };
    std::unique_ptr<double, Free>      block;
    std::size_t                        field_size = 0, capacity = 0;
    std::map<std::size_t, std::vector<double>> beyond;
    StressField                        scratch;        ///< the run's own thread's
    StressField                        helper_scratch; ///< help_with_level_stresses()'s, under `helping`

    std::mutex                         mutex; ///< guards state, queued, deferred_seconds
    std::condition_variable            done;  ///< a taken level is ready
    std::vector<State>                 state;
    /// Queued levels with their tractions, copied: the traction model's table
    /// may move them while another thread evaluates.
    std::map<std::size_t, std::pair<Field, Field>> queued;
    double                             deferred_seconds = 0.0; ///< evaluations on other threads
    std::mutex                         helping;    ///< one helper at a time
    std::mutex                         evaluating; ///< one evaluation at a time (the evaluator's buffers)

    double *at(std::size_t k) const { return block.get() + k * field_size; }

    LevelStore(std::size_t levels, std::size_t values) : field_size(values), capacity(levels), state(levels, State::none)
    {
      constexpr std::size_t huge  = std::size_t(2) << 20;
      const std::size_t     bytes = (levels * values * sizeof(double) + huge - 1) / huge * huge;
      block.reset(static_cast<double *>(std::aligned_alloc(huge, bytes)));
      if (!block)
        throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
      madvise(block.get(), bytes, MADV_HUGEPAGE); // advice only: failure is harmless
#endif
    }
  };

  void FrettingRun::evaluate_level(std::size_t level, const Field &tau_x, const Field &tau_y,
                                   StressField &scratch) const
  {
    LevelStore                 &store = *virgin_stress;
    std::lock_guard<std::mutex> lock(store.evaluating);
    stresses->evaluate(no_load, tau_x, tau_y, scratch);
    superposed_part(scratch, store.at(level));
  }

  const double *FrettingRun::ready_level(std::size_t level) const
  {
    LevelStore &store = *virgin_stress;
    if (level >= store.capacity)
      return store.beyond.at(level).data();
    std::unique_lock<std::mutex> lock(store.mutex);
    if (store.state[level] == LevelStore::State::queued)
      {
        // Not taken yet: evaluated here.
        auto tractions = std::move(store.queued.at(level));
        store.queued.erase(level);
        store.state[level] = LevelStore::State::taken;
        lock.unlock();
        evaluate_level(level, tractions.first, tractions.second, store.scratch);
        lock.lock();
        store.state[level] = LevelStore::State::ready;
      }
    else if (store.state[level] == LevelStore::State::none)
      {
        store.state[level] = LevelStore::State::taken;
        lock.unlock();
        evaluate_level(level, masing->virgin_level_x(level), masing->virgin_level_y(level), store.scratch);
        lock.lock();
        store.state[level] = LevelStore::State::ready;
      }
    store.done.wait(lock, [&] { return store.state[level] == LevelStore::State::ready; });
    return store.at(level);
  }

  void FrettingRun::help_with_level_stresses() const
  {
    if (!virgin_stress)
      return;
    LevelStore                  &store = *virgin_stress;
    std::unique_lock<std::mutex> helping(store.helping, std::try_to_lock);
    if (!helping.owns_lock())
      return;
    for (;;)
      {
        std::size_t                level;
        std::pair<Field, Field>    tractions;
        {
          std::lock_guard<std::mutex> lock(store.mutex);
          if (store.queued.empty())
            return;
          level     = store.queued.begin()->first;
          tractions = std::move(store.queued.begin()->second);
          store.queued.erase(store.queued.begin());
          store.state[level] = LevelStore::State::taken;
        }
        const auto start = Clock::now();
        evaluate_level(level, tractions.first, tractions.second, store.helper_scratch);
        {
          std::lock_guard<std::mutex> lock(store.mutex);
          store.state[level] = LevelStore::State::ready;
          store.deferred_seconds += seconds_since(start);
        }
        store.done.notify_all();
      }
  }

  const double *FrettingRun::level_stresses(std::size_t level)
  {
    LevelStore &store = *virgin_stress;
    if (level >= store.capacity)
      {
        std::vector<double> &field = store.beyond[level];
        if (field.empty())
          {
            std::lock_guard<std::mutex> lock(store.evaluating);
            stresses->evaluate(no_load, masing->virgin_level_x(level), masing->virgin_level_y(level), store.scratch);
            field.resize(store.field_size);
            superposed_part(store.scratch, field.data());
          }
        return field.data();
      }
    {
      std::lock_guard<std::mutex> lock(store.mutex);
      if (store.state[level] != LevelStore::State::none)
        return store.state[level] == LevelStore::State::ready ? store.at(level) : nullptr;
      if (level_stresses_deferred)
        {
          store.queued[level] = {masing->virgin_level_x(level), masing->virgin_level_y(level)};
          store.state[level]  = LevelStore::State::queued;
          return nullptr;
        }
      store.state[level] = LevelStore::State::taken;
    }
    evaluate_level(level, masing->virgin_level_x(level), masing->virgin_level_y(level), store.scratch);
    std::lock_guard<std::mutex> lock(store.mutex);
    store.state[level] = LevelStore::State::ready;
    return store.at(level);
  }

  std::size_t FrettingRun::superposed_plane() const
  {
    return static_cast<std::size_t>(surface.ny - mirror_row) * surface.nx;
  }

  void FrettingRun::superposed_part(const StressField &full, double *out) const
  {
    const std::size_t per_layer = surface.size(), plane = superposed_plane(), first_point = per_layer - plane;
    for (std::size_t part = 0; part < setup.depth_layers.size() * stress_component_count; ++part)
      std::copy_n(full.values.begin() + part * per_layer + first_point, plane, out + part * plane);
  }

  void FrettingRun::superposed_part(const StressField &full, std::vector<double> &out) const
  {
    out.resize(setup.depth_layers.size() * stress_component_count * superposed_plane());
    superposed_part(full, out.data());
  }

  void FrettingRun::compose_shear(const MasingTraction::Composition &recipe, std::vector<double> &out)
  {
    level_stresses(recipe.lower);
    level_stresses(recipe.upper);
    const double *lower = ready_level(recipe.lower);
    const double *upper = ready_level(recipe.upper);
    const double *base  = recipe.reversal >= 0 ? reversal_stress.at(recipe.reversal).data() : pressure_part.data();
    out.resize(pressure_part.size());
    double           *result = out.data();
    const double      f = recipe.factor, w = recipe.weight;
    const std::int64_t size = static_cast<std::int64_t>(out.size());
    // As MasingTraction composes the traction, value by value.
#pragma omp parallel for simd schedule(static) if (size > 65536)
    for (std::int64_t k = 0; k < size; ++k)
      result[k] = base[k] + f * ((1.0 - w) * lower[k] + w * upper[k]);
  }

  namespace
  {
    /// Where a step's stresses come from: sigma = pressure + shear + bulk with
    /// the shear given or none, or sigma = base + f ((1 - w) lower + w upper)
    /// + bulk, composed as the traction is, the base (the pressure's
    /// stresses, plus a reversal's shear) including the pressure.
    enum class Shear
    {
      none,
      given,
      composed
    };

    struct StressParts
    {
      const double *pressure = nullptr, *given = nullptr, *base = nullptr, *lower = nullptr, *upper = nullptr;
      double        factor = 0.0, weight = 0.0;

      Shear kind() const { return lower ? Shear::composed : (given ? Shear::given : Shear::none); }
    };

    /// The six components of `count` points from value `offset` on (component
    /// c at offset + c stride + k) into out[c][k]; returns the largest of
    /// `largest` and their 6 J2 = 2 sigma_vM^2. Branch-free for each kind, so
    /// that it vectorises.
    template <Shear kind>
    double sum_block(const StressParts &parts, std::size_t offset, std::size_t stride, const double *plus,
                     std::size_t count, double *const *out, double largest)
    {
      const double *p = parts.pressure + offset, *given = parts.given + offset, *base = parts.base + offset;
      const double *low = parts.lower + offset, *high = parts.upper + offset;
      const double  f = parts.factor, w = parts.weight;
#pragma omp simd reduction(max : largest)
      for (std::size_t k = 0; k < count; ++k)
        {
          double sigma[stress_component_count];
          for (int component = 0; component < stress_component_count; ++component)
            {
              const std::size_t at = component * stride + k;
              // As MasingTraction composes the traction, value by value.
              if constexpr (kind == Shear::composed)
                sigma[component] = base[at] + f * ((1.0 - w) * low[at] + w * high[at]) + plus[component];
              else if constexpr (kind == Shear::given)
                sigma[component] = p[at] + given[at] + plus[component];
              else
                sigma[component] = p[at] + 0.0 + plus[component];
              out[component][k] = sigma[component];
            }
          const double xx = sigma[0], yy = sigma[1], zz = sigma[2], yz = sigma[3], xz = sigma[4], xy = sigma[5];
          const double j2_times_6 = (xx - yy) * (xx - yy) + (yy - zz) * (yy - zz) + (zz - xx) * (zz - xx) +
                                    6.0 * (yz * yz + xz * xz + xy * xy);
          largest = std::max(largest, j2_times_6);
        }
      return largest;
    }

    double sum_block(const StressParts &parts, std::size_t offset, std::size_t stride, const double *plus,
                     std::size_t count, double *const *out, double largest)
    {
      switch (parts.kind())
        {
          case Shear::composed:
            return sum_block<Shear::composed>(parts, offset, stride, plus, count, out, largest);
          case Shear::given:
            return sum_block<Shear::given>(parts, offset, stride, plus, count, out, largest);
          case Shear::none:
            break;
        }
      return sum_block<Shear::none>(parts, offset, stride, plus, count, out, largest);
    }
  } // namespace

  std::vector<std::array<double, stress_component_count>> FrettingRun::bulk_parts() const
  {
    const std::size_t layers = setup.depth_layers.size();
    const bool        bulk   = !setup.bulk_stress.is_zero();
    std::vector<std::array<double, stress_component_count>> add(layers);
    for (std::size_t layer = 0; layer < layers; ++layer)
      {
        const StressTensor bulk_here =
          bulk ? setup.bulk_stress.at(setup.depth_layers[layer], time(), setup.period) : StressTensor{};
        for (int component = 0; component < stress_component_count; ++component)
          add[layer][component] = bulk_here[component];
      }
    return add;
  }

  void FrettingRun::add_stresses(const StressField *shear)
  {
    const std::size_t per_layer = surface.size();
    const std::size_t layers    = setup.depth_layers.size();
    const auto        add       = bulk_parts();
    StressParts       parts;
    parts.pressure = pressure_stress.values.data();
    parts.given    = shear ? shear->values.data() : nullptr;
    double *total  = total_stress.values.data();
    // The largest 6 J2 = 2 sigma_vM^2 (von_mises_max: sqrt is monotone, so
    // its root is the largest root). A maximum does not depend on the order:
    // neither the threads' split nor the vector lanes change it.
    double largest = largest_six_j2;
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
          const std::size_t offset = layer * stress_component_count * per_layer + begin;
          double           *out[stress_component_count];
          for (int component = 0; component < stress_component_count; ++component)
            out[component] = total + offset + component * per_layer;
          mine = sum_block(parts, offset, per_layer, add[layer].data(), end - begin, out, mine);
        }
#pragma omp critical(fretting_run_von_mises)
      largest = std::max(largest, mine);
    }
    largest_six_j2 = largest;
  }

  void FrettingRun::run_pending_steps() const
  {
    if (pending.empty())
      return;
    // Waiting for (or evaluating) levels still queued counts as stresses.
    const auto                     levels_start = Clock::now();
    const std::vector<PendingStep> steps        = std::move(pending);
    pending.clear();
    std::vector<StressParts> parts(steps.size());
    for (std::size_t k = 0; k < steps.size(); ++k)
      {
        const MasingTraction::Composition &recipe = steps[k].recipe;
        StressParts                       &part   = parts[k];
        part.pressure = pressure_part.data();
        part.lower    = ready_level(recipe.lower);
        part.upper    = ready_level(recipe.upper);
        part.base     = recipe.reversal >= 0 ? reversal_stress.at(recipe.reversal).data() : part.pressure;
        part.factor   = recipe.factor;
        part.weight   = recipe.weight;
      }
    times.stresses += seconds_since(levels_start);
    const auto start = Clock::now();
    // Mirrored, the criterion's points and the parts are the rows from
    // mirror_row on, and the von Mises maximum over them is that over every
    // point.
    const std::size_t plane = superposed_plane();
    // Per thread, a cache line apart; a maximum, so the split cannot change it.
    constexpr std::size_t apart = 8;
    std::vector<double>   largest(apart * static_cast<std::size_t>(omp_get_max_threads()), largest_six_j2);
    dang_van->add_steps(plane, steps.size(),
                        [&](std::size_t step, std::size_t layer, std::size_t first, std::size_t count,
                            double *const *out) {
                          double &mine = largest[apart * static_cast<std::size_t>(omp_get_thread_num())];
                          mine = sum_block(parts[step], layer * stress_component_count * plane + first, plane,
                                           steps[step].bulk[layer].data(), count, out, mine);
                        });
    for (std::size_t thread = 0; thread < largest.size(); thread += apart)
      largest_six_j2 = std::max(largest_six_j2, largest[thread]);
    times.dang_van += seconds_since(start);
  }

  const DangVanField &FrettingRun::risk() const
  {
    run_pending_steps();
    return *dang_van;
  }

  const FrettingStageTimes &FrettingRun::stage_times() const
  {
    run_pending_steps();
    if (virgin_stress)
      {
        // The levels' evaluations on other threads count as stresses too.
        std::lock_guard<std::mutex> lock(virgin_stress->mutex);
        times.stresses += virgin_stress->deferred_seconds;
        virgin_stress->deferred_seconds = 0.0;
      }
    return times;
  }

  double FrettingRun::von_mises_max() const
  {
    run_pending_steps();
    return std::sqrt(0.5 * largest_six_j2);
  }

  const StressField &FrettingRun::stress() const
  {
    if (!total_written)
      {
        // The same sums as the Dang Van step read, written out; mirrored, on
        // the rows from mirror_row on, and the rows below are their mirror
        // images (yz and xy change sign).
        StressParts parts;
        parts.pressure = pressure_part.data();
        parts.lower    = ready_level(total_recipe.lower);
        parts.upper    = ready_level(total_recipe.upper);
        parts.base = total_recipe.reversal >= 0 ? reversal_stress.at(total_recipe.reversal).data() : parts.pressure;
        parts.factor = total_recipe.factor;
        parts.weight = total_recipe.weight;
        const std::size_t per_layer = surface.size(), plane = superposed_plane(), first_point = per_layer - plane;
        const std::size_t nx = surface.nx, ny = surface.ny;
        const auto        add   = bulk_parts();
        double           *total = total_stress.values.data();
        for (std::size_t layer = 0; layer < add.size(); ++layer)
          {
            double *out[stress_component_count];
            for (int component = 0; component < stress_component_count; ++component)
              out[component] = total + (layer * stress_component_count + component) * per_layer + first_point;
            sum_block(parts, layer * stress_component_count * plane, plane, add[layer].data(), plane, out, 0.0);
            for (int component = 0; component < stress_component_count; ++component)
              {
                const double sign  = component == 3 || component == 5 ? -1.0 : 1.0;
                double      *field = total + (layer * stress_component_count + component) * per_layer;
                for (std::size_t j = 0; j < std::size_t(mirror_row); ++j)
                  for (std::size_t i = 0; i < nx; ++i)
                    field[j * nx + i] = sign * field[(ny - 1 - j) * nx + i];
              }
          }
        total_written = true;
      }
    return total_stress;
  }

  void FrettingRun::mirror_onto(const std::vector<double> &half, std::vector<double> &full) const
  {
    const std::size_t nx = surface.nx, ny = surface.ny, first = mirror_row, rows = ny - first;
    const std::size_t layers = setup.depth_layers.size();
    full.resize(layers * ny * nx);
    for (std::size_t layer = 0; layer < layers; ++layer)
      for (std::size_t j = 0; j < ny; ++j)
        {
          const std::size_t row = (j >= first ? j : ny - 1 - j) - first;
          std::copy_n(half.begin() + (layer * rows + row) * nx, nx, full.begin() + (layer * ny + j) * nx);
        }
  }

  const std::vector<double> &FrettingRun::whole_field(const std::vector<double> &field, std::vector<double> &whole,
                                                       std::int64_t &whole_step) const
  {
    if (!mirrored())
      return field;
    if (whole_step != dang_van->step_count())
      {
        mirror_onto(field, whole);
        whole_step = dang_van->step_count();
      }
    return whole;
  }

  const std::vector<double> &FrettingRun::risk_now() const
  {
    run_pending_steps();
    return whole_field(dang_van->risk(), mirrored_now, mirrored_now_step);
  }

  const std::vector<double> &FrettingRun::risk_max() const
  {
    run_pending_steps();
    return whole_field(dang_van->risk_max(), mirrored_max, mirrored_max_step);
  }

  std::size_t FrettingRun::infinite_risk_max_count() const
  {
    const std::vector<double> &values = risk_max();
    return static_cast<std::size_t>(std::count(values.begin(), values.end(), std::numeric_limits<double>::infinity()));
  }

  RiskMaximum FrettingRun::risk_maximum() const
  {
    run_pending_steps();
    const std::vector<double> &risk_max = this->risk_max();
    RiskMaximum                result;
    const std::size_t          worst = largest_finite_point(risk_max);
    if (worst == risk_max.size())
      return result;
    const std::size_t cell = worst % surface.size();
    result.value           = risk_max[worst];
    result.layer           = static_cast<int>(worst / surface.size());
    result.i               = static_cast<int>(cell % surface.nx);
    result.j               = static_cast<int>(cell / surface.nx);
    const int row          = result.j >= mirror_row ? result.j : surface.ny - 1 - result.j;
    result.step = dang_van->risk_max_step()[(result.layer * (surface.ny - mirror_row) + row - mirror_row) * surface.nx + result.i];
    return result;
  }

  std::optional<ContactEdgeRiskMaximum> FrettingRun::edge_risk_maximum() const
  {
    if (!edge)
      return std::nullopt;
    return edge->maximum();
  }

  RiskMaximum fretting_risk_maximum(const FrettingCase &fretting_case, const SurfaceGrid &grid)
  {
    FrettingRun run(fretting_case, grid);
    while (!run.finished())
      run.advance();
    return run.risk_maximum();
  }
} // namespace fretsim::contact
