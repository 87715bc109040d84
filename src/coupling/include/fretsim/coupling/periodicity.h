#pragma once
// The period of a sampled signal, for checking that the interface fields
// repeat at the ball pass frequency and for telling when they have become
// periodic.
#include <vector>

namespace fretsim::coupling
{
  /// The lag in [shortest, longest] [s] at which the normalised autocorrelation
  /// of `signal` (sampled every `interval` s, mean removed) peaks, refined
  /// between samples by a parabola through the peak and its neighbours [s].
  /// Also returns the correlation at the peak (1 for an exactly periodic
  /// signal). Throws std::invalid_argument if the signal is shorter than two
  /// of the longest lags or is constant.
  double autocorrelation_period(const std::vector<double> &signal, double interval, double shortest, double longest,
                                double *correlation = nullptr);

  /// max |a(t) - a(t - T)| / max |a| over the samples of the last period T of
  /// a series of fields (each of the same size) sampled every `interval`:
  /// 0 for fields that repeat with period T. T must be a whole number of
  /// intervals. NaN (no measure) when the series is shorter than two periods
  /// (summary.json then says null).
  double periodicity_error(const std::vector<std::vector<double>> &history, double interval, double period);
} // namespace fretsim::coupling
