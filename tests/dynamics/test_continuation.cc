// Requirements of the continuation of periodic orbits (dynamics/continuation.h, docs/dynamics.md
// "Continuation of periodic orbits"):
// - a period doubling is detected and located with its multiplier at -1, where an independent
//   monodromy of the linear system puts it, and the period-2 branch is followed from it to the
//   period-2 motion a time-marched run settles on;
// - the branch passes folds (the Kahraman-Singh oscillator, test_kahraman_singh.cc);
// - a step that collapses ends its branch with the reason, never silently.
#include "dynamics/continuation.h"

#include "common/errors.h"
#include "tests/dynamics/dynamics_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>

using namespace hertzgear::dynamics;
using namespace hertzgear::dynamics::testing;

namespace
{
  // The parametric oscillator of test_period_detection.cc beyond its instability (first harmonic
  // 0.3), with half backlash 0.05 m and F_0 = 0.1 N. In contact (x > b_c) it is linear; inside
  // the principal parametric resonance (Omega ~ 2) its period-1 motion is unstable and the
  // backlash limits a period-2 motion.
  GearPairParameters parametric_pair(const double omega)
  {
    return parametric_oscillator(omega, 0.1, 0.3, 0.05);
  }

  // The smallest real multiplier of the linear system in contact: k(t) x everywhere, the
  // homogeneous part of the contact zone's equation without its backlash.
  double smallest_linear_multiplier(const double omega)
  {
    const auto mu = linear_period_map_multipliers(parametric_oscillator(omega, 0.1, 0.3), 1e-13, 1e-16);
    return std::min(mu.first.real(), mu.second.real());
  }

  ContinuationSettings settings_for(const double lambda_min, const double lambda_max)
  {
    ContinuationSettings s;
    s.shooting.integrator.kind               = IntegratorKind::radau_iia;
    s.shooting.integrator.relative_tolerance = 1e-11;
    s.shooting.integrator.absolute_tolerance = 1e-14;
    // The period map of this piecewise-linear system is smooth to about 5e-11 of the state scale
    // at rtol 1e-11 to 1e-12 (event location; measured: Newton stalls at corrections of 2e-11 to
    // 6e-11), so the corrector stops at 1e-9.
    s.shooting.tolerance                     = 1e-9;
    s.analysis                               = run_settings(IntegratorKind::radau_iia, 1e-11, 1e-14, 1, 0, 64);
    s.lambda_min                             = lambda_min;
    s.lambda_max                             = lambda_max;
    s.lambda_start                           = lambda_min;
    s.step_max                               = 0.02;
    return s;
  }
} // namespace

