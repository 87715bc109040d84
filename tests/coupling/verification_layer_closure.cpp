// The layer's exponential closure (LocalCompliance::set_closure_pressure):
//     p = p_c ln(1 + e^((d - s)/δ)),  δ = p_c/k_n,  s = 10 δ,
// d the layer's compression. Checked against its scalar law where the
// pressure is uniform (one axial row on the closed circumference), against
// the sharp complementarity as p_c → 0, its sensitivity against central
// differences of the solve, the interface Jacobian across a patch's edge
// against central differences of the force, the bristles' stiffness that
// follows it, and in extreme settings.
#include <fretsim/coupling/local_compliance.h>
#include <fretsim/coupling/ring_coupling.h>
#include "finite_differences.h"
#include "synthetic_rings.h"

#include <fretsim/contact/convolution.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

using namespace fretsim;
using namespace fretsim::coupling;

namespace
{
  constexpr double radius = 0.04, k_n = 1e16; // the flexible housing's layer [m], [Pa/m]

  /// A structural compliance table [load row jj][cell] on the closed
  /// circumference: Love's half-space of `modulus` by (nearest di, j - jj),
  /// standing for the bodies' residual flexibility.
  std::vector<double> love_table(const contact::SurfaceGrid &grid, double modulus)
  {
    std::vector<double> table(grid.size() * grid.ny);
    for (int jj = 0; jj < grid.ny; ++jj)
      for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i)
          {
            const int di = i > grid.nx / 2 ? i - grid.nx : i;
            table[jj * grid.size() + grid.index(i, j)] =
              contact::influence::normal_displacement(di * grid.hx, (j - jj) * grid.hy, grid.hx, grid.hy, modulus);
          }
    return table;
  }

  std::unique_ptr<LocalCompliance> closure(const contact::SurfaceGrid &grid, double closure_pressure,
                                           double layer = k_n)
  {
    auto local = std::make_unique<LocalCompliance>(grid, 0.0, layer, true, 1e-6, love_table(grid, 1.15e11));
    local->set_closure_pressure(closure_pressure);
    return local;
  }

  /// The cosine approach of the structural tests: its crest 0.1 µm in.
  contact::Field cosine_penetration(const contact::SurfaceGrid &grid)
  {
    contact::Field penetration(grid.size());
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        penetration[grid.index(i, j)] = 1e-6 * (std::cos(grid.x(i) / radius) - 0.9) * (1.0 + 0.02 * j);
    return penetration;
  }

  contact::Field solved(LocalCompliance &local, const contact::Field &penetration, contact::Field start = {})
  {
    if (start.empty())
      start.assign(penetration.size(), 0.0);
    local.solve(penetration, start);
    return start;
  }

  double largest(const contact::Field &field) { return *std::max_element(field.begin(), field.end()); }

  /// Three approach changes on the cells carrying pressure p: uniform, cos θ
  /// and sin 3θ.
  std::vector<contact::Field> loaded_shapes(const contact::SurfaceGrid &grid, const contact::Field &p)
  {
    std::vector<contact::Field> shapes(3, contact::Field(grid.size(), 0.0));
    for (std::size_t c = 0; c < grid.size(); ++c)
      if (p[c] > 0.0)
        {
          const double theta = grid.x(static_cast<int>(c % grid.nx)) / radius;
          shapes[0][c]       = 1.0;
          shapes[1][c]       = std::cos(theta);
          shapes[2][c]       = std::sin(3.0 * theta);
        }
    return shapes;
  }

  /// A random ring of 5 coordinates with a residual flexibility (Love's
  /// coefficients as its table), for the interface's derivatives.
  ReducedRing closure_ring()
  {
    auto ring              = synthetic::random_ring(5, 36, 3, 7);
    ring.residual_pressure = love_table(ring.interface_grid, 4e11);
    return ring;
  }

  /// Its layer: μ = 10 keeps the bristles sticking; δ = 1e-12 m, s = 1e-11 m
  /// (the random ring carries ~10 kPa); the bristles follow the closure, so
  /// the derivatives below carry their stiffness's change with p.
  InterfaceSettings closure_settings()
  {
    InterfaceSettings settings;
    settings.normal_stiffness        = 1e15;
    settings.tangential_stiffness    = 2e15;
    settings.friction_coefficient    = 10.0;
    settings.closure_pressure        = 1e3;
    settings.radial_interference     = 2e-11;
    settings.bristles_follow_closure = true;
    return settings;
  }

  /// Its accepted state q0 and a trial state q near it (the closure's
  /// cells beyond its tail, in it and open).
  struct ClosureStates
  {
    std::vector<double> q0, q;
    ClosureStates()
    {
      for (std::size_t j = 0; j < 5; ++j)
        {
          q0.push_back(1e-10 * std::cos(1.3 * j));
          q.push_back(q0.back() + 0.02e-9 * std::cos(3.0 * j));
        }
    }
  };

  /// The interface's force at a state, for the finite differences.
  auto force_of(InterfaceContact &contact)
  {
    return [&contact](const std::vector<double> &at, const std::vector<double> &rate) {
      std::vector<double> out(at.size(), 0.0);
      contact.add_forces(at.data(), rate.data(), {out.data(), nullptr, nullptr});
      return out;
    };
  }
} // namespace

