// Requirements of the shooting method (dynamics/periodic_orbit.h, docs/dynamics.md "Periodic
// orbits by shooting"):
// - the monodromy matrix of a linear time-invariant oscillator has the analytic multipliers
//   exp(lambda T);
// - on a stable branch the orbit equals the steady state of a long time-marched run (RMS DTE and
//   Poincare point), with and without switching events;
// - across contact loss the saltation matrices make the monodromy matrix the derivative of the
//   period map (checked against central differences of the map);
// - multiple shooting finds the same orbit as single shooting;
// - a guess Newton cannot serve is reported as "no periodic orbit" with its reason.
#include "dynamics/periodic_orbit.h"

#include "common/errors.h"
#include "tests/dynamics/dynamics_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>

using namespace hertzgear::dynamics;
using namespace hertzgear::dynamics::testing;

namespace
{
  ShootingSettings shooting(const double rtol, const double atol,
                            const IntegratorKind kind = IntegratorKind::radau_iia)
  {
    ShootingSettings s;
    s.integrator.kind               = kind;
    s.integrator.relative_tolerance = rtol;
    s.integrator.absolute_tolerance = atol;
    s.tolerance                     = 1e-11;
    return s;
  }

  // The RMS DTE and the Poincare point of a long time-marched run at rtol 1e-12.
  struct Marched
  {
    double rms_dte, poincare_dte, poincare_rate;
  };
  Marched time_marched(const GearPairParameters &p, const std::vector<double> &start,
                       const int periods, const int transient)
  {
    GearPairModel model(p);
    const auto    r = simulate(model, run_settings(IntegratorKind::radau_iia, 1e-12, 1e-17, periods,
                                                   transient, 100),
                               start);
    const auto s = analyse(model, r);
    return {s.rms_dte_m, r.poincare.back().dte_m, r.poincare.back().dte_rate_m_per_s};
  }
  // Central differences of the period map over one mesh period at x0, each state's step `step`
  // times its scale, integrated by Radau IIA at rtol 1e-13.
  Eigen::MatrixXd period_map_differences(GearPairModel &model, const std::vector<double> &x0,
                                         const double step)
  {
    const auto     scale = model.state_scales();
    const unsigned n     = model.n_states();
    IntegratorSettings is;
    is.kind               = IntegratorKind::radau_iia;
    is.relative_tolerance = 1e-13;
    is.absolute_tolerance = 1e-18;
    const double T        = model.mesh_period();
    auto         map      = [&](std::vector<double> x) {
      auto integrator = make_integrator(is);
      integrator->integrate(model, 0.0, x, T, 1, [](double, const double *) {});
      return x;
    };
    Eigen::MatrixXd d(n, n);
    for (unsigned j = 0; j < n; ++j)
      {
        const double h  = step * scale[j];
        auto         xp = x0, xm = x0;
        xp[j] += h;
        xm[j] -= h;
        const auto yp = map(xp), ym = map(xm);
        for (unsigned i = 0; i < n; ++i)
          d(i, j) = (yp[i] - ym[i]) / (2 * h);
      }
    return d;
  }
} // namespace

TEST(PeriodicOrbit, LinearOscillatorHasTheAnalyticMultipliers)
{
  // m x'' + c x' + k x = k e(t): without backlash and with constant stiffness the variational
  // equations are those of the free oscillator, whose monodromy over the forcing period T has
  // the eigenvalues exp(lambda T), lambda = -zeta w_n +- i w_n sqrt(1 - zeta^2). Integrated at
  // rtol 1e-13 with Radau IIA (order 13), the multipliers are exact to rounding of the 1e-10
  // asked for.
  const double zeta = 0.05, omega = 700.0, w_n = 1000.0;
  auto         p    = unit_oscillator_with_ste(zeta, omega, 1e-5);
  GearPairModel model(p);
  const auto    orbit = find_periodic_orbit(model, model.static_equilibrium_state(),
                                            shooting(1e-13, 1e-20));
  ASSERT_TRUE(orbit.converged) << orbit.failure;
  const double               T = 2 * M_PI / omega;
  const std::complex<double> lambda(-zeta * w_n, w_n * std::sqrt(1 - zeta * zeta));
  const std::complex<double> mu = std::exp(lambda * T);
  ASSERT_EQ(orbit.multipliers.size(), 2u);
  const auto a = orbit.multipliers[0], b = orbit.multipliers[1];
  const auto upper = a.imag() > b.imag() ? a : b, lower = a.imag() > b.imag() ? b : a;
  std::printf("multipliers %.15f %+.15fi (analytic %.15f %+.15fi)\n", upper.real(), upper.imag(),
              mu.real(), mu.imag());
  EXPECT_LT(std::abs(upper - mu), 1e-10);
  EXPECT_LT(std::abs(lower - std::conj(mu)), 1e-10);
  EXPECT_TRUE(orbit.stable);
  // The orbit itself is the closed-form steady response.
  const double amplitude = unit_oscillator_response(p, omega, 1e-5);
  const auto   s = analyse_orbit(model, orbit, run_settings(IntegratorKind::radau_iia, 1e-13, 1e-20, 1, 0, 2000));
  EXPECT_NEAR(0.5 * (s.max_dte_m - s.min_dte_m), amplitude, 1e-9 * amplitude);
}

