#pragma once
// The exact elastic partial-slip traction under a constant pressure and a
// unidirectional shift, by Masing's superposition of the virgin (first
// loading) solution instead of a solve per step. For two elastic half-spaces
// with nested stick zones the traction after a reversal at shift s_r, where the
// traction was tau_r, is
//     tau(s) = tau_r + 2 sgn(s - s_r) tau_v(|s - s_r| / 2),
// tau_v the virgin traction of a monotone shift (Cattaneo-Mindlin
// superposition; exact for uncoupled normal and tangential problems: Jager,
// J. Appl. Mech. 65, 1998; Ciavarella, Int. J. Solids Struct. 35, 1998). Loops
// close by Masing's memory rule: a branch that passes the previous reversal
// rejoins the branch before it.
//
// tau_v comes from PartialSlipSolver on a monotone first loading, solved on
// demand at multiples of a level spacing (PartialSlipSettings::
// masing_level_spacing; or at the history's own shifts) and kept as a table,
// interpolated linearly in the shift in between. Uniform levels resolve the
// slip front evenly: it moves through the contact at a finite rate from the
// first micrometre on. Once the table spans the amplitude, a step costs two
// table look-ups and no solve. The neglected part: the cross
// compliance C_xy (Poisson), which turns the slip slightly away from the shift
// and which the incremental solver keeps; its effect is measured against that
// solver in the tests.
#include <fretsim/contact/material.h>
#include <fretsim/contact/partial_slip.h>
#include <fretsim/contact/surface_grid.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace fretsim::contact
{
  class MasingTraction
  {
  public:
    MasingTraction(const SurfaceGrid &grid, const MaterialPair &materials, const PartialSlipSettings &settings);
    ~MasingTraction();

    /// One step with the shift increment (dx, dy) [m]. Throws std::logic_error
    /// if the pressure or mu differ from the first step's or the increment is
    /// not along the first non-zero one's line (the superposition needs both).
    void advance(const Field &pressure, double friction_coefficient, double shift_x, double shift_y);
    void reset();

    const Field &traction_x() const { return tau_x; }
    const Field &traction_y() const { return tau_y; }
    /// |tau| / (mu p) per cell, 0 outside the contact.
    Field  effective_friction() const;
    /// Fraction of the loaded cells at |tau| >= (1 - 1e-9) mu p.
    double slip_area_fraction() const;
    /// Solver iterations of the last advance (0 when the table sufficed).
    int last_iterations() const { return iterations; }
    /// Virgin levels solved so far.
    std::size_t virgin_levels() const;

    /// How the current traction is composed, so that anything linear in the
    /// traction (its stresses) can be composed the same way:
    ///   tau = tau_r + factor ((1 - weight) T_lower + weight T_upper),
    /// T_k the traction of virgin level k (level 0: none), tau_r the traction
    /// of reversal `reversal` (the traction after the step before it; none if
    /// reversal < 0). Reversal ids are unique over the object's life.
    struct Composition
    {
      std::int64_t reversal = -1;
      double       factor   = 0.0;
      std::size_t  lower = 0, upper = 0;
      double       weight = 0.0;
    };
    const Composition &composition() const { return recipe; }
    /// The traction of virgin level k <= virgin_levels() [Pa].
    const Field &virgin_level_x(std::size_t level) const;
    const Field &virgin_level_y(std::size_t level) const;
    /// True while Masing's memory holds reversal `id`.
    bool holds_reversal(std::int64_t id) const;

  private:
    struct Reversal
    {
      double       shift; // along the line [m]
      Field        tau_x, tau_y;
      std::int64_t id;
    };
    struct Virgin;

    /// tau_v at shift s >= 0 along the line, into (vx, vy); the levels and
    /// weight used into recipe.
    void virgin_traction(double s, Field &vx, Field &vy);
    void compose();

    SurfaceGrid             grid;
    std::unique_ptr<Virgin> virgin;
    double                  level_spacing; // [m]; 0: the history's own shifts
    Field                   pressure;
    double                  friction = 0.0;
    bool                    started  = false;
    double                  direction_x = 1.0, direction_y = 0.0; // unit line of the shift
    bool                    direction_set = false;
    double                  shift = 0.0; // accumulated along the line [m]
    int                     heading = 0; // sign of the current branch's increments
    std::vector<Reversal>   reversals;   // Masing's memory, the newest last
    std::int64_t            next_reversal_id = 0;
    Composition             recipe;
    Field                   tau_x, tau_y, work_x, work_y;
    int                     iterations = 0;
  };
} // namespace fretsim::contact
