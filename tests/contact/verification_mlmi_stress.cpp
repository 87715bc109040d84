// MLMI subsurface stresses against direct summation of the same rectangle
// kernels: MLMI and FFT against direct summation, relative error (max over
// the field, normalised by p0) below 1e-3 at their default settings, and
// convergence of the MLMI error with interpolation order.
#include <fretsim/contact/multilevel_summation.h>
#include <fretsim/contact/rectangle_kernels.h>
#include <fretsim/contact/subsurface_stress.h>

#include "../../contact/src/stress_mlmi.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

using namespace fretsim::contact;

namespace
{
  // Paper case (docs/references.md §1.2): a = 752.8 um, p0 = 1053.2 MPa, nu = 0.3.
  const double contact_radius = 752.8e-6, peak_pressure = 1053.2e6, poisson = 0.3;

  /// nx × ny cells on [-1.5a, 1.5a] x [-1.5a * aspect, ...].
  SurfaceGrid grid_around_contact(int nx, int ny, double aspect = 1.0)
  {
    SurfaceGrid grid;
    grid.nx    = nx;
    grid.ny    = ny;
    grid.hx    = 3.0 * contact_radius / nx;
    grid.hy    = 3.0 * contact_radius * aspect / ny;
    grid.x_min = -1.5 * contact_radius;
    grid.y_min = -1.5 * contact_radius * aspect;
    return grid;
  }

  /// Hertz pressure on an ellipse with semi-axes a and a * aspect.
  Field hertz_pressure(const SurfaceGrid &grid, double aspect = 1.0)
  {
    Field p(grid.size(), 0.0);
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        {
          const double x = grid.x(i) / contact_radius, y = grid.y(j) / (contact_radius * aspect);
          const double r2 = x * x + y * y;
          p[grid.index(i, j)] = r2 < 1.0 ? peak_pressure * std::sqrt(1.0 - r2) : 0.0;
        }
    return p;
  }

  Field scaled(const Field &f, double factor)
  {
    Field g(f);
    for (double &v : g)
      v *= factor;
    return g;
  }

  StressField evaluate(const std::string &method, const SurfaceGrid &grid, const std::vector<double> &depths,
                       const Field &p, const Field &qx, const Field &qy, int order = 6, int width = 0,
                       int levels = 0)
  {
    StressEvaluatorSettings settings;
    settings.method                = method;
    settings.mlmi_order            = order;
    settings.mlmi_correction_width = width;
    settings.mlmi_levels           = levels;
    const auto  evaluator          = make_subsurface_stress(grid, depths, poisson, settings);
    StressField stress;
    evaluator->evaluate(p, qx, qy, stress);
    return stress;
  }

  /// max over components and cells of |a - b| on one layer, over p0.
  double layer_error(const StressField &a, const StressField &b, int layer)
  {
    double error = 0.0;
    for (int c = 0; c < stress_component_count; ++c)
      for (int j = 0; j < a.ny; ++j)
        for (int i = 0; i < a.nx; ++i)
          error = std::max(error, std::fabs(a.at(layer, c, j, i) - b.at(layer, c, j, i)));
    return error / peak_pressure;
  }

  double field_error(const StressField &a, const StressField &b)
  {
    double error = 0.0;
    for (int layer = 0; layer < a.n_layers; ++layer)
      error = std::max(error, layer_error(a, b, layer));
    return error;
  }
} // namespace