TEST(LayerClosure, AUniformPenetrationGivesTheScalarLaw)
{
  // One axial row: a uniform penetration b is an eigenvector of the closed
  // grid's kernel (its give C_u per unit uniform pressure), so the pressure
  // is uniform and solves C_u p + p/k_n + s + δ ln(1 − e^(−p/p_c)) = b,
  // here by bisection. From deep in (p ≫ p_c) through the tail to beyond
  // the cut (−40 δ: zero). Tolerance: the solve's stop, 1e-7 max(b, δ) of
  // gap, over the cell's stiffness, and the bisection's end.
  const auto     row = contact::SurfaceGrid::centred(96, 1, M_PI * radius, 0.009);
  const double   p_c = 3e7, delta = p_c / k_n, offset = 10.0 * delta;
  auto           local = closure(row, p_c);
  const auto   table   = love_table(row, 1.15e11);
  double       uniform = 0.0; // C_u [m/Pa]
  for (const double entry : table)
    uniform += entry;
  const auto   law     = [&](double p) { return (uniform + 1.0 / k_n) * p + offset + delta * std::log(-std::expm1(-p / p_c)); };
  for (const double b : {2e-6, 50.0 * delta, 10.0 * delta, 0.0, -5.0 * delta, -25.0 * delta})
    {
      double low = 1e-300, high = 1e12; // bisection in log p, then in p
      for (int it = 0; it < 400; ++it)
        {
          const double middle = high > 4.0 * low ? std::sqrt(low * high) : 0.5 * (low + high);
          (law(middle) < b ? low : high) = middle;
        }
      const contact::Field pressure = solved(*local, contact::Field(row.size(), b));
      const double stiffness_bound =
        1e-7 * std::max(std::abs(b), delta) * (1.0 / (uniform + 1.0 / k_n) + low / delta) + 1e-12 * low;
      std::printf("b = %9.3g m: p = %.6g Pa (scalar law %.6g)\n", b, pressure[0], low);
      for (const double p : pressure)
        EXPECT_NEAR(p, low, stiffness_bound) << "b = " << b;
    }
  // Beyond the tail's cut every cell is open.
  const contact::Field open = solved(*local, contact::Field(row.size(), -40.0 * delta));
  EXPECT_EQ(largest(open), 0.0);
  // Deep in the law is the linear layer shifted by s (within e^(−p/p_c)).
  EXPECT_NEAR(law(20.0 * p_c), (uniform + 1.0 / k_n) * 20.0 * p_c + offset, 1e-8 * delta);
  EXPECT_NEAR(local->contact_pressure(), p_c * std::exp(-10.0), 1e-12 * p_c);
  EXPECT_THROW(local->set_closure_pressure(-1.0), std::invalid_argument);
}