TEST(PeriodicOrbit, EqualsTheTimeMarchedSteadyStateOfThePaperPair)
{
  // The crowned paper pair at 150 rpm (dynamic Hertzian layer, k_h(t) with four harmonics): the
  // shooting orbit at rtol 1e-12 against 400 steady periods after 400 transient ones. The
  // transient decays by exp(-zeta w_n T) ~ 1e-40 per period, so the marched run is periodic to
  // its integration error (~1e-12 relative): 1e-8 relative is the requirement.
  const auto    p = paper_crowned();
  GearPairModel model(p);
  const auto    orbit = find_periodic_orbit(model, model.static_equilibrium_state(),
                                            shooting(1e-12, 1e-17));
  ASSERT_TRUE(orbit.converged) << orbit.failure;
  EXPECT_TRUE(orbit.stable);
  const auto s = analyse_orbit(model, orbit, run_settings(IntegratorKind::radau_iia, 1e-12, 1e-17, 1, 0, 100));
  const auto m = time_marched(p, model.static_equilibrium_state(), 800, 400);
  std::printf("iterations %d, RMS DTE %.12e (marched %.12e), Poincare %.12e (marched %.12e)\n",
              orbit.iterations, s.rms_dte_m, m.rms_dte, orbit.state[0], m.poincare_dte);
  EXPECT_NEAR(s.rms_dte_m, m.rms_dte, 1e-8 * m.rms_dte);
  EXPECT_NEAR(orbit.state[0], m.poincare_dte, 1e-8 * std::abs(m.poincare_dte));
  EXPECT_NEAR(orbit.state[1], m.poincare_rate, 1e-8 * model.state_scales()[1]);
  EXPECT_EQ(s.period_status, "period-1");
}

TEST(PeriodicOrbit, AcrossContactLossEqualsTheTimeMarchedSteadyState)
{
  // The crowned table pair at 16000 rpm loses contact once per mesh period: two switching events
  // of the layer and two of the backlash zone per period. Transient: the slowest multiplier
  // (measured below) to the power 600 is far below 1e-12.
  const auto    p = contact_loss_pair();
  GearPairModel model(p);
  const auto    start = contact_loss_start(model);
  const auto    m     = time_marched(p, start, 1000, 600);
  const auto    orbit = find_periodic_orbit(model, start, shooting(1e-12, 1e-17));
  ASSERT_TRUE(orbit.converged) << orbit.failure;
  const auto s = analyse_orbit(model, orbit, run_settings(IntegratorKind::radau_iia, 1e-12, 1e-17, 1, 0, 100));
  std::printf("iterations %d, events %ld, |mu|max %.6f, RMS DTE %.12e (marched %.12e), contact "
              "loss %.4f\n",
              orbit.iterations, orbit.events_per_period, orbit.largest_multiplier_modulus,
              s.rms_dte_m, m.rms_dte, s.contact_loss_fraction);
  ASSERT_LT(std::pow(orbit.largest_multiplier_modulus, 600), 1e-13);
  EXPECT_GT(s.contact_loss_fraction, 0.0);
  EXPECT_GE(orbit.events_per_period, 2);
  EXPECT_TRUE(orbit.stable);
  EXPECT_NEAR(s.rms_dte_m, m.rms_dte, 1e-8 * m.rms_dte);
  EXPECT_NEAR(orbit.state[0], m.poincare_dte, 1e-8 * std::abs(m.poincare_dte));
}