TEST(MlmiStress, SlidingHertzAgainstDirectSummationAtDefaultSettings)
{
  // Hertz pressure with full-slip shear q_x = mu p (mu = 0.5, the larger
  // friction coefficient of the requirement), layers on the surface, just under it
  // and near the subsurface maximum.
  const std::vector<double> depths{0.0, 0.1 * contact_radius, 0.5 * contact_radius};
  for (const int n : {64, 128})
    {
      const SurfaceGrid grid = grid_around_contact(n, n);
      const Field       p    = hertz_pressure(grid);
      const Field       qx   = scaled(p, 0.5), qy = grid.zeros();
      const StressField direct = evaluate("direct", grid, depths, p, qx, qy);
      const StressField mlmi   = evaluate("mlmi", grid, depths, p, qx, qy);
      ASSERT_EQ(mlmi.values.size(), direct.values.size());
      for (int layer = 0; layer < 3; ++layer)
        {
          const double error = layer_error(mlmi, direct, layer);
          std::printf("%d^2, z = %.1fa: max |MLMI - direct| / p0 = %.2e\n", n, depths[layer] / contact_radius,
                      error);
          // Required tolerance for MLMI at its default settings.
          EXPECT_LT(error, 1e-3) << n << " layer " << layer;
          // Kept a decade below (measured <= 1.3e-4): the default width
          // 2p - 2 holds the surface kernels' spike inside the window.
          EXPECT_LT(error, 3e-4) << n << " layer " << layer;
        }
    }
}

TEST(MlmiStress, AllThreeLoadsOnAnUnevenGrid)
{
  // Elliptical contact on a 90 x 61 grid with hy != hx, shear in both
  // directions, so every kernel pair and odd sizes are exercised.
  const double              aspect = 0.6;
  const SurfaceGrid         grid   = grid_around_contact(90, 61, aspect);
  const Field               p      = hertz_pressure(grid, aspect);
  const Field               qx = scaled(p, 0.3), qy = scaled(p, -0.2);
  const std::vector<double> depths{0.0, 0.05 * contact_radius, 0.3 * contact_radius};
  const StressField         direct = evaluate("direct", grid, depths, p, qx, qy);
  const StressField         mlmi   = evaluate("mlmi", grid, depths, p, qx, qy);
  const double              error  = field_error(mlmi, direct);
  std::printf("90 x 61, three loads: max |MLMI - direct| / p0 = %.2e\n", error);
  EXPECT_LT(error, 1e-3); // required tolerance
}

TEST(MlmiStress, ErrorConvergesWithInterpolationOrder)
{
  const SurfaceGrid         grid = grid_around_contact(64, 64);
  const Field               p    = hertz_pressure(grid);
  const Field               qx   = scaled(p, 0.5), qy = grid.zeros();
  const std::vector<double> depths{0.0, 0.1 * contact_radius, 0.5 * contact_radius};
  const StressField         direct = evaluate("direct", grid, depths, p, qx, qy);

  // (a) Each order at its automatic width 2p - 2.
  std::vector<double> errors;
  for (const int order : {2, 4, 6, 8})
    {
      errors.push_back(field_error(evaluate("mlmi", grid, depths, p, qx, qy, order), direct));
      std::printf("order %d (width %d): error %.2e p0\n", order, MultilevelSummation::default_correction_width(order),
                  errors.back());
    }
  for (std::size_t k = 1; k < errors.size(); ++k)
    EXPECT_LT(errors[k], errors[k - 1]) << "order " << 2 * (k + 1);

  // (b) One window, 14 (= 2p - 2 for p = 8), for every order: the error
  // falls with the order at fixed work per point.
  std::vector<double> at_width;
  for (const int order : {2, 4, 6, 8})
    {
      at_width.push_back(field_error(evaluate("mlmi", grid, depths, p, qx, qy, order, 14), direct));
      std::printf("order %d, width 14: error %.2e p0\n", order, at_width.back());
    }
  for (std::size_t k = 1; k < at_width.size(); ++k)
    EXPECT_LT(at_width[k], at_width[k - 1]) << "order " << 2 * (k + 1);
  // Order 2 is not good enough at any practical width (Brandt & Lubrecht
  // use p = 6); order 6 meets the required 1e-3 by a wide margin.
  EXPECT_GT(errors[0], 1e-3);
  EXPECT_LT(errors[2], 1e-4);
}

