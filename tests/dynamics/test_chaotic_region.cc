// Requirement (periodic orbits, hard cases): in a chaotic region shooting and continuation never
// give a silent wrong branch. An unstable period-1 orbit usually still exists there, so shooting
// may converge to it: that is correct only when the orbit really is periodic and is reported
// unstable, consistent with time marching never settling. Otherwise it fails with its reason; a
// continuation branch is made of true orbits with their correct stability, or ends with a reason.
//
// The case: the Kahraman-Singh backlash oscillator (dynamics_fixtures.h) at zeta = 0.05,
// F_m = 0.1 and a large alternating force F_a = 0.2 (F_a / F_m = 2), Omega = 0.85 of the natural
// frequency, where the teeth lose contact and impact irregularly.
#include "dynamics/analysis.h"
#include "dynamics/continuation.h"
#include "dynamics/gear_pair_model.h"
#include "dynamics/periodic_orbit.h"

#include "tests/dynamics/dynamics_fixtures.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace hertzgear::dynamics;
using namespace hertzgear::dynamics::testing;

namespace
{
  constexpr double zeta = 0.05, F_m = 0.1, F_a = 0.2, omega_chaos = 0.85;

  GearPairParameters oscillator(const double omega)
  {
    return kahraman_singh_oscillator(omega, zeta, F_m, F_a);
  }

  // Shooting as in the Kahraman-Singh continuation (test_kahraman_singh.cc): Radau IIA at rtol
  // 1e-10, Newton to 1e-6 of the state scale (the period map of this oscillator, whose damping
  // jumps at every contact switch, is smooth to about 1e-9 there).
  ShootingSettings shooting()
  {
    ShootingSettings s;
    s.integrator.kind               = IntegratorKind::radau_iia;
    s.integrator.relative_tolerance = 1e-10;
    s.integrator.absolute_tolerance = 1e-13;
    s.tolerance                     = 1e-6;
    return s;
  }

  double scaled_distance(const std::vector<double> &a, const std::vector<double> &b,
                         const std::vector<double> &scale)
  {
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
      d = std::max(d, std::abs(a[i] - b[i]) / scale[i]);
    return d;
  }

  // The state `periods` forcing periods after x at t = 0, by a plain time-marched run of another
  // integrator than the shooting's (cvode-bdf at rtol 1e-12): independent of the shooting code.
  std::vector<double> marched(const GearPairParameters &p, const std::vector<double> &x,
                              const int periods)
  {
    GearPairModel model(p);
    return simulate(model, run_settings(IntegratorKind::cvode_bdf, 1e-12, 1e-15, periods, 0, 4), x)
      .final_state;
  }

  // The period map at x and its Jacobian by central differences of marched runs (steps of 1e-6
  // of the state scale: the map is piecewise linear between its switching events, so the
  // differences are exact but for the rounding of the runs, 1e-12 / 1e-6 relative), scaled by
  // the state scale, with the largest modulus of its eigenvalues.
  struct IndependentPeriodMap
  {
    std::vector<double> image;
    Eigen::Matrix2d     M;
    double              largest_multiplier = 0.0;
  };
  IndependentPeriodMap independent_period_map(const GearPairParameters &p,
                                              const std::vector<double>  &x)
  {
    const auto           scale = GearPairModel(p).state_scales();
    IndependentPeriodMap map;
    map.image = marched(p, x, 1);
    for (int j = 0; j < 2; ++j)
      {
        const double h = 1e-6 * scale[j];
        auto         plus = x, minus = x;
        plus[j] += h;
        minus[j] -= h;
        const auto yp = marched(p, plus, 1), ym = marched(p, minus, 1);
        for (int i = 0; i < 2; ++i)
          map.M(i, j) = (yp[i] - ym[i]) / (2 * h) * scale[j] / scale[i];
      }
    map.largest_multiplier = map.M.eigenvalues().cwiseAbs().maxCoeff();
    return map;
  }

