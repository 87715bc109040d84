#pragma once
// One interface for the tangential traction models, so that
// a scene can switch `traction model = bristle | elastoplastic bristle | exact |
// exact masing` and feed the same stress and Dang Van stages:
//   bristle                 BristleTraction (paper eq. 4, docs/theory.md §2.3),
//   elastoplastic bristle   ElastoplasticBristleTraction (elastic–perfectly-
//                           plastic bristles with a true stick zone),
//   exact                   PartialSlipSolver (elastic half-spaces, Kalker type,
//                           docs/theory.md §2.4),
//   exact masing            MasingTraction (the exact model's solution by
//                           superposition of its first loading).
//
// Meaning of the inputs, common to all models: per load step the pressure p
// [Pa] per cell, the friction coefficient mu, and the increment since the last
// step of the imposed rigid shift: the relative tangential displacement of
// remote points of the upper body over the lower body [m], uniform or per
// cell. Output: the traction [Pa] the upper body exerts on the lower body's
// surface (the grid's body), positive along the shift while sticking.
// For the bristle models the bristles carry all the tangential compliance; for
// the exact model the two elastic half-spaces do (with Mindlin's stiffness
// 8 G* a both are calibrated to agree at small amplitude).
//
// Call order: construct (make_tangential_traction_model), then advance() once
// per step in time order; read the tractions and maps after each advance;
// reset() returns to the unloaded state.
#include <fretsim/contact/material.h>
#include <fretsim/contact/partial_slip.h>
#include <fretsim/contact/surface_grid.h>

#include <memory>
#include <string>

namespace fretsim::contact
{
  enum class TractionModel
  {
    bristle,
    elastoplastic_bristle,
    exact,
    /// The exact model's solution by Masing's superposition of its first
    /// loading (masing_traction.h): constant pressure, shift along one line.
    exact_masing
  };

  /// "bristle", "elastoplastic bristle", "exact" or "exact masing"; std::invalid_argument
  /// naming the valid choices otherwise.
  TractionModel parse_traction_model(const std::string &name);
  /// The scene name of a model (the inverse of parse_traction_model).
  std::string to_string(TractionModel model);

  class TangentialTractionModel
  {
  public:
    virtual ~TangentialTractionModel() = default;

    /// One load step with the same shift increment (dx, dy) [m] at every cell.
    virtual void advance(const Field &pressure, double friction_coefficient, double shift_x_increment,
                         double shift_y_increment) = 0;
    /// One load step with a shift increment per cell [m].
    virtual void advance(const Field &pressure, double friction_coefficient, const Field &shift_x_increment,
                         const Field &shift_y_increment) = 0;
    virtual void reset() = 0;

    virtual const Field &traction_x() const = 0; ///< [Pa], on the lower body
    virtual const Field &traction_y() const = 0; ///< [Pa]
    /// |tau| / (mu p) per cell after the last advance, 0 outside the contact
    /// (the paper's effective friction map divided by mu).
    virtual Field effective_friction() const = 0;
    /// Fraction of the loaded cells that slip after the last advance.
    virtual double slip_area_fraction() const = 0;
    /// Solver iterations of the last advance (0 for the local bristle models).
    virtual int last_iterations() const { return 0; }

    virtual TractionModel kind() const = 0;
  };

  /// The model `kind` on `grid`. bristle_stiffness k [Pa/m] is used by the
  /// two bristle models (usually BristleTraction::mindlin_stiffness(G*, a));
  /// materials and settings by the exact model.
  std::unique_ptr<TangentialTractionModel> make_tangential_traction_model(TractionModel kind, const SurfaceGrid &grid,
                                                                          const MaterialPair &materials,
                                                                          double bristle_stiffness,
                                                                          const PartialSlipSettings &settings = {});

  /// The exact model's solver, for its per-step statistics (iterations, FFT
  /// products, forces, dissipation); nullptr for the other models.
  const PartialSlipSolver *exact_solver(const TangentialTractionModel &model);

  class MasingTraction;
  /// The exact masing model's superposition, for its composition; nullptr
  /// for the other models.
  const MasingTraction *masing_traction(const TangentialTractionModel &model);
} // namespace fretsim::contact
