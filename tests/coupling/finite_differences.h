#pragma once
// Central finite differences of the coupling layer's generalised forces,
// against which the analytic Jacobians are checked.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace fretsim::coupling::testing
{
  /// max |J - J_fd| / max |J| for the derivative by position (which = 0) or velocity.
  /// h: the finite-difference step, ~1e-6 of the state's scale.
  template <class Evaluate>
  double jacobian_error(std::size_t n, const std::vector<double> &q, const std::vector<double> &v, int which,
                        double h, const Evaluate &evaluate, const std::vector<double> &analytic)
  {
    double difference = 0.0, scale = 0.0;
    for (std::size_t j = 0; j < n; ++j)
      {
        auto         plus_q = q, minus_q = q, plus_v = v, minus_v = v;
        (which == 0 ? plus_q : plus_v)[j] += h;
        (which == 0 ? minus_q : minus_v)[j] -= h;
        const auto f_plus = evaluate(plus_q, plus_v), f_minus = evaluate(minus_q, minus_v);
        for (std::size_t i = 0; i < n; ++i)
          {
            const double numeric = (f_plus[i] - f_minus[i]) / (2.0 * h);
            difference           = std::max(difference, std::abs(numeric - analytic[i * n + j]));
            scale                = std::max(scale, std::abs(analytic[i * n + j]));
          }
      }
    return difference / scale;
  }
} // namespace fretsim::coupling::testing
