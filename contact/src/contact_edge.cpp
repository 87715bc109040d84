#include <fretsim/contact/contact_edge.h>

#include <fretsim/contact/hertz.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fretsim::contact
{
  namespace
  {
    /// 20-point Gauss-Legendre on [-1, 1]: the ray integrand below is a
    /// trigonometric polynomial times a smooth factor, integrated to round-off.
    constexpr std::array<double, 10> gauss_nodes{0.0765265211334973, 0.2277858511416451, 0.3737060887154195,
                                                 0.5108670019508271, 0.6360536807265150, 0.7463319064601508,
                                                 0.8391169718222188, 0.9122344282513259, 0.9639719272779138,
                                                 0.9931285991850949};
    constexpr std::array<double, 10> gauss_weights{0.1527533871307258, 0.1491729864726037, 0.1420961093183820,
                                                   0.1316886384491766, 0.1181945319615184, 0.1019301198172404,
                                                   0.0832767415767048, 0.0626720483341091, 0.0406014298003869,
                                                   0.0176140071391521};

    /// The unit-peak Hertz-shaped traction in +x, surface stresses at (x, y).
    StressTensor shear_x_shape(double x, double y, double c, double nu)
    {
      StressTensor s;
      const double d = std::hypot(x, y);
      if (d <= c)
        {
          // Johnson, Contact Mechanics §7.1 (docs/references.md §3.2).
          s.xx = -M_PI * (4.0 + nu) * x / (8.0 * c);
          s.yy = -3.0 * M_PI * nu * x / (8.0 * c);
          s.xz = -std::sqrt(std::max(0.0, 1.0 - d * d / (c * c)));
          s.xy = -M_PI * (2.0 - nu) * y / (8.0 * c);
          return s;
        }
      // Outside: sources at distance t along rays of angle phi from the point;
      // Cerruti's surface kernel is g(phi) / t^2, and along a chord
      // [t1, t2] the load is sqrt((t - t1)(t2 - t)) / c, whose integral
      // against 1/t is pi ((t1 + t2)/2 - sqrt(t1 t2)) = pi (d cos psi - sqrt(d^2 - c^2))
      // with psi the ray's angle from the direction to the centre.
      const double toward = std::atan2(y, x) + M_PI, half_angle = std::asin(c / d), e = std::sqrt(d * d - c * c);
      for (std::size_t q = 0; q < 2 * gauss_nodes.size(); ++q)
        {
          const std::size_t n   = q % gauss_nodes.size();
          const double      psi = (q < gauss_nodes.size() ? -1.0 : 1.0) * gauss_nodes[n] * half_angle;
          const double      w   = gauss_weights[n] * half_angle * (d * std::cos(psi) - e);
          const double      cp = std::cos(toward + psi), sp = std::sin(toward + psi);
          s.xx += w * -cp / (2.0 * M_PI) * (-3.0 * cp * cp + (1.0 - 2.0 * nu) * (1.0 - 3.0 * sp * sp));
          s.yy += w * 3.0 * nu * cp * sp * sp / M_PI;
          s.xy += w * -sp / (2.0 * M_PI) * (-3.0 * cp * cp + (1.0 - 2.0 * nu) * (3.0 * cp * cp - 1.0));
        }
      for (int k = 0; k < stress_component_count; ++k)
        s[k] *= M_PI / c;
      return s;
    }

  } // namespace

  StressTensor hertz_pressure_surface_stress(double x, double y, double c, double nu)
  {
    // Johnson, Contact Mechanics eq. 3.41 (inside) and 3.42 (outside), polar.
    const double r2 = x * x + y * y, r = std::sqrt(r2);
    StressTensor s;
    if (r == 0.0)
      {
        s.xx = s.yy = -(1.0 + 2.0 * nu) / 2.0;
        s.zz        = -1.0;
        return s;
      }
    const double k      = std::sqrt(std::max(0.0, 1.0 - r2 / (c * c)));
    const double radial = (1.0 - 2.0 * nu) / 3.0 * (c * c / r2) * (1.0 - k * k * k);
    const double sr = radial - k, st = -radial - 2.0 * nu * k;
    const double cs = x / r, sn = y / r;
    s.xx = sr * cs * cs + st * sn * sn;
    s.yy = sr * sn * sn + st * cs * cs;
    s.zz = -k;
    s.xy = (sr - st) * sn * cs;
    return s;
  }

  StressTensor hertz_shear_surface_stress(double x, double y, double c, double nu, double angle)
  {
    // Along y: the x shape reflected in the plane x = y. Each part only where
    // the direction has a component along it.
    const double ca = std::cos(angle), sa = std::sin(angle);
    const StressTensor along_x  = ca != 0.0 ? shear_x_shape(x, y, c, nu) : StressTensor{};
    const StressTensor mirrored = sa != 0.0 ? shear_x_shape(y, x, c, nu) : StressTensor{};
    StressTensor       along_y;
    along_y.xx = mirrored.yy;
    along_y.yy = mirrored.xx;
    along_y.yz = mirrored.xz;
    along_y.xy = mirrored.xy;
    StressTensor s;
    for (int k = 0; k < stress_component_count; ++k)
      s[k] = ca * along_x[k] + sa * along_y[k];
    return s;
  }

  bool ContactEdgeRisk::fits(const SurfaceGrid &grid, double contact_radius)
  {
    // A point's stencil reaches the cell centres around it: half a cell
    // beyond the point, the border half a cell beyond those.
    const double half_width = std::min({-grid.x_min, -grid.y_min, grid.x_min + grid.nx * grid.hx,
                                        grid.y_min + grid.ny * grid.hy});
    return contact_radius + 1.5 * std::max(grid.hx, grid.hy) < half_width;
  }

  ContactEdgeRisk::ContactEdgeRisk(const ContactEdgeCase &edge_case, const SurfaceGrid &surface,
                                   const Field &pressure, int points)
    : setup(edge_case)
    , grid(surface)
    , no_load(surface.zeros())
  {
    const auto positive = [](double v) { return v > 0.0 && std::isfinite(v); };
    const auto non_negative = [](double v) { return v >= 0.0 && std::isfinite(v); };
    if (!positive(setup.contact_radius) || !positive(setup.peak_pressure) || !positive(setup.level_spacing) ||
        !non_negative(setup.friction_coefficient) || !non_negative(setup.gross_slip_shift) ||
        !non_negative(setup.stick_radius) || !(setup.stick_radius < setup.contact_radius) || points < 1)
      throw std::invalid_argument("contact edge risk: radius, peak pressure, level spacing and the number of points "
                                  "must be positive, friction, gross-slip shift and stick radius at least 0, the "
                                  "stick radius below the contact radius");
    const double a = setup.contact_radius;
    if (!fits(grid, a))
      throw std::invalid_argument("contact edge risk: the contact edge must lie a cell inside the grid");
    // The edge, the stick zone's largest front and circles between them: the
    // risk can peak anywhere in the slip annulus, its cusps at either end.
    std::vector<double> radii{a};
    if (setup.stick_radius > 0.0)
      for (int k = 0; k < annulus_circles; ++k)
        radii.push_back(setup.stick_radius + (a - setup.stick_radius) * k / annulus_circles);
    per_circle = static_cast<std::size_t>(points);
    for (std::size_t point = 0; point < radii.size() * per_circle; ++point)
      {
        const double r     = radii[point / per_circle];
        const double theta = setup.sliding_angle + 2.0 * M_PI * static_cast<double>(point % per_circle) / points;
        const double x = r * std::cos(theta), y = r * std::sin(theta);
        const double fx = (x - grid.x_min) / grid.hx - 0.5, fy = (y - grid.y_min) / grid.hy - 0.5;
        const int    i = static_cast<int>(std::floor(fx)), j = static_cast<int>(std::floor(fy));
        const double wx = fx - i, wy = fy - j;
        points_x.push_back(x);
        points_y.push_back(y);
        weights.push_back({(1 - wx) * (1 - wy), wx * (1 - wy), (1 - wx) * wy, wx * wy});
        cells.push_back({grid.index(i, j), grid.index(i + 1, j), grid.index(i, j + 1), grid.index(i + 1, j + 1)});
      }
    surface_stress = make_subsurface_stress(grid, {0.0}, setup.poisson_ratio, setup.stress_evaluator);

    // The pressure: its Hertz shape in closed form, the rest interpolated.
    const double p0     = setup.peak_pressure;
    const Field  shape_a = sampled_hertz_pressure(grid, a, a, 1.0);
    Field        rest   = pressure;
    for (std::size_t c = 0; c < rest.size(); ++c)
      rest[c] -= p0 * shape_a[c];
    surface_stress->evaluate(rest, no_load, no_load, scratch);
    const std::size_t count = points_x.size();
    pressure_part.assign(stress_component_count * count, 0.0);
    add_interpolated(scratch, 1.0, pressure_part);
    for (std::size_t m = 0; m < count; ++m)
      {
        const StressTensor exact = hertz_pressure_surface_stress(points_x[m], points_y[m], a, setup.poisson_ratio);
        for (int k = 0; k < stress_component_count; ++k)
          pressure_part[stress_component_count * m + k] += p0 * exact[k];
      }
    // The sliding traction's shape on the contact radius, per unit peak: its
    // closed form less what the grid makes of it.
    const double ca = std::cos(setup.sliding_angle), sa = std::sin(setup.sliding_angle);
    load_x = grid.zeros();
    load_y = grid.zeros();
    for (std::size_t c = 0; c < shape_a.size(); ++c)
      {
        load_x[c] = ca * shape_a[c];
        load_y[c] = sa * shape_a[c];
      }
    surface_stress->evaluate(no_load, load_x, load_y, scratch);
    radius_shape_part.assign(stress_component_count * count, 0.0);
    add_interpolated(scratch, -1.0, radius_shape_part);
    for (std::size_t m = 0; m < count; ++m)
      {
        const StressTensor exact =
          hertz_shear_surface_stress(points_x[m], points_y[m], a, setup.poisson_ratio, setup.sliding_angle);
        for (int k = 0; k < stress_component_count; ++k)
          radius_shape_part[stress_component_count * m + k] += exact[k];
      }
    criterion = std::make_unique<DangVanField>(count, setup.dang_van, setup.dang_van_settings);
    now.assign(stress_component_count * count, 0.0);
  }

  ContactEdgeRisk::~ContactEdgeRisk() = default;

  void ContactEdgeRisk::add_interpolated(const StressField &stress, double scale, EdgeValues &out) const
  {
    const std::size_t plane = grid.size();
    for (std::size_t m = 0; m < points_x.size(); ++m)
      for (int k = 0; k < stress_component_count; ++k)
        {
          const double *component = stress.values.data() + k * plane;
          double        value     = 0.0;
          for (int corner = 0; corner < 4; ++corner)
            value += weights[m][corner] * component[cells[m][corner]];
          out[stress_component_count * m + k] += scale * value;
        }
  }

  const ContactEdgeRisk::EdgeValues &ContactEdgeRisk::level(const MasingTraction &traction, std::size_t k)
  {
    const auto found = levels.find(k);
    if (found != levels.end())
      return found->second;
    EdgeValues values(stress_component_count * points_x.size(), 0.0);
    if (k > 0)
      {
        // Cattaneo-Mindlin: mu p0 (shape on a less c/a times shape on c),
        // c the stick radius of the level's shift.
        const double a = setup.contact_radius, amplitude = setup.friction_coefficient * setup.peak_pressure;
        const double shift = static_cast<double>(k) * setup.level_spacing;
        const double c = shift < setup.gross_slip_shift ? a * std::sqrt(1.0 - shift / setup.gross_slip_shift) : 0.0;
        load_x = traction.virgin_level_x(k);
        load_y = traction.virgin_level_y(k);
        if (c > 0.0)
          {
            const double ca = std::cos(setup.sliding_angle), sa = std::sin(setup.sliding_angle);
            const Field  shape_c = sampled_hertz_pressure(grid, c, c, 1.0);
            for (std::size_t cell = 0; cell < shape_c.size(); ++cell)
              {
                load_x[cell] += amplitude * (c / a) * ca * shape_c[cell];
                load_y[cell] += amplitude * (c / a) * sa * shape_c[cell];
              }
          }
        // The level less its shapes, interpolated; the shapes in closed form.
        surface_stress->evaluate(no_load, load_x, load_y, scratch);
        add_interpolated(scratch, 1.0, values);
        for (std::size_t m = 0; m < points_x.size(); ++m)
          {
            StressTensor inner;
            if (c > 0.0)
              inner = hertz_shear_surface_stress(points_x[m], points_y[m], c, setup.poisson_ratio, setup.sliding_angle);
            for (int q = 0; q < stress_component_count; ++q)
              values[stress_component_count * m + q] +=
                amplitude * (radius_shape_part[stress_component_count * m + q] - (c / a) * inner[q]);
          }
      }
    return levels.emplace(k, std::move(values)).first->second;
  }

  ContactEdgeRisk::EdgeValues ContactEdgeRisk::compose(const MasingTraction                &traction,
                                                       const MasingTraction::Composition &recipe)
  {
    const EdgeValues &lower = level(traction, recipe.lower);
    const EdgeValues &upper = level(traction, recipe.upper);
    EdgeValues        out(lower.size(), 0.0);
    if (recipe.reversal >= 0)
      out = reversals.at(recipe.reversal);
    const double f = recipe.factor, w = recipe.weight;
    for (std::size_t q = 0; q < out.size(); ++q)
      out[q] += f * ((1.0 - w) * lower[q] + w * upper[q]);
    return out;
  }

  void ContactEdgeRisk::add_step(const MasingTraction &traction, const MasingTraction::Composition &before,
                                 const std::array<double, stress_component_count> &surface_bulk)
  {
    const MasingTraction::Composition &recipe = traction.composition();
    if (recipe.reversal >= 0 && reversals.count(recipe.reversal) == 0)
      reversals[recipe.reversal] = compose(traction, before);
    for (auto kept = reversals.begin(); kept != reversals.end();)
      kept = traction.holds_reversal(kept->first) ? std::next(kept) : reversals.erase(kept);
    const EdgeValues shear = compose(traction, recipe);
    for (std::size_t q = 0; q < now.size(); ++q)
      now[q] = pressure_part[q] + shear[q] + surface_bulk[q % stress_component_count];
    criterion->add_step(now.data(), points_x.size());
  }

  ContactEdgeRiskMaximum ContactEdgeRisk::maximum() const
  {
    ContactEdgeRiskMaximum result;
    const auto       &risk_max = criterion->risk_max();
    const std::size_t worst    = largest_finite_point(risk_max);
    if (worst == risk_max.size())
      return result;
    result.value        = risk_max[worst];
    result.x            = points_x[worst];
    result.y            = points_y[worst];
    result.step         = criterion->risk_max_step()[worst];
    result.on_edge      = worst < per_circle;
    result.slip_annulus = setup.stick_radius > 0.0 ? setup.contact_radius - setup.stick_radius : 0.0;
    return result;
  }
} // namespace fretsim::contact
