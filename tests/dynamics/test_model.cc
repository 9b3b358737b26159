// Unit checks of the stiffness table and the gear-pair model's building blocks.
#include "dynamics/gear_pair_model.h"
#include "dynamics/stiffness_table.h"

#include "common/errors.h"
#include "tests/dynamics/dynamics_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace hertzgear::dynamics;
using namespace hertzgear::dynamics::testing;
using hertzgear::FourierSeries;
using hertzgear::fit_fourier_series;

// Requirement: a Fourier fit by FFTW of S uniform samples of a series with h <= (S-1)/2 harmonics
// returns its mean, amplitudes and phases. Tolerance 1e-12 relative: the DFT of exactly
// representable samples is exact up to round-off (a few ulp times log2 S).
// Requirement: the cos/sin-form evaluator the model uses at every new phase returns the series'
// value and its first two derivatives. 20 harmonics of decreasing amplitude at 50 phases: the
// recurrence's rounding grows like j eps, so 1e-13 of the amplitude sum (times the order j and
// j^2 that the derivatives weigh it with, at most 20 and 400) bounds the difference.
TEST(StiffnessTable, FourierEvaluatorMatchesTheSeries)
{
  FourierSeries series{5.0e10, {}, {}};
  for (int j = 1; j <= 20; ++j)
    {
      series.amplitudes.push_back(2.0e10 / j);
      series.phases_rad.push_back(0.7 * j - 3.0);
    }
  const FourierEvaluator fast(series);
  const double           scale = series.amplitude_bound();
  for (int i = 0; i < 50; ++i)
    {
      const double theta = -20.0 + 0.83 * i;
      const double c = std::cos(theta), s = std::sin(theta);
      double taylor[3];
      fast.taylor(c, s, taylor);
      double second = 0.0;
      for (unsigned j = 0; j < series.amplitudes.size(); ++j)
        second -= (j + 1.0) * (j + 1.0) * series.amplitudes[j] *
                  std::cos((j + 1) * theta - series.phases_rad[j]);
      EXPECT_NEAR(taylor[0], series.value(theta), 1e-13 * (series.mean + scale));
      EXPECT_NEAR(taylor[1], series.derivative(theta), 1e-13 * 20 * scale);
      EXPECT_NEAR(taylor[2], second, 1e-13 * 400 * scale);
    }
}

TEST(StiffnessTable, FourierFitRecoversTheSeries)
{
  const FourierSeries truth{5.0e10, {2.0e10, 4.0e9, 6.0e9}, {0.3, -2.0, 1.1}};
  std::vector<double> samples(9);
  for (int i = 0; i < 9; ++i)
    samples[i] = truth.value(2.0 * M_PI * i / 9);
  const FourierSeries fit = fit_fourier_series(samples, 3);
  EXPECT_NEAR(fit.mean, truth.mean, 1e-12 * truth.mean);
  for (int j = 0; j < 3; ++j)
    {
      EXPECT_NEAR(fit.amplitudes[j], truth.amplitudes[j], 1e-12 * truth.mean);
      EXPECT_NEAR(std::remainder(fit.phases_rad[j] - truth.phases_rad[j], 2 * M_PI), 0.0, 1e-12);
    }
  EXPECT_THROW(fit_fourier_series(samples, 5), hertzgear::InputError);
}

// Requirement: the stiffness table survives a JSON round trip, and a table given only as samples
// is fitted on reading. Exact equality for the round trip: JSON writes doubles with 17 digits.
TEST(StiffnessTable, JsonRoundTripAndSampledTables)
{
  StiffnessTable t;
  t.hertz_exponent        = 1.5;
  t.k_rest_N_per_m        = {2.79e8, {}, {}};
  t.k_hertz_N_per_m_pow_n = {5.095e10, {2.045e10}, {0.5}};
  t.unloaded_ste_m        = {0.0, {1e-6}, {0.0}};
  t.has_unloaded_ste      = true;
  const StiffnessTable back = stiffness_table_from_json_text(stiffness_table_to_json_text(t));
  EXPECT_EQ(back.hertz_exponent, t.hertz_exponent);
  EXPECT_EQ(back.k_hertz_N_per_m_pow_n.amplitudes, t.k_hertz_N_per_m_pow_n.amplitudes);
  EXPECT_EQ(back.k_hertz_N_per_m_pow_n.phases_rad, t.k_hertz_N_per_m_pow_n.phases_rad);
  EXPECT_TRUE(back.has_unloaded_ste);

  const std::string sampled = R"({"hertz_exponent": 1.0, "k_rest_N_per_m": {"mean": 4.17e8},
    "samples": {"mesh_phase": [0, 0.2, 0.4, 0.6, 0.8],
                "k_hertz_N_per_m_pow_n": [2e9, 1e9, 1e9, 1e9, 1e9]}})";
  const StiffnessTable s = stiffness_table_from_json_text(sampled);
  EXPECT_NEAR(s.k_hertz_N_per_m_pow_n.mean, 1.2e9, 1e-3);
  EXPECT_EQ(s.k_hertz_N_per_m_pow_n.n_harmonics(), 2u);

  // Bad tables fail with InputError naming the problem.
  EXPECT_THROW(stiffness_table_from_json_text(R"({"hertz_exponent": 3})"), hertzgear::InputError);
  EXPECT_THROW(stiffness_table_from_json_text("{not json"), hertzgear::InputError);
}

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
