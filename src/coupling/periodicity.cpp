#include <fretsim/coupling/periodicity.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace fretsim::coupling
{
  double autocorrelation_period(const std::vector<double> &signal, double interval, double shortest, double longest,
                                double *correlation)
  {
    const long first = std::max(1L, std::lround(std::floor(shortest / interval)) - 1);
    const long last  = std::lround(std::ceil(longest / interval)) + 1;
    const long size  = static_cast<long>(signal.size());
    if (size < 2 * last)
      throw std::invalid_argument("autocorrelation period: the signal must span at least two of the longest lags");
    const double mean = std::accumulate(signal.begin(), signal.end(), 0.0) / size;
    std::vector<double> centred(signal.size());
    std::transform(signal.begin(), signal.end(), centred.begin(), [&](double v) { return v - mean; });
    // Normalised over the overlap, so that shorter overlaps at long lags are
    // not penalised.
    const auto at = [&](long lag) {
      double product = 0.0, head = 0.0, tail = 0.0;
      for (long i = 0; i + lag < size; ++i)
        {
          product += centred[i] * centred[i + lag];
          head += centred[i] * centred[i];
          tail += centred[i + lag] * centred[i + lag];
        }
      return head > 0.0 && tail > 0.0 ? product / std::sqrt(head * tail) : 0.0;
    };
    if (at(0) == 0.0)
      throw std::invalid_argument("autocorrelation period: the signal is constant");
    long   best = first + 1;
    double peak = -2.0;
    for (long lag = first + 1; lag < last; ++lag)
      if (const double r = at(lag); r > peak)
        {
          peak = r;
          best = lag;
        }
    const double left = at(best - 1), right = at(best + 1);
    const double curvature = left - 2.0 * peak + right;
    const double shift     = curvature < 0.0 ? 0.5 * (left - right) / curvature : 0.0;
    if (correlation != nullptr)
      *correlation = peak;
    return (best + std::clamp(shift, -0.5, 0.5)) * interval;
  }

  double periodicity_error(const std::vector<std::vector<double>> &history, double interval, double period)
  {
    const long lag = std::lround(period / interval);
    if (lag < 1 || static_cast<long>(history.size()) < 2 * lag)
      return std::numeric_limits<double>::quiet_NaN(); // not enough history to tell
    double difference = 0.0, scale = 0.0;
    for (std::size_t k = history.size() - lag; k < history.size(); ++k)
      for (std::size_t c = 0; c < history[k].size(); ++c)
        {
          difference = std::max(difference, std::abs(history[k][c] - history[k - lag][c]));
          scale      = std::max(scale, std::abs(history[k][c]));
        }
    return scale > 0.0 ? difference / scale : 0.0;
  }
} // namespace fretsim::coupling
