#include <fretsim/contact/bristle.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fretsim::contact
{
  BristleTraction::BristleTraction(const SurfaceGrid &grid, double stiffness, double slip_tolerance)
    : grid(grid)
    , k(stiffness)
    , slip_tolerance(slip_tolerance)
    , tau_x(grid.zeros())
    , tau_y(grid.zeros())
  {
    if (!(stiffness > 0.0) || !std::isfinite(stiffness))
      throw std::invalid_argument("bristle stiffness must be positive and finite");
  }

  double BristleTraction::mindlin_stiffness(double tangential_modulus, double contact_radius)
  {
    return 8.0 * tangential_modulus / (M_PI * contact_radius);
  }

  void BristleTraction::reset()
  {
    std::fill(tau_x.begin(), tau_x.end(), 0.0);
    std::fill(tau_y.begin(), tau_y.end(), 0.0);
  }

  namespace
  {
    /// φ(λ) = (1 − e^(−λ))/λ and its derivative, by series near 0.
    double phi(double lambda) { return lambda > 1e-8 ? -std::expm1(-lambda) / lambda : 1.0 - 0.5 * lambda; }
    double phi_derivative(double lambda)
    {
      return lambda > 1e-3 ? (std::exp(-lambda) * (1.0 + lambda) - 1.0) / (lambda * lambda)
                           : -0.5 + lambda / 3.0 - lambda * lambda / 8.0;
    }
  } // namespace

  BristleStep bristle_step(double tau_x, double tau_y, double stiffness, double mu_p, double slip_x, double slip_y,
                           BristleUpdate update)
  {
    if (!(mu_p > 0.0))
      return {0.0, 0.0}; // no pressure or no friction: no traction can be transmitted
    if (update == BristleUpdate::exponential)
      {
        const double slip = std::hypot(slip_x, slip_y), lambda = stiffness * slip / mu_p;
        BristleStep  next{0.0, 0.0};
        if (std::isfinite(lambda))
          {
            const double decay = std::exp(-lambda), along = stiffness * phi(lambda);
            next               = {decay * tau_x + along * slip_x, decay * tau_y + along * slip_y};
          }
        else // k |ds| overflowed: full slip along ds
          next = {mu_p * slip_x / slip, mu_p * slip_y / slip};
        const double magnitude = std::hypot(next.x, next.y); // a traction above a lowered limit
        if (magnitude > mu_p)
          next = {next.x * mu_p / magnitude, next.y * mu_p / magnitude};
        return next;
      }
    // Implicit Euler of dtau = k ds - k |ds| tau/(mu p). Written with the slip
    // increment rather than v dt so that a prescribed displacement history is
    // followed exactly. The division form keeps |tau| <= mu p for any k |ds|:
    // |tau + k ds| <= mu p + k|ds| = mu p (1 + k|ds|/(mu p)).
    const double slip        = std::hypot(slip_x, slip_y);
    const double denominator = 1.0 + stiffness * slip / mu_p;
    BristleStep  next{(tau_x + stiffness * slip_x) / denominator, (tau_y + stiffness * slip_y) / denominator};
    if (!std::isfinite(denominator))
      next = {mu_p * slip_x / slip, mu_p * slip_y / slip}; // k |ds| overflowed: full slip along ds
    // Coulomb clamp: when the pressure dropped since the last step, the stored
    // traction may exceed the new limit.
    const double magnitude = std::hypot(next.x, next.y);
    if (magnitude > mu_p)
      next = {next.x * mu_p / magnitude, next.y * mu_p / magnitude};
    return next;
  }

  BristleStep bristle_step(double tau_x, double tau_y, double stiffness, double friction_coefficient,
                           double pressure, double slip_x, double slip_y, bool sliding_on,
                           BristleStepDerivatives &derivatives, BristleUpdate update)
  {
    const double mu_p = friction_coefficient * pressure;
    const BristleStep next = bristle_step(tau_x, tau_y, stiffness, mu_p, slip_x, slip_y, update);
    derivatives            = {};
    if (!(mu_p > 0.0))
      return next;
    const double          k = stiffness, mu = friction_coefficient;
    const Eigen::Vector2d start(tau_x, tau_y), slip(slip_x, slip_y);
    const double          slip_length = slip.norm();
    const auto store = [&derivatives](const Eigen::Matrix2d &by_slip, const Eigen::Vector2d &by_pressure,
                                      const Eigen::Vector2d &by_stiffness) {
      for (int i = 0; i < 2; ++i)
        {
          derivatives.by_slip[i][0]   = by_slip(i, 0);
          derivatives.by_slip[i][1]   = by_slip(i, 1);
          derivatives.by_pressure[i]  = by_pressure[i];
          derivatives.by_stiffness[i] = by_stiffness[i];
        }
    };
    if (update == BristleUpdate::exponential)
      {
        const double          lambda = k * slip_length / mu_p, decay = std::exp(-lambda), share = phi(lambda);
        const Eigen::Vector2d unclamped = decay * start + k * share * slip;
        // u = e^(−λ) τ + k φ(λ) ds: ∂u/∂λ = −e^(−λ) τ + k φ'(λ) ds, and λ
        // moves with |ds| (along ds), μp (as −λ/μp) and k (as λ/k).
        const Eigen::Vector2d by_lambda = -decay * start + k * phi_derivative(lambda) * slip;
        Eigen::Matrix2d       by_slip   = k * share * Eigen::Matrix2d::Identity();
        Eigen::Vector2d       by_pressure = Eigen::Vector2d::Zero(), by_stiffness = share * slip;
        // At ds = 0 as the implicit Euler step below (a sliding cell slides on).
        if (sliding_on && k * slip_length <= 1e-2 * mu_p && start.norm() > 0.0)
          by_slip -= k / mu_p * start * start.normalized().transpose();
        else if (slip_length > 0.0)
          {
            by_slip += k / mu_p * by_lambda * (slip / slip_length).transpose();
            by_pressure = -mu * lambda / mu_p * by_lambda;
            by_stiffness += lambda / k * by_lambda;
          }
        if (unclamped.norm() > mu_p)
          { // the Coulomb clamp (a lowered limit): τ' = μp u/|u|
            const Eigen::Vector2d unit      = unclamped.normalized();
            const Eigen::Matrix2d onto      = mu_p / unclamped.norm() *
                                         (Eigen::Matrix2d::Identity() - unit * unit.transpose());
            store(onto * by_slip, mu * unit + onto * by_pressure, onto * by_stiffness);
          }
        else
          store(by_slip, by_pressure, by_stiffness);
        return next;
      }
    const double          denominator = 1.0 + k * slip_length / mu_p;
    const Eigen::Vector2d numerator   = start + k * slip;
    Eigen::Matrix2d       by_slip;
    Eigen::Vector2d       by_pressure = Eigen::Vector2d::Zero(), by_stiffness = Eigen::Vector2d::Zero();
    if (numerator.norm() > mu_p * denominator)
      { // the Coulomb clamp: τ' = μp n/|n|
        const Eigen::Vector2d unit      = numerator.normalized();
        const Eigen::Matrix2d projector = Eigen::Matrix2d::Identity() - unit * unit.transpose();
        by_slip      = mu_p * k / numerator.norm() * projector;
        by_pressure  = mu * unit;
        by_stiffness = mu_p / numerator.norm() * projector * slip;
      }
    else
      {
        by_stiffness = (slip - numerator * (slip_length / (mu_p * denominator))) / denominator;
        by_slip      = (k / denominator) * Eigen::Matrix2d::Identity();
        // "At ds = 0" is within 1 % of the slip μp/k that saturates a fresh
        // bristle, where the law has moved τ by at most about 1 % of μp. The
        // derivative along τ there is near zero; the spring's k I instead
        // makes a Newton solver overshoot on sliding cells.
        if (sliding_on && k * slip_length <= 1e-2 * mu_p && start.norm() > 0.0)
          by_slip -= k / mu_p * start * start.normalized().transpose();
        else if (slip_length > 0.0)
          {
            by_slip -= k / (mu_p * denominator * denominator) * numerator * (slip / slip_length).transpose();
            by_pressure = (mu * k * slip_length / (mu_p * mu_p * denominator * denominator)) * numerator;
          }
      }
    store(by_slip, by_pressure, by_stiffness);
    return next;
  }

  void BristleTraction::advance_cell(std::size_t c, double mu_p, double slip_x, double slip_y)
  {
    const BristleStep next = bristle_step(tau_x[c], tau_y[c], k, mu_p, slip_x, slip_y);
    tau_x[c]               = next.x;
    tau_y[c]               = next.y;
  }

  void BristleTraction::advance(const Field &pressure, double friction_coefficient, double slip_x,
                                double slip_y)
  {
    for (std::size_t c = 0; c < grid.size(); ++c)
      advance_cell(c, friction_coefficient * pressure[c], slip_x, slip_y);
  }

  void BristleTraction::advance(const Field &pressure, double friction_coefficient,
                                const Field &slip_x, const Field &slip_y)
  {
    for (std::size_t c = 0; c < grid.size(); ++c)
      advance_cell(c, friction_coefficient * pressure[c], slip_x[c], slip_y[c]);
  }

  Field BristleTraction::effective_friction(const Field &pressure, double friction_coefficient) const
  {
    return contact::effective_friction(tau_x, tau_y, pressure, friction_coefficient);
  }

  double BristleTraction::slip_area_fraction(const Field &pressure, double friction_coefficient) const
  {
    return contact::slip_area_fraction(effective_friction(pressure, friction_coefficient), pressure, slip_tolerance);
  }

  Field effective_friction(const Field &traction_x, const Field &traction_y, const Field &pressure,
                           double friction_coefficient)
  {
    Field ratio(pressure.size(), 0.0);
    for (std::size_t c = 0; c < pressure.size(); ++c)
      {
        const double mu_p = friction_coefficient * pressure[c];
        if (mu_p > 0.0)
          ratio[c] = std::min(1.0, std::hypot(traction_x[c], traction_y[c]) / mu_p);
        else if (pressure[c] > 0.0)
          ratio[c] = 1.0; // frictionless contact: every loaded point slips
      }
    return ratio;
  }

  double slip_area_fraction(const Field &effective_friction, const Field &pressure, double slip_tolerance)
  {
    std::size_t loaded = 0, slipping = 0;
    for (std::size_t c = 0; c < pressure.size(); ++c)
      if (pressure[c] > 0.0)
        {
          ++loaded;
          if (effective_friction[c] >= 1.0 - slip_tolerance)
            ++slipping;
        }
    return loaded == 0 ? 0.0 : static_cast<double>(slipping) / static_cast<double>(loaded);
  }
} // namespace fretsim::contact
