#pragma once
// The Dang Van risk on the fronts of a circular contact under the exact masing
// traction: its edge, where pressure and traction end in square roots, and
// the stick zone's boundary at the largest shift, where the traction's
// Cattaneo-Mindlin correction does. The surface stress peaks in a cusp there
// that cell-centred samples miss: the grid's D_max converges as h^(1/2). Here
// each load is split into the square-root shapes of Hertz and
// Cattaneo-Mindlin, whose surface stresses are closed forms, and a remainder
// that is smooth at the fronts, interpolated from the grid's stresses
// (docs/theory.md §2.4, its convergence in docs/concentrated.md).
#include <fretsim/contact/dang_van.h>
#include <fretsim/contact/masing_traction.h>
#include <fretsim/contact/rectangle_kernels.h>
#include <fretsim/contact/subsurface_stress.h>
#include <fretsim/contact/surface_grid.h>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

namespace fretsim::contact
{
  /// Surface stress (z = 0) at (x, y) of the unit-peak Hertz pressure
  /// sqrt(1 - r^2/c^2) on a circle of radius c centred at the origin, inside
  /// and outside it [per unit peak].
  StressTensor hertz_pressure_surface_stress(double x, double y, double radius, double poisson_ratio);

  /// Surface stress at (x, y) of the unit-peak traction sqrt(1 - r^2/c^2)
  /// along (cos angle, sin angle) on a circle of radius c (the traction on the
  /// body's surface, as rectangle_stress_shear_x): Johnson's closed form
  /// inside, and outside the integral of Cerruti's kernel along the rays
  /// from the point, whose chord integrals are elementary [per unit peak].
  StressTensor hertz_shear_surface_stress(double x, double y, double radius, double poisson_ratio, double angle);

  /// What the edge evaluation needs of a fretting case.
  struct ContactEdgeCase
  {
    double contact_radius = 0.0;       ///< Hertz a [m]
    double peak_pressure  = 0.0;       ///< Hertz p0 [Pa]
    double friction_coefficient = 0.0; ///< mu
    /// Mindlin's shift to gross slip, 3 mu P / (16 G* a) [m]: a virgin level at
    /// shift s sticks within c = a sqrt(1 - s / that).
    double gross_slip_shift = 0.0;
    double level_spacing    = 0.0; ///< of the masing traction's virgin levels [m]
    /// The stick zone's radius at the history's largest shift [m], where a
    /// second circle of points goes; 0: none (gross slip).
    double stick_radius  = 0.0;
    double sliding_angle = 0.0; ///< [rad] from x: the virgin levels' direction
    double poisson_ratio    = 0.0; ///< of the lower body, whose stresses are evaluated
    DangVanConstants        dang_van;
    DangVanSettings         dang_van_settings;
    StressEvaluatorSettings stress_evaluator;
  };

  /// D_max on the fronts and where.
  struct ContactEdgeRiskMaximum
  {
    double       value = 0.0;
    double       x = 0.0, y = 0.0; ///< [m], on the surface
    std::int64_t step  = -1;       ///< 0-based step that set it
    bool         on_edge = true;   ///< on the edge circle, not in the slip annulus
    double       slip_annulus = 0.0; ///< contact radius less the stick radius [m] (0: no stick front)
  };

  /// The criterion on points of the contact edge and of the stick zone's
  /// largest front, stepped with the history: call add_step() after each step
  /// of the masing traction.
  class ContactEdgeRisk
  {
  public:
    /// Points on each circle, one at the sliding direction: 64 suffice (the
    /// risk varies as cos^2 of the angle away from its maximum).
    static constexpr int default_points = 64;
    /// Circles from the stick zone's largest front toward the edge, the front
    /// included: a peak of the risk inside the slip annulus is taken on the
    /// nearest of them (an eighth of the annulus apart).
    static constexpr int annulus_circles = 8;

    /// True if the edge circle of `contact_radius` and its interpolation
    /// stencils lie inside the (centred) grid, with half a cell to spare.
    static bool fits(const SurfaceGrid &grid, double contact_radius);

    /// `pressure` is the run's (numerical or sampled Hertz). Throws
    /// std::invalid_argument unless fits() or if a parameter is not positive. Points [0, points) lie on the edge,
    /// the next `points` on the stick zone's front and the following ones on
    /// the circles between them (if there is a front).
    ContactEdgeRisk(const ContactEdgeCase &edge_case, const SurfaceGrid &grid, const Field &pressure,
                    int points = default_points);
    ~ContactEdgeRisk();

    /// One step: the traction's composition after the step, the one before it
    /// (the traction of a reversal the step starts) and the uniform stress
    /// added at the surface (Voigt, [Pa]).
    void add_step(const MasingTraction &traction, const MasingTraction::Composition &before,
                  const std::array<double, stress_component_count> &surface_bulk);

    ContactEdgeRiskMaximum maximum() const;
    /// The stresses of the last step on the points, Voigt [Pa].
    const std::vector<double> &stress() const { return now; }
    std::size_t                point_count() const { return points_x.size(); }

  private:
    using EdgeValues = std::vector<double>; // 6 per point

    /// Bilinear interpolation of layer 0 of `stress` at every edge point, added to `out`.
    void add_interpolated(const StressField &stress, double scale, EdgeValues &out) const;
    const EdgeValues &level(const MasingTraction &traction, std::size_t k);
    EdgeValues        compose(const MasingTraction &traction, const MasingTraction::Composition &recipe);

    ContactEdgeCase                   setup;
    SurfaceGrid                       grid;
    std::size_t                       per_circle = 0;
    std::vector<double>               points_x, points_y;
    std::vector<std::array<double, 4>> weights;
    std::vector<std::array<std::size_t, 4>> cells;
    std::unique_ptr<SubsurfaceStress> surface_stress;
    EdgeValues                        pressure_part, radius_shape_part;
    std::map<std::size_t, EdgeValues>  levels;
    std::map<std::int64_t, EdgeValues> reversals;
    std::unique_ptr<DangVanField>     criterion;
    std::vector<double>               now;
    Field                             load_x, load_y, no_load;
    StressField                       scratch;
  };
} // namespace fretsim::contact
