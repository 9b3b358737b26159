// Period-k detection from the convergence of the Poincare section (dynamics/analysis.h,
// detect_period).
#include "dynamics/analysis.h"
#include "dynamics/gear_pair_model.h"

#include "tests/dynamics/dynamics_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>

using namespace hertzgear::dynamics;
using namespace hertzgear::dynamics::testing;

namespace
{
  // The Floquet multipliers of the parametric oscillator without load offset.
  std::pair<std::complex<double>, std::complex<double>> multipliers(const double omega)
  {
    return linear_period_map_multipliers(parametric_oscillator(omega, 1.0), 1e-12, 1e-14);
  }
} // namespace

// Requirement: a slowly decaying transient is not reported as a periodic motion. The parametric
// oscillator at Omega = 2 rad/s has a Floquet multiplier of -0.998 (checked here from its
// monodromy matrix): after 300 transient periods its Poincare points still alternate about the
// period-1 motion, with 2-step differences of a few 1e-4 of the DTE scale that a test on the
// differences alone reads as period 2. The detection must say "not settled", estimate the
// contraction per period as |mu| (within 2e-3: the fit over 28 points of a sequence that
// decays as |mu|^j) and put the points farther from the limit than the settle tolerance.
TEST(PeriodDetection, NearResonantTransientIsNotSettled)
{
  const double omega = 2.0;
  const auto   mu    = multipliers(omega);
  const double mu_min = std::min(mu.first.real(), mu.second.real());
  EXPECT_NEAR(mu_min, -0.998, 5e-4) << "the case must have a multiplier near -1";
  EXPECT_NEAR(mu.first.imag(), 0.0, 1e-12);

  GearPairModel model(parametric_oscillator(omega, 1.0));
  const auto    r = simulate(model, run_settings(IntegratorKind::radau_iia, 1e-10, 1e-14, 340, 300),
                             model.state(0.0, 0.0, 0.0));
  const auto s = analyse(model, r);
  std::printf("status %s, candidate %d, contraction %.6f per period, distance %.3e of the scale\n",
              s.period_status.c_str(), s.period_candidate, s.period_contraction, s.period_distance);
  EXPECT_NE(s.period_multiplicity, 2);
  EXPECT_EQ(s.period_multiplicity, 0);
  EXPECT_EQ(s.period_status, "not settled");
  EXPECT_NEAR(s.period_contraction, std::abs(mu_min), 2e-3);
  EXPECT_GT(s.period_distance, period_settle_tolerance(1e-10));
}

// Requirement: a true period-2 motion is reported as period 2. Beyond the parametric instability
// (first harmonic 0.3 instead of 0.2, multiplier below -1), a backlash of 2 x 0.05 m limits the
// growth: the teeth lose contact and the motion settles on a period-2 cycle, whose Poincare points
// repeat every second period to rounding (measured: 0.083141035 / 0.170449714 m).
TEST(PeriodDetection, TruePeriodTwoIsPeriodTwo)
{
  GearPairModel model(parametric_oscillator(2.0, 0.1, 0.3, 0.05));
  const auto    r = simulate(model, run_settings(IntegratorKind::radau_iia, 1e-10, 1e-14, 340, 300),
                             model.static_equilibrium_state());
  const auto s = analyse(model, r);
  EXPECT_EQ(s.period_multiplicity, 2);
  EXPECT_EQ(s.period_status, "period-2");
  EXPECT_GT(s.contact_loss_fraction, 0.0) << "the backlash must limit the motion";
}

// Requirement: detect_period on sections with known answers. A period-3 sequence with rounding
// noise is period 3; a sequence approaching a fixed point as 0.9^j is not settled while
// 0.9^j is above the tolerance, with the contraction 0.9 recovered (the fit is exact up to
// rounding, 1e-9 covers it); a sequence with no trend and large differences is aperiodic.
TEST(PeriodDetection, KnownSections)
{
  const auto section = [](auto x_of) {
    std::vector<PoincarePoint> s;
    for (int j = 0; j < 40; ++j)
      s.push_back({double(j), x_of(j), 0.0});
    return s;
  };
  const double tol = 1e-7;
  const auto   p3  = detect_period(section([](int j) {
                                  return (j % 3 == 0 ? 1.0 : j % 3 == 1 ? 0.5 : 0.2) +
                                         1e-12 * std::sin(12.345 * j);
                                }),
                                1.0, 1.0, tol);
  EXPECT_EQ(p3.multiplicity, 3);
  EXPECT_EQ(p3.status, "period-3");

  const auto decaying = detect_period(section([](int j) { return 1.0 + std::pow(0.9, j); }), 1.0,
                                      1.0, tol);
  EXPECT_EQ(decaying.multiplicity, 0);
  EXPECT_EQ(decaying.status, "not settled");
  EXPECT_EQ(decaying.candidate, 1);
  EXPECT_NEAR(decaying.contraction, 0.9, 1e-9);
  // The distance of the last point (j = 39) from the limit is 0.9^39; the estimate is the tail
  // of the geometric series of the differences, exact here.
  EXPECT_NEAR(decaying.distance, std::pow(0.9, 39), 1e-9 * std::pow(0.9, 39) + 1e-15);

  const auto chaotic = detect_period(section([](int j) { return std::sin(1.0 + 7.77 * j * j); }),
                                     1.0, 1.0, tol);
  EXPECT_EQ(chaotic.multiplicity, 0);
  EXPECT_EQ(chaotic.status, "aperiodic");
}