  // The largest Lyapunov exponent per forcing period by Benettin's method: a neighbour at scaled
  // distance d0 follows the run from x0 (after `transient` periods); after every period the
  // log of its scaled distance over d0 is summed and the neighbour is pulled back to d0 along the
  // separation. Both with radau-iia at `rtol`. The Poincare section of the run is returned too.
  double largest_lyapunov_exponent(const GearPairParameters &p, std::vector<double> y,
                                   const int transient, const int periods, const double rtol,
                                   const double d0, std::vector<PoincarePoint> &section)
  {
    GearPairModel      a(p), b(p);
    IntegratorSettings set;
    set.kind               = IntegratorKind::radau_iia;
    set.relative_tolerance = rtol;
    set.absolute_tolerance = 1e-3 * rtol;
    auto         ia = make_integrator(set), ib = make_integrator(set);
    const double T     = a.mesh_period();
    const auto   scale = a.state_scales();
    ia->integrate(a, 0.0, y, T, transient, {});
    auto z = y;
    z[0] += d0 * scale[0];
    double sum = 0.0;
    section.clear();
    for (int j = 0; j < periods; ++j)
      {
        const double t0 = (transient + j) * T;
        ia->integrate(a, t0, y, T, 1, {});
        ib->integrate(b, t0, z, T, 1, {});
        section.push_back({t0 + T, y[0], y[1]});
        double d = 0.0;
        for (std::size_t i = 0; i < y.size(); ++i)
          d += std::pow((z[i] - y[i]) / scale[i], 2);
        d = std::sqrt(d);
        sum += std::log(d / d0);
        for (std::size_t i = 0; i < y.size(); ++i)
          z[i] = y[i] + (z[i] - y[i]) * d0 / d;
      }
    return sum / periods;
  }

  // The period status of the run from the static equilibrium over `periods` periods at rtol.
  PeriodDetection marched_period(const double omega, const double rtol, const int periods)
  {
    GearPairModel model(oscillator(omega));
    const auto    r = simulate(model, run_settings(IntegratorKind::radau_iia, rtol, 1e-3 * rtol,
                                                   periods, periods - 40, 4),
                               model.static_equilibrium_state());
    const auto    scale = model.state_scales();
    return detect_period(r.poincare, scale[0], scale[1], period_settle_tolerance(rtol));
  }

