// Unit checks of the gear-pair model's building blocks.
#include "dynamics/gear_pair_model.h"

#include "common/errors.h"
#include "tests/dynamics/dynamics_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace hertzgear::dynamics;
using namespace hertzgear::dynamics::testing;
using hertzgear::FourierSeries;

// Requirement: an effect that is off is absent from the state: 3 components only with a dynamic
// Hertzian layer, and no root functions for the linear model.
TEST(GearPairModel, StateDimensionFollowsTheEffects)
{
  auto p = paper_crowned();
  EXPECT_EQ(GearPairModel(p).n_states(), 3u);
  EXPECT_EQ(GearPairModel(p).n_roots(), 3u); // |x| = b_c twice, delta = 0
  p.effects.hertzian_layer = HertzianLayer::quasi_static;
  EXPECT_EQ(GearPairModel(p).n_states(), 2u);
  p.effects.hertzian_layer = HertzianLayer::off;
  EXPECT_EQ(GearPairModel(p).n_states(), 2u);
  p.effects.backlash = false;
  EXPECT_EQ(GearPairModel(p).n_roots(), 0u);
}

// Requirement: the analytic Jacobian CVODE uses equals the derivative of the right-hand side, in
// contact, with the layer open and in separation. Central differences with a step of 1e-6 of the
// state scale have a truncation error ~1e-12 relative; 1e-5 relative allows for round-off.
TEST(GearPairModel, JacobianMatchesFiniteDifferences)
{
  GearPairModel model(paper_crowned());
  const std::vector<std::vector<double>> states = {
    {108e-6, 1e-3, 36e-6}, {108e-6, -0.3, 2e-6}, {70e-6, 0.2, -1e-6}, {0.0, 0.5, 1e-7}};
  for (const auto &y0 : states)
    {
      double J[9];
      model.jacobian(0.0031, y0.data(), J);
      for (int j = 0; j < 3; ++j)
        {
          const double h = 1e-6 * std::max(std::abs(y0[j]), 1e-6);
          auto         yp = y0, ym = y0;
          yp[j] += h;
          ym[j] -= h;
          double fp[3], fm[3];
          model.rhs(0.0031, yp.data(), fp);
          model.rhs(0.0031, ym.data(), fm);
          for (int i = 0; i < 3; ++i)
            {
              const double fd = (fp[i] - fm[i]) / (2 * h);
              EXPECT_NEAR(J[i * 3 + j], fd, 1e-5 * std::max(std::abs(fd), 1.0))
                << "d f_" << i << " / d y_" << j << " at x = " << y0[0];
            }
        }
    }
}

// Requirement: the right-hand side is a function of (t, y) alone: the model's store of recent
// time-dependent coefficients (kept by t for the Newton iterations of implicit integrators) never
// returns the coefficients of another time. Many times, revisited in a scrambled order, with the
// unloaded STE excitation and a varying rest stiffness on, must give bit-identical results to a
// fresh model evaluated once per time: the cache stores exactly what it would compute.
TEST(GearPairModel, CoefficientStoreGivesTheSameRightHandSide)
{
  auto p                                 = paper_crowned();
  p.effects.ste_excitation               = true;
  p.stiffness.has_unloaded_ste           = true;
  p.stiffness.unloaded_ste_m             = FourierSeries{0.0, {2e-6, 0.5e-6}, {0.3, 1.1}};
  p.effects.rest_stiffness_variation     = true;
  p.stiffness.k_rest_N_per_m.amplitudes  = {3e7, 1e7};
  p.stiffness.k_rest_N_per_m.phases_rad  = {0.2, -0.4};
  GearPairModel   model(p);
  const double    T = model.mesh_period();
  std::vector<double> times;
  for (int i = 0; i < 300; ++i)
    times.push_back(T * (0.37 * i + 1e-3 * (i % 7)));
  const std::vector<double> y = {108e-6, 1e-3, 36e-6};
  for (int pass = 0; pass < 3; ++pass)
    for (std::size_t k = 0; k < times.size(); ++k)
      {
        const double t = times[(k * 131 + pass * 17) % times.size()];
        double       f[3], f_fresh[3], J[9], J_fresh[9];
        model.rhs(t, y.data(), f);
        model.jacobian(t, y.data(), J);
        GearPairModel fresh(p);
        fresh.rhs(t, y.data(), f_fresh);
        fresh.jacobian(t, y.data(), J_fresh);
        for (int i = 0; i < 3; ++i)
          EXPECT_EQ(f[i], f_fresh[i]) << "t = " << t << ", component " << i;
        for (int i = 0; i < 9; ++i)
          EXPECT_EQ(J[i], J_fresh[i]) << "t = " << t << ", entry " << i;
        EXPECT_EQ(model.excitation(t), fresh.excitation(t));
      }
}

// Requirement: the static equilibrium state carries F_0 with the mean stiffness: zero
// acceleration. Relative 1e-9 of F_0/m_e: the state is computed in closed form.
TEST(GearPairModel, StaticEquilibriumIsAtRest)
{
  auto p                             = paper_crowned();
  p.effects.mesh_stiffness_variation = false;
  for (const auto layer : {HertzianLayer::dynamic, HertzianLayer::quasi_static, HertzianLayer::off})
    {
      p.effects.hertzian_layer = layer;
      GearPairModel model(p);
      auto          y = model.static_equilibrium_state();
      std::vector<double> y_dot(y.size());
      model.rhs(0.0, y.data(), y_dot.data());
      EXPECT_NEAR(y_dot[1], 0.0, 1e-9 * p.static_force_N / p.equivalent_mass_kg);
      if (y.size() == 3)
        {
          EXPECT_NEAR(y_dot[2], 0.0, 1e-9 * std::abs(y[2]) * p.mesh_frequency_rad_per_s);
        }
    }
}