TEST(LayerClosure, TendsToTheSharpContactAsItsPressureVanishes)
{
  // The cosine approach (a conformal patch over about a quarter of the
  // circumference): the closure's pressure against the complementarity
  // solution, max |p − p_sharp| / max p_sharp, falling with p_c.
  const auto     grid   = contact::SurfaceGrid::centred(120, 8, M_PI * radius, 0.009);
  const auto     b      = cosine_penetration(grid);
  LocalCompliance sharp(grid, 0.0, k_n, true, 1e-6, love_table(grid, 1.15e11));
  const auto     exact  = solved(sharp, b);
  std::vector<double> errors;
  for (const double p_c : {1e7, 1e6, 1e5})
    {
      auto         local = closure(grid, p_c);
      const auto   p     = solved(*local, b);
      double       worst = 0.0;
      for (std::size_t c = 0; c < p.size(); ++c)
        worst = std::max(worst, std::abs(p[c] - exact[c]));
      errors.push_back(worst / largest(exact));
      std::printf("p_c = %.0e Pa: max |p - p_sharp| = %.3g of the peak %.4g Pa\n", p_c, errors.back(), largest(exact));
    }
  // Linear in p_c within a factor of two.
  EXPECT_GT(errors[0] / errors[1], 5.0);
  EXPECT_GT(errors[1] / errors[2], 5.0);
  EXPECT_LT(errors[2], 2e-3); // measured 1.2e-3 against the sharp solution
}

TEST(LayerClosure, ItsSensitivityIsTheSolvesDerivative)
{
  // ∂p/∂b applied to a few right-hand sides (smooth shapes on every
  // loaded cell) against central differences of the solve itself, each
  // from the converged pressure. Cells where the closure is at most ten
  // times a cell's own compliance come coupled, the rest after them (one
  // block Gauss–Seidel sweep): measured 3 % of the response's peak (7 % at
  // three times, 0.2 % — the differences' own noise — with every cell
  // coupled).
  const auto     grid  = contact::SurfaceGrid::centred(120, 8, M_PI * radius, 0.009);
  const auto     b     = cosine_penetration(grid);
  const double   p_c   = 3e7;
  auto           local = closure(grid, p_c);
  const auto     p     = solved(*local, b); // the sensitivity is taken at the last solve
  std::vector<std::size_t> loaded;
  for (std::size_t c = 0; c < p.size(); ++c)
    if (p[c] > 0.0)
      loaded.push_back(c);
  ASSERT_GT(loaded.size(), grid.size() / 8);
  constexpr std::size_t columns = 3;
  std::vector<double>   rhs(loaded.size() * columns);
  for (std::size_t a = 0; a < loaded.size(); ++a)
    {
      const double theta = grid.x(static_cast<int>(loaded[a] % grid.nx)) / radius;
      rhs[a * columns + 0] = 1.0;
      rhs[a * columns + 1] = std::cos(theta);
      rhs[a * columns + 2] = std::sin(3.0 * theta);
    }
  std::vector<double> sensitivity;
  local->pressure_sensitivity(loaded, rhs.data(), columns, sensitivity);
  const double step = 1e-10; // [m], 1e-4 of the approach
  for (std::size_t j = 0; j < columns; ++j)
    {
      contact::Field plus = b, minus = b;
      for (std::size_t a = 0; a < loaded.size(); ++a)
        {
          plus[loaded[a]] += step * rhs[a * columns + j];
          minus[loaded[a]] -= step * rhs[a * columns + j];
        }
      const auto p_plus = solved(*local, plus, p), p_minus = solved(*local, minus, p);
      double     worst = 0.0, peak = 0.0;
      for (std::size_t a = 0; a < loaded.size(); ++a)
        {
          const double difference = (p_plus[loaded[a]] - p_minus[loaded[a]]) / (2.0 * step);
          worst = std::max(worst, std::abs(difference - sensitivity[a * columns + j]));
          peak  = std::max(peak, std::abs(difference));
        }
      std::printf("column %zu: sensitivity against central differences %.3g of the peak\n", j, worst / peak);
      EXPECT_LT(worst, 0.04 * peak) << "column " << j;
    }
}