TEST(PeriodicOrbit, SaltationMatricesGiveTheDerivativeOfThePeriodMap)
{
  // Central differences of the period map P(x0) (step h = 1e-5 of each state's scale, integrated
  // at rtol 1e-13: truncation ~h^2 ~ 1e-10 and integration error / h ~ 1e-8 of the scale) against
  // the monodromy matrix on the contact-loss orbit; without the saltation matrices the columns
  // differ by the jump of the vector field (c x' at contact loss), tens of per cent here.
  const auto    p = contact_loss_pair();
  GearPairModel model(p);
  auto          orbit = find_periodic_orbit(model, contact_loss_start(model), shooting(1e-12, 1e-17));
  ASSERT_TRUE(orbit.converged) << orbit.failure;
  const auto     scale = model.state_scales();
  const unsigned n     = model.n_states();
  const auto     d     = period_map_differences(model, orbit.state, 1e-5);
  double         worst = 0.0;
  for (unsigned j = 0; j < n; ++j)
    for (unsigned i = 0; i < n; ++i)
      {
        // Relative to the column's scaled size (entries of a strongly contracting map are small).
        const double fd = d(i, j) * scale[j] / scale[i];
        const double an = orbit.monodromy(i, j) * scale[j] / scale[i];
        worst           = std::max(worst, std::abs(fd - an));
        std::printf("M(%u,%u) scaled: shooting %.10e, differences %.10e\n", i, j, an, fd);
      }
  EXPECT_LT(worst, 1e-6);
}

// Requirement: on an orbit with impacts on the back flanks the monodromy matrix is the derivative
// of the period map too, and so are its multipliers, at the responses' integration tolerance and
// at a tighter one (a hard case: switchings a rounding apart). The case: the crowned table pair
// with its structural stiffness varying over the cycle at 15 260.57 rpm, whose stable orbit
// (reached from x = 300 um, x' = -6 m/s) has a dynamic factor of 13 and one back-side impact per
// mesh period, shot at rtol 1e-10 (Response/relative_tolerance's default) and 1e-12. Central
// differences of the map at rtol 1e-13 with a step of 1e-4 of each state's scale (its noise,
// about 1e-11 of the scale from locating its switchings, makes shorter steps worse: 1.6e-6 at
// 1e-5, 1.1e-5 at 1e-6; the truncation at 1e-4 is ~1e-8): measured agreement 5.2e-8 (1e-10) and
// 5.3e-8 (1e-12) of the scaled entries, the leading multiplier 0.7232988 +- 0.3503335i; 1e-6
// bounds it. Where a contact closes, the layer's own root changes sign a picosecond after the
// zone's, and the saltation matrices' f- and f+ once lay beyond both (0.7014 +- 0.3923i); where
// the teeth leave contact with the layer compressed, the layer's root (redefined outside the zone)
// changes sign on the zone's surface, and at rtol 1e-12 the integrator once resolved that seam as
// a seventh event whose saltation matrix counted the switching twice (0.7578 +- 0.2675i).
TEST(PeriodicOrbit, SaltationMatricesGiveTheDerivativeOfTheMapAcrossBacksideImpacts)
{
  auto p                             = contact_loss_pair();
  p.effects.rest_stiffness_variation = true;
  p.mesh_frequency_rad_per_s         = 2.0 * M_PI * 23.0 * 15260.57 / 60.0;
  GearPairModel model(p);
  const auto    marched =
    simulate(model, run_settings(IntegratorKind::radau_iia, 1e-10, 1e-15, 300, 299, 100),
             model.state(300e-6, -6.0, 1e-6));
  const auto s0 = analyse(model, marched);
  ASSERT_GT(s0.backside_impacts, 0) << "the case must reach the back flanks (DF " << s0.dynamic_factor << ")";
  const auto     scale = model.state_scales();
  const unsigned n     = model.n_states();
  Eigen::MatrixXd differences;
  for (const double rtol : {1e-10, 1e-12})
    {
      // Newton to 1e-9 of the scale: across six switchings per period the map is smooth to about
      // 1e-11 at rtol 1e-12, where Newton's steps stop reducing the residual (4e-12).
      auto settings      = shooting(rtol, 1e-15);
      settings.tolerance = 1e-9;
      auto orbit         = find_periodic_orbit(model, marched.final_state, settings);
      ASSERT_TRUE(orbit.converged) << orbit.failure;
      if (differences.size() == 0)
        differences = period_map_differences(model, orbit.state, 1e-4);
      double worst = 0.0;
      for (unsigned j = 0; j < n; ++j)
        for (unsigned i = 0; i < n; ++i)
          worst = std::max(worst, std::abs(differences(i, j) - orbit.monodromy(i, j)) * scale[j] / scale[i]);
      const auto mu = floquet_multipliers(orbit.monodromy), mu_fd = floquet_multipliers(differences);
      std::printf("rtol %.0e: DF %.3f, %ld events per period; multipliers %.7f %+.7fi (shooting), "
                  "%.7f %+.7fi (differences); largest scaled difference %.2e\n",
                  rtol, s0.dynamic_factor, orbit.events_per_period, mu[0].real(), mu[0].imag(),
                  mu_fd[0].real(), mu_fd[0].imag(), worst);
      EXPECT_LT(worst, 1e-6) << "rtol " << rtol;
      EXPECT_LT(std::abs(mu[0] - mu_fd[0]), 1e-6) << "rtol " << rtol;
    }
}

