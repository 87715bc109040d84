// The interface's local compliance (local_compliance.h): the layer in series
// with an elastic half-space, solved as Polonsky & Keer's bound-constrained
// problem with the approach given. Checked against Hertz (docs/references.md §1),
// the layer-only limit, the wrap-around of the closed circumference, its
// sensitivity's own system (on one thread and on two), and the sensitivity
// inside the interface Jacobian against finite differences.
#include <fretsim/coupling/local_compliance.h>
#include <fretsim/coupling/ring_coupling.h>
#include "finite_differences.h"
#include "synthetic_rings.h"

#include <fretsim/contact/convolution.h>

#include <Eigen/Dense>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>

using namespace fretsim;
using namespace fretsim::coupling;
using fretsim::coupling::testing::jacobian_error;

namespace
{
  double largest(const contact::Field &field) { return *std::max_element(field.begin(), field.end()); }

  /// Love's coefficient of a half-space of plane modulus `modulus` [Pa]
  /// between cells di columns (nearest image around the closed
  /// circumference) and dj rows apart [m/Pa].
  double periodic_love(const contact::SurfaceGrid &grid, int di, int dj, double modulus)
  {
    di = ((di % grid.nx) + grid.nx) % grid.nx;
    const int nearest = di > grid.nx / 2 ? di - grid.nx : di;
    return contact::influence::normal_displacement(nearest * grid.hx, dj * grid.hy, grid.hx, grid.hy, modulus);
  }

  /// A structural compliance table [load row jj][cell] of a kernel by (di, j - jj).
  template <typename Kernel>
  std::vector<double> structural_table(const contact::SurfaceGrid &grid, const Kernel &kernel)
  {
    std::vector<double> table(grid.size() * grid.ny);
    for (int jj = 0; jj < grid.ny; ++jj)
      for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i)
          table[jj * grid.size() + grid.index(i, j)] = kernel(i, j - jj);
    return table;
  }

  /// The structural-compliance tests' approach [m]: a cosine around the
  /// ring, its crest pressed 0.1 µm in, slightly uneven across the width.
  contact::Field ring_penetration(const contact::SurfaceGrid &grid, double radius)
  {
    contact::Field penetration(grid.size());
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        penetration[grid.index(i, j)] = 1e-6 * (std::cos(grid.x(i) / radius) - 0.9) * (1.0 + 0.02 * j);
    return penetration;
  }

  contact::Field pressure_under(LocalCompliance &compliance, const contact::Field &penetration)
  {
    contact::Field pressure(penetration.size(), 0.0);
    compliance.solve(penetration, pressure);
    return pressure;
  }

  /// max |a - b| / max b.
  double difference(const contact::Field &a, const contact::Field &b)
  {
    double worst = 0.0;
    for (std::size_t c = 0; c < a.size(); ++c)
      worst = std::max(worst, std::abs(a[c] - b[c]));
    return worst / largest(b);
  }

  /// The interface Jacobian checks' case: an interference fit keeps every
  /// cell loaded and a large μ every bristle sticking (a smooth map); the
  /// half-space in series; the accepted state (q0, v) and the perturbed q.
  struct JacobianCase
  {
    InterfaceSettings   settings;
    std::vector<double> q0 = std::vector<double>(5), v = std::vector<double>(5), q;
    JacobianCase()
    {
      settings.normal_stiffness         = 1e15;
      settings.tangential_stiffness     = 2e15;
      settings.friction_coefficient     = 10.0;
      settings.normal_damping_time      = 1e-6;
      settings.radial_interference      = 5e-9;
      settings.local_compliance_modulus = 2.3e11;
      settings.sensitivity_tolerance    = 1e-4; // the default 1e-2 is for Newton's matrix, too coarse for this check
      for (std::size_t j = 0; j < 5; ++j)
        {
          q0[j] = 1e-10 * std::cos(1.3 * j);
          v[j]  = 1e-7 * std::sin(0.7 * j);
        }
      q = q0;
      for (std::size_t j = 0; j < q.size(); ++j)
        q[j] += 0.02e-9 * std::cos(3.0 * j);
    }
  };

  /// The Jacobian of `contact` at the case's q after accepting q0: ∂f/∂q and ∂f/∂q̇ [n × n].
  std::pair<std::vector<double>, std::vector<double>> jacobian_at(InterfaceContact &contact, const JacobianCase &c)
  {
    const std::size_t   n = c.q.size();
    std::vector<double> f(n, 0.0), dq(n * n, 0.0), dv(n * n, 0.0);
    contact.accept(c.q0.data(), c.v.data());
    contact.add_forces(c.q.data(), c.v.data(), {f.data(), dq.data(), dv.data()});
    return {dq, dv};
  }

  /// The generalised force of `contact` at (q, q̇), for the differences.
  auto forces_of(InterfaceContact &contact)
  {
    return [&contact](const std::vector<double> &q, const std::vector<double> &v) {
      std::vector<double> out(q.size(), 0.0);
      contact.add_forces(q.data(), v.data(), {out.data(), nullptr, nullptr});
      return out;
    };
  }

  /// A contact patch of uneven extent (base + growth·j cells in row j), a few
  /// cells inside it open.
  std::vector<std::size_t> uneven_patch(const contact::SurfaceGrid &grid, int base, int growth, int open_every)
  {
    std::vector<std::size_t> loaded;
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < base + growth * j; ++i)
        if ((i * 7 + j * 3) % open_every != 0)
          loaded.push_back(grid.index(i, j));
    return loaded;
  }

  /// Smooth right-hand sides over the patch's cells, row-major [cell][column]:
  /// a constant, a first and a `harmonic`-th harmonic around, and with a
  /// fourth column an alternating one.
  std::vector<double> patch_rows(const contact::SurfaceGrid &grid, const std::vector<std::size_t> &loaded,
                                 std::size_t columns, double harmonic)
  {
    std::vector<double> rows(loaded.size() * columns);
    for (std::size_t a = 0; a < loaded.size(); ++a)
      {
        const double theta = 2.0 * M_PI * static_cast<double>(loaded[a] % grid.nx) / grid.nx;
        const double y     = static_cast<double>(loaded[a] / grid.nx);
        rows[a * columns + 0] = 1e-6;
        rows[a * columns + 1] = 1e-6 * std::cos(theta) * (1.0 + 0.1 * y);
        rows[a * columns + 2] = 1e-6 * std::sin(harmonic * theta) - 2e-7 * y;
        if (columns > 3)
          rows[a * columns + 3] = (a % 2 == 0 ? 1e-7 : -1e-7);
      }
    return rows;
  }
  /// The largest over the columns of max |s - exact| / max |exact| (s row-major [cell][column]).
  double worst_column_error(const std::vector<double> &sensitivity, const Eigen::MatrixXd &exact)
  {
    double worst = 0.0;
    for (Eigen::Index k = 0; k < exact.cols(); ++k)
      {
        double difference = 0.0, size = 0.0;
        for (Eigen::Index a = 0; a < exact.rows(); ++a)
          {
            difference = std::max(difference,
                                  std::abs(sensitivity[static_cast<std::size_t>(a * exact.cols() + k)] - exact(a, k)));
            size       = std::max(size, std::abs(exact(a, k)));
          }
        worst = std::max(worst, difference / size);
      }
    return worst;
  }
} // namespace