TEST(LayerClosure, ItsPressureChangeIsTheSolvesDerivative)
{
  // LocalCompliance::pressure_change (conjugate gradients on every loaded
  // cell, no split into coupled and tail cells) for the same shapes against
  // the same central differences: bound 1 % of the response's peak at a
  // tolerance of 1e-6 (measured up to 0.19 %, the differences' own noise, as
  // the factorisation's with every cell coupled), 3 % at Newton-Krylov's 1e-2
  // (measured up to 1.65 %).
  const auto   grid  = contact::SurfaceGrid::centred(120, 8, M_PI * radius, 0.009);
  const auto   b     = cosine_penetration(grid);
  auto         local = closure(grid, 3e7);
  const auto   p     = solved(*local, b);
  const auto shapes = loaded_shapes(grid, p);
  std::vector<contact::Field> tight(3), loose(3);
  for (std::size_t j = 0; j < shapes.size(); ++j) // all at the last solve's state, before the differences' solves
    {
      local->pressure_change(p, shapes[j], tight[j], 1e-6);
      local->pressure_change(p, shapes[j], loose[j], 1e-2);
    }
  const double step = 1e-10; // [m]
  for (std::size_t j = 0; j < shapes.size(); ++j)
    {
      contact::Field plus = b, minus = b;
      for (std::size_t c = 0; c < grid.size(); ++c)
        {
          plus[c] += step * shapes[j][c];
          minus[c] -= step * shapes[j][c];
        }
      const auto p_plus = solved(*local, plus, p), p_minus = solved(*local, minus, p);
      double     worst_tight = 0.0, worst_loose = 0.0, peak = 0.0;
      for (std::size_t c = 0; c < grid.size(); ++c)
        {
          const double difference = (p_plus[c] - p_minus[c]) / (2.0 * step);
          worst_tight             = std::max(worst_tight, std::abs(difference - tight[j][c]));
          worst_loose             = std::max(worst_loose, std::abs(difference - loose[j][c]));
          peak                    = std::max(peak, std::abs(difference));
        }
      std::printf("shape %zu: pressure change against central differences %.3g (tolerance 1e-6), %.3g (1e-2) of the peak\n",
                  j, worst_tight / peak, worst_loose / peak);
      EXPECT_LT(worst_tight, 0.01 * peak) << "shape " << j;
      EXPECT_LT(worst_loose, 0.03 * peak) << "shape " << j;
    }
}

