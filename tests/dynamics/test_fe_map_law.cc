// Requirements on the FE force law (dynamics/fe_map_law.cc, docs/dynamics.md "The FE force law"):
// - on a ladder made from the serial law it is the serial law (one model, two implementations):
//   forces, derivatives, static compressions and the dynamics of an orbit;
// - at every rung and position it reproduces the ladder (the static equilibrium of the FE);
// - it is monotone and C3 in the compression, its derivatives are those of its forces, and
//   below the lowest rung the structure is linear and the layer continues its spline's slope
//   (clamped to n where that would soften the contact);
// - a ladder it cannot serve is refused, naming the position and load.
#include "dynamics/mesh_force_law.h"
#include "dynamics/periodic_orbit.h"

#include "common/errors.h"
#include "tests/dynamics/dynamics_fixtures.h"
#include "tests/support/serial_ladder.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

using namespace hertzgear::dynamics;
using hertzgear::dynamics::testing::PhaseAt;
using hertzgear::testing::ladder_loads;
using hertzgear::testing::serial_law_ladder;

namespace
{

  // The crowned pair's table with a varying structural stiffness and exponent n, and a ladder of
  // 16 positions from its own serial law.
  hertzgear::table::StiffnessTable serial_table(const double n)
  {
    auto t           = hertzgear::dynamics::testing::paper_crowned().stiffness;
    t.hertz_exponent = n;
    t.k_rest_N_per_m = {2.79e8, {3.0e7, 1.0e7}, {0.4, 1.1}};
    return t;
  }
  const double F0 = hertzgear::dynamics::testing::paper_crowned().static_force_N;

  // A ladder that no power law makes: the structural part stiffens with the load (u grows like
  // F^0.85 about F_0) and the Hertzian part's exponent drifts (delta ~ F^(1/n) (F/F_0)^0.05).
  hertzgear::table::StiffnessTable nonlinear_table()
  {
    auto t   = serial_table(1.5);
    t.ladder = serial_law_ladder(t, ladder_loads(F0), 16, F0);
    for (std::size_t j = 0; j < t.ladder.n_rungs(); ++j)
      for (std::size_t s = 0; s < t.ladder.n_positions(); ++s)
        {
          const double r  = t.ladder.load_N[j] / F0;
          const double ah = t.ladder.hertz_approach_m[j][s] * std::pow(r, 0.05);
          const double u  = (t.ladder.approach_m[j][s] - t.ladder.hertz_approach_m[j][s]) *
                           std::pow(r, -0.15);
          t.ladder.hertz_approach_m[j][s] = ah;
          t.ladder.approach_m[j][s]       = u + ah;
        }
    return t;
  }

  double rel(const double a, const double b) { return std::abs(a - b) / std::abs(b); }
} // namespace