TEST(LocalCompliance, ASpherePressedIntoTheHalfSpaceCarriesHertzsLoadAndPeak)
{
  // Sphere R = 10 mm on a half-space of E' = E/(1 - ν²), approach δ = 2 µm:
  // a = √(Rδ) = 141 µm, P = (4/3) E' √R δ^{3/2}, p0 = 2 E' a / (π R).
  // A layer of 1e21 Pa/m adds 1e-21 m/Pa to a cell's 4e-17 m/Pa: nothing.
  const double radius = 0.01, approach = 2e-6, modulus = 2.1e11 / (1.0 - 0.09);
  const double contact_radius = std::sqrt(radius * approach);
  const auto   grid           = contact::SurfaceGrid::centred(64, 64, 1.6 * contact_radius, 1.6 * contact_radius);
  LocalCompliance half_space(grid, modulus, 1e21, false);
  contact::Field  penetration(grid.size()), pressure(grid.size(), 0.0);
  for (int j = 0; j < grid.ny; ++j)
    for (int i = 0; i < grid.nx; ++i)
      penetration[grid.index(i, j)] =
        approach - (grid.x(i) * grid.x(i) + grid.y(j) * grid.y(j)) / (2.0 * radius);
  const int iterations = half_space.solve(penetration, pressure);
  EXPECT_GT(iterations, 0);
  const double load = contact::integrate(grid, pressure);
  const double hertz_load = 4.0 / 3.0 * modulus * std::sqrt(radius) * std::pow(approach, 1.5);
  const double hertz_peak = 2.0 * modulus * contact_radius / (M_PI * radius);
  std::printf("against Hertz: load %.4f, peak %.4f\n", load / hertz_load, largest(pressure) / hertz_peak);
  // Tolerances: 1 %, the project's Hertz bound for the normal contact solver
  // (tests/contact/verification_normal_contact.cpp, docs/references.md §1); this
  // 64² grid, 40 cells across the contact, gives 0.02 % (load), 0.05 % (peak).
  EXPECT_NEAR(load / hertz_load, 1.0, 0.01);
  EXPECT_NEAR(largest(pressure) / hertz_peak, 1.0, 0.01);
  // The solution is a fixed point: started from it, no iteration is needed.
  EXPECT_EQ(half_space.solve(penetration, pressure), 0);
}

TEST(LocalCompliance, AStiffHalfSpaceLeavesTheLayerAlone)
{
  // E' = 1e25 Pa: the half-space gives nothing, p = k_n b where b > 0.
  const auto      grid = contact::SurfaceGrid::centred(32, 8, 0.01, 0.002);
  LocalCompliance half_space(grid, 1e25, 1e15, false);
  contact::Field  penetration(grid.size()), pressure(grid.size(), 0.0);
  for (std::size_t c = 0; c < grid.size(); ++c)
    penetration[c] = 1e-9 * std::sin(0.37 * static_cast<double>(c));
  half_space.solve(penetration, pressure);
  double worst = 0.0;
  for (std::size_t c = 0; c < grid.size(); ++c)
    worst = std::max(worst, std::abs(pressure[c] - 1e15 * std::max(penetration[c], 0.0)));
  // Tolerance: the solver's stopping gap, 1e-7 × max b, times k_n, against
  // the 1 MPa peak (the half-space's own 1e-25 m/Pa are far below).
  EXPECT_LT(worst / 1e6, 2e-7);
}

