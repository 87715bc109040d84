#pragma once
// Richardson extrapolation of a result computed on three grids refined by a
// constant ratio, with an error bar in the manner of Roache's grid convergence
// index (GCI; Roache, J. Fluids Eng. 116, 1994): the observed order p from the
// three values, the extrapolated limit, and a safety factor on the size of the
// extrapolation (1.25 where the three grids agree with one power law, 3 where
// they do not).
namespace fretsim::contact
{
  struct RichardsonSettings
  {
    double refinement_ratio = 2.0;  ///< r = h_coarse / h_medium = h_medium / h_fine
    double min_order        = 0.3;  ///< below (or diverging): not asymptotic, this order is assumed
    double max_order        = 2.0;  ///< above: clamped (no faster convergence is believed)
    double safety_factor    = 1.25; ///< asymptotic sequences
    double fallback_safety  = 3.0;  ///< non-asymptotic or oscillating sequences
  };

  struct RichardsonEstimate
  {
    double converged      = 0.0; ///< the extrapolated value (the finest value if the sequence oscillates)
    double error_estimate = 0.0; ///< bound on |converged - limit|, >= 0
    double observed_order = 0.0; ///< p = ln(e_coarse / e_fine) / ln r; NaN if the differences change sign or vanish
    bool   asymptotic     = false; ///< monotone with p >= min_order
  };

  /// fine, medium, coarse: the result on grids of spacing h, r h, r^2 h.
  /// Three equal values give the value with zero error.
  RichardsonEstimate richardson_estimate(double fine, double medium, double coarse,
                                         const RichardsonSettings &settings = {});
} // namespace fretsim::contact