// Requirement: on the serial law's own ladder the FE law gives the serial law's forces, their
// derivatives in the compressions and in time, the damping weight, the static compressions, the
// quasi-static penetration and the energies, at phases between the positions and at
// compressions below, inside and above the ladder. The trigonometric interpolant of 16 positions
// is exact for series of up to 7 harmonics, and the quintic spline is exact on the straight lines
// of a power law in (log a, log F): the two agree to the rounding of log, exp and the Fourier
// sums, some 1e-15 relative; 1e-11 leaves room for the 1e3 range of the compressions. The
// energies use a 5-point Gauss rule on the rung intervals, exact here to 1e-12.
TEST(FeMapLaw, OnTheSerialLawsOwnLadderItIsTheSerialLaw)
{
  for (const double n : {1.0, 1.5})
    {
      auto t     = serial_table(n);
      t.ladder   = serial_law_ladder(t, ladder_loads(F0), 16, F0);
      const auto serial = serial_hertz_law(t), fe = fe_map_law(t, true, true);
      ASSERT_EQ(fe->varies_with_phase(), true);
      double us, ds, uf, df;
      serial->static_compressions(F0, us, ds);
      fe->static_compressions(F0, uf, df);
      EXPECT_LT(rel(uf, us), 1e-11);
      EXPECT_LT(rel(df, ds), 1e-11);
      for (const double theta : {0.0, 0.37, 2.9, 5.5})
        {
          const PhaseAt a(*serial, theta), b(*fe, theta);
          for (const double load_factor : {0.002, 0.03, 0.7, 1.0, 2.3, 6.0})
            {
              double u = 0, d = 0;
              serial->static_compressions(load_factor * F0, u, d);
              for (const double sign : {1.0, -1.0})
                {
                  MeshLawForces s, f;
                  serial->evaluate(a.phase, sign * u, sign * 1.3 * d, s);
                  fe->evaluate(b.phase, sign * u, sign * 1.3 * d, f);
                  const double tol = 1e-11;
                  EXPECT_LT(rel(f.structural, s.structural), tol) << n << ' ' << theta << ' ' << load_factor;
                  EXPECT_LT(rel(f.structural_du, s.structural_du), tol);
                  EXPECT_NEAR(f.structural_dt, s.structural_dt, tol * std::abs(s.structural));
                  EXPECT_LT(rel(f.hertz, s.hertz), tol) << n << ' ' << theta << ' ' << load_factor;
                  EXPECT_LT(rel(f.hertz_ddelta, s.hertz_ddelta), tol);
                  EXPECT_NEAR(f.hertz_dt, s.hertz_dt, tol * std::abs(s.hertz));
                  EXPECT_EQ(f.damping_weight, s.damping_weight);
                  EXPECT_EQ(f.damping_weight_slope, s.damping_weight_slope);
                }
              const double f_total = u + d;
              EXPECT_LT(rel(fe->quasi_static_penetration(b.phase, f_total),
                            serial->quasi_static_penetration(a.phase, f_total)),
                        1e-11);
              const auto es = serial->elastic_energy(a.phase, u, d), ef = fe->elastic_energy(b.phase, u, d);
              EXPECT_LT(rel(ef.structural, es.structural), 1e-11);
              EXPECT_LT(rel(ef.hertz, es.hertz), 1e-11);
            }
        }
    }
}

// Requirement (static consistency): at every rung j and position s the law carries the rung's load
// F_j in both members at the ladder's own compressions, and the quasi-static split of the
// ladder's approach a_js is its Hertzian part. Interpolation nodes are met to rounding: 1e-12.
TEST(FeMapLaw, ReproducesTheLadderAtEveryRungAndPosition)
{
  const auto  t   = nonlinear_table();
  const auto  law = fe_map_law(t, true, true);
  const auto &l   = t.ladder;
  for (std::size_t s = 0; s < l.n_positions(); ++s)
    {
      const PhaseAt at(*law, 2.0 * M_PI * double(s) / l.n_positions());
      for (std::size_t j = 0; j < l.n_rungs(); ++j)
        {
          const double a = l.approach_m[j][s], ah = l.hertz_approach_m[j][s];
          MeshLawForces f;
          law->evaluate(at.phase, a - ah, ah, f);
          EXPECT_LT(rel(f.structural, l.load_N[j]), 1e-12) << "position " << s << " rung " << j;
          EXPECT_LT(rel(f.hertz, l.load_N[j]), 1e-12) << "position " << s << " rung " << j;
          EXPECT_LT(rel(law->quasi_static_penetration(at.phase, a), ah), 1e-12);
        }
    }
}