TEST(LocalCompliance, TheSensitivitySolvesItsSystemWhateverTheThreads)
{
  // (C_AA + I/k_n) S = R, every cell loaded (a wavy interference), several
  // columns: each column's residual within the conjugate gradients' stop
  // (1e-4 of its right-hand side), and the columns, shared out over the
  // threads, give the same numbers to the last bit on one thread as on two;
  // so does the Cholesky factorisation (the default up to
  // default_direct_sensitivity_cells loaded cells), within 10 × the
  // conjugate gradients' stop of their answer (measured 1.8e-4).
  const auto            grid = contact::SurfaceGrid::centred(48, 8, 0.02, 0.004);
  constexpr double      modulus = 2.3e11, layer_stiffness = 1e18, tolerance = 1e-4;
  constexpr std::size_t columns = 6;
  contact::Field        start(grid.size()), rows(grid.size() * columns);
  for (int j = 0; j < grid.ny; ++j)
    for (int i = 0; i < grid.nx; ++i)
      {
        const std::size_t c = grid.index(i, j);
        const double      x = grid.x(i) / 0.01, y = grid.y(j) / 0.002;
        start[c]            = 1e-6 * (1.0 + 0.05 * std::cos(2.0 * x));
        for (std::size_t k = 0; k < columns; ++k)
          rows[c * columns + k] = 1e-6 * std::cos(static_cast<double>(k) * x + 0.3 * static_cast<double>(k) * y);
      }
  std::vector<std::size_t> loaded(grid.size());
  std::iota(loaded.begin(), loaded.end(), std::size_t{0});
  // The conjugate gradients (first), then the factorisation.
  std::vector<std::vector<double>> by_threads;
  for (const std::size_t direct_cells : {std::size_t{0}, LocalCompliance::default_direct_sensitivity_cells})
    for (const int threads : {1, 2})
      {
        omp_set_num_threads(threads);
        LocalCompliance half_space(grid, modulus, layer_stiffness, false, tolerance);
        half_space.set_direct_sensitivity_cells(direct_cells);
        std::vector<double> sensitivity;
        half_space.pressure_sensitivity(loaded, rows.data(), columns, sensitivity);
        by_threads.push_back(sensitivity);
      }
  omp_set_num_threads(omp_get_num_procs());
  EXPECT_EQ(by_threads[0], by_threads[1]);
  EXPECT_EQ(by_threads[2], by_threads[3]);
  double largest_change = 0.0, largest_entry = 0.0; // the factorisation within the CG's stop of it
  for (std::size_t k = 0; k < by_threads[0].size(); ++k)
    {
      largest_change = std::max(largest_change, std::abs(by_threads[2][k] - by_threads[0][k]));
      largest_entry  = std::max(largest_entry, std::abs(by_threads[2][k]));
    }
  std::printf("conjugate gradients against the factorisation: %.2e of the largest entry\n",
              largest_change / largest_entry);
  EXPECT_LT(largest_change / largest_entry, 10.0 * tolerance);

  const contact::SurfaceConvolution compliance(grid, [&](int di, int dj) {
    return contact::influence::normal_displacement(di * grid.hx, dj * grid.hy, grid.hx, grid.hy, modulus);
  });
  double worst = 0.0;
  for (std::size_t k = 0; k < columns; ++k)
    {
      contact::Field column(grid.size()), response;
      double         largest_rhs = 0.0;
      for (std::size_t c = 0; c < grid.size(); ++c)
        {
          column[c]   = by_threads[0][c * columns + k];
          largest_rhs = std::max(largest_rhs, std::abs(rows[c * columns + k]));
        }
      compliance.apply(column, response);
      for (std::size_t c = 0; c < grid.size(); ++c)
        worst = std::max(worst, std::abs(response[c] + column[c] / layer_stiffness - rows[c * columns + k]) /
                                  largest_rhs);
    }
  std::printf("sensitivity residual %.2e of the right-hand side\n", worst);
  // Tolerance: the conjugate gradients stop when their recursively updated
  // residual is within 1e-4; the true one may drift from it by round-off.
  EXPECT_LT(worst, 1.5 * tolerance);
}