TEST(LayerClosure, ItsSolveStartsFromThePressureChangesAskedFor)
{
  // Newton-Krylov asks for pressure changes along GMRES's directions and
  // then evaluates at the state their combination reaches: the next solve
  // starts from that combination of the changes (first order in the step),
  // not from the last pressure. Same answer as a solve without them (both
  // to 1e-7 of the penetration's scale, compared to 1e-5 of the peak
  // pressure; measured 1.5e-6), in fewer convolutions (measured 7 against
  // 17: bound half); a change outside their span keeps the plain start (as
  // many convolutions, the same answer).
  const auto grid = contact::SurfaceGrid::centred(120, 8, M_PI * radius, 0.009);
  const auto b    = cosine_penetration(grid);
  auto       with = closure(grid, 3e7), without = closure(grid, 3e7);
  const auto p    = solved(*with, b);
  ASSERT_EQ(p, solved(*without, b));
  const auto shapes = loaded_shapes(grid, p);
  std::vector<contact::Field> changes(3);
  const auto moved = [&](const std::vector<double> &weights, const contact::Field &from) {
    contact::Field to = from;
    for (std::size_t c = 0; c < grid.size(); ++c)
      for (std::size_t j = 0; j < shapes.size(); ++j)
        to[c] += 2e-10 * weights[j] * shapes[j][c];
    return to;
  };
  const auto compare = [&](const contact::Field &target, bool in_span) {
    for (std::size_t j = 0; j < shapes.size(); ++j)
      with->pressure_change(p, shapes[j], changes[j], 1e-2);
    contact::Field p_with = p, p_without = p;
    const int      predicted = with->solve(target, p_with), plain = without->solve(target, p_without);
    double         worst = 0.0;
    for (std::size_t c = 0; c < grid.size(); ++c)
      worst = std::max(worst, std::abs(p_with[c] - p_without[c]));
    std::printf("%s: %d convolutions against %d from the last pressure; answers %.3g of the peak apart\n",
                in_span ? "in their span" : "outside it", predicted, plain, worst / largest(p_without));
    EXPECT_LT(worst, 1e-5 * largest(p_without));
    if (in_span)
      EXPECT_LE(2 * predicted, plain);
    else
      EXPECT_EQ(predicted, plain);
    // back to p for the next case
    ASSERT_EQ(solved(*with, b), solved(*without, b));
  };
  compare(moved({0.7, -0.4, 0.2}, b), true);
  contact::Field outside = b; // along a shape none of the changes had
  for (std::size_t c = 0; c < grid.size(); ++c)
    outside[c] += 2e-10 * std::cos(5.0 * grid.x(static_cast<int>(c % grid.nx)) / radius) * (p[c] > 0.0);
  compare(outside, false);
}

TEST(LayerClosure, ExtremeSettingsStayFinite)
{
  // A layer 1 000 times stiffer (δ = 3e-12 m) and a closure pressure far
  // above the contact's (the law's tail everywhere): finite, non-negative,
  // and the load still within the sharp solution's order.
  const auto grid = contact::SurfaceGrid::centred(120, 8, M_PI * radius, 0.009);
  const auto b    = cosine_penetration(grid);
  LocalCompliance sharp(grid, 0.0, k_n, true, 1e-6, love_table(grid, 1.15e11));
  const double    load = [&] {
    const auto p = solved(sharp, b);
    double     sum = 0.0;
    for (const double value : p)
      sum += value;
    return sum;
  }();
  for (const auto &[layer, p_c] : {std::pair{1e19, 3e7}, std::pair{k_n, 1e10}, std::pair{1e13, 1e3}})
    {
      auto       local = closure(grid, p_c, layer);
      const auto p     = solved(*local, b);
      double     sum   = 0.0;
      for (const double value : p)
        {
          ASSERT_TRUE(std::isfinite(value) && value >= 0.0);
          sum += value;
        }
      std::printf("k_n = %.0e, p_c = %.0e: load %.3g of the sharp layer at 1e16\n", layer, p_c, sum / load);
      EXPECT_GT(sum, 0.1 * load);
      EXPECT_LT(sum, 10.0 * load);
    }
}