// Requirement: the law's derivatives in the compressions and in time are those of its forces
// (central differences, as for the serial law: step 1e-4 relative, truncation ~1e-8, 1e-6
// bounds it), inside the ladder, below and above it; and it is C3 across every rung (C4 across
// the inner ones, which this does not resolve), except the structural member at its lowest rung,
// below which it is linear (C2 there), so that an integrator's error estimate does not see the
// rungs. Value and slope on either side of a rung (1e-9 of the compression away) agree to 1e-6
// relative (the slope's change over that step is ~1e-9 of it; a kink would differ by the
// secants' ratio); so do the one-sided differences of the slope, (dF/da(a (1 + 2e)) -
// dF/da(a (1 + e))) / (a e) and its mirror, e = 1e-6: they are apart by the truncation
// ~3 e a F'''/F'' (at most 1.0e-4 of F'' here) and by rounding ~1e-9, which 1e-3 bounds, while the
// jump of the curvature at a rung of a C1 cubic (the monotone Hermite one) fails 66 of these
// checks on this ladder, by up to 1.8 F''. The one-sided second differences of the slope
// (F''', step E = 3e-5) are apart by their truncation ~4 E a F''''/F''' (at most 2.7e-3 here) and
// by rounding ~1e-6, which 1e-2 bounds, while the C2 cubic spline through the same rungs fails
// 21 of these 69 checks, by up to 1.7 F'''.
TEST(FeMapLaw, DerivativesAreThoseOfTheForcesAndTheLawIsC3AcrossRungs)
{
  const auto t   = nonlinear_table();
  const auto law = fe_map_law(t, true, true);
  for (const double theta : {0.2, 1.7, 4.4})
    {
      const PhaseAt at(*law, theta), plus(*law, theta + 1e-4), minus(*law, theta - 1e-4);
      double        u0 = 0, d0 = 0;
      law->static_compressions(F0, u0, d0);
      for (const double factor : {0.01, 0.3, 0.77, 1.0, 1.9, 3.3, 5.0, 9.0})
        {
          const double u = factor * u0, d = factor * d0;
          MeshLawForces f, up, um, tp, tm;
          const double  hu = 1e-4 * u, hd = 1e-4 * d;
          law->evaluate(at.phase, u, d, f);
          law->evaluate(at.phase, u + hu, d + hd, up);
          law->evaluate(at.phase, u - hu, d - hd, um);
          law->evaluate(plus.phase, u, d, tp);
          law->evaluate(minus.phase, u, d, tm);
          EXPECT_LT(rel((up.structural - um.structural) / (2 * hu), f.structural_du), 1e-6) << factor;
          EXPECT_LT(rel((up.hertz - um.hertz) / (2 * hd), f.hertz_ddelta), 1e-6) << factor;
          EXPECT_NEAR((tp.structural - tm.structural) / 2e-4, f.structural_dt, 1e-6 * f.structural);
          EXPECT_NEAR((tp.hertz - tm.hertz) / 2e-4, f.hertz_dt, 1e-6 * f.hertz);
        }
      // Across each rung: the compressions that carry the rung's load at this phase (bisection
      // on the monotone forces).
      for (const double F : t.ladder.load_N)
        {
          const auto carrying = [&](const bool hertz) {
            double lo = 0.0, hi = 1e-3;
            for (int it = 0; it < 200; ++it)
              {
                MeshLawForces m;
                const double  mid = 0.5 * (lo + hi);
                law->evaluate(at.phase, hertz ? 0.0 : mid, hertz ? mid : 0.0, m);
                ((hertz ? m.hertz : m.structural) < F ? lo : hi) = mid;
              }
            return 0.5 * (lo + hi);
          };
          const double u = carrying(false), d = carrying(true);
          MeshLawForces below, above;
          law->evaluate(at.phase, u * (1 - 1e-9), d * (1 - 1e-9), below);
          law->evaluate(at.phase, u * (1 + 1e-9), d * (1 + 1e-9), above);
          EXPECT_LT(rel(above.structural_du, below.structural_du), 1e-6) << F;
          EXPECT_LT(rel(above.hertz_ddelta, below.hertz_ddelta), 1e-6) << F;
          EXPECT_LT(rel(above.structural, below.structural), 1e-8) << F;
          const bool lowest = F == t.ladder.load_N.front();
          const auto slopes = [&](const double f) {
            MeshLawForces m;
            law->evaluate(at.phase, u * f, d * f, m);
            return std::array<double, 2>{m.structural_du, m.hertz_ddelta};
          };
          constexpr double e  = 1e-6;
          const auto       s2 = slopes(1 + 2 * e), s1 = slopes(1 + e);
          const auto       s_1 = slopes(1 - e), s_2 = slopes(1 - 2 * e);
          for (int i = 0; i < 2; ++i)
            {
              const double a               = i == 0 ? u : d;
              const double above_curvature = (s2[i] - s1[i]) / (a * e);
              const double below_curvature = (s_1[i] - s_2[i]) / (a * e);
              if (lowest && i == 0)
                {
                  // The structure is linear below its lowest rung and its spline's curvature is
                  // zero there: F'' = 0 on both sides, to the differences' truncation ~1.5 e a
                  // F''' (measured 3e-6 of F'/a) and rounding, which 1e-4 of F'/a bounds.
                  const double scale = s1[i] / a;
                  EXPECT_LT(std::abs(above_curvature), 1e-4 * scale) << "structural at " << F << " N";
                  EXPECT_LT(std::abs(below_curvature), 1e-4 * scale) << "structural at " << F << " N";
                  continue;
                }
              EXPECT_LT(rel(above_curvature, below_curvature), 1e-3)
                << (i == 0 ? "structural" : "Hertzian") << " at " << F << " N: " << above_curvature
                << " against " << below_curvature;
            }
          // C3: the second differences of the slope on either side, (s(1 + 3E) - 2 s(1 + 2E) +
          // s(1 + E)) / (a E)^2 and its mirror, E = 3e-5 (at the lowest rung the Hertzian member
          // only: the structural one continues linearly below it, C2).
          constexpr double E  = 3e-5;
          const auto       t3 = slopes(1 + 3 * E), t2 = slopes(1 + 2 * E), t1 = slopes(1 + E);
          const auto       b1 = slopes(1 - E), b2 = slopes(1 - 2 * E), b3 = slopes(1 - 3 * E);
          for (int i = lowest ? 1 : 0; i < 2; ++i)
            {
              const double a     = i == 0 ? u : d;
              const double above = (t3[i] - 2 * t2[i] + t1[i]) / (a * E * a * E);
              const double below = (b1[i] - 2 * b2[i] + b3[i]) / (a * E * a * E);
              EXPECT_LT(rel(above, below), 1e-2)
                << (i == 0 ? "structural" : "Hertzian") << " at " << F << " N: F''' " << above
                << " against " << below;
            }
        }
    }
}