TEST(LocalCompliance, OnTheClosedCircumferenceAPatchAcrossTheSeamIsThePatchMidGrid)
{
  // The same penetration pattern centred on the seam (x = 0 and 2πR meet) and
  // half a turn away gives the same pressure, shifted: the distances wrap.
  // Without the wrap the seam's patch would be two half patches, softer.
  const double    radius = 0.04;
  const auto      grid   = contact::SurfaceGrid::centred(120, 8, M_PI * radius, 0.009);
  LocalCompliance closed(grid, 2.3e11, 1e15, true), open(grid, 2.3e11, 1e15, false);
  contact::Field  seam(grid.size()), middle(grid.size());
  for (int j = 0; j < grid.ny; ++j)
    for (int i = 0; i < grid.nx; ++i)
      {
        const double theta = grid.x(i) / radius; // from -π to π: the seam is at ±π
        const double shape = 1e-6 * (std::cos(theta) - 0.9);
        middle[grid.index(i, j)]                         = shape;
        seam[grid.index((i + grid.nx / 2) % grid.nx, j)] = shape;
      }
  contact::Field p_seam(grid.size(), 0.0), p_middle(grid.size(), 0.0), p_open(grid.size(), 0.0);
  closed.solve(seam, p_seam);
  closed.solve(middle, p_middle);
  open.solve(seam, p_open);
  double worst = 0.0;
  for (int j = 0; j < grid.ny; ++j)
    for (int i = 0; i < grid.nx; ++i)
      worst = std::max(worst, std::abs(p_seam[grid.index((i + grid.nx / 2) % grid.nx, j)] -
                                       p_middle[grid.index(i, j)]));
  // Tolerance: twice the stopping gap, 1e-7 × max b, over the smallest
  // compliance of a cell (self + 1/k_n) — an upper bound on the pressure it
  // leaves.
  EXPECT_LT(worst / largest(p_middle), 1e-4);
  EXPECT_GT(largest(p_open) / largest(p_middle), 1.05); // the seam matters
}

TEST(LocalCompliance, TheInterfaceJacobianCarriesTheHalfSpacesSensitivity)
{
  // An interference fit keeps every cell loaded and a large μ keeps every
  // bristle sticking: the map is smooth, and central differences check
  // ∂f/∂q = A Bᵀ (C_AA + I/k_n)⁻¹ R, cell to cell coupled.
  const auto               ring = synthetic::random_ring(5, 36, 3, 7);
  const JacobianCase       c;
  const InterfaceSettings &settings = c.settings;
  const auto              &q0 = c.q0, &v = c.v, &q = c.q;
  InterfaceContact         contact(ring, settings);
  const auto [dq, dv]      = jacobian_at(contact, c);
  ASSERT_GT(contact.contact_fraction(), 0.0);
  const auto evaluate = forces_of(contact);
  // Steps: the pressure solve stops within 1e-7 × 5 nm of the gap, so the
  // differences move the approach by ≥ 1e-12 m (q by 1e-12, q̇ by 1e-6 × τ_d):
  // noise ≤ 5e-4. Every cell stays loaded and sticking: no truncation error.
  // Tolerance: the sensitivity's conjugate gradients stop at 1e-4 of the
  // right-hand side; 2e-3 leaves room for both.
  EXPECT_LT(jacobian_error(5, q, v, 0, 1e-12, evaluate, dq), 2e-3);
  EXPECT_LT(jacobian_error(5, q, v, 1, 1e-6, evaluate, dv), 2e-3);
  // The scene's sensitivity tolerance, 1e-2 (for Newton's matrix): the
  // Jacobian within the same 1e-2, plus the differences' noise above.
  InterfaceSettings coarse_settings = settings;
  coarse_settings.sensitivity_tolerance = InterfaceSettings{}.sensitivity_tolerance;
  InterfaceContact    coarse(ring, coarse_settings);
  std::vector<double> h(5, 0.0), dq_coarse(25, 0.0), dv_coarse(25, 0.0);
  coarse.accept(q0.data(), v.data());
  coarse.add_forces(q.data(), v.data(), {h.data(), dq_coarse.data(), dv_coarse.data()});
  const double coarse_error = jacobian_error(5, q, v, 0, 1e-12, evaluate, dq_coarse);
  std::printf("with the default sensitivity tolerance %.0e: FD error %.2g\n", coarse_settings.sensitivity_tolerance,
              coarse_error);
  EXPECT_LT(coarse_error, 1e-2 + 2e-3);
  // And it is not the layer's own, uncoupled Jacobian: on these 7 mm cells
  // the half-space is far more compliant than the layer's 1e-15 m/Pa, and
  // the normal part (all of ∂f/∂q̇) drops by most of its size.
  InterfaceSettings layer_only = settings;
  layer_only.local_compliance_modulus = 0.0;
  layer_only.onset_pressure           = 0.0;
  InterfaceContact    alone(ring, layer_only);
  std::vector<double> g(5, 0.0), dq_alone(25, 0.0), dv_alone(25, 0.0);
  alone.accept(q0.data(), v.data());
  alone.add_forces(q.data(), v.data(), {g.data(), dq_alone.data(), dv_alone.data()});
  double change = 0.0, size = 0.0;
  for (std::size_t k = 0; k < 25; ++k)
    {
      change = std::max(change, std::abs(dv_alone[k] - dv[k]));
      size   = std::max(size, std::abs(dv_alone[k]));
    }
  std::printf("velocity Jacobian (normal part only): change %.3g of the layer's own; FD errors %.2g, %.2g\n",
              change / size, jacobian_error(5, q, v, 0, 1e-12, evaluate, dq),
              jacobian_error(5, q, v, 1, 1e-6, evaluate, dv));
  EXPECT_GT(change / size, 0.5);
}