  // Checks the orbit x of `p` reported with largest multiplier modulus `mu_max` and stability
  // `stable` against marched runs, independently of the shooting code:
  // - periodic: one marched period returns to x within ||M - I|| tolerance (the Newton iterate
  //   is within the last correction, below `tolerance`, of the orbit, and the residual grows from
  //   there at most by the scaled period map's M - I), plus 1e-8 for the marched run's own error
  //   (rtol 1e-12 amplified by |mu| ~ 3 over one period);
  // - its multipliers: the largest modulus of the differenced period map equals the reported
  //   one within 1e-3 relative (the difference quotients are exact to ~1e-6);
  // - its stability: marching from x + 1e-3 of the scale (radau-iia at rtol 1e-10), the
  //   distance to x grows at least tenfold, beyond 1e-2 of the scale (unstable: within the
  //   ln(100) / ln |mu|max periods that growth by 100 at |mu|max per period takes, plus 30 for
  //   the offset to align with the unstable direction; checked when that is at most 1000
  //   periods), or is below 1e-3 after `periods` (stable). A stable orbit cannot let the offset
  //   grow tenfold. Growth to 0.1 of the scale is not implied by |mu|max > 1: just past a
  //   bifurcation the attractor born there lies within O(sqrt(|mu|max - 1)) of the orbit (at
  //   Omega = 0.812, |mu|max 1.037, marching saturates at 0.08 of the scale).
  void expect_true_orbit(const GearPairParameters &p, const std::vector<double> &x,
                         const double mu_max, const bool stable, const double tolerance,
                         const int periods, const std::string &where)
  {
    const auto   scale    = GearPairModel(p).state_scales();
    const auto   map      = independent_period_map(p, x);
    const double residual = scaled_distance(map.image, x, scale);
    const double M_minus_I =
      (map.M - Eigen::Matrix2d::Identity()).cwiseAbs().rowwise().sum().maxCoeff();
    const double bound = M_minus_I * tolerance + 1e-8;
    EXPECT_LT(residual, bound) << where;
    EXPECT_NEAR(map.largest_multiplier, mu_max, 1e-3 * mu_max) << where;
    EXPECT_EQ(stable, mu_max < 1.0) << where;
    auto y = x;
    y[0] += 1e-3 * scale[0];
    GearPairModel model(p);
    // The forcing is T-periodic: the Poincare points at t = jT are the period map's iterates.
    const double departure =
      mu_max > 1.0 ? std::ceil(std::log(100.0) / std::log(mu_max)) + 30 : 1e300;
    const bool check_departure = !stable && departure <= 1000;
    const int  marched_periods = stable ? periods : int(std::min(departure, 1000.0));
    const auto run             = simulate(
      model, run_settings(IntegratorKind::radau_iia, 1e-10, 1e-13, marched_periods, 0, 4), y);
    double farthest = 0.0, last = 0.0;
    for (const auto &q : run.poincare)
      {
        last     = scaled_distance({q.dte_m, q.dte_rate_m_per_s}, x, scale);
        farthest = std::max(farthest, last);
      }
    std::printf("%s: |mu|max %.5f (marched differences %.5f), %s; residual %.2e (bound %.2e); "
                "distance from 1e-3 after marching: %.3g\n",
                where.c_str(), mu_max, map.largest_multiplier, stable ? "stable" : "unstable",
                residual, bound, stable ? last : farthest);
    if (stable)
      {
        EXPECT_LT(last, 1e-3) << where << ": reported stable, but marching does not return";
      }
    else if (check_departure)
      {
        EXPECT_GT(farthest, 1e-2) << where << ": reported unstable, but marching stays near it";
      }
  }
} // namespace

// Requirement: the case is chaotic. A run of 1000 periods (after 400) from the static
// equilibrium is "aperiodic" (no k <= 8 contracts) at rtol 1e-10 and 1e-11, and its largest
// Lyapunov exponent (Benettin, d0 = 1e-6 of the scale: well above the integration error of
// rtol, well inside the linear range) is positive, the same at both tolerances within 0.05 per
// period (measured 0.524 and 0.527; the estimate from 1000 renormalisations fluctuates by a
// few 1e-2). The estimator itself is checked on a stable period-1 motion (Omega = 0.6): there it
// equals ln |mu|max of the orbit, within 0.01 (the separation's initial alignment with the
// leading direction enters the mean over 400 periods as O(1) / 400; measured -0.3484 against
// ln 0.7094 = -0.3434).
TEST(ChaoticRegion, KahramanSinghOscillatorIsChaotic)
{
  GearPairModel model(oscillator(omega_chaos));
  const auto    scale = model.state_scales();
  double        exponents[2];
  int           i = 0;
  for (const double rtol : {1e-10, 1e-11})
    {
      std::vector<PoincarePoint> section;
      exponents[i] = largest_lyapunov_exponent(oscillator(omega_chaos),
                                               model.static_equilibrium_state(), 400, 1000, rtol,
                                               1e-6, section);
      const auto d = detect_period(section, scale[0], scale[1], period_settle_tolerance(rtol));
      std::printf("Omega = %.2f, rtol %.0e: %s over %zu periods, largest Lyapunov exponent %.4f "
                  "per period\n",
                  omega_chaos, rtol, d.status.c_str(), section.size(), exponents[i]);
      EXPECT_EQ(d.status, "aperiodic");
      EXPECT_GT(exponents[i], 0.3);
      ++i;
    }
  EXPECT_NEAR(exponents[0], exponents[1], 0.05);

  // The estimator on the stable period-1 motion at Omega = 0.6.
  GearPairModel              stable_model(oscillator(0.6));
  std::vector<PoincarePoint> section;
  const double               lambda = largest_lyapunov_exponent(
    oscillator(0.6), stable_model.static_equilibrium_state(), 400, 400, 1e-11, 1e-6, section);
  const auto orbit = find_periodic_orbit(
    stable_model, {section.back().dte_m, section.back().dte_rate_m_per_s}, shooting());
  ASSERT_TRUE(orbit.converged) << orbit.failure;
  std::printf("Omega = 0.6: Lyapunov exponent %.4f, ln |mu|max %.4f\n", lambda,
              std::log(orbit.largest_multiplier_modulus));
  EXPECT_NEAR(lambda, std::log(orbit.largest_multiplier_modulus), 0.01);
}