// Requirement: the force grows strictly with the compression everywhere (a monotone law: one
// static state per load), on 4000 compressions from far below the ladder to far above it.
TEST(FeMapLaw, ForceGrowsStrictlyWithTheCompression)
{
  const auto t   = nonlinear_table();
  const auto law = fe_map_law(t, true, true);
  double     u0 = 0, d0 = 0;
  law->static_compressions(F0, u0, d0);
  for (const double theta : {0.0, 0.9, 3.0, 5.9})
    {
      const PhaseAt at(*law, theta);
      double        last_r = 0, last_h = 0;
      for (int i = 0; i < 4000; ++i)
        {
          const double  factor = std::pow(10.0, -3.0 + 4.0 * i / 3999.0);
          MeshLawForces f;
          law->evaluate(at.phase, factor * u0, factor * d0, f);
          EXPECT_GT(f.structural, last_r);
          EXPECT_GT(f.hertz, last_h);
          EXPECT_GT(f.structural_du, 0.0);
          EXPECT_GT(f.hertz_ddelta, 0.0);
          last_r = f.structural;
          last_h = f.hertz;
        }
    }
}

// Requirement: below the lowest rung the structure is linear down to first touch, F(a / 2) /
// F(a) = 1/2, and the Hertzian layer continues as the power law of its spline's slope at the
// lowest rung (natural end): F(a / 2) / F(a) = 2^-m0 with m0 the slope d log F / d log a just
// above the rung (one-sided difference over 1e-7 in log a: truncation ~1e-7 m0'' ~ 1e-9, rounding
// ~1e-16 / 1e-7; 1e-7 bounds both); here m0 = 1/(1/1.5 + 0.05) = 1.395, not n = 1.5: the
// ladder's Hertzian part is the power law F^(1/1.5 + 0.05) (nonlinear_table), on which the natural
// spline is exact (1e-6 leaves room for the difference's truncation and rounding). A ladder whose natural slope would fall below 1 (a
// softening contact, F^(1/0.9) here) has its end clamped to n: 2^-1.5 to rounding (1e-12).
// Above the top the law is the power law of the spline's end slope and says where its data end.
TEST(FeMapLaw, BelowTheLowestRungTheStructureIsLinearAndTheLayerContinuesItsSpline)
{
  const auto    t   = nonlinear_table();
  const auto    law = fe_map_law(t, true, true);
  const PhaseAt at(*law, 1.1);
  double        u0 = 0, d0 = 0;
  law->static_compressions(0.01 * F0, u0, d0); // below the 2 % rung
  MeshLawForces f, g;
  law->evaluate(at.phase, u0, d0, f);
  law->evaluate(at.phase, 0.5 * u0, 0.5 * d0, g);
  EXPECT_NEAR(g.structural / f.structural, 0.5, 1e-12);
  // The Hertzian compression of the lowest rung at this phase (bisection on the monotone force).
  const double F_low = t.ladder.load_N.front();
  double       lo = 0.0, hi = 1e-3;
  for (int it = 0; it < 200; ++it)
    {
      MeshLawForces m;
      law->evaluate(at.phase, 0.0, 0.5 * (lo + hi), m);
      (m.hertz < F_low ? lo : hi) = 0.5 * (lo + hi);
    }
  MeshLawForces r0, r1;
  law->evaluate(at.phase, 0.0, hi, r0);
  law->evaluate(at.phase, 0.0, hi * std::exp(1e-7), r1);
  const double m0 = std::log(r1.hertz / r0.hertz) / 1e-7;
  EXPECT_NEAR(m0, 1.0 / (1.0 / 1.5 + 0.05), 1e-6); // the ladder's own exponent (a power law)
  EXPECT_NEAR(std::log(g.hertz / f.hertz) / std::log(0.5), m0, 1e-7);
  EXPECT_EQ(law->tabulated_force_limit(), t.ladder.load_N.back());
  EXPECT_TRUE(std::isinf(serial_hertz_law(t)->tabulated_force_limit()));

  auto soft = serial_table(1.5);
  soft.ladder = serial_law_ladder(soft, ladder_loads(F0), 16, F0);
  for (std::size_t j = 0; j < soft.ladder.n_rungs(); ++j)
    for (std::size_t s = 0; s < soft.ladder.n_positions(); ++s)
      {
        const double u = soft.ladder.approach_m[j][s] - soft.ladder.hertz_approach_m[j][s];
        soft.ladder.hertz_approach_m[j][s] =
          soft.ladder.hertz_approach_m[j][s] * std::pow(soft.ladder.load_N[j] / F0, 1.0 / 0.9 - 1.0 / 1.5);
        soft.ladder.approach_m[j][s] = u + soft.ladder.hertz_approach_m[j][s];
      }
  const auto    clamped = fe_map_law(soft, true, true);
  const PhaseAt sat(*clamped, 1.1);
  clamped->static_compressions(0.01 * F0, u0, d0);
  clamped->evaluate(sat.phase, u0, d0, f);
  clamped->evaluate(sat.phase, 0.5 * u0, 0.5 * d0, g);
  EXPECT_NEAR(g.hertz / f.hertz, std::pow(0.5, 1.5), 1e-12);
}