TEST(LocalCompliance, AStructuralComplianceAddsInSeriesWithTheHalfSpace)
{
  // The ring's residual flexibility enters as a structural compliance table
  // ([load row][cell], invariant around the circumference). Given a second
  // half-space's own influence coefficients (E'_2) as that table, the
  // pressure must be that of one half-space with 1/E' = 1/E'_1 + 1/E'_2
  // (Love's coefficients are linear in 1/E'), and the table alone (no
  // half-space, modulus 0) that of E'_2: same approach, both to the solver's
  // stopping gap (bound as in the seam test above).
  const double radius = 0.04, first = 2.3e11, second = 1.1e11, layer = 1e17;
  const auto   grid   = contact::SurfaceGrid::centred(120, 8, M_PI * radius, 0.009);
  auto table = structural_table(grid, [&](int di, int dj) { return periodic_love(grid, di, dj, second); });
  LocalCompliance with_table(grid, first, layer, true, LocalCompliance::default_sensitivity_tolerance, table);
  LocalCompliance combined(grid, 1.0 / (1.0 / first + 1.0 / second), layer, true);
  LocalCompliance table_alone(grid, 0.0, layer, true, LocalCompliance::default_sensitivity_tolerance, table);
  LocalCompliance second_alone(grid, second, layer, true);
  EXPECT_LT(with_table.structural_asymmetry(), 1e-12); // Love's coefficients: symmetric and even
  const contact::Field penetration = ring_penetration(grid, radius);
  const auto solve = [&](LocalCompliance &compliance) { return pressure_under(compliance, penetration); };
  const contact::Field reference = solve(combined), softer = solve(second_alone);
  EXPECT_LT(difference(solve(with_table), reference), 1e-4);
  EXPECT_LT(difference(solve(table_alone), softer), 1e-4);
  EXPECT_GT(largest(softer) / largest(reference), 1.2); // the table matters

  // A table that is neither symmetric nor even is averaged, and says so:
  // one entry 1.5×, R(1; 0, 0), sits 0.375 R(1; 0, 0) above its four-way
  // mean: 0.076 of the table's largest entry (the self term) measured;
  // bound 0.05.
  table[grid.index(1, 0)] *= 1.5;
  const LocalCompliance skewed(grid, first, layer, true, LocalCompliance::default_sensitivity_tolerance, table);
  EXPECT_GT(skewed.structural_asymmetry(), 0.05);
  EXPECT_THROW(LocalCompliance(grid, 0.0, layer, true), std::invalid_argument);
}

TEST(LocalCompliance, TheInterfaceJacobianCarriesTheRingsResidualFlexibility)
{
  // The same check as above with the ring's residual flexibility in series
  // (a second half-space's coefficients as its table) and a ball's residual
  // displacement of the interface (a bump under the ball, set per ball load:
  // constant in q, so the Jacobian is still exact). The ball's bump must
  // raise the force pushing the ring in, in proportion to its load.
  auto ring = synthetic::random_ring(5, 36, 3, 7);
  const auto &grid    = ring.interface_grid;
  const auto  nearest = [&](int di) {
    di = ((di % grid.nx) + grid.nx) % grid.nx;
    return di > grid.nx / 2 ? di - grid.nx : di;
  };
  ring.residual_pressure.resize(grid.size() * grid.ny);
  ring.residual_ball.resize(grid.size());
  for (int jj = 0; jj < grid.ny; ++jj)
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        ring.residual_pressure[jj * grid.size() + grid.index(i, j)] =
          contact::influence::normal_displacement(nearest(i) * grid.hx, (j - jj) * grid.hy, grid.hx, grid.hy, 4e11);
  for (int j = 0; j < grid.ny; ++j)
    for (int i = 0; i < grid.nx; ++i)
      ring.residual_ball[grid.index(i, j)] = 1e-12 * std::exp(-0.5 * nearest(i) * nearest(i)); // m/N
  ring.residual_column_angle = grid.x(0) / ring.interface_radius;
  const JacobianCase        c;
  const auto               &v = c.v, &q = c.q;
  InterfaceContact          contact(ring, c.settings);
  const std::vector<double> angles{0.3, 2.0}, loads{1000.0, 2000.0};
  contact.set_ball_loads(angles, loads);
  const auto [dq, dv] = jacobian_at(contact, c);
  ASSERT_GT(contact.contact_fraction(), 0.99);
  const auto evaluate = forces_of(contact);
  // Tolerance as in the test above (the same steps, noise and CG stop).
  EXPECT_LT(jacobian_error(5, q, v, 0, 1e-12, evaluate, dq), 2e-3);
  EXPECT_LT(jacobian_error(5, q, v, 1, 1e-6, evaluate, dv), 2e-3);
  // The interface load grows with the balls' bumps (1-2 nm on a 5 nm fit),
  // linearly while every cell stays loaded: to the solver's stopping gap,
  // 1e-7 of the penetration against a 4 % change.
  const auto total_pressure = [&](const std::vector<double> &ball_loads) {
    contact.set_ball_loads(angles, ball_loads);
    contact.accept(q.data(), v.data());
    EXPECT_EQ(contact.contact_fraction(), 1.0);
    return std::accumulate(contact.pressure().begin(), contact.pressure().end(), 0.0);
  };
  const double without = total_pressure({0.0, 0.0}), with_balls = total_pressure(loads),
               more    = total_pressure({1500.0, 3000.0});
  EXPECT_GT(with_balls - without, 0.02 * without);
  EXPECT_NEAR((more - without) / (with_balls - without), 1.5, 1e-4);
  // One ball over column 10 raises the pressure most in column 10.
  contact.set_ball_loads({grid.x(10) / ring.interface_radius}, {2000.0});
  contact.accept(q.data(), v.data());
  const contact::Field with_one = contact.pressure();
  contact.set_ball_loads({}, {});
  contact.accept(q.data(), v.data());
  int    top  = -1;
  double rise = 0.0;
  for (int i = 0; i < grid.nx; ++i)
    if (const double d = with_one[grid.index(i, 1)] - contact.pressure()[grid.index(i, 1)]; d > rise)
      {
        rise = d;
        top  = i;
      }
  EXPECT_EQ(top, 10);
}