TEST(LayerClosure, TheInterfaceJacobianCarriesTheClosuresSensitivity)
{
  // The interface's generalised force on a random ring with a residual
  // flexibility (Love's coefficients as its table), its approach about the
  // closure's offset: cells beyond the tail, in it, and open.
  // With the closure p(q) is smooth across the patch's edge, so its
  // Jacobian (coupled and tail cells, normal and bristles) must match
  // central differences there too; μ = 10 keeps the bristles sticking.
  const auto          ring     = closure_ring();
  InterfaceSettings   settings = closure_settings();
  const ClosureStates states;
  const auto         &q0 = states.q0, &q = states.q;
  const std::vector<double> v(5, 0.0);
  // Both in-step bristle laws, and the exponential update: each carries the
  // faded stiffness's ∂k/∂p (left out: 1.2e-2 with the implicit Euler law).
  using Update = contact::BristleUpdate;
  for (const auto &[law, update] : {std::pair{InStepBristleLaw::implicit_euler, Update::implicit_euler},
                                    std::pair{InStepBristleLaw::linearised, Update::implicit_euler},
                                    std::pair{InStepBristleLaw::implicit_euler, Update::exponential}})
    {
      settings.in_step_bristle_law = law;
      settings.bristle_update      = update;
      InterfaceContact    contact(ring, settings);
      std::vector<double> f(5, 0.0), dq(25, 0.0), dv(25, 0.0);
      contact.accept(q0.data(), v.data());
      contact.add_forces(q.data(), v.data(), {f.data(), dq.data(), dv.data()});
      const contact::Field &p = contact.trial_pressure();
      const double          p_c = settings.closure_pressure;
      std::size_t           tail = 0, deep = 0, open = 0;
      for (const double value : p)
        {
          tail += value > 0.0 && value < p_c;
          deep += value >= p_c;
          open += value == 0.0;
        }
      std::printf("cells: %zu beyond p_c, %zu in the tail, %zu open; p %g..%g\n", deep, tail, open,
                  *std::min_element(p.begin(), p.end()), *std::max_element(p.begin(), p.end()));
      ASSERT_GT(deep, 10u);
      ASSERT_GT(tail, 5u);
      ASSERT_GT(open, 10u);
      const double error = fretsim::coupling::testing::jacobian_error(5, q, v, 0, 1e-13, force_of(contact), dq);
      std::printf("interface Jacobian with the closure, %s law, %s update, against central differences: %.3g\n",
                  law == InStepBristleLaw::linearised ? "linearised" : "implicit Euler",
                  update == Update::exponential ? "exponential" : "implicit Euler", error);
      // measured 4e-6 (7e-4 and 3e-4 at fits of 0 and 5e-11 m, other cells
      // at the tail's bends) with each
      EXPECT_LT(error, 1e-4);
    }
}

TEST(LayerClosure, TheInterfaceDerivativeFollowsTheLastEvaluation)
{
  // InterfaceContact::add_derivative on the random ring above, after a
  // Jacobian at another state and an evaluation at q: its columns against
  // central differences of the force at q (by position) and against the
  // Jacobian's own by velocity there (the damping's share, through the same
  // pressure coupling). Its pressure coupling is solved to 1e-2: bound 2e-2
  // of the largest entry (measured 1.3e-4 and 9.8e-4).
  const auto        ring     = closure_ring();
  InterfaceSettings settings = closure_settings();
  settings.normal_damping_time  = 1e-5;
  constexpr std::size_t n = 5;
  const ClosureStates   states;
  const auto           &q0 = states.q0, &q = states.q;
  std::vector<double>   v(n, 0.0), elsewhere = q0;
  for (std::size_t j = 0; j < n; ++j)
    elsewhere[j] += 0.05e-9 * std::sin(2.0 * j);
  InterfaceContact contact(ring, settings);
  contact.keep_derivatives();
  contact.accept(q0.data(), v.data());
  std::vector<double> f(n, 0.0), by_position(n * n, 0.0), by_velocity(n * n, 0.0);
  contact.add_forces(elsewhere.data(), v.data(), {f.data(), by_position.data(), by_velocity.data()});
  std::fill(by_position.begin(), by_position.end(), 0.0);
  std::fill(by_velocity.begin(), by_velocity.end(), 0.0);
  contact.add_forces(q.data(), v.data(), {f.data(), by_position.data(), by_velocity.data()}); // the reference's
  contact.add_forces(elsewhere.data(), v.data(), {f.data(), nullptr, nullptr});
  contact.add_forces(q.data(), v.data(), {f.data(), nullptr, nullptr}); // the last evaluation
  std::vector<double> along_position(n * n, 0.0), along_velocity(n * n, 0.0), unit(n, 0.0), zero(n, 0.0),
    column(n);
  for (std::size_t j = 0; j < n; ++j)
    {
      unit.assign(n, 0.0);
      unit[j] = 1.0;
      for (auto *matrix : {&along_position, &along_velocity})
        {
          column.assign(n, 0.0);
          contact.add_derivative(matrix == &along_position ? unit.data() : zero.data(),
                                 matrix == &along_position ? zero.data() : unit.data(), column.data());
          for (std::size_t i = 0; i < n; ++i)
            (*matrix)[i * n + j] = column[i];
        }
    }
  double velocity_error = 0.0, velocity_scale = 0.0;
  for (std::size_t k = 0; k < n * n; ++k)
    {
      velocity_error = std::max(velocity_error, std::abs(along_velocity[k] - by_velocity[k]));
      velocity_scale = std::max(velocity_scale, std::abs(by_velocity[k]));
    }
  ASSERT_GT(velocity_scale, 0.0);
  const double position_error =
    fretsim::coupling::testing::jacobian_error(n, q, v, 0, 1e-13, force_of(contact), along_position);
  std::printf("interface derivative: by position %.3g against central differences, by velocity %.3g against the Jacobian\n",
              position_error, velocity_error / velocity_scale);
  EXPECT_LT(position_error, 2e-2);
  EXPECT_LT(velocity_error, 2e-2 * velocity_scale);
}

