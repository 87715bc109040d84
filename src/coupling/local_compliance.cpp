#include <fretsim/coupling/local_compliance.h>

#include <fretsim/contact/convolution.h>

#include "thread_team.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace fretsim::coupling
{
  struct LocalCompliance::Impl
  {
    contact::SurfaceGrid        grid;
    double                      structural_asymmetry = 0.0; // (these two set while `compliance` is built)
    std::vector<double>         completion_share;           ///< the half-space completion's per k
    /// C's entries tabulated (the kernel the convolution applies), from
    /// which the sensitivity's direct solve assembles C_AA.
    struct Entries
    {
      int                 nx = 0, ny = 0;
      bool                by_row_pair = false; ///< [j][jj][di mod nx]; else [dj][di], |di| < nx, |dj| < ny
      std::vector<double> values;
      /// Between a cell in row j and one in row jj, di columns apart [m/Pa].
      double operator()(int di, int j, int jj) const
      {
        if (by_row_pair)
          return values[(static_cast<std::size_t>(j) * ny + jj) * nx + ((di % nx) + nx) % nx];
        return values[static_cast<std::size_t>(j - jj + ny - 1) * (2 * nx - 1) + (di + nx - 1)];
      }
    };
    Entries entry;
    contact::SurfaceConvolution compliance;
    /// On the closed circumference, (C + I/k_n)⁻¹ on the whole grid: the
    /// conjugate gradients' preconditioner, restricted to the loaded cells
    /// (Vollebregt, J. Comput. Phys. 257, 2014: an FFT preconditioner for
    /// the bound-constrained contact problem). The ring's residual
    /// flexibility is smooth and strong over long distances, which
    /// unpreconditioned iterations resolve slowly.
    std::optional<contact::SurfaceConvolution> preconditioner;
    double                      layer_compliance; ///< 1/k_n [m/Pa]
    double                      sensitivity_tolerance;
    std::size_t                 direct_cells = default_direct_sensitivity_cells;
    bool                        single_precision = false;
    double                      self = 0.0; ///< the largest diagonal entry of C [m/Pa]
    std::vector<double>         row_self;   ///< C's diagonal entry per grid row [m/Pa]
    double                      uniform = 0.0; ///< the largest displacement under p = 1 everywhere [m/Pa]
    contact::Field              response, gap, direction, masked, preconditioned; // work arrays of solve()
    // and of solve_with_closure, sized once: it runs at every right-hand side
    contact::Field              residual, step;
    /// conjugate_gradients' vectors, in single precision.
    std::vector<float>          single_x, single_r, single_z, single_search, single_image, single_masked;
    std::vector<unsigned char>  on, stiff;
    /// The layer's closure (set_closure_pressure): p_c [Pa], 0 for the sharp
    /// one, and the closure's compliance D per cell at the last solve [m/Pa]
    /// (empty when that solve left every cell at zero).
    double                      closure_pressure = 0.0;
    std::vector<double>         closure_diagonal;
    /// The closure's offset s and decay length δ in units of δ, and where
    /// its tail is cut [-].
    static constexpr double     closure_offset = 10.0, closure_cut = 30.0;
    Statistics                  statistics;
    /// The last sensitivity per grid cell and column: the next one's start,
    /// or the answer itself while the loaded cells stay nearly the same (the
    /// operator depends on nothing else).
    std::vector<double>        last_sensitivity;
    std::vector<std::size_t>   last_loaded;
    std::vector<unsigned char> last_known; ///< per grid cell: in last_loaded
    std::size_t              last_columns = 0;
    /// pressure_change's answers since the last closure solve, on the cells
    /// then loaded: the next solve starts from the combination of them whose
    /// approach changes best make up its own (Newton's update is GMRES's
    /// combination of the products it took them for).
    struct Changes
    {
      contact::Field              approach; ///< b of the last closure solve
      std::vector<std::size_t>    cells;
      std::vector<Eigen::VectorXd> by_approach, by_pressure;
    } changes;
    /// Starts the closure solve for b from p + Σ c_k Δp_k (see Changes).
    void predict_from_changes(const contact::Field &b, contact::Field &p) const;

    /// Readies the last sensitivity's store (the conjugate gradients' start)
    /// for `columns` columns; emptied when their number changes.
    void prepare_sensitivity_store(std::size_t columns);
    /// Whether the last sensitivity serves for `loaded` (then in `result`).
    bool reuse_sensitivity(const std::vector<std::size_t> &loaded, const double *rhs, std::size_t columns,
                           std::vector<double> &result);
    struct SensitivityColumns;
    /// (C_AA + I/k_n)⁻¹ rhs by Cholesky; false if the factorisation fails.
    /// `in_single`: it was done in single precision.
    bool direct_sensitivity(const std::vector<std::size_t> &loaded, const double *rhs, std::size_t columns,
                            std::vector<double> &result, bool &in_single);
    template <class Scalar>
    static bool factorise_and_solve(const Eigen::MatrixXd &operator_aa, const double *rhs, std::size_t columns,
                                    std::vector<double> &result);

    Impl(const contact::SurfaceGrid &g, double modulus, double layer_stiffness, bool periodic_x,
         double cg_tolerance, const std::vector<double> &structural, const HalfSpaceCompletion &completion,
         const UniformCompliance &wall)
      : grid(g)
      , compliance(kernel(g, modulus, periodic_x, structural, completion, wall, 1.0 / layer_stiffness,
                          structural_asymmetry, completion_share, entry))
      , layer_compliance(1.0 / layer_stiffness)
      , sensitivity_tolerance(cg_tolerance)
    {
      for (int j = 0; j < g.ny; ++j)
        {
          row_self.push_back(diagonal(j));
          self = std::max(self, row_self.back());
        }
      for (auto *field : {&response, &gap, &direction, &masked, &preconditioned, &residual, &step})
        field->assign(g.size(), 0.0);
      on.assign(g.size(), 0);
      stiff.assign(g.size(), 0);
      if (periodic_x)
        preconditioner = compliance.inverse(layer_compliance);
      compliance.apply(contact::Field(g.size(), 1.0), response);
      uniform = *std::max_element(response.begin(), response.end()) + layer_compliance;
    }

    /// The closure's Newton iteration (LocalCompliance::solve): per cell in
    /// the tail or beyond, r = (C + I/k_n) p − b + s + δ ln(1 − e^(−p/p_c)),
    /// the gradient of a strictly convex energy whose Hessian
    /// C + I/k_n + D is symmetric positive definite. Each step by
    /// conjugate gradients, preconditioned by the FFT inverse on the cells
    /// stiffer than their own closure (D ≤ C_cc) and by the diagonal on the
    /// others; a step never lowers a pressure below a tenth of itself (the
    /// logarithm's barrier), and in the tail it is taken in the logarithm
    /// (closure_update). Cells that rejoin enter the same step. Returns the
    /// convolutions.
    int solve_with_closure(const contact::Field &b, contact::Field &p)
    {
      const std::size_t cells    = grid.size();
      const double      decay    = closure_pressure * layer_compliance; // δ [m]
      const double      offset   = closure_offset * decay;              // s [m]
      const double      cut      = closure_pressure * std::exp(-closure_cut);
      double            scale = 0.0, deepest = -std::numeric_limits<double>::infinity();
      for (const double value : b)
        {
          scale   = std::max(scale, std::abs(value));
          deepest = std::max(deepest, value);
        }
      closure_diagonal.clear();
      predict_from_changes(b, p);
      changes.by_approach.clear();
      changes.by_pressure.clear();
      changes.approach = b;
      if (deepest - offset < -closure_cut * decay)
        { // every cell open beyond the tail's cut
          std::fill(p.begin(), p.end(), 0.0);
          return 0;
        }
      ++statistics.solves;
      const double tolerance = 1e-7 * std::max(scale, decay);
      closure_diagonal.assign(cells, 0.0);
      std::size_t convolutions = 0;
      constexpr int max_newton = 200;
      for (int newton = 0; newton < max_newton; ++newton)
        {
          apply(p, gap, convolutions);
          // The residual cell by cell, on two threads (its logarithms cost
          // as much as a convolution).
          std::array<double, 2>        part_worst{};
          std::array<unsigned char, 2> part_joined{};
          ThreadTeam::shared().run([&](const TeamPart &team) {
            double worst = 0.0;
            bool   joined = false;
            const auto [begin, end] = team.share(cells);
            for (std::size_t c = begin; c < end; ++c)
              {
                residual[c]         = 0.0;
                closure_diagonal[c] = 0.0;
                if (!(p[c] > 0.0))
                  { // a cell at zero rejoins once its compression reaches the tail
                    const double free = b[c] - offset - gap[c];
                    if (free > -closure_cut * decay)
                      {
                        p[c]   = closure_pressure * std::exp(std::min(free / decay, 0.0));
                        joined = true;
                      }
                  }
                on[c] = p[c] > 0.0;
                if (on[c])
                  {
                    const double engaged = -std::expm1(-p[c] / closure_pressure); // 1 − e^(−p/p_c)
                    residual[c]          = gap[c] - b[c] + offset + decay * std::log(engaged);
                    closure_diagonal[c]  = layer_compliance * (1.0 - engaged) / engaged; // δ/p_c/(e^(p/p_c) − 1)
                    worst                = std::max(worst, std::abs(residual[c]));
                  }
                stiff[c] = on[c] && closure_diagonal[c] <= self;
              }
            part_worst[team.part]  = worst;
            part_joined[team.part] = joined;
          });
          const double worst  = std::max(part_worst[0], part_worst[1]);
          const bool   joined = part_joined[0] || part_joined[1];
          if (worst <= tolerance)
            {
              if (joined)
                continue;
              statistics.solve_convolutions += convolutions;
              return static_cast<int>(convolutions);
            }
          // (C + I/k_n + D) step = −r on the cells carrying pressure, to a
          // hundredth of the residual (an inexact Newton step).
          for (std::size_t c = 0; c < cells; ++c)
            residual[c] = on[c] ? -residual[c] : 0.0;
          if (!conjugate_gradients(residual, step, std::max(0.5 * tolerance, 1e-2 * worst), convolutions))
            break;
          for (std::size_t c = 0; c < cells; ++c)
            if (on[c])
              {
                const double next = closure_update(p[c], step[c]);
                p[c]              = next < cut ? 0.0 : next;
              }
        }
      statistics.solve_convolutions += convolutions;
      throw std::runtime_error("local compliance: the interface pressure with the layer's closure did not converge");
    }

    /// (C + I/k_n + D) x = r on the cells `on` (D the closure's, none
    /// without one), by conjugate gradients from x = 0 until the largest
    /// residual is at most `inner`; preconditioned by the FFT inverse on the
    /// `stiff` cells and by the diagonal on the others. False if it did not
    /// converge. In single precision (the vectors and
    /// both convolutions; the sums in double): its callers ask for at most
    /// two digits of the residual (a Newton step's, or the pressure's change
    /// to 1e-2), float's rounding is 1e-7 of it, and the single convolution
    /// takes about two thirds of the double's time.
    bool conjugate_gradients(const contact::Field &r_in, contact::Field &x_out, double inner, std::size_t &convolutions)
    {
      // The vector operations fused into few passes over the grid per
      // iteration (they cost as much as the two convolutions when each is a
      // pass of its own). On two threads (ThreadTeam) each takes the cells of
      // its convolution rows' part, and every sum is the parts' sums in the
      // order of the cells, added in the parts' order.
      constexpr int     max_cg = 500;
      const std::size_t cells  = grid.size();
      const bool        closed = !closure_diagonal.empty();
      for (auto *vector : {&single_x, &single_r, &single_z, &single_search, &single_image, &single_masked})
        vector->assign(cells, 0.0f);
      x_out.resize(cells);
      std::vector<float> &x = single_x, &r = single_r, &z = single_z, &search = single_search, &image = single_image,
                         &masked = single_masked;
      const auto diagonal = [&](std::size_t c) {
        return static_cast<float>(self + layer_compliance + closure_at(c));
      };
      const auto layer = static_cast<float>(layer_compliance);
      // Part 0's cells: the rows before the convolutions' split (each part
      // then reads only the rows it wrote); the preconditioner's own split
      // on the same grid is the same, else its part waits around it.
      const int  split_row = compliance.shared_split_row();
      const bool same_split = !preconditioner || preconditioner->shared_split_row() == split_row;
      const std::size_t split = static_cast<std::size_t>(split_row > 0 ? split_row : grid.ny / 2) * grid.nx;
      // The parts' sums, two sets used in turn: a part may write the next
      // while the other still reads the last.
      std::array<std::array<std::array<double, 2>, 2>, 2> sums{};
      bool converged = false;
      ThreadTeam::shared().run([&](const TeamPart &team) {
        const std::size_t begin = team.parts == 1 || team.part == 0 ? 0 : split,
                          end   = team.parts == 1 || team.part == 1 ? cells : split;
        int               turn  = 0;
        // (Σ first, max second) over the parts.
        const auto combine = [&](double first, double second) {
          sums[turn][team.part] = {first, second};
          team.wait();
          std::array<double, 2> total = sums[turn][0];
          for (int part = 1; part < team.parts; ++part)
            total = {total[0] + sums[turn][part][0], std::max(total[1], sums[turn][part][1])};
          turn ^= 1;
          return total;
        };
        const auto convolve = [&](const contact::SurfaceConvolution &op, const std::vector<float> &in,
                                  std::vector<float> &out, bool aligned) {
          if (team.parts == 1)
            return op.apply(in, out);
          if (!aligned)
            team.wait();
          op.apply_shared(in, out, team.part, [&] { team.wait(); });
          if (!aligned)
            team.wait();
        };
        // z = M⁻¹ r from `masked` (r on the stiff cells), and this part's r·z.
        const auto precondition = [&]() {
          if (preconditioner)
            {
              if (team.part == 0)
                ++convolutions;
              convolve(*preconditioner, masked, z, same_split);
            }
          else
            std::copy(masked.begin() + begin, masked.begin() + end, z.begin() + begin);
          double product = 0.0;
          for (std::size_t c = begin; c < end; ++c)
            {
              if (!stiff[c])
                z[c] = on[c] ? r[c] / diagonal(c) : 0.0f;
              product += on[c] ? static_cast<double>(r[c]) * z[c] : 0.0;
            }
          return product;
        };
        double largest = 0.0;
        for (std::size_t c = begin; c < end; ++c)
          {
            r[c]      = static_cast<float>(r_in[c]);
            masked[c] = stiff[c] ? r[c] : 0.0f;
            largest   = std::max(largest, std::abs(r_in[c]));
          }
        auto [product, largest_r] = combine(precondition(), largest);
        largest = largest_r;
        std::copy(z.begin() + begin, z.begin() + end, search.begin() + begin); // zero off the loaded cells, as r
        for (int it = 0; it < max_cg; ++it)
          {
            if (largest <= inner)
              {
                if (team.part == 0)
                  converged = true;
                break;
              }
            if (team.part == 0)
              ++convolutions;
            convolve(compliance, search, image, true);
            double curvature = 0.0;
            for (std::size_t c = begin; c < end; ++c)
              {
                image[c] += (closed ? layer + static_cast<float>(closure_diagonal[c]) : layer) * search[c];
                curvature += on[c] ? static_cast<double>(search[c]) * image[c] : 0.0;
              }
            const auto length = static_cast<float>(product / combine(curvature, 0.0)[0]);
            largest           = 0.0;
            for (std::size_t c = begin; c < end; ++c)
              {
                if (on[c])
                  {
                    x[c] += length * search[c];
                    r[c] -= length * image[c];
                  }
                masked[c] = stiff[c] ? r[c] : 0.0f;
                largest   = std::max(largest, static_cast<double>(std::abs(r[c])));
              }
            const auto [next, largest_next] = combine(precondition(), largest);
            largest                         = largest_next;
            const auto ratio                = static_cast<float>(next / product);
            for (std::size_t c = begin; c < end; ++c)
              search[c] = on[c] ? z[c] + ratio * search[c] : 0.0f;
            product = next;
          }
        std::copy(x.begin() + begin, x.begin() + end, x_out.begin() + begin);
      });
      return converged;
    }

    /// LocalCompliance::pressure_change.
    void pressure_change(const contact::Field &p, const contact::Field &approach_change, contact::Field &change,
                         double relative_tolerance)
    {
      const std::size_t cells = grid.size();
      double            largest = 0.0;
      for (std::size_t c = 0; c < cells; ++c)
        {
          on[c]    = p[c] > 0.0;
          stiff[c] = on[c] && closure_at(c) <= self;
          residual[c] = on[c] ? approach_change[c] : 0.0;
          largest     = std::max(largest, std::abs(residual[c]));
        }
      change.assign(cells, 0.0);
      if (largest == 0.0)
        return;
      std::size_t convolutions = 0;
      if (!conjugate_gradients(residual, change, relative_tolerance * largest, convolutions))
        throw std::runtime_error("local compliance: the pressure's change did not converge");
      if (closure_pressure > 0.0 && changes.by_approach.size() < max_changes)
        {
          if (changes.by_approach.empty())
            {
              changes.cells.clear();
              for (std::size_t c = 0; c < cells; ++c)
                if (on[c])
                  changes.cells.push_back(c);
            }
          const std::size_t loaded = changes.cells.size();
          Eigen::VectorXd   db(loaded), dp(loaded);
          for (std::size_t k = 0; k < loaded; ++k)
            {
              db[k] = approach_change[changes.cells[k]];
              dp[k] = change[changes.cells[k]];
            }
          changes.by_approach.push_back(std::move(db));
          changes.by_pressure.push_back(std::move(dp));
        }
      ++statistics.changes;
      statistics.change_convolutions += convolutions;
    }

    static constexpr std::size_t max_changes = 40; ///< GMRES's most vectors

    /// The closure's compliance D of cell c at the last solve [m/Pa].
    double closure_at(std::size_t c) const { return closure_diagonal.empty() ? 0.0 : closure_diagonal[c]; }

    /// p after a linearised change Δp. Below p_c the closure's own
    /// compliance dominates and the pressure follows the approach
    /// exponentially, p ∝ e^(−gap/δ): the change is taken as p e^(Δp/p),
    /// exact for a cell that carries its closure alone (a step linear in p
    /// crawls there, a decade per step down, and a fifth fewer convolutions
    /// per solve on the paper's scene this way). At most a tenth down and
    /// e² up; above p_c linear.
    double closure_update(double p, double change) const
    {
      constexpr double ln_tenth = -2.302585092994046;
      if (p < closure_pressure)
        return p * std::exp(std::clamp(change / p, ln_tenth, 2.0));
      return std::max(p + change, 0.1 * p);
    }

    /// The sensitivity with the closure (LocalCompliance::pressure_sensitivity):
    /// cells whose closure compliance D is at most ten times a cell's own
    /// ("coupled") solved together; then each of the others ("weak": in the
    /// tail) from what is left of its right-hand side once the coupled
    /// cells' pressure has moved it, (R_w − (C Δp_coupled)_w) /
    /// (C_ww + 1/k_n + D_w), one convolution per column (one block
    /// Gauss–Seidel sweep: the weak cells' own answer does not move the
    /// coupled ones; 3 % of the response at ten times, 7 % at three, against
    /// central differences of the solve). Returns whether the coupled
    /// cells' answer came in single precision.
    bool closure_sensitivity(const std::vector<std::size_t> &loaded, const double *rhs, std::size_t columns,
                             std::vector<double> &result);
    /// Every loaded cell coupled: the factorisation, the last answer or the
    /// conjugate gradients (LocalCompliance::pressure_sensitivity).
    bool coupled_sensitivity(const std::vector<std::size_t> &loaded, const double *rhs, std::size_t columns,
                             std::vector<double> &result);

    /// C's diagonal entry of a cell in row j [m/Pa].
    double diagonal(int j) const
    {
      contact::Field unit(grid.size(), 0.0), response;
      unit[grid.index(0, j)] = 1.0;
      compliance.apply(unit, response);
      return response[grid.index(0, j)];
    }

    /// Per circumferential wavenumber k, the ny × ny block of R,
    /// R̂(k) = Σ_di R(di) cos(2π k di/nx) (R even in di), is mended in two
    /// ways, and the table transformed back. `table` [j][jj][di], in place.
    ///  * R is positive semidefinite in exact arithmetic (the part of K⁻¹
    ///    the basis does not hold). Sampled from an FE mesh coarser than the
    ///    grid, its blocks at the shortest wavelengths come out slightly
    ///    indefinite (on the 6208 ring down to -1 % of the largest
    ///    eigenvalue, at 153 of 180 wavenumbers); without a half-space's
    ///    compliance in series the contact problem would then be
    ///    indefinite: negative eigenvalues are set to zero.
    ///  * With `completion` (Love's kernel at E'_s by (di, j - jj)), the
    ///    half-space completion: at wavelengths well below the wall
    ///    thickness a body's surface is as compliant as a half-space of its
    ///    material, and the reduced basis holds none of it, so the exact R
    ///    tends to the half-space's block
    ///    Ĥ(k) (Love's rectangles at E'_s); an FE mesh with a few elements
    ///    per wave loses it (scripts/residual_spectrum.py: the 6208 models
    ///    below λ ≈ 3 mm). Where R̂(k) holds less than Ĥ(k), the shortfall
    ///    (Ĥ − R̂)₊, its positive eigenvalues, is added; where the mesh
    ///    resolves the body (R̂ ≥ Ĥ: thin-wall bending) nothing is. Only
    ///    below the wavelength λ_c (`completion_wavelength`, the wall's
    ///    thickness), fading out linearly in k up to 2 λ_c: at longer waves
    ///    the half-space is no limit of anything (on the 6208 ring R̂ falls
    ///    short of it by 40-75 % at k ≤ 10, where the basis holds the
    ///    compliance). `added` [k]: the trace added over Ĥ's [-].
    static void mend_per_wavenumber(const contact::SurfaceGrid &g, std::vector<double> &table,
                                    const std::function<double(int, int)> &completion, double completion_wavelength,
                                    std::vector<double> &added)
    {
      const int nx = g.nx, ny = g.ny, frequencies = nx / 2 + 1;
      const auto at = [&](int j, int jj, int di) -> double & {
        return table[(static_cast<std::size_t>(j) * ny + jj) * nx + di];
      };
      std::vector<double> cosine(static_cast<std::size_t>(nx));
      for (int n = 0; n < nx; ++n)
        cosine[n] = std::cos(2.0 * M_PI * n / nx);
      // the completion's kernel by (di, j - jj)
      std::vector<double> half_space;
      if (completion)
        {
          half_space.resize(static_cast<std::size_t>(nx) * (2 * ny - 1));
          for (int dj = 1 - ny; dj < ny; ++dj)
            for (int di = 0; di < nx; ++di)
              half_space[static_cast<std::size_t>(dj + ny - 1) * nx + di] = completion(di, dj);
        }
      added.assign(completion ? frequencies : 0, 0.0);
      const double full_from = completion ? nx * g.hx / completion_wavelength : 0.0; // k at λ_c
      const auto   weight    = [full_from](int k) { return std::clamp(2.0 * k / full_from - 1.0, 0.0, 1.0); };
      std::vector<Eigen::MatrixXd> blocks(frequencies, Eigen::MatrixXd(ny, ny));
#pragma omp parallel for schedule(dynamic)
      for (int k = 0; k < frequencies; ++k)
        {
          Eigen::MatrixXd target(ny, ny);
          for (int j = 0; j < ny; ++j)
            for (int jj = 0; jj < ny; ++jj)
              {
                double sum = 0.0, reference = 0.0;
                for (int di = 0; di < nx; ++di)
                  {
                    const double c = cosine[(static_cast<long>(k) * di) % nx];
                    sum += at(j, jj, di) * c;
                    if (completion)
                      reference += half_space[static_cast<std::size_t>(j - jj + ny - 1) * nx + di] * c;
                  }
                blocks[k](j, jj) = sum;
                target(j, jj)    = reference;
              }
          const auto positive_part = [](const Eigen::MatrixXd &m) -> Eigen::MatrixXd {
            const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> split(m);
            return split.eigenvectors() * split.eigenvalues().cwiseMax(0.0).asDiagonal() *
                   split.eigenvectors().transpose();
          };
          blocks[k] = positive_part(blocks[k]);
          if (completion && weight(k) > 0.0)
            {
              const Eigen::MatrixXd shortfall = weight(k) * positive_part(target - blocks[k]);
              blocks[k] += shortfall;
              added[k] = target.trace() > 0.0 ? shortfall.trace() / target.trace() : 0.0;
            }
        }
      // back: R(di) = (1/nx) Σ_k w_k R̂(k) cos(2π k di/nx), w = 1 at k = 0
      // and (nx even) k = nx/2, else 2 (the mirrored half).
#pragma omp parallel for schedule(static)
      for (int j = 0; j < ny; ++j)
        for (int jj = 0; jj < ny; ++jj)
          for (int di = 0; di < nx; ++di)
            {
              double sum = 0.0;
              for (int k = 0; k < frequencies; ++k)
                sum += (k == 0 || 2 * k == nx ? 1.0 : 2.0) * blocks[k](j, jj) *
                       cosine[(static_cast<long>(k) * di) % nx];
              at(j, jj, di) = sum / nx;
            }
    }

    /// The constant that, added to every entry of the half-space's kernel
    /// `love` (by column offset and row offset), makes the mean give under a
    /// uniform unit pressure `uniform.compliance` (UniformCompliance); 0
    /// without one. The constant adds n_x c 1 1ᵀ to the k = 0 block B_0 (rows
    /// × rows): with c < 0 it stays positive definite while
    /// 1 + n_x c 1ᵀ (B_0 + I/k_n)⁻¹ 1 > 0 (the residual flexibility's share is
    /// positive semidefinite and only helps).
    static double uniform_shift(const contact::SurfaceGrid &g, const std::function<double(int, int)> &love,
                                const UniformCompliance &uniform, double layer_compliance)
    {
      if (!(uniform.compliance > 0.0))
        return 0.0;
      Eigen::MatrixXd block = Eigen::MatrixXd::Zero(g.ny, g.ny);
      for (int j = 0; j < g.ny; ++j)
        for (int jj = 0; jj < g.ny; ++jj)
          for (int di = 0; di < g.nx; ++di)
            block(j, jj) += love(di, j - jj);
      const Eigen::VectorXd ones  = Eigen::VectorXd::Ones(g.ny);
      const double          mean  = ones.dot(block * ones) / g.ny; // the half-space's own mean give [m/Pa]
      const double          shift = (uniform.compliance - mean) / (static_cast<double>(g.nx) * g.ny);
      block.diagonal().array() += layer_compliance;
      if (1.0 + g.nx * shift * ones.dot(block.llt().solve(ones)) <= 0.0)
        throw std::invalid_argument("local compliance: a uniform compliance of " + std::to_string(uniform.compliance) +
                                    " m/Pa is too far below the half-space's own (" + std::to_string(mean) +
                                    " m/Pa) for its kernel to stay positive definite");
      return shift;
    }

    /// The half-space's kernel (Love's rectangles; on the closed
    /// circumference the nearest image acts: periodic, convolved without
    /// padding in x), and the structural compliance added to it if given.
    static contact::SurfaceConvolution kernel(const contact::SurfaceGrid &g, double modulus, bool periodic_x,
                                              const std::vector<double> &structural, const HalfSpaceCompletion &completion,
                                              const UniformCompliance &uniform, double layer_compliance,
                                              double &asymmetry, std::vector<double> &added, Entries &entry)
    {
      const auto nearest = [g](int di) {
        di = ((di % g.nx) + g.nx) % g.nx;
        return di > g.nx / 2 ? di - g.nx : di;
      };
      const auto love_at = [g, periodic_x, nearest](double modulus) {
        return [g, periodic_x, nearest, modulus](int di, int dj) {
          if (modulus <= 0.0)
            return 0.0;
          return contact::influence::normal_displacement((periodic_x ? nearest(di) : di) * g.hx, dj * g.hy, g.hx,
                                                         g.hy, modulus);
        };
      };
      const auto   half_space = love_at(modulus);
      const double shift      = uniform_shift(g, half_space, uniform, layer_compliance);
      const auto   love       = [half_space, shift](int di, int dj) { return half_space(di, dj) + shift; };
      if (structural.empty())
        {
          entry = Entries{g.nx, g.ny, false, std::vector<double>(static_cast<std::size_t>(2 * g.nx - 1) * (2 * g.ny - 1))};
          for (int dj = 1 - g.ny; dj < g.ny; ++dj)
            for (int di = 1 - g.nx; di < g.nx; ++di)
              entry.values[static_cast<std::size_t>(dj + g.ny - 1) * (2 * g.nx - 1) + (di + g.nx - 1)] = love(di, dj);
          return contact::SurfaceConvolution(g, love, periodic_x);
        }
      // R(di; j, jj): cell (di, j) under pressure on (0, jj). Reciprocity
      // (R(di; j, jj) = R(-di; jj, j)) and the ring's mirror symmetry
      // (even in di) hold for the exact compliance; the FE mesh, whose
      // divisions are not the grid's, and the sampling from one column break
      // them slightly: averaged over the four, the operator is symmetric and
      // its row spectra real.
      const auto raw = [g, &structural](int di, int j, int jj) {
        di = ((di % g.nx) + g.nx) % g.nx;
        return structural[static_cast<std::size_t>(jj) * g.size() + g.index(di, j)];
      };
      std::vector<double> table(static_cast<std::size_t>(g.nx) * g.ny * g.ny);
      double              largest = 0.0, deviation = 0.0;
      for (int j = 0; j < g.ny; ++j)
        for (int jj = 0; jj < g.ny; ++jj)
          for (int di = 0; di < g.nx; ++di)
            {
              const double value = raw(di, j, jj);
              const double mean  = 0.25 * (value + raw(-di, j, jj) + raw(-di, jj, j) + raw(di, jj, j));
              table[(static_cast<std::size_t>(j) * g.ny + jj) * g.nx + di] = mean;
              largest   = std::max(largest, std::abs(value));
              deviation = std::max(deviation, std::abs(value - mean));
            }
      asymmetry = largest > 0.0 ? deviation / largest : 0.0;
      mend_per_wavenumber(g, table,
                          completion.modulus > 0.0 ? std::function<double(int, int)>(love_at(completion.modulus))
                                                   : std::function<double(int, int)>(),
                          completion.wavelength, added);
      // the kernel: Love's (periodic) plus the mended table, by row pair
      for (int j = 0; j < g.ny; ++j)
        for (int jj = 0; jj < g.ny; ++jj)
          for (int di = 0; di < g.nx; ++di)
            table[(static_cast<std::size_t>(j) * g.ny + jj) * g.nx + di] += love(di, j - jj);
      entry = Entries{g.nx, g.ny, true, std::move(table)};
      return contact::SurfaceConvolution(g, contact::RowPairInfluenceFunction(
                                              [&entry](int di, int j, int jj) { return entry(di, j, jj); }));
    }

    /// z = P_A M⁻¹ P_A r with A the cells where `pressure` > 0 (M⁻¹ the
    /// preconditioner; without one, z = P_A r).
    void precondition(const contact::Field &pressure, const contact::Field &r, contact::Field &z, std::size_t &count)
    {
      const std::size_t cells = grid.size();
      for (std::size_t c = 0; c < cells; ++c)
        masked[c] = pressure[c] > 0.0 ? r[c] : 0.0;
      if (!preconditioner)
        {
          z = masked;
          return;
        }
      ++count;
      preconditioner->apply(masked, z);
      for (std::size_t c = 0; c < cells; ++c)
        if (!(pressure[c] > 0.0))
          z[c] = 0.0;
    }

    /// out = (C + I/k_n) in, on the whole grid.
    void apply(const contact::Field &in, contact::Field &out, std::size_t &count)
    {
      ++count;
      compliance.apply(in, out);
      for (std::size_t c = 0; c < in.size(); ++c)
        out[c] += layer_compliance * in[c];
    }
  };

  LocalCompliance::LocalCompliance(const contact::SurfaceGrid &grid, double contact_modulus, double layer_stiffness,
                                   bool periodic_x, double sensitivity_tolerance,
                                   const std::vector<double> &structural_compliance, const HalfSpaceCompletion &completion,
                                   const UniformCompliance &uniform)
  {
    if (!(contact_modulus >= 0.0) || !std::isfinite(contact_modulus) ||
        (contact_modulus == 0.0 && structural_compliance.empty()))
      throw std::invalid_argument("local compliance: the contact modulus must be positive and finite (or 0 with a "
                                  "structural compliance)");
    if (!structural_compliance.empty() &&
        (!periodic_x || structural_compliance.size() != grid.size() * static_cast<std::size_t>(grid.ny)))
      throw std::invalid_argument("local compliance: the structural compliance needs the closed circumference and "
                                  "[rows][cells] entries");
    if (!(layer_stiffness > 0.0) || !std::isfinite(layer_stiffness))
      throw std::invalid_argument("local compliance: the layer stiffness must be positive and finite");
    if (!(sensitivity_tolerance > 0.0 && sensitivity_tolerance < 1.0))
      throw std::invalid_argument("local compliance: the sensitivity tolerance must be in (0, 1)");
    if (!(completion.modulus >= 0.0) || !std::isfinite(completion.modulus) ||
        (completion.modulus > 0.0 && (structural_compliance.empty() || !(completion.wavelength > 0.0) ||
                                      !std::isfinite(completion.wavelength))))
      throw std::invalid_argument("local compliance: the half-space completion needs a structural compliance, a "
                                  "finite modulus >= 0 and a positive wavelength");
    if (!(uniform.compliance >= 0.0) || !std::isfinite(uniform.compliance) ||
        (uniform.compliance > 0.0 && (!periodic_x || !(contact_modulus > 0.0))))
      throw std::invalid_argument("local compliance: a uniform compliance must be finite and >= 0, and needs the "
                                  "closed circumference and a half-space");
    impl = std::make_unique<Impl>(grid, contact_modulus, layer_stiffness, periodic_x, sensitivity_tolerance,
                                  structural_compliance, completion, uniform);
  }

  double lame_bore_compliance(double bore_radius, double outer_radius, double youngs_modulus, double poisson_ratio)
  {
    if (!(bore_radius > 0.0) || !(outer_radius > bore_radius) || !std::isfinite(outer_radius) ||
        !(youngs_modulus > 0.0))
      throw std::invalid_argument("Lamé ring: need 0 < bore radius < outer radius and a positive Young's modulus");
    const double b2 = bore_radius * bore_radius, c2 = outer_radius * outer_radius;
    return bore_radius / youngs_modulus * ((c2 + b2) / (c2 - b2) + poisson_ratio);
  }

  double LocalCompliance::structural_asymmetry() const { return impl->structural_asymmetry; }

  const std::vector<double> &LocalCompliance::completion_by_wavenumber() const { return impl->completion_share; }

  void LocalCompliance::Impl::predict_from_changes(const contact::Field &b, contact::Field &p) const
  {
    const std::size_t columns = changes.by_approach.size(), loaded = changes.cells.size();
    if (columns == 0 || changes.approach.size() != b.size())
      return;
    Eigen::MatrixXd approach(loaded, columns);
    Eigen::VectorXd wanted(loaded);
    for (std::size_t k = 0; k < columns; ++k)
      approach.col(k) = changes.by_approach[k];
    for (std::size_t k = 0; k < loaded; ++k)
      wanted[k] = b[changes.cells[k]] - changes.approach[changes.cells[k]];
    const double wanted_norm = wanted.norm();
    if (!(wanted_norm > 0.0))
      return;
    const Eigen::VectorXd weight = approach.colPivHouseholderQr().solve(wanted);
    // Only an update that lies in their span (else the plain start).
    if (!weight.allFinite() || (approach * weight - wanted).norm() > 0.1 * wanted_norm)
      return;
    Eigen::VectorXd change = Eigen::VectorXd::Zero(loaded);
    for (std::size_t k = 0; k < columns; ++k)
      change += weight[k] * changes.by_pressure[k];
    for (std::size_t k = 0; k < loaded; ++k)
      {
        double &cell = p[changes.cells[k]];
        if (!(cell > 0.0))
          continue;
        cell = closure_update(cell, change[k]);
      }
  }

  LocalCompliance::~LocalCompliance() = default;

  void LocalCompliance::set_direct_sensitivity_cells(std::size_t cells) { impl->direct_cells = cells; }

  void LocalCompliance::set_single_precision_factorisation(bool single) { impl->single_precision = single; }

  const LocalCompliance::Statistics &LocalCompliance::statistics() const { return impl->statistics; }

  void LocalCompliance::set_closure_pressure(double closure_pressure)
  {
    if (!(closure_pressure >= 0.0) || !std::isfinite(closure_pressure))
      throw std::invalid_argument("local compliance: the closure pressure must be finite and >= 0");
    impl->closure_pressure = closure_pressure;
    impl->closure_diagonal.clear();
  }

  double LocalCompliance::contact_pressure() const
  {
    return impl->closure_pressure * std::exp(-Impl::closure_offset);
  }

  void LocalCompliance::pressure_change(const contact::Field &pressure, const contact::Field &approach_change,
                                        contact::Field &change, double relative_tolerance)
  {
    impl->pressure_change(pressure, approach_change, change, relative_tolerance);
  }

  int LocalCompliance::solve(const contact::Field &b, contact::Field &p)
  {
    if (impl->closure_pressure > 0.0)
      return impl->solve_with_closure(b, p);
    auto             &d     = *impl;
    const std::size_t cells = d.grid.size();
    double            scale = 0.0;
    for (const double value : b)
      scale = std::max(scale, value);
    if (scale <= 0.0)
      { // nothing penetrates: the half-space only pushes the surfaces apart
        std::fill(p.begin(), p.end(), 0.0);
        return 0;
      }
    const double tolerance = 1e-7 * scale;
    ++d.statistics.solves;
    // Polonsky & Keer (Wear 231, 1999) with the approach given: conjugate
    // directions on the loaded cells, cells that would pull dropped, open
    // cells that penetrate taken in along the gradient with the same step
    // (and the directions restarted). When no cell is loaded, a start below
    // the solution: the pressure the same penetration everywhere would need.
    const auto start_from_uniform = [&]() {
      for (std::size_t c = 0; c < cells; ++c)
        p[c] = std::max(b[c], 0.0) / d.uniform;
    };
    double previous    = 1.0;
    bool   restart     = true;
    bool   gap_current = false;
    bool   any_loaded  = std::any_of(p.begin(), p.end(), [](double value) { return value > 0.0; });
    std::fill(d.direction.begin(), d.direction.end(), 0.0);
    constexpr int max_iterations = 2000;
    for (int it = 0; it < max_iterations; ++it)
      {
        if (!any_loaded)
          {
            start_from_uniform();
            any_loaded  = true; // scale > 0: some cell penetrates
            restart     = true;
            gap_current = false;
          }
        if (!gap_current)
          {
            d.apply(p, d.gap, d.statistics.solve_convolutions);
            for (std::size_t c = 0; c < cells; ++c)
              d.gap[c] -= b[c];
          }
        double worst = 0.0;
        for (std::size_t c = 0; c < cells; ++c)
          {
            if (p[c] > 0.0)
              worst = std::max(worst, std::abs(d.gap[c]));
            else if (d.gap[c] < 0.0)
              worst = std::max(worst, -d.gap[c]);
          }
        if (worst <= tolerance)
          return it;
        d.precondition(p, d.gap, d.preconditioned, d.statistics.solve_convolutions);
        double squared = 0.0; // gapᵀ M⁻¹ gap over the loaded cells
        for (std::size_t c = 0; c < cells; ++c)
          if (p[c] > 0.0)
            squared += d.gap[c] * d.preconditioned[c];
        const double ratio = restart ? 0.0 : squared / previous;
        previous           = squared;
        for (std::size_t c = 0; c < cells; ++c)
          d.direction[c] = p[c] > 0.0 ? d.preconditioned[c] + ratio * d.direction[c] : 0.0;
        d.apply(d.direction, d.response, d.statistics.solve_convolutions);
        double along = 0.0, curvature = 0.0;
        for (std::size_t c = 0; c < cells; ++c)
          if (p[c] > 0.0)
            {
              along += d.gap[c] * d.direction[c];
              curvature += d.response[c] * d.direction[c];
            }
        const double length = curvature > 0.0 ? along / curvature : 0.0;
        restart             = false;
        bool clipped        = false;
        any_loaded          = false;
        for (std::size_t c = 0; c < cells; ++c)
          {
            if (p[c] > 0.0)
              {
                const double next = p[c] - length * d.direction[c];
                clipped           = clipped || next < 0.0;
                p[c]              = std::max(next, 0.0);
              }
            else if (d.gap[c] < 0.0)
              {
                p[c]    = -length * d.gap[c];
                restart = true;
              }
            any_loaded = any_loaded || p[c] > 0.0;
          }
        // Without cells dropped or taken in, the step's gap follows from the
        // direction's response: one convolution per iteration instead of two.
        gap_current = !clipped && !restart;
        if (gap_current)
          for (std::size_t c = 0; c < cells; ++c)
            d.gap[c] -= length * d.response[c];
      }
    throw std::runtime_error("local compliance: the interface pressure did not converge in " +
                             std::to_string(max_iterations) + " conjugate gradient iterations");
  }

  void LocalCompliance::Impl::prepare_sensitivity_store(std::size_t columns)
  {
    if (last_columns == columns)
      return;
    last_sensitivity.assign(grid.size() * columns, 0.0);
    last_known.assign(grid.size(), 0);
    last_columns = columns;
    last_loaded.clear();
  }

  bool LocalCompliance::Impl::reuse_sensitivity(const std::vector<std::size_t> &loaded, const double *rhs,
                                                std::size_t columns, std::vector<double> &result)
  {
    const std::size_t m = loaded.size();
    // Newton's matrix needs no more than this: while the loaded set differs
    // from the last computed one in at most 2 % of its cells, the last
    // sensitivity serves (a cell new to it starts as a lone cell), as ARKODE
    // itself keeps a Jacobian over many steps.
    std::size_t added = 0;
    for (const std::size_t c : loaded)
      added += !last_known[c];
    const std::size_t dropped = last_loaded.size() - (m - added);
    const std::size_t differ  = added + dropped;
    if (last_loaded.empty() || differ > m / 50)
      return false;
    for (std::size_t a = 0; a < m; ++a)
      for (std::size_t j = 0; j < columns; ++j)
        result[a * columns + j] = last_known[loaded[a]] ? last_sensitivity[loaded[a] * columns + j]
                                                        : rhs[a * columns + j] / (self + layer_compliance);
    return true;
  }

  /// One thread's conjugate gradients for columns of the pressure
  /// sensitivity, on its own work arrays.
  struct LocalCompliance::Impl::SensitivityColumns
  {
    Impl                           &d;
    const std::vector<std::size_t> &loaded;
    const double                   *rhs;
    std::size_t                     columns, m;
    std::vector<double>             x, r, s, as, z;
    contact::Field                  full, response;
    std::size_t                     convolutions = 0;

    SensitivityColumns(Impl &impl, const std::vector<std::size_t> &loaded_cells, const double *right_hand_sides,
                       std::size_t column_count)
      : d(impl)
      , loaded(loaded_cells)
      , rhs(right_hand_sides)
      , columns(column_count)
      , m(loaded_cells.size())
      , x(m)
      , r(m)
      , s(m)
      , as(m)
      , z(m)
      , full(impl.grid.size(), 0.0)
      , response(impl.grid.size(), 0.0)
    {}

    /// out = P_A M⁻¹ P_A in (Impl::precondition, on this thread's arrays).
    void precondition(const std::vector<double> &in, std::vector<double> &out)
    {
      if (!d.preconditioner)
        {
          out = in;
          return;
        }
      for (std::size_t a = 0; a < m; ++a)
        full[loaded[a]] = in[a];
      ++convolutions;
      d.preconditioner->apply(full, response);
      for (std::size_t a = 0; a < m; ++a)
        out[a] = response[loaded[a]];
    }

    /// out = (C_AA + I/k_n) in.
    void apply(const std::vector<double> &in, std::vector<double> &out)
    {
      for (std::size_t a = 0; a < m; ++a)
        full[loaded[a]] = in[a];
      ++convolutions;
      d.compliance.apply(full, response);
      for (std::size_t a = 0; a < m; ++a)
        out[a] = response[loaded[a]] + (d.layer_compliance + d.closure_at(loaded[a])) * in[a];
    }

    double dot(const std::vector<double> &u, const std::vector<double> &v) const
    {
      double sum = 0.0;
      for (std::size_t a = 0; a < m; ++a)
        sum += u[a] * v[a];
      return sum;
    }

    /// Column j into `result` and the last sensitivity; false if it did not
    /// converge.
    bool solve(std::size_t j, std::vector<double> &result)
    {
      double b_norm = 0.0;
      for (std::size_t a = 0; a < m; ++a)
        {
          r[a]   = rhs[a * columns + j];
          b_norm = std::max(b_norm, std::abs(r[a]));
        }
      if (b_norm == 0.0)
        return true;
      // Conjugate gradients on the symmetric positive definite
      // C_AA + I/k_n, from the last solution (the loaded set and the
      // operator change little between Jacobians).
      for (std::size_t a = 0; a < m; ++a)
        x[a] = d.last_sensitivity[loaded[a] * columns + j];
      apply(x, as);
      for (std::size_t a = 0; a < m; ++a)
        r[a] -= as[a];
      precondition(r, z);
      s         = z;
      double rr = dot(r, z);
      int    it = 0;
      for (; it < 1000; ++it)
        {
          double worst = 0.0;
          for (std::size_t a = 0; a < m; ++a)
            worst = std::max(worst, std::abs(r[a]));
          if (worst <= d.sensitivity_tolerance * b_norm)
            break;
          apply(s, as);
          const double alpha = rr / dot(s, as);
          for (std::size_t a = 0; a < m; ++a)
            {
              x[a] += alpha * s[a];
              r[a] -= alpha * as[a];
            }
          precondition(r, z);
          const double rr_next = dot(r, z);
          for (std::size_t a = 0; a < m; ++a)
            s[a] = z[a] + rr_next / rr * s[a];
          rr = rr_next;
        }
      if (it == 1000)
        return false;
      for (std::size_t a = 0; a < m; ++a)
        result[a * columns + j] = d.last_sensitivity[loaded[a] * columns + j] = x[a];
      return true;
    }
  };

  bool LocalCompliance::Impl::closure_sensitivity(const std::vector<std::size_t> &loaded, const double *rhs,
                                                  std::size_t columns, std::vector<double> &result)
  {
    const double             own = self + layer_compliance;
    std::vector<std::size_t> coupled, coupled_at, weak_at;
    for (std::size_t a = 0; a < loaded.size(); ++a)
      (closure_diagonal[loaded[a]] <= 10.0 * own ? coupled_at : weak_at).push_back(a);
    if (weak_at.empty())
      return coupled_sensitivity(loaded, rhs, columns, result);
    for (const std::size_t a : coupled_at)
      coupled.push_back(loaded[a]);
    std::vector<double> coupled_rhs(coupled.size() * columns), coupled_result;
    for (std::size_t k = 0; k < coupled.size(); ++k)
      std::copy_n(rhs + coupled_at[k] * columns, columns, coupled_rhs.begin() + k * columns);
    const bool in_single =
      !coupled.empty() && coupled_sensitivity(coupled, coupled_rhs.data(), columns, coupled_result);
    result.assign(loaded.size() * columns, 0.0);
    for (std::size_t k = 0; k < coupled.size(); ++k)
      std::copy_n(coupled_result.begin() + k * columns, columns, result.begin() + coupled_at[k] * columns);
    std::size_t convolutions = 0;
#pragma omp parallel reduction(+ : convolutions)
    {
      contact::Field moved(grid.size(), 0.0), displacement(grid.size(), 0.0);
#pragma omp for schedule(dynamic, 1)
      for (std::size_t j = 0; j < columns; ++j)
        {
          if (!coupled.empty())
            {
              for (std::size_t k = 0; k < coupled.size(); ++k)
                moved[coupled[k]] = coupled_result[k * columns + j];
              compliance.apply(moved, displacement);
              ++convolutions;
            }
          for (const std::size_t a : weak_at)
            {
              const std::size_t c = loaded[a];
              result[a * columns + j] =
                (rhs[a * columns + j] - displacement[c]) / (row_self[c / grid.nx] + layer_compliance + closure_diagonal[c]);
            }
        }
    }
    statistics.sensitivity_convolutions += convolutions;
    return in_single;
  }

  bool LocalCompliance::Impl::direct_sensitivity(const std::vector<std::size_t> &loaded, const double *rhs,
                                                 std::size_t columns, std::vector<double> &result, bool &in_single)
  {
    const auto     m = static_cast<Eigen::Index>(loaded.size());
    Eigen::MatrixXd operator_aa(m, m); // C_AA + I/k_n
#pragma omp parallel for schedule(dynamic, 16)
    for (Eigen::Index b = 0; b < m; ++b)
      {
        const int ib = static_cast<int>(loaded[b] % grid.nx), jb = static_cast<int>(loaded[b] / grid.nx);
        for (Eigen::Index a = b; a < m; ++a)
          {
            const int ia = static_cast<int>(loaded[a] % grid.nx), ja = static_cast<int>(loaded[a] / grid.nx);
            operator_aa(a, b) = entry(ia - ib, ja, jb);
          }
        operator_aa(b, b) += layer_compliance + closure_at(loaded[b]);
      }
    // Single precision where it fails or is too ill-conditioned falls back to double.
    in_single = single_precision && factorise_and_solve<float>(operator_aa, rhs, columns, result);
    return in_single || factorise_and_solve<double>(operator_aa, rhs, columns, result);
  }

  template <class Scalar>
  bool LocalCompliance::Impl::factorise_and_solve(const Eigen::MatrixXd &operator_aa, const double *rhs,
                                                  std::size_t columns, std::vector<double> &result)
  {
    using Matrix    = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
    using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    const auto m = operator_aa.rows(), width = static_cast<Eigen::Index>(columns);
    const Eigen::Map<const RowMatrix> right(rhs, m, width);
    Eigen::Map<RowMatrix>             answer(result.data(), m, width);
    // (LLT reads the lower triangle only, the one filled)
    const Eigen::LLT<Matrix> factor(operator_aa.template cast<Scalar>());
    if (factor.info() != Eigen::Success)
      return false;
    // The solution's relative error is about the condition times the
    // precision's rounding: single precision only where that stays far
    // below the 1e-2 Newton's matrix needs (the estimate costs O(m²)).
    constexpr double largest_error = 1e-4;
    if (std::is_same_v<Scalar, float> &&
        !(std::numeric_limits<float>::epsilon() < largest_error * static_cast<double>(factor.rcond())))
      return false;
    Matrix solution = right.template cast<Scalar>();
    factor.solveInPlace(solution);
    answer = solution.template cast<double>();
    return true;
  }

  bool LocalCompliance::pressure_sensitivity(const std::vector<std::size_t> &loaded, const double *rhs,
                                             std::size_t columns, std::vector<double> &result)
  {
    ++impl->statistics.sensitivities;
    if (!impl->closure_diagonal.empty())
      return impl->closure_sensitivity(loaded, rhs, columns, result);
    return impl->coupled_sensitivity(loaded, rhs, columns, result);
  }

  bool LocalCompliance::Impl::coupled_sensitivity(const std::vector<std::size_t> &loaded, const double *rhs,
                                                  std::size_t columns, std::vector<double> &result)
  {
    auto &d = *this;
    result.assign(loaded.size() * columns, 0.0);
    // Up to a few thousand loaded cells, C_AA + I/k_n is assembled from the
    // tabulated kernel and factored: the exact sensitivity, cheaper than
    // the conjugate gradients' columns. Without a half-space (a flexible
    // housing: the residual flexibilities and the layer alone) the operator
    // can be ill-conditioned, and the conjugate gradients' 1e-2 residual left
    // errors of tens of per cent in Newton's matrix (docs/bearing.md).
    bool in_single = false;
    if (loaded.size() <= d.direct_cells && d.direct_sensitivity(loaded, rhs, columns, result, in_single))
      {
        ++d.statistics.sensitivity_factorisations;
        d.statistics.sensitivity_single_precision += in_single;
        return in_single;
      }
    d.prepare_sensitivity_store(columns);
    // (the closure's operator depends on the pressure, not the loaded set alone)
    if (d.closure_diagonal.empty() && d.reuse_sensitivity(loaded, rhs, columns, result))
      {
        ++d.statistics.sensitivity_reuses;
        return false;
      }
    // The columns are independent solves: shared out over the threads
    // (SurfaceConvolution::apply is safe to call concurrently), each with
    // its own work arrays, so that the result does not depend on which
    // thread solved which column.
    std::size_t convolutions = 0;
    bool        diverged     = false;
#pragma omp parallel reduction(+ : convolutions) reduction(|| : diverged)
    {
      Impl::SensitivityColumns solver(d, loaded, rhs, columns);
#pragma omp for schedule(dynamic, 1)
      for (std::size_t j = 0; j < columns; ++j)
        if (!diverged && !solver.solve(j, result))
          diverged = true;
      convolutions += solver.convolutions;
    }
    d.statistics.sensitivity_convolutions += convolutions;
    if (diverged)
      throw std::runtime_error("local compliance: the pressure sensitivity did not converge");
    d.last_loaded = loaded;
    std::fill(d.last_known.begin(), d.last_known.end(), 0);
    for (const std::size_t c : loaded)
      d.last_known[c] = 1;
    return false;
  }
} // namespace fretsim::coupling
