#pragma once
// Richardson extrapolation of a result computed on three grids refined by a
// constant ratio, with an error bar in the manner of Roache's grid convergence
// index (GCI; Roache, J. Fluids Eng. 116, 1994).
//
// The extrapolation uses the order the theory gives, not the one the three
// grids show: the maximum Dang Van risk of a contact sits at the contact edge,
// where pressure and traction have square-root edges and a cell-centred
// sample lies a fraction of a cell inside, so its error falls as h^(1/2) once
// the cells resolve the edge's slip band. On coarser grids the observed order
// wanders (0.1-0.9 on the paper case from 32 to 512 cells); the bar, the
// larger of the two grid differences carried to the limit, covers that.
namespace fretsim::contact
{
  struct RichardsonSettings
  {
    double refinement_ratio = 2.0; ///< r = h_coarse / h_medium = h_medium / h_fine
    double order            = 0.5; ///< asymptotic order p of the error, > 0
    double safety_factor    = 1.0; ///< on the bar below
  };

  struct RichardsonEstimate
  {
    /// f_fine + (f_fine - f_medium) / (r^p - 1)
    double converged = 0.0;
    /// safety max(|f_fine - f_medium|, |f_medium - f_coarse|) / (r^p - 1)
    double error_estimate = 0.0;
    /// ln(e_coarse / e_fine) / ln r; NaN if the differences change sign or vanish
    double observed_order = 0.0;
    /// Monotone, with the observed order within 0.25 of p (informative only)
    bool asymptotic = false;
  };

  /// fine, medium, coarse: the result on grids of spacing h, r h, r^2 h.
  /// Throws std::invalid_argument for non-finite values or settings.
  RichardsonEstimate richardson_estimate(double fine, double medium, double coarse,
                                         const RichardsonSettings &settings = {});
} // namespace fretsim::contact