// Requirement (bad input): a table without a ladder, a ladder that does not grow with the load
// (named by position and load), one whose interpolated force would not grow with the compression
// between two rungs (named by the rungs' loads), one that stops below the nominal load or has one
// rung, and the FE law without the Hertzian layer are refused with InputError saying so.
TEST(FeMapLaw, RefusesALadderItCannotServe)
{
  const auto message = [](const hertzgear::table::StiffnessTable &t) -> std::string {
    try
      {
        t.check();
        fe_map_law(t, true, true);
      }
    catch (const hertzgear::InputError &e)
      {
        return e.what();
      }
    return "";
  };
  auto none = serial_table(1.5);
  EXPECT_NE(message(none).find("load ladder"), std::string::npos) << message(none);

  auto shrinking = nonlinear_table();
  // Below the approach of the rung before, above its own Hertzian part.
  shrinking.ladder.approach_m[5][3] =
    0.5 * (shrinking.ladder.approach_m[4][3] + shrinking.ladder.hertz_approach_m[5][3]);
  const std::string m1 = message(shrinking);
  EXPECT_NE(m1.find("position 3"), std::string::npos) << m1;
  EXPECT_NE(m1.find(" N"), std::string::npos) << m1;
  EXPECT_NE(m1.find("does not grow"), std::string::npos) << m1;

  // The Hertzian approach at 140 % of F_0 a thousandth above that at 100 %: the stiffness jumps
  // by a factor ~300 between two rungs and the spline through them overshoots.
  auto jump = nonlinear_table();
  for (std::size_t s = 0; s < jump.ladder.n_positions(); ++s)
    {
      const double before = jump.ladder.hertz_approach_m[8][s];
      jump.ladder.hertz_approach_m[8][s] = 1.001 * jump.ladder.hertz_approach_m[7][s];
      jump.ladder.approach_m[8][s] += jump.ladder.hertz_approach_m[8][s] - before;
    }
  const std::string m2 = message(jump);
  EXPECT_NE(m2.find("Hertzian force"), std::string::npos) << m2;
  EXPECT_NE(m2.find("does not grow with the compression"), std::string::npos) << m2;
  EXPECT_NE(m2.find(" N and "), std::string::npos) << m2;

  auto low = nonlinear_table();
  low.ladder.nominal_load_N = 10.0 * low.ladder.load_N.back();
  EXPECT_NE(message(low).find("does not reach the nominal load"), std::string::npos) << message(low);

  auto one = nonlinear_table();
  one.ladder.load_N.resize(1);
  one.ladder.approach_m.resize(1);
  one.ladder.hertz_approach_m.resize(1);
  EXPECT_NE(message(one).find("at least 2 loads"), std::string::npos) << message(one);

  auto p      = hertzgear::dynamics::testing::paper_crowned();
  p.stiffness = nonlinear_table();
  p.effects.mesh_force_law = MeshForceLawKind::fe_map;
  p.effects.hertzian_layer = HertzianLayer::off;
  try
    {
      GearPairModel model(p);
      ADD_FAILURE() << "the FE law without a Hertzian layer was accepted";
    }
  catch (const hertzgear::InputError &e)
    {
      EXPECT_NE(std::string(e.what()).find("hertzian_layer"), std::string::npos) << e.what();
    }
}

