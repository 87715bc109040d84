#include <fretsim/coupling/ring_coupling.h>

#include "thread_team.h"

#include <fretsim/coupling/bearing.h>
#include <fretsim/coupling/local_compliance.h>

#include <fretsim/contact/bristle.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fretsim::coupling
{
  using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  using Eigen::VectorXd;

  void ReducedRing::check() const
  {
    const auto fail = [](const std::string &what) { throw std::invalid_argument("reduced ring: " + what); };
    if (n == 0)
      fail("no coordinates");
    if (mass.size() != n * n || stiffness.size() != n * n)
      fail("mass and stiffness must be n x n");
    if (interface_grid.size() == 0 || interface_displacement.size() != interface_grid.size() * 3 * n)
      fail("the interface operator must have 3 n values per grid cell");
    if (!(interface_radius > 0.0))
      fail("the interface radius must be positive");
    if (raceway_angles < 4 || raceway_approach.size() != raceway_footprints() * raceway_angles * n)
      fail("the raceway ball operator must have n values at each of at least 4 angles per footprint");
    if (!std::is_sorted(raceway_footprint_loads.begin(), raceway_footprint_loads.end()) ||
        std::adjacent_find(raceway_footprint_loads.begin(), raceway_footprint_loads.end()) !=
          raceway_footprint_loads.end() ||
        (!raceway_footprint_loads.empty() && !(raceway_footprint_loads.front() > 0.0)))
      fail("the raceway footprints' ball loads must be positive and increasing");
    if ((!residual_pressure.empty() && residual_pressure.size() != interface_grid.size() * interface_grid.ny) ||
        (!residual_ball.empty() &&
         (residual_pressure.empty() || residual_ball.size() != raceway_footprints() * interface_grid.size())))
      fail("the residual flexibility must have [rows][cells] pressure entries and none or [footprint][cells] ball "
           "entries");
  }

  namespace
  {
    /// visit(b, cell, R): the ball table shifted to ball b's angle, linear
    /// between the grid's columns, for each cell of the columns i where
    /// wanted(b, i) (the others contribute nothing): the one placement both
    /// directions of the reciprocal pair use, so that they are each other's
    /// transposes exactly. Ball b's table is its footprint's, blended at its
    /// load (footprint_blend) where it is read: most columns are not visited.
    template <class Wanted, class Visit>
    void for_each_shifted_ball_cell(const contact::SurfaceGrid &grid, double radius, const std::vector<double> &table,
                                    const std::vector<double> &footprint_loads, double column_angle,
                                    const std::vector<double> &angles, const std::vector<double> &loads,
                                    Wanted wanted, Visit visit)
    {
      const int         nx = grid.nx, ny = grid.ny;
      const double      angle_step = grid.hx / radius;
      const std::size_t cells      = grid.size();
      for (std::size_t b = 0; b < angles.size(); ++b)
        {
          const FootprintBlend blend = footprint_blend(footprint_loads, loads[b]);
          const auto           at    = [&](std::size_t cell) {
            return blend.of([&](std::size_t f) { return table[f * cells + cell]; });
          };
          const double shift = std::remainder(angles[b] - column_angle, 2.0 * M_PI) / angle_step;
          for (int i = 0; i < nx; ++i)
            {
              if (!wanted(b, i))
                continue;
              const double at_column = i - shift, lower = std::floor(at_column), fraction = at_column - lower;
              const int    k0 = ((static_cast<int>(lower) % nx) + nx) % nx, k1 = (k0 + 1) % nx;
              for (int j = 0; j < ny; ++j)
                visit(b, grid.index(i, j), (1.0 - fraction) * at(grid.index(k0, j)) + fraction * at(grid.index(k1, j)));
            }
        }
    }
  } // namespace

  void add_ball_residual(const contact::SurfaceGrid &grid, double radius, const std::vector<double> &table,
                         const std::vector<double> &footprint_loads, double column_angle,
                         const std::vector<double> &angles, const std::vector<double> &loads,
                         std::vector<double> &field)
  {
    for_each_shifted_ball_cell(
      grid, radius, table, footprint_loads, column_angle, angles, loads,
      [&](std::size_t b, int) { return loads[b] != 0.0; },
      [&](std::size_t b, std::size_t cell, double value) { field[cell] += loads[b] * value; });
  }

  std::vector<double> pressure_residual_at_balls(const contact::SurfaceGrid &grid, double radius,
                                                 const std::vector<double> &table,
                                                 const std::vector<double> &footprint_loads, double column_angle,
                                                 const std::vector<double> &angles, const std::vector<double> &loads,
                                                 const contact::Field &pressure)
  {
    // Most columns carry no pressure (the unloaded half, the gaps between
    // the balls): they are skipped.
    std::vector<char> loaded(grid.nx, 0);
    for (int i = 0; i < grid.nx; ++i)
      for (int j = 0; j < grid.ny && !loaded[i]; ++j)
        loaded[i] = pressure[grid.index(i, j)] != 0.0;
    std::vector<double> inward(angles.size(), 0.0);
    const double        area = grid.cell_area();
    for_each_shifted_ball_cell(
      grid, radius, table, footprint_loads, column_angle, angles, loads,
      [&](std::size_t, int i) { return loaded[i] != 0; },
      [&](std::size_t b, std::size_t cell, double value) { inward[b] += value * pressure[cell] * area; });
    return inward;
  }

  ReducedRing with_flexible_housing(const ReducedRing &ring, const ReducedHousing &housing)
  {
    ring.check();
    const auto fail = [](const std::string &what) { throw std::invalid_argument("flexible housing: " + what); };
    const std::size_t n_r = ring.n, n_h = housing.n, n = n_r + n_h;
    if (ring.housing_coordinates != 0)
      fail("the ring already has a housing");
    if (n_h == 0 || housing.mass.size() != n_h * n_h || housing.stiffness.size() != n_h * n_h)
      fail("its mass and stiffness must be n x n with n > 0");
    const auto &a = ring.interface_grid, &b = housing.interface_grid;
    const auto  close = [](double x, double y, double scale) { return std::abs(x - y) <= 1e-9 * scale; };
    if (a.nx != b.nx || a.ny != b.ny || !close(a.hx, b.hx, a.hx) || !close(a.hy, b.hy, a.hy) ||
        !close(a.x_min, b.x_min, a.hx) || !close(a.y_min, b.y_min, a.hy) ||
        !close(ring.interface_radius, housing.interface_radius, ring.interface_radius))
      fail("its bore grid (" + std::to_string(b.nx) + " x " + std::to_string(b.ny) + " cells, radius " +
           std::to_string(housing.interface_radius) + " m) is not the ring's outer-surface grid (" +
           std::to_string(a.nx) + " x " + std::to_string(a.ny) + ", " + std::to_string(ring.interface_radius) +
           " m): build both with the same Ring/Outer radius, Ring/Width and interface grid cells");
    if (housing.interface_displacement.size() != a.size() * 3 * n_h)
      fail("its interface operator must have 3 n values per grid cell");
    if (!housing.residual_pressure.empty() && housing.residual_pressure.size() != a.size() * a.ny)
      fail("its residual flexibility must have [rows][cells] entries");

    ReducedRing joint;
    joint.n                           = n;
    joint.housing_coordinates         = n_h;
    joint.lowest_elastic_frequency_hz = ring.lowest_elastic_frequency_hz;
    joint.interface_radius            = ring.interface_radius;
    joint.interface_grid              = ring.interface_grid;
    joint.raceway_angles              = ring.raceway_angles;
    joint.raceway_footprint_loads     = ring.raceway_footprint_loads;
    joint.residual_pressure           = ring.residual_pressure;
    if (joint.residual_pressure.empty())
      joint.residual_pressure = housing.residual_pressure;
    else if (!housing.residual_pressure.empty())
      for (std::size_t k = 0; k < joint.residual_pressure.size(); ++k)
        joint.residual_pressure[k] += housing.residual_pressure[k];
    const auto compliance_of = [](double modulus, const std::vector<double> &table) {
      return table.empty() || modulus <= 0.0 ? 0.0 : 1.0 / modulus;
    };
    const double completion_compliance = compliance_of(ring.residual_half_space_modulus, ring.residual_pressure) +
                                         compliance_of(housing.residual_half_space_modulus, housing.residual_pressure);
    joint.residual_half_space_modulus = completion_compliance > 0.0 ? 1.0 / completion_compliance : 0.0;
    joint.residual_ball               = ring.residual_ball;
    joint.residual_column_angle       = ring.residual_column_angle;
    joint.mass.assign(n * n, 0.0);
    joint.stiffness.assign(n * n, 0.0);
    const auto place = [n](std::vector<double> &to, const std::vector<double> &from, std::size_t size,
                           std::size_t offset) {
      for (std::size_t i = 0; i < size; ++i)
        std::copy_n(from.begin() + i * size, size, to.begin() + (offset + i) * n + offset);
    };
    place(joint.mass, ring.mass, n_r, 0);
    place(joint.stiffness, ring.stiffness, n_r, 0);
    place(joint.mass, housing.mass, n_h, n_r);
    place(joint.stiffness, housing.stiffness, n_h, n_r);
    joint.interface_displacement.resize(a.size() * 3 * n);
    for (std::size_t row = 0; row < a.size() * 3; ++row)
      {
        double *to = joint.interface_displacement.data() + row * n;
        std::copy_n(ring.interface_displacement.data() + row * n_r, n_r, to);
        const double *from = housing.interface_displacement.data() + row * n_h;
        for (std::size_t j = 0; j < n_h; ++j)
          to[n_r + j] = -from[j];
      }
    const std::size_t raceway_rows = ring.raceway_footprints() * ring.raceway_angles;
    joint.raceway_approach.assign(raceway_rows * n, 0.0);
    for (std::size_t k = 0; k < raceway_rows; ++k)
      std::copy_n(ring.raceway_approach.data() + k * n_r, n_r, joint.raceway_approach.data() + k * n);
    return joint;
  }

  namespace
  {
    /// |τ| / (μ p) above which a cell slides on within the next step. The
    /// paper's law approaches the limit only asymptotically; at 0.9 its
    /// tangent is a tenth of the stick stiffness.
    constexpr double slip_threshold = 0.9;

    // Eight lanes of float rows times double vectors, summed in one fixed
    // order however wide the registers (GCC's vector extension, like the
    // convolution's row sums): compiled also for AVX2 and chosen at run time,
    // without FMA contraction, so that every machine gets the same result
    // to the last bit. The structural u_r of every cell is the
    // co-simulation's largest single cost (a fifth of a run with SSE2 alone).
    using Float4  = float __attribute__((vector_size(16), aligned(4), __may_alias__));
    using Double4 = double __attribute__((vector_size(32), aligned(8), __may_alias__));

    inline double lanes_sum(const Double4 &low, const Double4 &high)
    {
      return ((low[0] + low[1]) + (low[2] + low[3])) + ((high[0] + high[1]) + (high[2] + high[3]));
    }

    /// Σ_j values[j] x[j] over n values.
    __attribute__((target_clones("avx2", "default"))) double row_dot(const float *values, const double *x,
                                                                     std::size_t n)
    {
      Double4           low = {}, high = {};
      const std::size_t whole = n - n % 8;
      for (std::size_t j = 0; j < whole; j += 8)
        {
          low += __builtin_convertvector(*reinterpret_cast<const Float4 *>(values + j), Double4) *
                 *reinterpret_cast<const Double4 *>(x + j);
          high += __builtin_convertvector(*reinterpret_cast<const Float4 *>(values + j + 4), Double4) *
                  *reinterpret_cast<const Double4 *>(x + j + 4);
        }
      double sum = lanes_sum(low, high);
      for (std::size_t j = whole; j < n; ++j)
        sum += static_cast<double>(values[j]) * x[j];
      return sum;
    }

    /// The same row against two vectors in one pass over it.
    __attribute__((target_clones("avx2", "default"))) void
    row_dot2(const float *values, const double *x, const double *y, std::size_t n, double &x_sum, double &y_sum)
    {
      Double4           x_low = {}, x_high = {}, y_low = {}, y_high = {};
      const std::size_t whole = n - n % 8;
      for (std::size_t j = 0; j < whole; j += 8)
        {
          const Double4 low  = __builtin_convertvector(*reinterpret_cast<const Float4 *>(values + j), Double4);
          const Double4 high = __builtin_convertvector(*reinterpret_cast<const Float4 *>(values + j + 4), Double4);
          x_low += low * *reinterpret_cast<const Double4 *>(x + j);
          x_high += high * *reinterpret_cast<const Double4 *>(x + j + 4);
          y_low += low * *reinterpret_cast<const Double4 *>(y + j);
          y_high += high * *reinterpret_cast<const Double4 *>(y + j + 4);
        }
      x_sum = lanes_sum(x_low, x_high);
      y_sum = lanes_sum(y_low, y_high);
      for (std::size_t j = whole; j < n; ++j)
        {
          x_sum += static_cast<double>(values[j]) * x[j];
          y_sum += static_cast<double>(values[j]) * y[j];
        }
    }

    // The same in single precision throughout, for the derivative's
    // products (InterfaceContact::add_derivative, whose pressure coupling
    // is solved to 1e-2 anyway): twice the lanes.
    using Float8 = float __attribute__((vector_size(32), aligned(4), __may_alias__));

    inline float lanes_sum(const Float8 &lanes)
    {
      return ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3])) + ((lanes[4] + lanes[5]) + (lanes[6] + lanes[7]));
    }

    /// Σ_j a[j] b[j] and Σ_j c[j] d[j] over n values, in single precision
    /// (one row against two vectors, or two rows against one).
    __attribute__((target_clones("avx2", "default"))) void two_dots_single(const float *a, const float *b,
                                                                           const float *c, const float *d,
                                                                           std::size_t n, float &first, float &second)
    {
      Float8            first_lanes = {}, second_lanes = {};
      const std::size_t whole = n - n % 8;
      for (std::size_t j = 0; j < whole; j += 8)
        {
          first_lanes += *reinterpret_cast<const Float8 *>(a + j) * *reinterpret_cast<const Float8 *>(b + j);
          second_lanes += *reinterpret_cast<const Float8 *>(c + j) * *reinterpret_cast<const Float8 *>(d + j);
        }
      first  = lanes_sum(first_lanes);
      second = lanes_sum(second_lanes);
      for (std::size_t j = whole; j < n; ++j)
        {
          first += a[j] * b[j];
          second += c[j] * d[j];
        }
    }

    /// Σ_j a[j] b[j] over n values, in single precision.
    __attribute__((target_clones("avx2", "default"))) float row_dot_single(const float *a, const float *b,
                                                                          std::size_t n)
    {
      Float8            lanes = {};
      const std::size_t whole = n - n % 8;
      for (std::size_t j = 0; j < whole; j += 8)
        lanes += *reinterpret_cast<const Float8 *>(a + j) * *reinterpret_cast<const Float8 *>(b + j);
      float sum = lanes_sum(lanes);
      for (std::size_t j = whole; j < n; ++j)
        sum += a[j] * b[j];
      return sum;
    }

    /// out += Σ_k weights[k] rows[k] over `count` rows of n values, in single precision.
    __attribute__((target_clones("avx2", "default"))) void
    add_rows_single(const float *const *rows, const float *weights, int count, std::size_t n, float *out)
    {
      const std::size_t whole = n - n % 8;
      for (std::size_t j = 0; j < whole; j += 8)
        {
          Float8 sum = *reinterpret_cast<const Float8 *>(out + j);
          for (int k = 0; k < count; ++k)
            sum += weights[k] * *reinterpret_cast<const Float8 *>(rows[k] + j);
          *reinterpret_cast<Float8 *>(out + j) = sum;
        }
      for (std::size_t j = whole; j < n; ++j)
        for (int k = 0; k < count; ++k)
          out[j] += weights[k] * rows[k][j];
    }
  } // namespace

  // ---------------------------------------------------------------------------
  struct InterfaceContact::Impl
  {
    InterfaceSettings settings;
    double            cell_area;
    double            radius;
    contact::SurfaceGrid grid;
    std::size_t       n, cells;
    // The operator's rows in single precision, on the interface columns
    // only (interface_columns: a body's fixed-interface modes do not move
    // the interface, a fifth of the paper's coordinates): first every cell's radial
    // row, [cell][width], which every right-hand side streams whole for the
    // structural approach (a third of the operator, contiguous), then the
    // tangential pairs, [cell][2][width], which only the loaded cells read. At
    // the paper's size (5760 cells × 3 × 160) it is 22 MB in double, and
    // streaming it from memory was what a right-hand side cost; in float it
    // is half that.
    // Its relative rounding, 6e-8, moves the interface by 6e-8 of the ring's
    // displacement (< 1e-13 m here, against a 1e-11 m tolerance), and the
    // same rounded rows are used both ways, so the transfer stays exactly
    // conservative. Products accumulate in double.
    std::vector<float> rows;
    // Per-cell derivatives of the last Jacobian evaluation: the traction
    // (t_r = -p, τ_θ, τ_z) by the penetration, and the bristle's stiffness
    // against the tangential slip (symmetric: k I when sticking, k the
    // bristles' stiffness at the cell's pressure, the tangent of the Coulomb
    // cap, or zero when sliding).
    std::vector<Eigen::Vector3d> by_penetration;
    std::vector<Eigen::Matrix2d> slip_stiffness;
    /// The bristles' stiffness at every cell at the last evaluation and at
    /// the last Jacobian's (zero where a cell carries no shear), kept only
    /// when asked (track_slip_stiffness).
    std::vector<Eigen::Matrix2d> slip_now, slip_at_jacobian;
    bool                         track_slip = false;
    /// Every evaluation keeps the loaded cells' derivatives (as a
    /// Jacobian's), for add_derivative.
    bool                         keep_derivatives = false;
    contact::Field               approach_change, pressure_change; // add_derivative's work arrays
    /// The share of ∂t/∂d that is not in ∂t/∂ḋ / τ_d: nonzero only in the
    /// closure band, where the damping's c_n g''(d) ḋ adds to ∂p/∂d but not
    /// to ∂p/∂ḋ.
    std::vector<double> band_share;

    /// Above this pressure a cell is in contact [Pa] (LocalCompliance::contact_pressure).
    double contact_pressure() const { return contact_floor; }
    double contact_floor = 0.0;
    /// p_c where the bristles follow the closure (bristle_stiffness), else 0 [Pa].
    double fading_pressure = 0.0;

    /// Row `component` (0 radial, 1 circumferential, 2 axial) of cell c.
    const float *row(std::size_t c, int component) const
    {
      return rows.data() + (component == 0 ? c : cells + 2 * c + component - 1) * width;
    }

    /// x (n values) at the interface columns, the rows' coordinates.
    template <typename Value>
    void gather(const double *x, std::vector<Value> &out) const
    {
      out.resize(width);
      for (std::size_t k = 0; k < width; ++k)
        out[k] = static_cast<Value>(x[interface_columns[k]]);
    }
    /// out (n values) += part (on the interface columns).
    template <typename Value>
    void scatter_add(const Value *part, double *out) const
    {
      for (std::size_t k = 0; k < width; ++k)
        out[interface_columns[k]] += part[k];
    }

    // Committed (last accepted) state. A cell's tangential position u_t, u_z
    // at the accepted q is taken when the cell is first evaluated loaded
    // after the acceptance (tangential_current): most cells stay open, and
    // their two rows are not read.
    contact::Field             tau_x, tau_y, u_t, u_z, pressure;
    std::vector<double>        accepted_q; ///< on the interface columns
    /// The last evaluation's q and q̇ on the interface columns.
    std::vector<double>        interface_q, interface_v;
    std::vector<unsigned char> tangential_current;
    // Trial state of the last evaluation.
    contact::Field trial_tau_x, trial_tau_y, trial_pressure;
    std::vector<unsigned char> loaded;
    /// Cells whose committed traction is near the Coulomb limit (within the
    /// step they slide on at the limit).
    std::vector<unsigned char> slipping;
    bool                       committing = false; ///< evaluating for accept()
    /// InStepBristleLaw::implicit_euler: the step sees the update's own law.
    bool consistent;

    // The half-space in series with the layer (InterfaceSettings::
    // local_compliance_modulus), its last pressure (the next solve's start)
    // and approach, and this evaluation's structural penetration and rate.
    std::unique_ptr<LocalCompliance> local;
    contact::Field                   local_pressure, local_penetration, structural, structural_rate;
    /// The ring's residual flexibility: a ball's u_r per N at the column
    /// angle, and the balls' residual u_r at the loads last set [m].
    std::vector<double> residual_ball, footprint_loads;
    double              residual_column_angle = 0.0;
    contact::Field      ball_residual;
    /// The coordinates that move the interface (not a body's fixed-interface
    /// modes): the rows, the Jacobian's sensitivity and products on these only.
    std::vector<Eigen::Index> interface_columns;
    std::size_t               width = 0; ///< their number

    Impl(const ReducedRing &ring, const InterfaceSettings &s)
      : settings(s)
      , cell_area(ring.interface_grid.cell_area())
      , radius(ring.interface_radius)
      , grid(ring.interface_grid)
      , n(ring.n)
      , cells(ring.interface_grid.size())
      , by_penetration(cells)
      , slip_stiffness(cells)
      , band_share(cells)
      , consistent(s.in_step_bristle_law == InStepBristleLaw::implicit_euler)
    {
      const auto &operator_rows = ring.interface_displacement; // [cell][component][n]
      for (std::size_t j = 0; j < n; ++j)
        for (std::size_t r = 0; r < 3 * cells; ++r)
          if (static_cast<float>(operator_rows[r * n + j]) != 0.0f)
            {
              interface_columns.push_back(static_cast<Eigen::Index>(j));
              break;
            }
      width = interface_columns.size();
      rows.resize(3 * cells * width);
      for (std::size_t c = 0; c < cells; ++c)
        for (int component = 0; component < 3; ++component)
          {
            float *to = rows.data() + (row(c, component) - rows.data());
            for (std::size_t k = 0; k < width; ++k)
              to[k] = static_cast<float>(operator_rows[(3 * c + component) * n + interface_columns[k]]);
          }
      for (auto *field : {&tau_x, &tau_y, &u_t, &u_z, &pressure, &trial_tau_x, &trial_tau_y, &trial_pressure})
        field->assign(cells, 0.0);
      loaded.assign(cells, 0);
      slipping.assign(cells, 0);
      accepted_q.assign(width, 0.0);
      tangential_current.assign(cells, 0);
      if (settings.local_compliance_modulus > 0.0 || !ring.residual_pressure.empty())
        {
          const bool closed = std::abs(grid.nx * grid.hx - 2.0 * M_PI * radius) <= 1e-9 * radius;
          local = std::make_unique<LocalCompliance>(grid, settings.local_compliance_modulus,
                                                    settings.normal_stiffness, closed,
                                                    settings.sensitivity_tolerance, ring.residual_pressure,
                                                    HalfSpaceCompletion{
                                                      ring.residual_pressure.empty() ? 0.0 : ring.residual_half_space_modulus,
                                                      settings.half_space_completion_wavelength},
                                                    UniformCompliance{settings.housing_uniform_compliance});
          // Newton's matrix needs its pressure sensitivity to about 1 %:
          // single precision gives 1e-6 where a half-space or the residual
          // flexibility's half-space completion conditions the operator (the
          // factorisation checks its condition and falls back to double).
          local->set_single_precision_factorisation(true);
          if (settings.local_compliance_modulus == 0.0)
            {
              local->set_closure_pressure(settings.closure_pressure);
              if (settings.bristles_follow_closure)
                fading_pressure = settings.closure_pressure;
            }
          contact_floor = local->contact_pressure();
          for (auto *field : {&local_pressure, &local_penetration})
            field->assign(cells, 0.0);
        }
      structural.assign(cells, 0.0);
      structural_rate.assign(cells, 0.0);
      ball_residual.assign(cells, 0.0);
      residual_ball         = ring.residual_ball;
      footprint_loads       = ring.raceway_footprint_loads;
      residual_column_angle = ring.residual_column_angle;
    }

    void set_ball_loads(const std::vector<double> &angles, const std::vector<double> &loads)
    {
      if (residual_ball.empty())
        return; // ball_residual stays zero
      std::fill(ball_residual.begin(), ball_residual.end(), 0.0);
      add_ball_residual(grid, radius, residual_ball, footprint_loads, residual_column_angle, angles, loads,
                        ball_residual);
    }

    /// A row against x on the interface columns.
    double dot(const float *values, const double *x) const { return row_dot(values, x, width); }

    void dot2(const float *values, const double *x, const double *y, double &x_sum, double &y_sum) const
    {
      row_dot2(values, x, y, width, x_sum, y_sum);
    }

    /// out += G_r,cᵀ w, the radial row of cell c alone.
    void add_radial_row(std::size_t c, double weight, double *out) const
    {
      const float *r = row(c, 0);
#pragma omp simd
      for (std::size_t j = 0; j < width; ++j)
        out[j] += weight * r[j];
    }

    /// out += G_cᵀ w, w = A (t_r, t_θ, t_z) of cell c.
    void add_rows(std::size_t c, const Eigen::Vector3d &weights, double *out) const
    {
      const float *r = row(c, 0), *t = row(c, 1), *z = row(c, 2);
#pragma omp simd
      for (std::size_t j = 0; j < width; ++j)
        out[j] += weights[0] * r[j] + weights[1] * t[j] + weights[2] * z[j];
    }

    struct LayerPressure
    {
      double pressure = 0.0, by_penetration = 0.0; ///< p [Pa] and ∂p/∂d [Pa/m]
      double band_share = 0.0; ///< the share of ∂p/∂d not in ∂p/∂ḋ / τ_d: c_n g'' ḋ / (∂p/∂d)
    };

    /// The Winkler layer at penetration d and rate ḋ (InterfaceSettings::
    /// onset_pressure): p = k_n g(d) + c_n g'(d) ḋ, never pulling, with the C¹
    /// closure g(d) = d²/(4 d_s) on (0, 2 d_s), d - d_s beyond, d_s = p_s/k_n.
    /// ∂p/∂ḋ = c_n g'(d) = τ_d (∂p/∂d - c_n g''(d) ḋ).
    LayerPressure layer_pressure(double penetration, double rate) const
    {
      const double k_n = settings.normal_stiffness, c_n = k_n * settings.normal_damping_time;
      if (penetration <= 0.0)
        return {};
      const double onset = settings.onset_pressure / k_n; // d_s [m]
      double       g = penetration, slope = 1.0, curvature = 0.0;
      if (penetration < 2.0 * onset)
        {
          g         = penetration * penetration / (4.0 * onset);
          slope     = penetration / (2.0 * onset);
          curvature = 1.0 / (2.0 * onset);
        }
      else
        g = penetration - onset;
      const double p = k_n * g + c_n * slope * rate;
      if (p <= 0.0)
        return {};
      // ∂p/∂d > 0 wherever p > 0 (in the band p = g'(d) (k_n d / 2 + c_n ḋ)).
      const double by_penetration = k_n * slope + c_n * curvature * rate;
      return {p, by_penetration, c_n * curvature * rate / by_penetration};
    }

    /// Pressure and tractions at a trial state, their generalised force, and
    /// if asked its derivatives by q and q̇ (from the per-cell derivatives
    /// by_penetration and slip_stiffness of the loaded cells).
    void evaluate(const double *q_data, const double *v_data, const ForceOutput &out)
    {
      const bool jacobian = out.by_position != nullptr;
      set_structural_approach(q_data, v_data);
      const VectorXd force = cell_forces(jacobian || keep_derivatives);
      scatter_add(force.data(), out.force);
      if (jacobian)
        add_jacobian(out);
    }

    /// The structural penetration and its rate at every cell and, with the
    /// half-space, the layer's pressure on its give.
    void set_structural_approach(const double *q_data, const double *v_data)
    {
      gather(q_data, interface_q);
      gather(v_data, interface_v);
      ThreadTeam::shared().run([&](const TeamPart &team) {
        const auto [begin, end] = team.share(cells);
        for (std::size_t c = begin; c < end; ++c)
          {
            double u_r = 0.0, u_r_rate = 0.0;
            dot2(row(c, 0), interface_q.data(), interface_v.data(), u_r, u_r_rate);
            structural[c]      = settings.radial_interference + u_r;
            structural_rate[c] = u_r_rate;
          }
      });
      if (local)
        { // the layer on the half-space's give; its damping through the
          // structural approach rate (w's rate is not in it)
          for (std::size_t c = 0; c < cells; ++c)
            local_penetration[c] =
              structural[c] + ball_residual[c] + settings.normal_damping_time * structural_rate[c];
          local->solve(local_penetration, local_pressure);
        }
    }

    /// The cells' generalised force at the structural approach's q (on the
    /// interface columns); sets the trial pressure and tractions, and with
    /// `jacobian` the loaded cells' derivatives.
    VectorXd cell_forces(bool jacobian)
    {
      std::array<VectorXd, 2> part_forces; // summed in the parts' order
      ThreadTeam::shared().run([&](const TeamPart &team) {
        VectorXd &local_force = part_forces[team.part] = VectorXd::Zero(static_cast<Eigen::Index>(width));
        const auto [begin, end] = team.share(cells);
        for (std::size_t c = begin; c < end; ++c)
          {
            loaded[c] = 0;
            if (track_slip)
              slip_now[c].setZero();
            // Damping never pulls: a fast-opening cell carries no pressure.
            const LayerPressure layer =
              local ? LayerPressure{local_pressure[c], settings.normal_stiffness, 0.0}
                    : layer_pressure(structural[c], structural_rate[c]);
            const double p = layer.pressure;
            trial_pressure[c] = p;
            if (p <= contact_pressure() && tau_x[c] == 0.0 && tau_y[c] == 0.0)
              { // open, or in the layer closure's tail: no shear (at most μ p_c e^-10)
                trial_tau_x[c] = trial_tau_y[c] = 0.0;
                if (p <= 0.0)
                  continue;
                add_radial_row(c, -cell_area * p, local_force.data());
                if (jacobian)
                  {
                    by_penetration[c] = Eigen::Vector3d(-1.0, 0.0, 0.0);
                    band_share[c]     = 0.0;
                    slip_stiffness[c].setZero();
                    loaded[c] = 1;
                  }
                continue;
              }
            if (!tangential_current[c])
              { // every cell's, open ones too: a cell that closes during a step slips from where it was
                u_t[c]                = dot(row(c, 1), accepted_q.data());
                u_z[c]                = dot(row(c, 2), accepted_q.data());
                tangential_current[c] = 1;
              }
            const double   ut = dot(row(c, 1), interface_q.data()), uz = dot(row(c, 2), interface_q.data());
            const BristleStep step = bristle_traction(c, p, -(ut - u_t[c]), -(uz - u_z[c]), jacobian || track_slip);
            if (track_slip && p > 0.0)
              slip_now[c] = step.by_slip;
            trial_tau_x[c] = step.traction.x();
            trial_tau_y[c] = step.traction.y();
            add_rows(c, cell_area * Eigen::Vector3d(-p, step.traction.x(), step.traction.y()), local_force.data());
            if (!jacobian || p <= 0.0)
              continue;
            // A loaded cell is not damped out (p > 0): the traction depends on
            // the penetration through p (normal, and the bristle through μp),
            // on its rate through c_n = k_n τ_d the same way, and on the slip.
            // (With the half-space, ∂p/∂d0 couples the cells: applied below.)
            by_penetration[c] = Eigen::Vector3d(-1.0, step.by_pressure.x(), step.by_pressure.y()) *
                                (local ? 1.0 : layer.by_penetration);
            band_share[c]     = layer.band_share;
            slip_stiffness[c] = step.by_slip;
            loaded[c]         = 1;
          }
      });
      VectorXd force = part_forces[0];
      if (part_forces[1].size() > 0)
        force += part_forces[1];
      if (track_slip && jacobian)
        slip_at_jacobian = slip_now;
      return force;
    }

    /// A cell's tangential traction within the step and its derivatives.
    struct BristleStep
    {
      Eigen::Vector2d traction;
      Eigen::Vector2d by_pressure = Eigen::Vector2d::Zero(); ///< ∂τ/∂p
      Eigen::Matrix2d by_slip     = Eigen::Matrix2d::Zero(); ///< ∂τ/∂(slip)
    };

    /// The bristles' stiffness at pressure p and its derivative ∂k/∂p
    /// (InterfaceSettings::bristles_follow_closure): under the layer's
    /// exponential closure the asperities in contact, and with them the
    /// normal stiffness, fade as k_n (1 − e^(−p/p_c)); an asperity's
    /// tangential stiffness is proportional to its normal one (Mindlin), so
    /// the bristles fade alike. Else k_t. (Without it a cell of the closure's
    /// tail is a stiff spring that lets go within a slip of μp/k_t, a
    /// fraction of a nanometre: a switch within Newton's correction.)
    double bristle_stiffness(double p, double &by_pressure) const
    {
      by_pressure = 0.0;
      if (fading_pressure == 0.0)
        return settings.tangential_stiffness;
      const double disengaged = std::exp(-std::max(p, 0.0) / fading_pressure); // e^(−p/p_c) of k_t
      by_pressure             = settings.tangential_stiffness * disengaged / fading_pressure;
      return settings.tangential_stiffness * (1.0 - disengaged);
    }

    /// The bristle of cell c under pressure p after the slip (ds_x, ds_y)
    /// since the last accepted state.
    BristleStep bristle_traction(std::size_t c, double p, double ds_x, double ds_y, bool jacobian) const
    {
      double       k_by_pressure;
      const double k = bristle_stiffness(p, k_by_pressure), mu = settings.friction_coefficient;
      const double mu_p = mu * p;
      BristleStep  step;
      if (committing || consistent)
        { // the paper's implicit Euler law over the slip so far: the update
          // after the accepted step, or the step itself (with its derivative)
          if (jacobian)
            {
              contact::BristleStepDerivatives derivatives;
              const auto next = contact::bristle_step(tau_x[c], tau_y[c], k, mu, p, ds_x, ds_y, slipping[c] != 0,
                                                      derivatives, settings.bristle_update);
              step.traction = Eigen::Vector2d(next.x, next.y);
              step.by_slip =
                Eigen::Map<const Eigen::Matrix<double, 2, 2, Eigen::RowMajor>>(&derivatives.by_slip[0][0]);
              step.by_pressure = Eigen::Map<const Eigen::Vector2d>(derivatives.by_pressure) +
                                 k_by_pressure * Eigen::Map<const Eigen::Vector2d>(derivatives.by_stiffness);
            }
          else
            {
              const auto next = contact::bristle_step(tau_x[c], tau_y[c], k, mu_p, ds_x, ds_y, settings.bristle_update);
              step.traction   = Eigen::Vector2d(next.x, next.y);
            }
        }
      else if (slipping[c])
        { // sliding on: the traction keeps its ratio to the pressure (≥ 0.9 μ) and its direction
          step.by_pressure = Eigen::Vector2d(tau_x[c], tau_y[c]) / pressure[c];
          step.traction    = step.by_pressure * p;
        }
      else
        { // sticking: the bristle is a linear spring within the step, capped
          // at the Coulomb limit (so that very stiff bristles cannot push
          // the in-step traction far beyond what the update will accept)
          const Eigen::Vector2d slip(ds_x, ds_y), trial = Eigen::Vector2d(tau_x[c], tau_y[c]) + k * slip;
          const double          length = trial.norm();
          if (length <= mu_p)
            {
              step.traction    = trial;
              step.by_slip     = k * Eigen::Matrix2d::Identity();
              step.by_pressure = k_by_pressure * slip;
            }
          else
            {
              const Eigen::Vector2d unit      = trial / length;
              const Eigen::Matrix2d projector = Eigen::Matrix2d::Identity() - unit * unit.transpose();
              step.traction                   = mu_p * unit;
              step.by_slip                    = mu_p * k / length * projector;
              step.by_pressure = mu * unit + k_by_pressure * mu_p / length * projector * slip;
            }
        }
      return step;
    }

    /// InterfaceContact::add_derivative: the products of add_jacobian's
    /// factors with (dq, dv), cell by cell, and the pressure's coupling
    /// solved rather than factorised.
    void add_derivative(const double *dq, const double *dv, double *out)
    {
      const double       damping_time = settings.normal_damping_time;
      std::vector<float> position, velocity;
      gather(dq, position);
      approach_change.assign(cells, 0.0);
      if (local)
        { // with the half-space the approach's change is u_r's along dq + τ_d dv: one product per row
          std::vector<float> combined(width);
          for (std::size_t k = 0; k < width; ++k)
            combined[k] = static_cast<float>(dq[interface_columns[k]] + damping_time * dv[interface_columns[k]]);
          ThreadTeam::shared().run([&](const TeamPart &team) {
            const auto [begin, end] = team.share(cells);
            for (std::size_t c = begin; c < end; ++c)
              if (loaded[c])
                approach_change[c] = row_dot_single(row(c, 0), combined.data(), width);
          });
        }
      else
        {
          gather(dv, velocity);
          ThreadTeam::shared().run([&](const TeamPart &team) {
            const auto [begin, end] = team.share(cells);
            for (std::size_t c = begin; c < end; ++c)
              if (loaded[c])
                {
                  float by_position = 0.0f, by_velocity = 0.0f;
                  two_dots_single(row(c, 0), position.data(), row(c, 0), velocity.data(), width, by_position,
                                  by_velocity);
                  approach_change[c] = by_position + damping_time * (1.0 - band_share[c]) * by_velocity;
                }
          });
        }
      if (local)
        local->pressure_change(local_pressure, approach_change, pressure_change, derivative_tolerance);
      const contact::Field &normal = local ? pressure_change : approach_change;
      std::array<std::vector<float>, 2> parts; // summed in the parts' order
      ThreadTeam::shared().run([&](const TeamPart &team) {
        std::vector<float> &part = parts[team.part];
        part.assign(width, 0.0f);
        const auto [begin, end] = team.share(cells);
        for (std::size_t c = begin; c < end; ++c)
          {
            if (!loaded[c])
              continue;
            Eigen::Vector3d traction = by_penetration[c] * normal[c];
            const float    *cell_rows[3] = {row(c, 0), row(c, 1), row(c, 2)};
            if (slip_stiffness[c].isZero(0.0) && by_penetration[c].tail<2>().isZero(0.0))
              { // no shear (the closure's tail): the radial row alone
                const float weight = static_cast<float>(cell_area * traction[0]);
                add_rows_single(cell_rows, &weight, 1, width, part.data());
                continue;
              }
            if (!slip_stiffness[c].isZero(0.0))
              {
                float along_t = 0.0f, along_z = 0.0f;
                two_dots_single(cell_rows[1], position.data(), cell_rows[2], position.data(), width, along_t,
                                along_z);
                traction.tail<2>() -= slip_stiffness[c] * Eigen::Vector2d(along_t, along_z);
              }
            const float weights[3] = {static_cast<float>(cell_area * traction[0]),
                                      static_cast<float>(cell_area * traction[1]),
                                      static_cast<float>(cell_area * traction[2])};
            add_rows_single(cell_rows, weights, 3, width, part.data());
          }
      });
      if (!parts[1].empty())
        for (std::size_t j = 0; j < width; ++j)
          parts[0][j] += parts[1][j];
      scatter_add(parts[0].data(), out);
    }
    /// add_derivative's pressure change to this fraction of the largest
    /// approach change (1e-3 took a third more convolutions for as many
    /// Newton failures on the paper's case).
    static constexpr double derivative_tolerance = 1e-2;

    /// The loaded cells' factors of the Jacobian (add_jacobian), one row (or
    /// two, tangential) per cell.
    struct JacobianRows
    {
      RowMatrix normal, radial, tangential, slipped;
      bool      single_precision = false; ///< the sensitivity came from a single precision factorisation
    };

    JacobianRows jacobian_rows(const std::vector<std::size_t> &active) const
    {
      const auto m = static_cast<Eigen::Index>(active.size()), size = static_cast<Eigen::Index>(interface_columns.size());
      // Tangential rows only for cells whose bristle has a stiffness (not
      // the layer closure's tail).
      Eigen::Index sheared = 0;
      for (const std::size_t c : active)
        sheared += !slip_stiffness[c].isZero(0.0);
      // The implicit Euler law's ∂τ/∂ds is not symmetric: its tangential part
      // is the general product G_tᵀ (S_c G_t) (`slipped` the latter).
      JacobianRows rows_of{RowMatrix(m, size), RowMatrix(m, size), RowMatrix(2 * sheared, size),
                           RowMatrix(consistent ? 2 * sheared : 0, size)};
      RowMatrix    g(3, size); // one cell's rows in double, on the interface's coordinates
      Eigen::Index t = 0;      // the next tangential pair
      for (Eigen::Index a = 0; a < m; ++a)
        {
          const std::size_t c = active[a];
          for (int component = 0; component < 3; ++component)
            {
              const float *values = row(c, component);
              for (Eigen::Index k = 0; k < size; ++k)
                g(component, k) = values[k];
            }
          rows_of.radial.row(a) = g.row(0);
          rows_of.normal.row(a) = by_penetration[c].transpose() * g;
          if (slip_stiffness[c].isZero(0.0))
            continue;
          if (consistent)
            {
              rows_of.tangential.middleRows(2 * t, 2) = g.bottomRows(2);
              rows_of.slipped.middleRows(2 * t, 2)    = slip_stiffness[c] * g.bottomRows(2);
              ++t;
              continue;
            }
          const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> split(slip_stiffness[c]);
          for (int k = 0; k < 2; ++k)
            rows_of.tangential.row(2 * t + k) = std::sqrt(std::max(split.eigenvalues()[k], 0.0)) *
                                                (split.eigenvectors().col(k).transpose() * g.bottomRows(2));
          ++t;
        }
      if (local)
        { // ∂p_A/∂d0_A = (C_AA + I/k_n)⁻¹: the radial rows through it
          std::vector<double> sensitivity;
          rows_of.single_precision =
            local->pressure_sensitivity(active, rows_of.radial.data(), static_cast<std::size_t>(size), sensitivity);
          rows_of.radial = Eigen::Map<const RowMatrix>(sensitivity.data(), m, size);
        }
      return rows_of;
    }

    /// ∂f/∂q = A Σ_c G_cᵀ D_c G_c over the loaded cells, with
    /// D_c = [∂t/∂d | 0; 0 | -S_c] in (radial, tangential) blocks:
    ///   normal part      N = Σ (G_cᵀ ∂t/∂d) g_r,cᵀ   (one product, m rows),
    ///   tangential part  -Σ G_t,cᵀ S_c G_t,c = -Zᵀ Z with S_c = L Lᵀ, Z the
    ///                    rows Lᵀ G_t,c (a symmetric rank update),
    /// and ∂f/∂q̇ = τ_d (N - N_b), N_b the part of N from the closure band's
    /// c_n g'' ḋ (few cells; the damping acts through p only). A third of
    /// the work of forming G_cᵀ D_c G_c as a full product, twice.
    void add_jacobian(const ForceOutput &out) const
    {
      std::vector<std::size_t> active;
      for (std::size_t c = 0; c < cells; ++c)
        if (loaded[c])
          active.push_back(c);
      if (active.empty())
        return; // (and Eigen's product blocking divides by a zero depth)
      const auto            size    = static_cast<Eigen::Index>(interface_columns.size());
      const JacobianRows    rows_of = jacobian_rows(active);
      // A Lᵀ R over the loaded cells; in single precision, twice as fast,
      // where the sensitivity was (see the constructor).
      const auto product = [&](const RowMatrix &left, const RowMatrix &right) -> Eigen::MatrixXd {
        if (!rows_of.single_precision)
          return cell_area * (left.transpose() * right);
        const Eigen::MatrixXf in_single = cell_area * (left.cast<float>().transpose() * right.cast<float>());
        return in_single.cast<double>();
      };
      Eigen::MatrixXd normal = product(rows_of.normal, rows_of.radial);
      Eigen::MatrixXd by_position = normal;
      if (rows_of.tangential.rows() == 0)
        ; // no bristle with a stiffness (and Eigen's blocking divides by the depth)
      else if (consistent)
        by_position -= product(rows_of.tangential, rows_of.slipped);
      else
        {
          Eigen::MatrixXd tangential = Eigen::MatrixXd::Zero(size, size);
          tangential.selfadjointView<Eigen::Lower>().rankUpdate(rows_of.tangential.transpose(), -cell_area);
          by_position += tangential.selfadjointView<Eigen::Lower>();
        }
      subtract_band_damping(active, rows_of, normal);
      add_on_interface_columns(by_position, 1.0, out.by_position);
      add_on_interface_columns(normal, settings.normal_damping_time, out.by_velocity);
    }

    /// out[i][j] += scale × compact(k, l) at i, j the interface columns k, l.
    void add_on_interface_columns(const Eigen::MatrixXd &compact, double scale, double *out) const
    {
      const auto size = static_cast<Eigen::Index>(interface_columns.size());
      for (Eigen::Index k = 0; k < size; ++k)
        for (Eigen::Index l = 0; l < size; ++l)
          out[static_cast<std::size_t>(interface_columns[k]) * n + static_cast<std::size_t>(interface_columns[l])] +=
            scale * compact(k, l);
    }

    /// N -= N_b for ∂f/∂q̇ = τ_d (N - N_b): the closure band's c_n g'' ḋ is
    /// in ∂p/∂d, not in ∂p/∂ḋ.
    void subtract_band_damping(const std::vector<std::size_t> &active, const JacobianRows &rows_of,
                               Eigen::MatrixXd &normal) const
    {
      std::vector<Eigen::Index> band;
      for (Eigen::Index a = 0; a < static_cast<Eigen::Index>(active.size()); ++a)
        if (band_share[active[a]] != 0.0)
          band.push_back(a);
      if (band.empty())
        return;
      const auto b = static_cast<Eigen::Index>(band.size()), size = rows_of.normal.cols();
      RowMatrix  band_rows(b, size), band_radial(b, size);
      for (Eigen::Index k = 0; k < b; ++k)
        {
          band_rows.row(k)   = band_share[active[band[k]]] * rows_of.normal.row(band[k]);
          band_radial.row(k) = rows_of.radial.row(band[k]);
        }
      normal -= cell_area * (band_rows.transpose() * band_radial);
    }
  };

  InterfaceContact::InterfaceContact(const ReducedRing &ring, const InterfaceSettings &settings)
  {
    ring.check();
    if (!(settings.normal_stiffness > 0.0) || !std::isfinite(settings.normal_stiffness) ||
        !(settings.tangential_stiffness > 0.0) || !std::isfinite(settings.tangential_stiffness))
      throw std::invalid_argument("interface contact: stiffnesses must be positive and finite");
    if (!(settings.friction_coefficient >= 0.0) || !std::isfinite(settings.friction_coefficient))
      throw std::invalid_argument("interface contact: the friction coefficient must be finite and >= 0");
    if (!(settings.normal_damping_time >= 0.0) || !std::isfinite(settings.normal_damping_time))
      throw std::invalid_argument("interface contact: the damping time must be finite and >= 0");
    if (!(settings.onset_pressure >= 0.0) || !std::isfinite(settings.onset_pressure))
      throw std::invalid_argument("interface contact: the onset pressure must be finite and >= 0");
    impl = std::make_unique<Impl>(ring, settings);
  }

  InterfaceContact::~InterfaceContact() = default;

  void InterfaceContact::add_forces(const double *q, const double *velocity, const ForceOutput &out)
  {
    impl->evaluate(q, velocity, out);
  }

  void InterfaceContact::set_ball_loads(const std::vector<double> &angles, const std::vector<double> &loads)
  {
    impl->set_ball_loads(angles, loads);
  }

  void InterfaceContact::accept(const double *q, const double *velocity)
  {
    std::vector<double> scratch(impl->n, 0.0);
    impl->committing = true;
    impl->evaluate(q, velocity, {scratch.data(), nullptr, nullptr});
    impl->committing = false;
    impl->tau_x    = impl->trial_tau_x;
    impl->tau_y    = impl->trial_tau_y;
    impl->pressure = impl->trial_pressure;
    for (std::size_t c = 0; c < impl->cells; ++c)
      impl->slipping[c] = impl->pressure[c] > 0.0 &&
                          std::hypot(impl->tau_x[c], impl->tau_y[c]) >=
                            slip_threshold * impl->settings.friction_coefficient * impl->pressure[c];
    // The tangential positions from now on at this q (taken when needed).
    impl->gather(q, impl->accepted_q);
    std::fill(impl->tangential_current.begin(), impl->tangential_current.end(), 0);
  }

  const contact::Field &InterfaceContact::trial_pressure() const { return impl->trial_pressure; }
  const contact::Field &InterfaceContact::pressure() const { return impl->pressure; }
  const contact::Field &InterfaceContact::shear_x() const { return impl->tau_x; }
  const contact::Field &InterfaceContact::shear_y() const { return impl->tau_y; }

  const LocalCompliance *InterfaceContact::local_compliance() const { return impl->local.get(); }

  void InterfaceContact::keep_derivatives() { impl->keep_derivatives = true; }

  void InterfaceContact::add_derivative(const double *dq, const double *dv, double *out)
  {
    impl->add_derivative(dq, dv, out);
  }

  void InterfaceContact::track_slip_stiffness()
  {
    impl->track_slip = true;
    impl->slip_now.assign(impl->cells, Eigen::Matrix2d::Zero());
    impl->slip_at_jacobian = impl->slip_now;
  }

  void InterfaceContact::slip_stiffness_changes(std::vector<double> &rows, std::vector<double> &changes) const
  {
    const auto &d = *impl;
    rows.clear();
    changes.clear();
    if (!d.track_slip)
      return;
    // A change of a quarter of the bristles' full stiffness k_t: a cell that
    // turned from sticking (k, k_t but where the bristles follow the
    // closure) to sliding (the cap's tangent) or back.
    const double                                  least = 0.25 * d.settings.tangential_stiffness;
    std::vector<std::pair<double, std::size_t>> changed;
    for (std::size_t c = 0; c < d.cells; ++c)
      if (const double size = (d.slip_now[c] - d.slip_at_jacobian[c]).norm(); size > least)
        changed.emplace_back(size, c);
    const std::size_t most = std::min(changed.size(), slip_stiffness_changes_kept);
    std::partial_sort(changed.begin(), changed.begin() + static_cast<std::ptrdiff_t>(most), changed.end(),
                      [](const auto &a, const auto &b) { return a.first > b.first; });
    for (std::size_t k = 0; k < most; ++k)
      {
        const std::size_t c = changed[k].second;
        for (int component = 1; component <= 2; ++component)
          {
            rows.resize(rows.size() + d.n, 0.0);
            d.scatter_add(d.row(c, component), rows.data() + rows.size() - d.n);
          }
        const Eigen::Matrix2d area_change = d.cell_area * (d.slip_now[c] - d.slip_at_jacobian[c]);
        changes.insert(changes.end(), {area_change(0, 0), area_change(0, 1), area_change(1, 0), area_change(1, 1)});
      }
  }

  contact::Field InterfaceContact::effective_friction() const
  {
    contact::Field ratio(impl->cells, 0.0);
    for (std::size_t c = 0; c < impl->cells; ++c)
      if (impl->pressure[c] > impl->contact_pressure())
        ratio[c] = std::hypot(impl->tau_x[c], impl->tau_y[c]) / impl->pressure[c];
    return ratio;
  }

  double InterfaceContact::contact_fraction() const
  {
    std::size_t loaded = 0;
    for (const double p : impl->pressure)
      loaded += p > impl->contact_pressure();
    return static_cast<double>(loaded) / impl->cells;
  }

  double InterfaceContact::slip_fraction() const
  {
    std::size_t loaded = 0, slipping = 0;
    const double mu = impl->settings.friction_coefficient;
    for (std::size_t c = 0; c < impl->cells; ++c)
      if (impl->pressure[c] > impl->contact_pressure())
        {
          ++loaded;
          slipping += std::hypot(impl->tau_x[c], impl->tau_y[c]) >= (1.0 - 1e-3) * mu * impl->pressure[c];
        }
    return loaded > 0 ? static_cast<double>(slipping) / loaded : 0.0;
  }

  void InterfaceContact::resultant(double &force_x, double &force_y) const
  {
    force_x = force_y = 0.0;
    const auto &g = impl->grid;
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i)
        {
          const std::size_t c     = g.index(i, j);
          const double      theta = g.x(i) / impl->radius;
          // traction (t_r, t_θ) = (-p, τ_θ) in the radial/hoop basis
          const double t_r = -impl->pressure[c], t_theta = impl->tau_x[c];
          force_x += impl->cell_area * (t_r * std::cos(theta) - t_theta * std::sin(theta));
          force_y += impl->cell_area * (t_r * std::sin(theta) + t_theta * std::cos(theta));
        }
  }

  // ---------------------------------------------------------------------------
  struct BallContacts::Impl
  {
    std::size_t         n, angles, footprints;
    RowMatrix           approach; // [footprint × angles + angle][n]
    std::vector<double> footprint_loads;
    unsigned int        balls;
    double              stiffness, damping, clearance;
    std::vector<double> loads, raceway_residual;
    Linearisation       linearisation;
  };

  BallContacts::BallContacts(const ReducedRing &ring, unsigned int ball_count, double stiffness, double damping,
                             double radial_clearance)
    : impl(std::make_unique<Impl>())
  {
    ring.check();
    if (ball_count == 0 || !(stiffness > 0.0) || !(damping >= 0.0))
      throw std::invalid_argument("ball contacts: need balls, a positive stiffness and a damping >= 0");
    impl->n               = ring.n;
    impl->angles          = ring.raceway_angles;
    impl->footprints      = ring.raceway_footprints();
    impl->approach        = Eigen::Map<const RowMatrix>(ring.raceway_approach.data(),
                                                        impl->footprints * ring.raceway_angles, ring.n);
    impl->footprint_loads = ring.raceway_footprint_loads;
    impl->balls           = ball_count;
    impl->stiffness       = stiffness;
    impl->damping         = damping;
    impl->clearance       = radial_clearance;
    impl->loads.assign(ball_count, 0.0);
    impl->raceway_residual.assign(ball_count, 0.0);
    impl->linearisation.rows.assign(ball_count * ring.n, 0.0);
    impl->linearisation.slopes.assign(ball_count * ring.n, 0.0);
    impl->linearisation.by_deflection.assign(ball_count, 0.0);
    impl->linearisation.by_deflection_rate.assign(ball_count, 0.0);
  }

  void BallContacts::set_raceway_residual(const std::vector<double> &inward)
  {
    if (inward.size() != impl->balls)
      throw std::invalid_argument("ball contacts: one raceway residual per ball");
    impl->raceway_residual = inward;
  }

  BallContacts::~BallContacts() = default;

  void BallContacts::add_forces(const std::vector<double> &angles, double cage_speed, const double inner_displacement[2],
                                const double inner_velocity[2], const double *q_data, const double *v_data,
                                const ForceOutput &out)
  {
    auto                              &d = *impl;
    const Eigen::Map<const VectorXd>   q(q_data, d.n), v(v_data, d.n);
    Eigen::Map<VectorXd>               force(out.force, d.n);
    const double                       spacing = 2.0 * M_PI / d.angles;
    const std::size_t                  F       = d.footprints;
    VectorXd                           r(d.n), slope(d.n);
    // Per footprint at the ball's angle: r·q, r·q̇ and (dr/dψ)·q.
    VectorXd on_q(F), on_v(F), slope_q(F);
    d.linearisation.cage_speed = cage_speed;
    for (unsigned int j = 0; j < d.balls; ++j)
      {
        double position = std::fmod(angles[j], 2.0 * M_PI);
        if (position < 0.0)
          position += 2.0 * M_PI;
        const double      scaled = position / spacing;
        const std::size_t k0     = static_cast<std::size_t>(scaled) % d.angles, k1 = (k0 + 1) % d.angles;
        const double      w      = scaled - std::floor(scaled);
        for (std::size_t f = 0; f < F; ++f)
          {
            const auto   r0 = d.approach.row(f * d.angles + k0), r1 = d.approach.row(f * d.angles + k1);
            const double a0 = r0.dot(q), a1 = r1.dot(q);
            on_q[f]    = (1.0 - w) * a0 + w * a1;
            on_v[f]    = (1.0 - w) * r0.dot(v) + w * r1.dot(v);
            slope_q[f] = (a1 - a0) / spacing;
          }
        const auto blended = [](const FootprintBlend &b, const VectorXd &x) {
          return b.of([&](std::size_t f) { return x[f]; });
        };
        const double c = std::cos(angles[j]), s = std::sin(angles[j]);
        const double deflection_rest = inner_displacement[0] * c + inner_displacement[1] * s - 0.5 * d.clearance +
                                       d.raceway_residual[j];
        // The ball moves along a deformed raceway: its approach changes with ψ too.
        const double rate_rest = inner_velocity[0] * c + inner_velocity[1] * s +
                                 cage_speed * (-inner_displacement[0] * s + inner_displacement[1] * c);
        // The footprint follows the load and the load the approach under that
        // footprint: a scalar fixed point from the last load, contracting
        // strongly (the footprint moves the approach by a small fraction of
        // the deflection); one pass with a single footprint.
        FootprintBlend blend = footprint_blend(d.footprint_loads, d.loads[j]);
        BallLoad       load;
        for (int iteration = 0; iteration < 50; ++iteration)
          {
            load = ball_load(d.stiffness, d.damping, deflection_rest - blended(blend, on_q),
                             rate_rest - blended(blend, on_v) - cage_speed * blended(blend, slope_q));
            const FootprintBlend next = footprint_blend(d.footprint_loads, load.load);
            // The weights sum to one: the first two settle the third.
            if (F == 1 || (next.first == blend.first && std::abs(next.weights[0] - blend.weights[0]) <= 1e-12 &&
                           std::abs(next.weights[1] - blend.weights[1]) <= 1e-12))
              break;
            blend = next;
          }
        const auto row = [&](std::size_t f, std::size_t k) { return d.approach.row(f * d.angles + k).transpose(); };
        const auto add_rows = [&](std::size_t f, double factor) {
          r.noalias() += factor * ((1.0 - w) * row(f, k0) + w * row(f, k1));
          slope.noalias() += (factor / spacing) * (row(f, k1) - row(f, k0));
        };
        r.setZero();
        slope.setZero();
        for (std::size_t m = 0; m < blend.count; ++m)
          add_rows(blend.first + m, blend.weights[m]);
        d.loads[j] = load.load;
        force.noalias() += load.load * r;
        VectorXd::Map(d.linearisation.rows.data() + j * d.n, d.n)   = r;
        VectorXd::Map(d.linearisation.slopes.data() + j * d.n, d.n) = slope;
        d.linearisation.by_deflection[j]      = load.by_deflection;
        d.linearisation.by_deflection_rate[j] = load.by_deflection_rate;
        if (out.by_position != nullptr)
          {
            // The row's change with the load (through the footprint) is left out.
            Eigen::Map<RowMatrix> dq(out.by_position, d.n, d.n), dv(out.by_velocity, d.n, d.n);
            dq.noalias() -= load.by_deflection * r * r.transpose();
            dq.noalias() -= (load.by_deflection_rate * cage_speed) * r * slope.transpose();
            dv.noalias() -= load.by_deflection_rate * r * r.transpose();
          }
      }
  }

  const std::vector<double> &BallContacts::loads() const { return impl->loads; }

  const BallContacts::Linearisation &BallContacts::linearisation() const { return impl->linearisation; }

  void BallContacts::Linearisation::add_derivative(const double *dq, const double *dv, double *out) const
  {
    if (by_deflection.empty())
      return;
    const auto                       n = static_cast<Eigen::Index>(rows.size() / by_deflection.size());
    const Eigen::Map<const VectorXd> by_position(dq, n), by_velocity(dv, n);
    Eigen::Map<VectorXd>             force_change(out, n);
    for (std::size_t j = 0; j < by_deflection.size(); ++j)
      {
        const double k = by_deflection[j], c = by_deflection_rate[j];
        if (k == 0.0 && c == 0.0)
          continue;
        const Eigen::Map<const VectorXd> r(rows.data() + j * n, n), slope(slopes.data() + j * n, n);
        force_change -= r * (k * r.dot(by_position) + c * cage_speed * slope.dot(by_position) + c * r.dot(by_velocity));
      }
  }
} // namespace fretsim::coupling