TEST(LocalCompliance, TheHalfSpaceCompletionAddsWhatATableLacksAtShortWavesOnly)
{
  // A coarse FE mesh's residual flexibility loses the short wavelengths
  // around the circumference, where the exact one tends to a half-space of
  // the body's material. Given a half-space's own coefficients (E'_2) as the
  // table, low-passed to the wavenumbers k ≤ 10 of the 120-column grid, the
  // completion at E'_2 must restore the half-space where it acts in full
  // (the same pressure as E'_2 alone, to the solver's stopping gap as
  // above), add nothing to the complete table, and act only in its band:
  // in full from the wavenumber of λ_c, none below half of it, linear in k
  // between (the share added is exactly the ramp where the table holds
  // nothing).
  const double radius = 0.04, modulus = 1.1e11, layer = 1e17;
  const auto   grid    = contact::SurfaceGrid::centred(120, 8, M_PI * radius, 0.009);
  const double length  = grid.nx * grid.hx;
  const int    kept    = 10;
  const auto   love    = [&](int di, int dj) { return periodic_love(grid, di, dj, modulus); };
  // low-passed kernel by (di, dj): (1/nx) Σ_{k ≤ kept} w_k Ĥ(k; dj) cos(2π k di/nx)
  const auto low_passed = [&](int di, int dj) {
    double sum = 0.0;
    for (int k = 0; k <= kept; ++k)
      {
        double spectrum = 0.0;
        for (int d = 0; d < grid.nx; ++d)
          spectrum += love(d, dj) * std::cos(2.0 * M_PI * k * d / grid.nx);
        sum += (k == 0 ? 1.0 : 2.0) * spectrum * std::cos(2.0 * M_PI * k * di / grid.nx);
      }
    return sum / grid.nx;
  };
  const auto complete = structural_table(grid, love), lacking = structural_table(grid, low_passed);
  const auto tolerance = LocalCompliance::default_sensitivity_tolerance;
  // in full from k = kept + 1 on
  const HalfSpaceCompletion from_the_cut{modulus, length / (kept + 1)};
  LocalCompliance           reference(grid, modulus, layer, true);
  LocalCompliance           completed(grid, 0.0, layer, true, tolerance, lacking, from_the_cut);
  LocalCompliance           uncompleted(grid, 0.0, layer, true, tolerance, lacking);
  LocalCompliance           already(grid, 0.0, layer, true, tolerance, complete, from_the_cut);
  const contact::Field      penetration = ring_penetration(grid, radius);
  const auto solve = [&](LocalCompliance &compliance) { return pressure_under(compliance, penetration); };
  const contact::Field exact = solve(reference);
  EXPECT_LT(difference(solve(completed), exact), 1e-4);
  EXPECT_LT(difference(solve(already), exact), 1e-4);
  EXPECT_GT(largest(solve(uncompleted)) / largest(exact), 1.2); // what the short waves hold matters
  ASSERT_EQ(completed.completion_by_wavenumber().size(), static_cast<std::size_t>(grid.nx / 2 + 1));
  EXPECT_TRUE(uncompleted.completion_by_wavenumber().empty());
  for (int k = 0; k <= grid.nx / 2; ++k)
    {
      // each k's trace; Love's blocks and their low-pass agree to rounding
      EXPECT_NEAR(completed.completion_by_wavenumber()[k], k <= kept ? 0.0 : 1.0, 1e-9) << "k = " << k;
      EXPECT_NEAR(already.completion_by_wavenumber()[k], 0.0, 1e-9) << "k = " << k;
    }

  // The band: λ_c at k = 40, so none up to k = 20, half at 30, all from 40.
  const LocalCompliance banded(grid, 0.0, layer, true, tolerance, lacking, HalfSpaceCompletion{modulus, length / 40});
  for (const auto &[k, share] : std::vector<std::pair<int, double>>{{11, 0.0}, {20, 0.0}, {25, 0.25}, {30, 0.5},
                                                                    {39, 0.95}, {40, 1.0}, {60, 1.0}})
    EXPECT_NEAR(banded.completion_by_wavenumber()[k], share, 1e-9) << "k = " << k;

  EXPECT_THROW(LocalCompliance(grid, modulus, layer, true, tolerance, {}, from_the_cut), std::invalid_argument);
  EXPECT_THROW(LocalCompliance(grid, 0.0, layer, true, tolerance, lacking, HalfSpaceCompletion{modulus, 0.0}),
               std::invalid_argument);
}