// Requirement: shooting in the chaotic region, from the static equilibrium and from ten points
// of the chaotic motion, either fails with a non-empty reason or returns a true periodic orbit
// reported unstable (checked in expect_true_orbit against marched runs: periodicity, the
// multipliers of the differenced period map, and marching away from it: |mu|max ~ 2.6 takes a
// 1e-3 offset to 0.1 in about 5 periods). At least one start converges (measured:
// 5 of 11, all to the orbit with multipliers -2.555 and -0.295; the others fail where an iterate
// flies through the backlash for a whole period, whose period map has the double multiplier +1,
// or where Newton stops reducing the residual).
TEST(ChaoticRegion, ShootingFailsWithItsReasonOrFindsAnUnstableOrbit)
{
  const auto    p = oscillator(omega_chaos);
  GearPairModel model(p);
  const auto    r =
    simulate(model, run_settings(IntegratorKind::radau_iia, 1e-10, 1e-13, 440, 400, 4),
             model.static_equilibrium_state());
  std::vector<std::vector<double>> starts{model.static_equilibrium_state()};
  for (int j = 0; j < 40; j += 4)
    starts.push_back({r.poincare[j].dte_m, r.poincare[j].dte_rate_m_per_s});
  int converged = 0;
  for (std::size_t s = 0; s < starts.size(); ++s)
    {
      const auto orbit = find_periodic_orbit(model, starts[s], shooting());
      if (!orbit.converged)
        {
          std::printf("start %zu: no orbit: %s\n", s, orbit.failure.c_str());
          EXPECT_FALSE(orbit.failure.empty()) << "start " << s;
          continue;
        }
      ++converged;
      EXPECT_FALSE(orbit.stable) << "start " << s;
      EXPECT_GT(orbit.largest_multiplier_modulus, 1.0) << "start " << s;
      expect_true_orbit(p, orbit.state, orbit.largest_multiplier_modulus, orbit.stable,
                        shooting().tolerance, 400, "start " + std::to_string(s));
    }
  EXPECT_GE(converged, 1) << "no start exercises the checks of a converged orbit";

  // A start that flies through the backlash for the whole period (its marched period has no
  // switching event and no sample in contact) has the monodromy [[1, T], [0, 1]]: the reason
  // names the free flight, not a fold.
  const std::vector<double> flying{0.44100781, -0.34963108};
  const auto flight =
    simulate(model, run_settings(IntegratorKind::radau_iia, 1e-10, 1e-13, 1, 0, 64), flying);
  EXPECT_EQ(flight.stats.events, 0);
  for (const auto &sample : flight.steady)
    EXPECT_EQ(sample.contact, 0);
  const auto free_flight = find_periodic_orbit(model, flying, shooting());
  EXPECT_FALSE(free_flight.converged);
  EXPECT_NE(free_flight.failure.find("free flight"), std::string::npos) << free_flight.failure;
}