TEST(Continuation, PeriodDoublingIsLocatedAndItsBranchFollowed)
{
  ParameterFamily family{"omega_rad_per_s", parametric_pair};
  auto            s = settings_for(1.6, 2.4);
  s.max_points      = 150; // the period-2 branches reach Omega = 2 within 50 points
  GearPairModel   start(parametric_pair(1.6));
  const auto      r = continue_periodic_orbits(family, start.static_equilibrium_state(), s);
  ASSERT_GE(r.branches.size(), 2u);
  // The time-marched period-2 motion at Omega = 2: 400 periods at rtol 1e-12 from the static
  // equilibrium (the period-2 map contracts by 0.8, so the last points are settled to rounding).
  GearPairModel marched_model(parametric_pair(2.0));
  const auto    marched =
    simulate(marched_model, run_settings(IntegratorKind::radau_iia, 1e-12, 1e-15, 400, 396, 10),
             marched_model.static_equilibrium_state());
  const double p_a = marched.poincare[0].dte_m, p_b = marched.poincare[1].dte_m;
  const auto &main = r.branches[0];
  std::vector<ContinuationPoint> pds;
  for (const auto &p : main.points)
    if (p.bifurcation == Bifurcation::period_doubling)
      pds.push_back(p);
  ASSERT_GE(pds.size(), 1u) << main.end_reason;
  for (const auto &pd : pds)
    {
      // The multiplier through -1, at the located point.
      double nearest = 1e9;
      for (const auto &m : pd.multipliers)
        nearest = std::min(nearest, std::abs(m + 1.0));
      const double linear = smallest_linear_multiplier(pd.lambda);
      std::printf("period doubling at Omega = %.9f: |mu + 1| = %.2e; linear monodromy there: %.9f\n",
                  pd.lambda, nearest, linear);
      // Located to 1e-6 of a step of at most 0.02 of the range (0.8 rad/s): |dmu/dOmega| ~ 10
      // puts the multiplier within ~1e-7 of -1.
      EXPECT_LT(nearest, 1e-6);
      EXPECT_NEAR(linear, -1.0, 1e-6);
    }
  // Below the first period doubling the period-1 motion is stable, just above it unstable.
  EXPECT_TRUE(main.points.front().stable);

  // The period-2 branches: one from each period doubling. The one born at the upper period
  // doubling turns back to lower Omega and crosses Omega = 2 on the stable period-2 motion the
  // time-marched run settles on there.
  int crossings = 0;
  for (std::size_t b = 1; b < r.branches.size(); ++b)
    {
      const auto &child = r.branches[b];
      EXPECT_EQ(child.period_multiple, 2);
      EXPECT_EQ(child.parent, 0);
      std::printf("period-2 branch %zu from Omega = %.6f: %zu points, %s\n", b, child.start_lambda,
                  child.points.size(), child.end_reason.c_str());
      for (std::size_t i = 1; i < child.points.size(); ++i)
        {
          const auto &a = child.points[i - 1], &c = child.points[i];
          if ((a.lambda - 2.0) * (c.lambda - 2.0) > 0 || !c.stable)
            continue;
          GearPairModel    model(parametric_pair(2.0));
          ShootingSettings sh = s.shooting;
          sh.period_multiple  = 2;
          const auto orbit    = find_periodic_orbit(model, c.state, sh);
          ASSERT_TRUE(orbit.converged) << orbit.failure;
          const double x0 = orbit.state[0];
          const double d  = std::min(std::abs(x0 - p_a), std::abs(x0 - p_b));
          std::printf("  stable crossing of Omega = 2: x(0) = %.10f, |mu|max = %.6f; marched %.10f / "
                      "%.10f\n",
                      x0, orbit.largest_multiplier_modulus, p_a, p_b);
          // Newton stops at 1e-9 of the 0.15 m state scale: 1e-8 of the scale is the bound.
          EXPECT_LT(d, 1e-8 * model.state_scales()[0]);
          EXPECT_TRUE(orbit.stable);
          ++crossings;
        }
    }
  EXPECT_GE(crossings, 1) << "no period-2 branch reaches the period-2 motion at Omega = 2";
}

TEST(Continuation, CollapsedStepEndsTheBranchWithItsReason)
{
  // A corrector allowed too few iterations for any step: the step halves down to its minimum
  // and the branch ends with the reason, flagged as a failure.
  ParameterFamily family{"omega_rad_per_s", parametric_pair};
  auto            s      = settings_for(1.6, 2.4);
  s.corrector_iterations = 2;
  s.shooting.tolerance   = 1e-14; // unreachable in two iterations from a predicted point
  s.step_min             = 1e-3;
  s.step_initial         = 0.01;
  GearPairModel start(parametric_pair(1.6));
  const auto    r = continue_periodic_orbits(family, start.static_equilibrium_state(), s);
  ASSERT_EQ(r.branches.size(), 1u);
  EXPECT_TRUE(r.branches[0].ended_in_failure);
  EXPECT_NE(r.branches[0].end_reason.find("collapsed below its minimum"), std::string::npos)
    << r.branches[0].end_reason;
}

TEST(Continuation, NoOrbitAtTheStartIsANumericalError)
{
  ParameterFamily family{"omega_rad_per_s", parametric_pair};
  auto            s               = settings_for(1.6, 2.4);
  s.shooting.max_iterations       = 1;
  s.shooting.tolerance            = 1e-14;
  GearPairModel start(parametric_pair(1.6));
  auto          guess = start.static_equilibrium_state();
  guess[0] += 1.0;
  EXPECT_THROW(continue_periodic_orbits(family, guess, s), hertzgear::NumericalError);
}