TEST(LocalCompliance, AHousingWallSetsTheFitsUniformPressure)
{
  // Lamé's thick ring against a hand evaluation: bore 40 mm, outside 60 mm,
  // steel: 0.04 / 2.08e11 × (5200/2000 + 0.3) m/Pa.
  const double steel = lame_bore_compliance(0.04, 0.06, 2.08e11, 0.3);
  EXPECT_NEAR(steel, 0.04 / 2.08e11 * 2.9, 1e-12 * steel);
  EXPECT_THROW(lame_bore_compliance(0.04, 0.04, 2.08e11, 0.3), std::invalid_argument);

  // One axial row: a uniform penetration is an eigenvector of the closed
  // grid's kernel, so the pressure is uniform and exactly b / (C_0 + 1/k_n),
  // C_0 the wall's — whatever the half-space's own uniform give. Tolerance:
  // the solve's stopping gap, 1e-7 of b, relative to C_0's share.
  const double radius = 0.04, k_n = 1e16, b = 10e-6;
  const auto   row    = contact::SurfaceGrid::centred(96, 1, M_PI * radius, 0.009);
  for (const double wall : {steel, lame_bore_compliance(0.04, 0.06, 7e10, 0.33)})
    {
      LocalCompliance local(row, 2.3e11, k_n, true, LocalCompliance::default_sensitivity_tolerance, {}, {},
                            UniformCompliance{wall});
      contact::Field pressure(row.size(), 0.0);
      local.solve(contact::Field(row.size(), b), pressure);
      const double expected = b / (wall + 1.0 / k_n);
      for (const double p : pressure)
        EXPECT_NEAR(p, expected, 1e-6 * expected);
    }
  // Without a wall the half-space's own give sets it: another pressure.
  LocalCompliance half_space(row, 2.3e11, k_n, true);
  contact::Field  pressure(row.size(), 0.0);
  half_space.solve(contact::Field(row.size(), b), pressure);
  EXPECT_GT(std::abs(pressure[0] - b / (steel + 1.0 / k_n)), 0.05 * pressure[0]);

  // Across the width the shift must leave the kernel positive definite: a
  // wall far stiffer than the half-space's mean give cannot be represented.
  const auto strip = contact::SurfaceGrid::centred(96, 8, M_PI * radius, 0.009);
  EXPECT_THROW(LocalCompliance(strip, 2.3e11, k_n, true, LocalCompliance::default_sensitivity_tolerance, {}, {},
                               UniformCompliance{1e-25}),
               std::invalid_argument);
  EXPECT_THROW(LocalCompliance(strip, 2.3e11, k_n, false, LocalCompliance::default_sensitivity_tolerance, {}, {},
                               UniformCompliance{steel}),
               std::invalid_argument);
}