// Requirement (one model, two implementations): the dynamics on the serial law's own ladder equal
// those of the serial law: the periodic orbit with contact loss of the crowned FE table at 16 000
// rpm (shooting at rtol 1e-12, Newton to 1e-11), its RMS DTE, dynamic factor and largest
// multiplier within 1e-6 relative. The forces agree to ~1e-14; the orbits then agree to the
// shooting tolerances, far inside 1e-6.
TEST(FeMapLaw, DynamicsOnTheSerialLawsLadderAreThoseOfTheSerialLaw)
{
  auto p = hertzgear::dynamics::testing::contact_loss_pair();
  p.stiffness.ladder = serial_law_ladder(p.stiffness, ladder_loads(p.static_force_N), 16,
                                         p.static_force_N);
  ShootingSettings shooting;
  shooting.integrator.kind               = IntegratorKind::radau_iia;
  shooting.integrator.relative_tolerance = 1e-12;
  shooting.integrator.absolute_tolerance = 1e-17;
  shooting.tolerance                     = 1e-11;
  const auto run = hertzgear::dynamics::testing::run_settings(IntegratorKind::radau_iia, 1e-12,
                                                              1e-17, 1, 0, 100);
  SteadyStateSummary summary[2];
  double             multiplier[2];
  for (const auto kind : {MeshForceLawKind::serial_hertz, MeshForceLawKind::fe_map})
    {
      p.effects.mesh_force_law = kind;
      GearPairModel model(p);
      const auto    orbit =
        find_periodic_orbit(model, hertzgear::dynamics::testing::contact_loss_start(model), shooting);
      ASSERT_TRUE(orbit.converged) << orbit.failure;
      const int i   = kind == MeshForceLawKind::fe_map;
      summary[i]    = analyse_orbit(model, orbit, run);
      multiplier[i] = orbit.largest_multiplier_modulus;
    }
  std::printf("serial: RMS %.12e DF %.12e |mu| %.12e\nfe-map: RMS %.12e DF %.12e |mu| %.12e\n",
              summary[0].rms_dte_m, summary[0].dynamic_factor, multiplier[0], summary[1].rms_dte_m,
              summary[1].dynamic_factor, multiplier[1]);
  EXPECT_GT(summary[0].contact_loss_fraction, 0.0);
  EXPECT_LT(rel(summary[1].rms_dte_m, summary[0].rms_dte_m), 1e-6);
  EXPECT_LT(rel(summary[1].dynamic_factor, summary[0].dynamic_factor), 1e-6);
  EXPECT_LT(rel(multiplier[1], multiplier[0]), 1e-6);
}