TEST(LayerClosure, TheBristlesStiffnessFollowsTheClosure)
{
  // One committed step from rest on the random ring above: each loaded
  // cell's traction is the implicit Euler law's from zero,
  // |τ| = k |ds| / (1 + k |ds| / (μ p)), with k = k_t (1 − e^(−p/p_c))
  // (InterfaceSettings::bristles_follow_closure) or k = k_t (the paper's).
  // ds the cell's slip from q = 0, from the ring's rows; to round-off.
  const auto                ring = closure_ring();
  const auto                n    = static_cast<std::size_t>(ring.n);
  const std::vector<double> q = ClosureStates().q, v(n, 0.0);
  for (const bool follow : {true, false})
    {
      InterfaceSettings settings       = closure_settings();
      settings.bristles_follow_closure = follow;
      InterfaceContact contact(ring, settings);
      contact.accept(q.data(), v.data());
      const contact::Field &p = contact.pressure();
      double      error = 0.0, faded = 1.0;
      std::size_t sheared = 0, in_tail = 0;
      for (std::size_t c = 0; c < p.size(); ++c)
        {
          const double traction = std::hypot(contact.shear_x()[c], contact.shear_y()[c]);
          if (traction == 0.0)
            continue; // open, or below the tail's shear floor
          double slip[2] = {0.0, 0.0};
          for (int component = 1; component <= 2; ++component)
            for (std::size_t j = 0; j < n; ++j)
              slip[component - 1] += ring.interface_displacement[(3 * c + component) * n + j] * q[j];
          const double fraction = follow ? -std::expm1(-p[c] / settings.closure_pressure) : 1.0,
                       k = settings.tangential_stiffness * fraction, slip_length = std::hypot(slip[0], slip[1]),
                       mu_p = settings.friction_coefficient * p[c];
          const double expected = k * slip_length / (1.0 + k * slip_length / mu_p);
          error = std::max(error, std::abs(traction - expected) / expected);
          ++sheared;
          if (p[c] < settings.closure_pressure)
            {
              ++in_tail;
              faded = std::min(faded, fraction);
            }
        }
      std::printf("bristles %s: %zu sheared cells (%zu below p_c), law error %.3g\n",
                  follow ? "following the closure" : "at k_t", sheared, in_tail, error);
      if (follow)
        std::printf("  their stiffness down to %.3g k_t\n", faded);
      ASSERT_GT(sheared, 20u); // measured 25, 5 of them below p_c
      ASSERT_GT(in_tail, 2u);
      EXPECT_LT(error, 1e-9); // measured 3e-16
      if (follow)
        { // the tail's cells are softened, not only the deep ones tested
          EXPECT_LT(faded, 0.5);
        }
    }
}