TEST(LocalCompliance, TheSensitivityIsExactOnAnIllConditionedStructuralCompliance)
{
  // What a flexible housing leaves: no half-space, a structural compliance
  // that is smooth around the circumference and the same across the width
  // (semidefinite: most of its spectrum near zero), and a stiff layer, whose
  // compliance alone bounds the operator's smallest eigenvalue (condition
  // ≈ 2 000 here). The sensitivity's columns against a dense solve of the same
  // system: the conjugate gradients at the scene's tolerance (1e-2 of the
  // residual) leave errors far beyond it, the factorisation none.
  const auto       grid = contact::SurfaceGrid::centred(72, 4, 2.0 * M_PI * 0.04, 0.016);
  constexpr double layer_stiffness = 1e16, scale = 3e-15, width = 6.0; // [Pa/m], [m/Pa], [cells]
  const auto       kernel = [&](int di) {
    double sum = 0.0; // periodic Gaussian: positive spectrum
    for (int image = -2; image <= 2; ++image)
      sum += std::exp(-0.5 * std::pow((di + image * grid.nx) / width, 2));
    return scale * sum;
  };
  const std::vector<double> table = structural_table(grid, [&](int di, int) { return kernel(di); });
  const std::vector<std::size_t> loaded = uneven_patch(grid, 24, 4, 11);
  const std::size_t              m = loaded.size(), columns = 3;
  const std::vector<double>      rows = patch_rows(grid, loaded, columns, 3.0);
  Eigen::MatrixXd dense(m, m);
  for (std::size_t a = 0; a < m; ++a)
    for (std::size_t b = 0; b < m; ++b)
      dense(a, b) = kernel(static_cast<int>(loaded[a] % grid.nx) - static_cast<int>(loaded[b] % grid.nx)) +
                    (a == b ? 1.0 / layer_stiffness : 0.0);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> spectrum(dense);
  const double condition = spectrum.eigenvalues().maxCoeff() / spectrum.eigenvalues().minCoeff();
  const Eigen::MatrixXd exact =
    dense.llt().solve(Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      rows.data(), static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(columns)));
  const auto error_of = [&](const std::vector<double> &sensitivity) { return worst_column_error(sensitivity, exact); };
  std::vector<double> direct, iterative;
  LocalCompliance     factored(grid, 0.0, layer_stiffness, true, LocalCompliance::default_sensitivity_tolerance, table);
  factored.pressure_sensitivity(loaded, rows.data(), columns, direct);
  EXPECT_EQ(factored.statistics().sensitivity_factorisations, 1u);
  LocalCompliance conjugate(grid, 0.0, layer_stiffness, true, LocalCompliance::default_sensitivity_tolerance, table);
  conjugate.set_direct_sensitivity_cells(0);
  conjugate.pressure_sensitivity(loaded, rows.data(), columns, iterative);
  EXPECT_EQ(conjugate.statistics().sensitivity_factorisations, 0u);
  // Single precision asked for: its condition check (float's epsilon × the
  // condition estimate > 1e-4) sends this operator to double.
  std::vector<double> checked;
  LocalCompliance     single(grid, 0.0, layer_stiffness, true, LocalCompliance::default_sensitivity_tolerance, table);
  single.set_single_precision_factorisation(true);
  EXPECT_FALSE(single.pressure_sensitivity(loaded, rows.data(), columns, checked));
  EXPECT_EQ(single.statistics().sensitivity_factorisations, 1u);
  EXPECT_EQ(single.statistics().sensitivity_single_precision, 0u);
  EXPECT_LT(error_of(checked), 1e-9);
  std::printf("condition %.3g: sensitivity error, factorised %.2g, conjugate gradients at 1e-2 %.2g\n", condition,
              error_of(direct), error_of(iterative));
  EXPECT_GT(condition, 1e3);
  // Tolerances: the factorisation to rounding times the condition
  // (measured 7e-14); the conjugate gradients stop short of it (measured
  // 0.017: their 1e-2 is on the residual, and the error is up to the
  // condition times that).
  EXPECT_LT(error_of(direct), 1e-9);
  EXPECT_GT(error_of(iterative), 5e-3);
}

TEST(LocalCompliance, TheSinglePrecisionFactorisationIsWithinItsRoundingOnAHalfSpacePatch)
{
  // The co-simulation's Newton matrix takes the sensitivity from a single
  // precision factorisation where a half-space conditions the operator. On
  // a contact patch of a closed ring's grid (a half-space of steel, the
  // scene's penalty layer) the columns against a dense double solve of
  // C_AA + I/k_n assembled here from Love's coefficients (nearest image
  // around the circumference): the double factorisation to rounding, the
  // single one within 10 × the condition × float's epsilon, and far within
  // the 1e-2 Newton's matrix needs.
  const auto       grid = contact::SurfaceGrid::centred(120, 8, 2.0 * M_PI * 0.04, 0.008);
  constexpr double modulus = 2.3e11, layer_stiffness = 1e18; // [Pa], [Pa/m]
  const std::vector<std::size_t> loaded = uneven_patch(grid, 30, 3, 13);
  const std::size_t              m = loaded.size(), columns = 4;
  const std::vector<double>      rows = patch_rows(grid, loaded, columns, 5.0);
  Eigen::MatrixXd dense(m, m);
  for (std::size_t a = 0; a < m; ++a)
    for (std::size_t b = 0; b < m; ++b)
      {
        const int di = static_cast<int>(loaded[a] % grid.nx) - static_cast<int>(loaded[b] % grid.nx);
        const int dj = static_cast<int>(loaded[a] / grid.nx) - static_cast<int>(loaded[b] / grid.nx);
        dense(a, b)  = periodic_love(grid, di, dj, modulus) + (a == b ? 1.0 / layer_stiffness : 0.0);
      }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> spectrum(dense);
  const double condition = spectrum.eigenvalues().maxCoeff() / spectrum.eigenvalues().minCoeff();
  const Eigen::MatrixXd exact =
    dense.llt().solve(Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      rows.data(), static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(columns)));
  const auto error_of = [&](bool single) {
    LocalCompliance half_space(grid, modulus, layer_stiffness, true);
    half_space.set_single_precision_factorisation(single);
    std::vector<double> sensitivity;
    EXPECT_EQ(half_space.pressure_sensitivity(loaded, rows.data(), columns, sensitivity), single);
    EXPECT_EQ(half_space.statistics().sensitivity_factorisations, 1u);
    EXPECT_EQ(half_space.statistics().sensitivity_single_precision, single ? 1u : 0u); // its condition passed
    return worst_column_error(sensitivity, exact);
  };
  const double in_double = error_of(false), in_single = error_of(true);
  const double epsilon = std::numeric_limits<float>::epsilon();
  std::printf("%zu cells, condition %.3g: sensitivity error, double %.2g, single %.2g (condition x epsilon %.2g)\n",
              m, condition, in_double, in_single, condition * epsilon);
  EXPECT_LT(in_double, 1e-9);
  EXPECT_LT(in_single, 10.0 * condition * epsilon);
  EXPECT_LT(in_single, 1e-3);
  EXPECT_GT(in_single, in_double); // it is the single precision one
}