// Requirement: continuation across the chaotic region reports true orbits with their correct
// stability, or ends its branch with the reason; nothing reported stable where the motion is
// chaotic. Time marching from the static equilibrium is aperiodic at Omega = 0.82, 0.85 and 0.90
// (checked here at 0.82 and 0.90 over 400 periods, at 0.85 by the first test). Two branches:
// - from Omega = 0.95 down to 0.75 on the period-1 orbit with two contact switches per period,
//   unstable throughout (|mu|max 2.3 to 2.8, a real multiplier below -1);
// - from the stable period-1 motion at Omega = 0.75 (four switches per period) up into the
//   region: it stays stable to its fold at Omega = 0.8123, coexisting there with the chaotic
//   motion (marching from the static equilibrium is aperiodic at 0.80 and 0.81 too), and
//   returns unstable. Stable points inside the region are checked to attract.
// Every point within 0.82 ... 0.90 must be unstable; six points of each branch, spread over it,
// and the stable points at Omega >= 0.80 nearest 0.80, 0.806 and the fold are checked against
// marched runs (expect_true_orbit; a stable one after 400 periods: |mu|max is at most 0.998 next
// to the fold, 0.998^400 = 0.45, so the offset of 1e-3 has shrunk).
TEST(ChaoticRegion, ContinuationAcrossTheChaoticRegionGivesTrueOrbitsOrItsReason)
{
  for (const double omega : {0.82, 0.90})
    {
      const auto d = marched_period(omega, 1e-10, 400);
      std::printf("Omega = %.2f: time marching %s\n", omega, d.status.c_str());
      EXPECT_EQ(d.status, "aperiodic") << "Omega = " << omega;
    }
  ParameterFamily family{"omega", oscillator};
  for (const int direction : {-1, +1})
    {
      ContinuationSettings s;
      s.shooting     = shooting();
      s.analysis     = run_settings(IntegratorKind::radau_iia, 1e-10, 1e-13, 1, 0, 16);
      s.lambda_min   = 0.75;
      s.lambda_max   = 0.95;
      s.direction    = direction;
      s.lambda_start = direction < 0 ? s.lambda_max : s.lambda_min;
      GearPairModel start(family.at(s.lambda_start));
      const auto    guess =
        simulate(start, run_settings(IntegratorKind::radau_iia, 1e-10, 1e-13, 400, 399, 4),
                 start.static_equilibrium_state())
          .final_state;
      const auto r = continue_periodic_orbits(family, guess, s);
      for (const auto &branch : r.branches)
        {
          std::printf("branch %d (period-%d) from Omega = %.4f: %zu points, %s%s\n", branch.id,
                      branch.period_multiple, branch.start_lambda, branch.points.size(),
                      branch.end_reason.c_str(), branch.ended_in_failure ? " (failure)" : "");
          EXPECT_FALSE(branch.end_reason.empty());
          ASSERT_FALSE(branch.points.empty());
          std::vector<std::size_t> checked;
          for (int c = 0; c < 6; ++c)
            checked.push_back(c * (branch.points.size() - 1) / 5);
          for (const double target : {0.80, 0.806, 1.0})
            {
              std::size_t best = branch.points.size();
              for (std::size_t i = 0; i < branch.points.size(); ++i)
                if (branch.points[i].stable && branch.points[i].lambda >= 0.80 &&
                    (best == branch.points.size() ||
                     std::abs(branch.points[i].lambda - target) <
                       std::abs(branch.points[best].lambda - target)))
                  best = i;
              if (best < branch.points.size())
                checked.push_back(best);
            }
          for (std::size_t i = 0; i < branch.points.size(); ++i)
            {
              const auto &pt = branch.points[i];
              if (pt.lambda >= 0.82 && pt.lambda <= 0.90)
                {
                  EXPECT_FALSE(pt.stable) << "reported stable in the chaotic region at Omega = "
                                          << pt.lambda;
                }
              if (std::find(checked.begin(), checked.end(), i) == checked.end() ||
                  pt.bifurcation != Bifurcation::none)
                continue;
              const double mu_max = std::abs(pt.multipliers.front());
              expect_true_orbit(oscillator(pt.lambda), pt.state, mu_max, pt.stable,
                                s.shooting.tolerance, 400,
                                "branch " + std::to_string(branch.id) + " (from " +
                                  std::to_string(s.lambda_start) + ") at Omega = " +
                                  std::to_string(pt.lambda));
            }
        }
    }
}
