#include <fretsim/contact/normal_contact.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace fretsim::contact
{
  namespace
  {
    SurfaceConvolution make_deflection_operator(const SurfaceGrid &grid, double contact_modulus)
    {
      if (!(contact_modulus > 0.0) || !std::isfinite(contact_modulus))
        throw std::invalid_argument("NormalContactSolver: the contact modulus must be positive and finite");
      if (grid.nx <= 0 || grid.ny <= 0 || !(grid.hx > 0.0) || !(grid.hy > 0.0))
        throw std::invalid_argument("NormalContactSolver: the grid is empty or has non-positive spacing");
      const double hx = grid.hx, hy = grid.hy;
      return SurfaceConvolution(grid, [=](int di, int dj) {
        return influence::normal_displacement(di * hx, dj * hy, hx, hy, contact_modulus);
      });
    }
  } // namespace

  NormalContactSolver::NormalContactSolver(const SurfaceGrid &grid, double contact_modulus, Settings settings)
    : grid(grid)
    , settings(settings)
    , deflection_operator(make_deflection_operator(grid, contact_modulus))
  {
    if (!(settings.tolerance > 0.0) || settings.max_iterations <= 0)
      throw std::invalid_argument("NormalContactSolver: tolerance and max_iterations must be positive");
  }

  NormalContactResult NormalContactSolver::solve(const Field &initial_gap, double normal_load) const
  {
    const std::size_t n_cells = grid.size();
    if (initial_gap.size() != n_cells)
      throw std::invalid_argument("NormalContactSolver::solve: initial gap size does not match the grid");
    if (!(normal_load >= 0.0) || !std::isfinite(normal_load))
      throw std::invalid_argument("NormalContactSolver::solve: the normal load must be non-negative and finite");
    for (const double h : initial_gap)
      if (!std::isfinite(h))
        throw std::invalid_argument("NormalContactSolver::solve: the initial gap must be finite");

    const double lowest_gap = *std::min_element(initial_gap.begin(), initial_gap.end());
    NormalContactResult result;
    if (normal_load == 0.0)
      {
        // Unloaded: the bodies just touch at the lowest point.
        result.pressure = grid.zeros();
        result.gap      = initial_gap;
        for (double &h : result.gap)
          h -= lowest_gap;
        result.approach = lowest_gap;
        return result;
      }

    // Work in scaled units so that every test below is relative, whatever the
    // load (1e-6 N ... 1e6 N): pressure in units of the load spread over the
    // whole grid, lengths in units of the displacement that this pressure
    // gives at the centre of its own cell. The self-influence coefficient is
    // the largest one, so the scaled kernel is O(1).
    const double area           = grid.cell_area();
    const double pressure_scale = normal_load / (static_cast<double>(n_cells) * area);
    // K(0,0) in m/Pa, read from the operator itself so that the scaling uses
    // exactly the kernel the iteration applies.
    Field displacement_probe = grid.zeros(), probe_result;
    displacement_probe[0] = 1.0;
    deflection_operator.apply(displacement_probe, probe_result);
    const double kernel_self  = probe_result[0];
    const double length_scale = pressure_scale * kernel_self;
    const double load_sum     = static_cast<double>(n_cells); // sum of scaled p that carries P

    Field gap0(n_cells);
    for (std::size_t c = 0; c < n_cells; ++c)
      gap0[c] = (initial_gap[c] - lowest_gap) / length_scale;
    const double kernel_to_scaled = 1.0 / kernel_self;

    // Polonsky & Keer (1999), load-controlled variant. Start from a uniform
    // pressure over the whole grid: every cell is in the trial contact set.
    Field  pressure(n_cells, 1.0), displacement, gap(n_cells), direction(n_cells, 0.0), response;
    double gap_norm_old = 1.0;
    bool   conjugate    = false;
    int    iteration    = 0;
    double residual     = 0.0, mean_gap = 0.0;
    for (;; ++iteration)
      {
        deflection_operator.apply(pressure, displacement);
        std::size_t n_contact = 0;
        double      gap_sum = 0.0, displacement_sum = 0.0;
        for (std::size_t c = 0; c < n_cells; ++c)
          {
            displacement[c] *= kernel_to_scaled;
            gap[c] = gap0[c] + displacement[c];
            if (pressure[c] > 0.0)
              {
                ++n_contact;
                gap_sum += gap[c];
                displacement_sum += displacement[c];
              }
          }
        // The mean gap over the contact set is the Lagrange multiplier of
        // the load constraint: the rigid approach.
        mean_gap = gap_sum / n_contact;
        double gap_norm    = 0.0;
        bool   penetration = false;
        for (std::size_t c = 0; c < n_cells; ++c)
          {
            gap[c] -= mean_gap;
            if (pressure[c] > 0.0)
              gap_norm += gap[c] * gap[c];
            else if (gap[c] < 0.0)
              penetration = true;
          }
        // RMS gap on the contact set relative to the mean elastic displacement
        // there: independent of the load, the grid and any offset of h0.
        residual = std::sqrt(gap_norm / n_contact) / (displacement_sum / n_contact);
        if (residual < settings.tolerance && !penetration)
          break;
        if (iteration >= settings.max_iterations)
          {
            std::ostringstream message;
            message << "NormalContactSolver: no convergence after " << iteration
                    << " iterations (relative gap error " << residual << ", tolerance " << settings.tolerance
                    << (penetration ? ", with penetration outside the contact set" : "") << ")";
            throw std::runtime_error(message.str());
          }

        const double beta = conjugate ? gap_norm / gap_norm_old : 0.0;
        for (std::size_t c = 0; c < n_cells; ++c)
          direction[c] = pressure[c] > 0.0 ? gap[c] + beta * direction[c] : 0.0;
        gap_norm_old = gap_norm;

        deflection_operator.apply(direction, response);
        double response_sum = 0.0;
        for (std::size_t c = 0; c < n_cells; ++c)
          if (pressure[c] > 0.0)
            response_sum += (response[c] *= kernel_to_scaled);
        const double response_mean = response_sum / n_contact;
        double       numerator = 0.0, denominator = 0.0;
        for (std::size_t c = 0; c < n_cells; ++c)
          if (pressure[c] > 0.0)
            {
              numerator += gap[c] * direction[c];
              denominator += (response[c] - response_mean) * direction[c];
            }
        const double step = numerator / denominator;
        if (!std::isfinite(step))
          throw std::runtime_error("NormalContactSolver: conjugate-gradient step is not finite");

        for (std::size_t c = 0; c < n_cells; ++c)
          if (pressure[c] > 0.0)
            pressure[c] = std::max(pressure[c] - step * direction[c], 0.0);
        // Cells outside the contact set that penetrate re-enter it; the
        // conjugate directions are then no longer valid and CG restarts.
        bool overlap = false;
        for (std::size_t c = 0; c < n_cells; ++c)
          if (pressure[c] == 0.0 && gap[c] < 0.0)
            {
              pressure[c] = -step * gap[c];
              overlap     = true;
            }
        conjugate = !overlap;

        double pressure_sum = 0.0;
        for (const double p : pressure)
          pressure_sum += p;
        if (!(pressure_sum > 0.0))
          {
            // Every cell left contact (possible only after a wild step): restart
            // from the lowest point of the current gap.
            const auto lowest = std::min_element(gap.begin(), gap.end()) - gap.begin();
            std::fill(pressure.begin(), pressure.end(), 0.0);
            pressure[lowest] = load_sum;
            conjugate        = false;
            continue;
          }
        // Load constraint, enforced by rescaling as in Polonsky & Keer.
        const double scale = load_sum / pressure_sum;
        for (double &p : pressure)
          p *= scale;
      }

    result.pressure.resize(n_cells);
    result.gap.resize(n_cells);
    std::size_t n_contact = 0;
    for (std::size_t c = 0; c < n_cells; ++c)
      {
        result.pressure[c] = pressure[c] * pressure_scale;
        if (pressure[c] > 0.0)
          {
            ++n_contact;
            result.gap[c] = 0.0; // zero by complementarity; the error is in `residual`
          }
        else
          result.gap[c] = std::max(gap[c], 0.0) * length_scale;
      }
    result.approach     = mean_gap * length_scale + lowest_gap;
    result.contact_area = static_cast<double>(n_contact) * area;
    result.iterations   = iteration;
    result.residual     = residual;
    return result;
  }
} // namespace fretsim::contact
