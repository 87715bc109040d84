// The common interface of the tangential traction models
// (tangential_traction_model.h): names, factory, and that each adapter gives
// exactly what the wrapped class gives.
#include <fretsim/contact/bristle.h>
#include <fretsim/contact/elastoplastic_bristle.h>
#include <fretsim/contact/material.h>
#include <fretsim/contact/partial_slip.h>
#include <fretsim/contact/tangential_traction_model.h>

#include "reference/hertz_field.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

using namespace fretsim::contact;

namespace
{
  const double       mu = 0.53, a = 0.75e-3, p0 = 1.06e9;
  const MaterialPair steel{{200e9, 0.3}, {200e9, 0.3}};
  const double       k = BristleTraction::mindlin_stiffness(steel.tangential_modulus(), a);

  SurfaceGrid grid() { return SurfaceGrid::centred(24, 24, 1.5 * a, 1.5 * a); }

  Field hertz(const SurfaceGrid &g) { return fretsim::reference::hertz_pressure_field(g, a, p0); }
} // namespace

TEST(TangentialTractionModel, NamesRoundTripAndUnknownNamesAreErrors)
{
  for (const auto model : {TractionModel::bristle, TractionModel::elastoplastic_bristle, TractionModel::exact,
                           TractionModel::exact_masing})
    EXPECT_EQ(parse_traction_model(to_string(model)), model);
  EXPECT_EQ(parse_traction_model("elastoplastic bristle"), TractionModel::elastoplastic_bristle);
  try
    {
      parse_traction_model("kalker");
      FAIL() << "no exception";
    }
  catch (const std::invalid_argument &error)
    {
      const std::string message = error.what();
      EXPECT_NE(message.find("kalker"), std::string::npos);
      EXPECT_NE(message.find("bristle, elastoplastic bristle, exact, exact masing"), std::string::npos);
    }
}

TEST(TangentialTractionModel, AdaptersReproduceTheWrappedModels)
{
  const auto  g = grid();
  const Field p = hertz(g);
  auto        bristle     = make_tangential_traction_model(TractionModel::bristle, g, steel, k);
  auto        plastic     = make_tangential_traction_model(TractionModel::elastoplastic_bristle, g, steel, k);
  auto        exact       = make_tangential_traction_model(TractionModel::exact, g, steel, k);
  BristleTraction              direct_bristle(g, k);
  ElastoplasticBristleTraction direct_plastic(g, k);
  PartialSlipSolver            direct_exact(g, steel);
  EXPECT_EQ(bristle->kind(), TractionModel::bristle);
  EXPECT_EQ(plastic->kind(), TractionModel::elastoplastic_bristle);
  EXPECT_EQ(exact->kind(), TractionModel::exact);
  EXPECT_EQ(exact_solver(*bristle), nullptr);
  ASSERT_NE(exact_solver(*exact), nullptr);

  const double shifts[][2] = {{1e-6, 0.0}, {0.5e-6, 0.3e-6}, {-2e-6, 0.0}};
  for (const auto &shift : shifts)
    {
      bristle->advance(p, mu, shift[0], shift[1]);
      plastic->advance(p, mu, shift[0], shift[1]);
      exact->advance(p, mu, shift[0], shift[1]);
      direct_bristle.advance(p, mu, shift[0], shift[1]);
      direct_plastic.advance(p, mu, shift[0], shift[1]);
      direct_exact.advance(p, mu, shift[0], shift[1]);
      EXPECT_EQ(bristle->traction_x(), direct_bristle.traction_x());
      EXPECT_EQ(bristle->traction_y(), direct_bristle.traction_y());
      EXPECT_EQ(plastic->traction_x(), direct_plastic.traction_x());
      EXPECT_EQ(exact->traction_x(), direct_exact.traction_x());
      EXPECT_EQ(exact->traction_y(), direct_exact.traction_y());
      EXPECT_EQ(bristle->effective_friction(), direct_bristle.effective_friction(p, mu));
      EXPECT_EQ(plastic->slip_area_fraction(), direct_plastic.slip_area_fraction(p, mu));
      EXPECT_EQ(exact->slip_area_fraction(), direct_exact.slip_area_fraction());
      EXPECT_EQ(exact->last_iterations(), direct_exact.last_step().iterations);
      EXPECT_GT(exact->last_iterations(), 0);
      EXPECT_EQ(bristle->last_iterations(), 0);
    }
  // The per-cell overload with a uniform field is the uniform step.
  const Field dx(g.size(), 0.7e-6), dy(g.size(), -0.2e-6);
  for (auto *model : {bristle.get(), plastic.get(), exact.get()})
    model->advance(p, mu, dx, dy);
  direct_bristle.advance(p, mu, 0.7e-6, -0.2e-6);
  direct_plastic.advance(p, mu, 0.7e-6, -0.2e-6);
  direct_exact.advance(p, mu, 0.7e-6, -0.2e-6);
  EXPECT_EQ(bristle->traction_x(), direct_bristle.traction_x());
  EXPECT_EQ(plastic->traction_x(), direct_plastic.traction_x());
  for (std::size_t c = 0; c < g.size(); ++c)
    EXPECT_NEAR(exact->traction_x()[c], direct_exact.traction_x()[c], 1e-9 * mu * p0);

  // Effective friction is |tau|/(mu p) in [0, 1] for all three.
  for (auto *model : {bristle.get(), plastic.get(), exact.get()})
    {
      const Field ratio = model->effective_friction();
      for (std::size_t c = 0; c < g.size(); ++c)
        {
          EXPECT_GE(ratio[c], 0.0);
          EXPECT_LE(ratio[c], 1.0);
          if (p[c] > 0.0)
            {
              EXPECT_NEAR(ratio[c], std::hypot(model->traction_x()[c], model->traction_y()[c]) / (mu * p[c]), 1e-9);
            }
        }
      const double slipping = model->slip_area_fraction();
      EXPECT_GE(slipping, 0.0);
      EXPECT_LE(slipping, 1.0);
      model->reset();
      EXPECT_EQ(integrate(g, model->traction_x()), 0.0);
    }
}
