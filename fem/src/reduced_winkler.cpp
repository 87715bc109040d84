// ReducedWinklerSolver (winkler_foundation.h): the Winkler foundation in a
// reduced model's coordinates, dense and small (n ~ 10²), Eigen's Cholesky.
#include "winkler_active_set.h"

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace fretsim::fem
{
  namespace
  {
    using Clock    = std::chrono::steady_clock;
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

    double since(const Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

    const std::string who = "fem::ReducedWinklerSolver";
  } // namespace

  struct ReducedWinklerSolver::Impl
  {
    Eigen::MatrixXd shifted; ///< K_r - σ M_r
    RowMajor        rows;    ///< g_c, [cell][n]
    double          cell_area = 0.0;
    WinklerLayer    layer;
    unsigned int    max_iterations = 50;
  };

  ReducedWinklerSolver::ReducedWinklerSolver(const std::size_t n, const std::vector<double> &shifted,
                                             const std::vector<double> &penetration_rows, const double cell_area,
                                             const WinklerLayer &layer, const unsigned int max_iterations)
    : impl(std::make_unique<Impl>())
  {
    check_layer(layer, who);
    if (n == 0 || shifted.size() != n * n)
      throw std::invalid_argument(who + ": the shifted matrix needs n x n = " + std::to_string(n * n) + " entries");
    if (penetration_rows.empty() || penetration_rows.size() % n != 0)
      throw std::invalid_argument(who + ": the penetration rows need a whole number of rows of n = " +
                                  std::to_string(n) + " entries");
    if (!(cell_area > 0.0))
      throw std::invalid_argument(who + ": the cell area must be > 0");
    const auto size = static_cast<Eigen::Index>(n);
    impl->shifted   = Eigen::Map<const RowMajor>(shifted.data(), size, size);
    impl->rows      = Eigen::Map<const RowMajor>(penetration_rows.data(),
                                                 static_cast<Eigen::Index>(penetration_rows.size() / n), size);
    impl->cell_area      = cell_area;
    impl->layer          = layer;
    impl->max_iterations = max_iterations;
  }

  ReducedWinklerSolver::~ReducedWinklerSolver()                                   = default;
  ReducedWinklerSolver::ReducedWinklerSolver(ReducedWinklerSolver &&) noexcept    = default;
  ReducedWinklerSolver &ReducedWinklerSolver::operator=(ReducedWinklerSolver &&) noexcept = default;

  std::size_t ReducedWinklerSolver::n() const { return static_cast<std::size_t>(impl->shifted.rows()); }
  std::size_t ReducedWinklerSolver::n_cells() const { return static_cast<std::size_t>(impl->rows.rows()); }

  ReducedWinklerSolver::Solution ReducedWinklerSolver::solve(const std::vector<double>          &generalised_load,
                                                             const std::vector<unsigned char> &initial_active) const
  {
    const auto start = Clock::now();
    if (generalised_load.size() != n())
      throw std::invalid_argument(who + ": the generalised load needs n = " + std::to_string(n()) + " entries");
    const Eigen::Map<const Eigen::VectorXd> g(generalised_load.data(), static_cast<Eigen::Index>(n()));
    const double                            k_area = impl->layer.normal_stiffness * impl->cell_area;
    const double                            fit    = impl->layer.radial_interference;
    const std::size_t                       cells  = n_cells();

    Solution        solution;
    Eigen::VectorXd q, candidate;
    ActiveSetSolver callbacks;
    callbacks.solve = [&](const std::vector<unsigned char> &active) {
      const auto factor_start = Clock::now();
      std::vector<Eigen::Index> in_contact;
      for (std::size_t c = 0; c < cells; ++c)
        if (active[c])
          in_contact.push_back(static_cast<Eigen::Index>(c));
      RowMajor contact_rows(static_cast<Eigen::Index>(in_contact.size()), impl->rows.cols());
      for (std::size_t k = 0; k < in_contact.size(); ++k)
        contact_rows.row(static_cast<Eigen::Index>(k)) = impl->rows.row(in_contact[k]);
      Eigen::MatrixXd matrix = impl->shifted;
      if (!in_contact.empty()) // Eigen's product blocking divides by the inner size
        matrix.selfadjointView<Eigen::Lower>().rankUpdate(contact_rows.transpose(), k_area);
      const Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> factor(matrix);
      if (factor.info() != Eigen::Success)
        throw std::runtime_error(who + ": K_r - sigma M_r + the foundation is not positive definite");
      solution.grid.factorisation_seconds += since(factor_start);
      ++solution.grid.factorisations;
      Eigen::VectorXd rhs = g;
      if (fit != 0.0 && !in_contact.empty())
        rhs += (k_area * fit) * (contact_rows.transpose() * Eigen::VectorXd::Ones(contact_rows.rows()));
      candidate                         = factor.solve(rhs);
      const Eigen::VectorXd penetration = (impl->rows * candidate).array() + fit;
      return std::vector<double>(penetration.data(), penetration.data() + penetration.size());
    };
    callbacks.accept = [&](double t) {
      if (q.size() == 0 || t == 1.0)
        q = candidate;
      else
        q += t * (candidate - q);
    };
    iterate_active_set(cells, initial_active, impl->max_iterations, k_area, who, callbacks, solution.grid);

    auto        &grid       = solution.grid;
    const double foundation = foundation_pressure(impl->layer.normal_stiffness, k_area, grid);
    grid.energy = 0.5 * q.dot(impl->shifted * q) - g.dot(q) + foundation;
    solution.q.assign(q.data(), q.data() + q.size());
    grid.seconds = since(start);
    return solution;
  }
} // namespace fretsim::fem
