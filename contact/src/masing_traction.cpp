#include <fretsim/contact/masing_traction.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fretsim::contact
{
  /// The virgin branch: levels of shift with their tractions, and the solver
  /// left at the highest level to continue the monotone loading.
  struct MasingTraction::Virgin
  {
    /// The first loading is monotone: each level starts from the last two
    /// extrapolated.
    static PartialSlipSettings monotone(PartialSlipSettings settings)
    {
      settings.extrapolated_start = true;
      return settings;
    }

    Virgin(const SurfaceGrid &grid, const MaterialPair &materials, const PartialSlipSettings &settings)
      : solver(grid, materials, monotone(settings))
      , shifts{0.0}
      , tau_x{grid.zeros()}
      , tau_y{grid.zeros()}
    {
    }

    PartialSlipSolver  solver;
    std::vector<double> shifts; // ascending, shifts[0] = 0
    std::vector<Field>  tau_x, tau_y;
    double              widest_spacing = 0.0;
  };

  MasingTraction::MasingTraction(const SurfaceGrid &grid_, const MaterialPair &materials,
                                 const PartialSlipSettings &settings)
    : grid(grid_)
    , virgin(std::make_unique<Virgin>(grid_, materials, settings))
    , level_spacing(settings.masing_level_spacing)
    , tau_x(grid_.zeros())
    , tau_y(grid_.zeros())
    , work_x(grid_.zeros())
    , work_y(grid_.zeros())
  {
  }

  MasingTraction::~MasingTraction() = default;

  std::size_t MasingTraction::virgin_levels() const { return virgin->shifts.size() - 1; }

  const Field &MasingTraction::virgin_level_x(std::size_t level) const { return virgin->tau_x.at(level); }
  const Field &MasingTraction::virgin_level_y(std::size_t level) const { return virgin->tau_y.at(level); }

  bool MasingTraction::holds_reversal(std::int64_t id) const
  {
    return std::any_of(reversals.begin(), reversals.end(), [id](const Reversal &r) { return r.id == id; });
  }

  void MasingTraction::reset()
  {
    virgin->solver.reset();
    virgin->shifts = {0.0};
    virgin->tau_x  = {grid.zeros()};
    virgin->tau_y  = {grid.zeros()};
    virgin->widest_spacing = 0.0;
    started = direction_set = false;
    shift   = 0.0;
    heading = 0;
    reversals.clear();
    recipe = Composition{};
    std::fill(tau_x.begin(), tau_x.end(), 0.0);
    std::fill(tau_y.begin(), tau_y.end(), 0.0);
  }

  void MasingTraction::virgin_traction(double s, Field &vx, Field &vy)
  {
    auto &v = *virgin;
    if (s > v.shifts.back() * (1.0 + 1e-12))
      {
        // Continue the monotone first loading: to the next multiples of the
        // level spacing past s, or (no spacing) in increments no wider than
        // the table's widest, so the table stays as fine as the history's steps.
        const double top = v.shifts.back();
        double       width;
        int          count;
        if (level_spacing > 0.0)
          {
            width = level_spacing;
            count = std::max(1, static_cast<int>(std::ceil(s / width * (1.0 - 1e-12))) -
                                  static_cast<int>(std::lround(top / width)));
          }
        else
          {
            width = v.widest_spacing > 0.0 ? v.widest_spacing : s - top;
            count = std::max(1, static_cast<int>(std::ceil((s - top) / width * (1.0 - 1e-12))));
          }
        for (int k = 1; k <= count; ++k)
          {
            const double level     = level_spacing > 0.0 ? top + k * width : (k == count ? s : top + (s - top) * k / count);
            const double increment = level - v.shifts.back();
            iterations += v.solver.advance(pressure, friction, increment * direction_x, increment * direction_y)
                            .iterations;
            v.widest_spacing = std::max(v.widest_spacing, increment);
            v.shifts.push_back(level);
            v.tau_x.push_back(v.solver.traction_x());
            v.tau_y.push_back(v.solver.traction_y());
          }
      }
    // Linear interpolation between the two levels around s.
    const auto   upper = std::min<std::size_t>(
      std::upper_bound(v.shifts.begin(), v.shifts.end(), s) - v.shifts.begin(), v.shifts.size() - 1);
    const auto   lower = upper - 1;
    const double span  = v.shifts[upper] - v.shifts[lower];
    const double w     = span > 0.0 ? std::clamp((s - v.shifts[lower]) / span, 0.0, 1.0) : 1.0;
    recipe.lower       = lower;
    recipe.upper       = upper;
    recipe.weight      = w;
    for (std::size_t c = 0; c < vx.size(); ++c)
      {
        vx[c] = (1.0 - w) * v.tau_x[lower][c] + w * v.tau_x[upper][c];
        vy[c] = (1.0 - w) * v.tau_y[lower][c] + w * v.tau_y[upper][c];
      }
  }

  void MasingTraction::compose()
  {
    if (reversals.empty())
      {
        // The virgin branch; the virgin traction is odd in the shift.
        virgin_traction(std::abs(shift), work_x, work_y);
        const double sign = shift < 0.0 ? -1.0 : 1.0;
        recipe.reversal   = -1;
        recipe.factor     = sign;
        for (std::size_t c = 0; c < tau_x.size(); ++c)
          {
            tau_x[c] = sign * work_x[c];
            tau_y[c] = sign * work_y[c];
          }
        return;
      }
    const Reversal &r    = reversals.back();
    const double    d    = shift - r.shift;
    const double    sign = d < 0.0 ? -1.0 : 1.0;
    virgin_traction(0.5 * std::abs(d), work_x, work_y);
    recipe.reversal = r.id;
    recipe.factor   = 2.0 * sign;
    for (std::size_t c = 0; c < tau_x.size(); ++c)
      {
        tau_x[c] = r.tau_x[c] + 2.0 * sign * work_x[c];
        tau_y[c] = r.tau_y[c] + 2.0 * sign * work_y[c];
      }
  }

  void MasingTraction::advance(const Field &p, double mu, double dx, double dy)
  {
    iterations = 0;
    if (!started)
      {
        if (p.size() != grid.size())
          throw std::invalid_argument("MasingTraction: the pressure does not match the grid");
        pressure = p;
        friction = mu;
        started  = true;
      }
    else if (mu != friction || p != pressure)
      throw std::logic_error("MasingTraction: the superposition needs the pressure and friction coefficient of the "
                             "first step at every step");
    const double length = std::hypot(dx, dy);
    if (length == 0.0)
      return;
    if (!direction_set)
      {
        direction_x   = dx / length;
        direction_y   = dy / length;
        direction_set = true;
      }
    else if (std::abs(dx * direction_y - dy * direction_x) > 1e-9 * length)
      throw std::logic_error("MasingTraction: the superposition needs a shift along one line; use the exact model "
                             "for a shift that turns");
    const double increment = dx * direction_x + dy * direction_y;
    const int    sign      = increment > 0.0 ? 1 : -1;
    if (heading != 0 && sign != heading)
      reversals.push_back({shift, tau_x, tau_y, next_reversal_id++});
    heading = sign;
    shift += increment;

    // Masing's memory: a branch that passes the reversal it heads for (the
    // mirror of the first reversal for the branch back from it) closes its
    // loop and continues the branch before.
    while (!reversals.empty())
      {
        const bool   first  = reversals.size() == 1;
        const double target = first ? -reversals.back().shift : reversals[reversals.size() - 2].shift;
        const double slack  = 1e-12 * std::max(std::abs(target), std::abs(reversals.back().shift));
        if (heading * (shift - target) <= slack)
          break;
        reversals.pop_back();
        if (!first)
          reversals.pop_back();
      }
    compose();
  }

  Field MasingTraction::effective_friction() const
  {
    Field result = grid.zeros();
    for (std::size_t c = 0; c < result.size(); ++c)
      if (started && pressure[c] > 0.0 && friction > 0.0)
        result[c] = std::hypot(tau_x[c], tau_y[c]) / (friction * pressure[c]);
    return result;
  }

  double MasingTraction::slip_area_fraction() const
  {
    std::size_t loaded = 0, slipping = 0;
    for (std::size_t c = 0; c < tau_x.size(); ++c)
      if (started && pressure[c] > 0.0)
        {
          ++loaded;
          slipping += std::hypot(tau_x[c], tau_y[c]) >= (1.0 - 1e-9) * friction * pressure[c];
        }
    return loaded > 0 ? static_cast<double>(slipping) / loaded : 0.0;
  }
} // namespace fretsim::contact
