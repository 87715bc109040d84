#pragma once
#include <fretsim/contact/convolution.h>
#include <fretsim/contact/surface_grid.h>

namespace fretsim::contact
{
  /// Result of a normal contact solve.
  struct NormalContactResult
  {
    Field  pressure;        ///< p >= 0 per cell [Pa]
    Field  gap;             ///< h >= 0 per cell after loading [m]
    double approach = 0.0;  ///< rigid-body approach delta [m]
    double contact_area = 0.0; ///< area of cells with p > 0 [m^2]
    int    iterations = 0;
    double residual = 0.0;  ///< relative gap error on the contact set
  };

  /// Frictionless normal contact of two elastic half-spaces under a given total
  /// load (docs/theory.md §2.2): gap h = h0 - delta + u_z, u_z = K * p; p >= 0,
  /// h >= 0, p h = 0, sum p A = P. Solved by the conjugate-gradient method of
  /// Polonsky & Keer (Wear 231, 1999) with the convolution by DC-FFT.
  class NormalContactSolver
  {
  public:
    struct Settings
    {
      double tolerance = 1e-10;   ///< relative gap error on the contact set
      int    max_iterations = 2000;
    };

    NormalContactSolver(const SurfaceGrid &grid, double contact_modulus, Settings settings);
    NormalContactSolver(const SurfaceGrid &grid, double contact_modulus)
      : NormalContactSolver(grid, contact_modulus, Settings{}) {}

    /// initial_gap: the undeformed separation h0 per cell [m] (e.g. r^2 / 2R).
    /// Throws std::runtime_error if the iteration does not converge.
    NormalContactResult solve(const Field &initial_gap, double normal_load) const;

    /// The elastic normal displacement operator u_z = K * p.
    const SurfaceConvolution &deflection() const { return deflection_operator; }

  private:
    SurfaceGrid        grid;
    Settings           settings;
    SurfaceConvolution deflection_operator;
  };
} // namespace fretsim::contact
