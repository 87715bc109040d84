#include <fretsim/contact/bristle.h>
#include <fretsim/contact/elastoplastic_bristle.h>
#include <fretsim/contact/masing_traction.h>
#include <fretsim/contact/tangential_traction_model.h>

#include <algorithm>
#include <stdexcept>

namespace fretsim::contact
{
  TractionModel parse_traction_model(const std::string &name)
  {
    if (name == "bristle")
      return TractionModel::bristle;
    if (name == "elastoplastic bristle")
      return TractionModel::elastoplastic_bristle;
    if (name == "exact")
      return TractionModel::exact;
    if (name == "exact masing")
      return TractionModel::exact_masing;
    throw std::invalid_argument("traction model '" + name +
                                "' is not one of: bristle, elastoplastic bristle, exact, exact masing");
  }

  std::string to_string(TractionModel model)
  {
    switch (model)
      {
        case TractionModel::bristle:
          return "bristle";
        case TractionModel::elastoplastic_bristle:
          return "elastoplastic bristle";
        case TractionModel::exact:
          return "exact";
        case TractionModel::exact_masing:
          return "exact masing";
      }
    throw std::invalid_argument("unknown traction model");
  }

  namespace
  {
    /// The local bristle models keep the last pressure and mu for their maps.
    template <typename Bristles, TractionModel Kind>
    class BristleAdapter final : public TangentialTractionModel
    {
    public:
      BristleAdapter(const SurfaceGrid &grid, double stiffness)
        : bristles(grid, stiffness)
        , pressure(grid.zeros())
      {
      }

      void advance(const Field &p, double mu, double dx, double dy) override
      {
        bristles.advance(p, mu, dx, dy);
        remember(p, mu);
      }
      void advance(const Field &p, double mu, const Field &dx, const Field &dy) override
      {
        bristles.advance(p, mu, dx, dy);
        remember(p, mu);
      }
      void reset() override
      {
        bristles.reset();
        std::fill(pressure.begin(), pressure.end(), 0.0);
        friction = 0.0;
      }
      const Field  &traction_x() const override { return bristles.traction_x(); }
      const Field  &traction_y() const override { return bristles.traction_y(); }
      Field         effective_friction() const override { return bristles.effective_friction(pressure, friction); }
      double        slip_area_fraction() const override { return bristles.slip_area_fraction(pressure, friction); }
      TractionModel kind() const override { return Kind; }

    private:
      void remember(const Field &p, double mu)
      {
        pressure = p;
        friction = mu;
      }

      Bristles bristles;
      Field    pressure;
      double   friction = 0.0;
    };

    class ExactAdapter final : public TangentialTractionModel
    {
    public:
      ExactAdapter(const SurfaceGrid &grid, const MaterialPair &materials, const PartialSlipSettings &settings)
        : solver(grid, materials, settings)
      {
      }

      void advance(const Field &p, double mu, double dx, double dy) override { solver.advance(p, mu, dx, dy); }
      void advance(const Field &p, double mu, const Field &dx, const Field &dy) override
      {
        solver.advance(p, mu, dx, dy);
      }
      void          reset() override { solver.reset(); }
      const Field  &traction_x() const override { return solver.traction_x(); }
      const Field  &traction_y() const override { return solver.traction_y(); }
      Field         effective_friction() const override { return solver.effective_friction(); }
      double        slip_area_fraction() const override { return solver.slip_area_fraction(); }
      int           last_iterations() const override { return solver.last_step().iterations; }
      TractionModel kind() const override { return TractionModel::exact; }

      PartialSlipSolver solver;
    };

    class MasingAdapter final : public TangentialTractionModel
    {
    public:
      MasingAdapter(const SurfaceGrid &grid, const MaterialPair &materials, const PartialSlipSettings &settings)
        : model(grid, materials, settings)
      {
      }

      void advance(const Field &p, double mu, double dx, double dy) override { model.advance(p, mu, dx, dy); }
      void advance(const Field &, double, const Field &, const Field &) override
      {
        throw std::logic_error("the exact masing traction model needs a uniform shift; use the exact model");
      }
      void          reset() override { model.reset(); }
      const Field  &traction_x() const override { return model.traction_x(); }
      const Field  &traction_y() const override { return model.traction_y(); }
      Field         effective_friction() const override { return model.effective_friction(); }
      double        slip_area_fraction() const override { return model.slip_area_fraction(); }
      int           last_iterations() const override { return model.last_iterations(); }
      TractionModel kind() const override { return TractionModel::exact_masing; }

      MasingTraction model;
    };
  } // namespace

  std::unique_ptr<TangentialTractionModel> make_tangential_traction_model(TractionModel kind, const SurfaceGrid &grid,
                                                                          const MaterialPair &materials,
                                                                          double bristle_stiffness,
                                                                          const PartialSlipSettings &settings)
  {
    switch (kind)
      {
        case TractionModel::bristle:
          return std::make_unique<BristleAdapter<BristleTraction, TractionModel::bristle>>(grid, bristle_stiffness);
        case TractionModel::elastoplastic_bristle:
          return std::make_unique<BristleAdapter<ElastoplasticBristleTraction, TractionModel::elastoplastic_bristle>>(
            grid, bristle_stiffness);
        case TractionModel::exact:
          return std::make_unique<ExactAdapter>(grid, materials, settings);
        case TractionModel::exact_masing:
          return std::make_unique<MasingAdapter>(grid, materials, settings);
      }
    throw std::invalid_argument("unknown traction model");
  }

  const PartialSlipSolver *exact_solver(const TangentialTractionModel &model)
  {
    const auto *exact = dynamic_cast<const ExactAdapter *>(&model);
    return exact ? &exact->solver : nullptr;
  }

  const MasingTraction *masing_traction(const TangentialTractionModel &model)
  {
    const auto *masing = dynamic_cast<const MasingAdapter *>(&model);
    return masing ? &masing->model : nullptr;
  }
} // namespace fretsim::contact