TEST(MlmiStress, ShallowLayersGetTheWideCorrectionWindow)
{
  // The rule (stress_mlmi.cpp): layers with z < (2p - 2) h get at least the
  // 2p - 2 window; deeper ones keep the requested width.
  const double h = 1e-5;
  EXPECT_EQ(detail::mlmi_layer_correction_width(0.0, h, 6, 6), 10);
  EXPECT_EQ(detail::mlmi_layer_correction_width(9.9 * h, h, 6, 6), 10);
  EXPECT_EQ(detail::mlmi_layer_correction_width(10.1 * h, h, 6, 6), 6);
  EXPECT_EQ(detail::mlmi_layer_correction_width(0.0, h, 6, 12), 12);
  EXPECT_EQ(detail::mlmi_layer_correction_width(0.0, h, 6, 0), 10);

  // Why: at z = 0 with a narrow window (6 for p = 6, no widening) the
  // surface kernels' spike leaks through the interpolation; the evaluator
  // widens the window and stays accurate.
  const SurfaceGrid grid = grid_around_contact(64, 64);
  const Field       p    = hertz_pressure(grid);
  const Field       qx   = scaled(p, 0.5), qy = grid.zeros();
  const std::vector<double> surface{0.0};
  const StressField direct = evaluate("direct", grid, surface, p, qx, qy);
  const StressField widened = evaluate("mlmi", grid, surface, p, qx, qy, 6, 6);

  MultilevelSettings narrow;
  narrow.interpolation_order = 6;
  narrow.correction_width    = 6;
  const double hx = grid.hx, hy = grid.hy;
  const MultilevelSummation plain(
    grid, stress_component_count, 3,
    [hx, hy](int di, int dj, double *values) {
      const RectangleStresses s = rectangle_stresses(di * hx, dj * hy, 0.0, 0.5 * hx, 0.5 * hy, poisson);
      for (int c = 0; c < stress_component_count; ++c)
        {
          values[c * 3 + 0] = s.pressure[c];
          values[c * 3 + 1] = s.shear_x[c];
          values[c * 3 + 2] = s.shear_y[c];
        }
    },
    narrow);
  StressField unwidened;
  unwidened.resize(1, grid.ny, grid.nx);
  std::vector<double *> results;
  for (int c = 0; c < stress_component_count; ++c)
    results.push_back(unwidened.values.data() + c * grid.size());
  plain.apply({p.data(), qx.data(), qy.data()}, results);

  const double error_widened = field_error(widened, direct), error_narrow = field_error(unwidened, direct);
  std::printf("z = 0, requested width 6: %.2e p0 widened to 10, %.2e p0 kept at 6\n", error_widened, error_narrow);
  EXPECT_LT(error_widened, 1e-3); // required tolerance
  EXPECT_GT(error_narrow, 1e-2);  // measured 7e-2: the failure the rule prevents
}

TEST(MlmiStress, FactoryNameAndBadSettings)
{
  const SurfaceGrid grid = grid_around_contact(64, 64);
  StressEvaluatorSettings settings;
  settings.method = "mlmi";
  EXPECT_EQ(make_subsurface_stress(grid, {0.0}, poisson, settings)->name(), "mlmi");

  settings.mlmi_order = 5;
  EXPECT_THROW(make_subsurface_stress(grid, {0.0}, poisson, settings), std::invalid_argument);
  settings.mlmi_order  = 6;
  settings.mlmi_levels = 30;
  try
    {
      make_subsurface_stress(grid, {0.0}, poisson, settings);
      FAIL() << "30 levels on a 64^2 grid accepted";
    }
  catch (const std::invalid_argument &e)
    {
      EXPECT_NE(std::string(e.what()).find("allows at most"), std::string::npos) << e.what();
    }

  settings.mlmi_levels = 0;
  const auto  evaluator = make_subsurface_stress(grid, {0.0, 1e-4}, poisson, settings);
  StressField stress;
  EXPECT_THROW(evaluator->evaluate(Field(5, 0.0), grid.zeros(), grid.zeros(), stress), std::invalid_argument);
  // Zero loads give zero stresses (every load is skipped exactly).
  evaluator->evaluate(grid.zeros(), grid.zeros(), grid.zeros(), stress);
  EXPECT_EQ(stress.n_layers, 2);
  EXPECT_TRUE(std::all_of(stress.values.begin(), stress.values.end(), [](double v) { return v == 0.0; }));
}