TEST(PeriodicOrbit, MultipleShootingFindsTheSameOrbit)
{
  // Four segments per period from a guess 2 um off the single-shooting orbit: the same x(0) to
  // the Newton tolerance, and the same multipliers (the product of the segments' Jacobians).
  // From the scene's start itself, at a speed where both coexist, multiple shooting converges to
  // the other stable period-1 orbit, the one without contact loss (the resonance bends: both
  // branches are stable there, docs/dynamics.md); that orbit closes too.
  const auto    p = contact_loss_pair();
  GearPairModel model(p);
  const auto    single = find_periodic_orbit(model, contact_loss_start(model), shooting(1e-12, 1e-17));
  ASSERT_TRUE(single.converged) << single.failure;
  auto settings     = shooting(1e-12, 1e-17);
  settings.segments = 4;
  auto guess        = single.state;
  guess[0] += 2e-6;
  const auto multiple = find_periodic_orbit(model, guess, settings);
  ASSERT_TRUE(multiple.converged) << multiple.failure;
  const auto scale = model.state_scales();
  for (unsigned i = 0; i < model.n_states(); ++i)
    EXPECT_NEAR(single.state[i], multiple.state[i], 1e-9 * scale[i]);
  EXPECT_NEAR(std::abs(single.multipliers[0]), std::abs(multiple.multipliers[0]), 1e-7);

  // Both stable orbits coexist between the table's two folds (14 958 and 15 996 rpm on the serial
  // law, docs/paper-reproduction.md), so this part runs at 15 500 rpm, where the contact-losing
  // orbit is found from the single-shooting orbit of 16 000 rpm.
  auto p_mid                     = p;
  p_mid.mesh_frequency_rad_per_s = 2.0 * M_PI * 23.0 * 15500.0 / 60.0;
  GearPairModel mid(p_mid);
  const auto    losing = find_periodic_orbit(mid, single.state, shooting(1e-12, 1e-17));
  ASSERT_TRUE(losing.converged) << losing.failure;
  const auto other = find_periodic_orbit(mid, contact_loss_start(mid), settings);
  ASSERT_TRUE(other.converged) << other.failure;
  const auto run = run_settings(IntegratorKind::radau_iia, 1e-12, 1e-17, 1, 0, 100);
  const auto a = analyse_orbit(mid, losing, run), b = analyse_orbit(mid, other, run);
  std::printf("contact-loss orbit: RMS %.6e, loss %.3f, |mu| %.4f; other: RMS %.6e, loss %.3f, "
              "|mu| %.4f\n",
              a.rms_dte_m, a.contact_loss_fraction, losing.largest_multiplier_modulus, b.rms_dte_m,
              b.contact_loss_fraction, other.largest_multiplier_modulus);
  EXPECT_TRUE(losing.stable);
  EXPECT_GT(a.contact_loss_fraction, 0.0);
  EXPECT_TRUE(other.stable);
  EXPECT_EQ(b.contact_loss_fraction, 0.0);
  EXPECT_GT(std::abs(other.state[1] - losing.state[1]), 0.1 * scale[1]);
  std::vector<double> x = other.state;
  IntegratorSettings  is = settings.integrator;
  make_integrator(is)->integrate(mid, 0.0, x, mid.mesh_period(), 1, [](double, const double *) {});
  for (unsigned i = 0; i < model.n_states(); ++i)
    EXPECT_NEAR(x[i], other.state[i], 1e-9 * scale[i]);
}

TEST(PeriodicOrbit, ReportsWhyItFoundNone)
{
  // Two Newton iterations from a guess 50 um off cannot reach 1e-11: not converged, with the
  // reason, and no exception.
  const auto    p = contact_loss_pair();
  GearPairModel model(p);
  auto          settings  = shooting(1e-10, 1e-16);
  settings.max_iterations = 2;
  auto guess              = contact_loss_start(model);
  guess[0] += 50e-6;
  const auto orbit = find_periodic_orbit(model, guess, settings);
  EXPECT_FALSE(orbit.converged);
  EXPECT_NE(orbit.failure.find("did not converge in 2 iterations"), std::string::npos) << orbit.failure;
  settings.integrator.kind = IntegratorKind::rk4;
  EXPECT_THROW(find_periodic_orbit(model, guess, settings), hertzgear::ParameterError);
}
