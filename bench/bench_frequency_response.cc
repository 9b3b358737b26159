// Benchmark of the periodic-orbit methods (docs/accuracy-dynamics.md, "Frequency response:
// shooting against time marching"): the crowned paper pair on its shipped FE table
// (data/scenes/paper_crowned_table.prm), 200 speeds from 1000 to 20000 rpm, up.
//
//   build/bench/bench_frequency_response [alternations, default 3]
//   build/bench/bench_frequency_response orbit [solves, default 50] [rpm, default 150] [law,
//     serial-hertz (default), fe-map or fe-map-serial-ladder]
//     (one orbit alone)
//   build/bench/bench_frequency_response curve [law]
//     (the 200-speed shooting curve alone on one law, for instruction counts under callgrind)
//   build/bench/bench_frequency_response laws [alternations, default 3]
//     (the serial Hertz law against the FE force law on the table's load ladder and on a ladder
//     made from the serial law itself, which moves as the serial law does: one orbit at
//     10 000 rpm, median of 20 solves, and the 200-speed shooting curve at the scene's defaults,
//     timed in alternation; medians and their ratio, and the largest difference of the RMS DTE)
//
// - Reference: the periodic orbit at every speed by shooting at rtol 1e-11, Newton to 1e-9 of the
//   state scale, each started from the orbit of the speed before (where Newton fails, past the
//   fold where the branch ends, from 400 time-marched periods: the jump an up sweep makes).
// - Shooting: the same at the scene's defaults (radau-iia rtol 1e-8, Newton 1e-6).
// - Time marching: dynamics::sweep's up chain (each speed from the last state of the one before)
//   with T transient and 5 analysed periods per speed, T = 25 ... 400, on one thread.
// Accuracy: the largest relative error of the RMS DTE against the reference over the speeds
// where the reference orbit is stable. The ratio compares shooting with the cheapest time-marching
// rung at least as accurate, timed in alternation (medians). Then one orbit at 150 rpm: median of
// 50 solves from the static equilibrium.
#include "dynamics/periodic_orbit.h"
#include "dynamics/sweep.h"

#include "tests/dynamics/dynamics_fixtures.h"
#include "tests/support/serial_ladder.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace hertzgear::dynamics;

namespace
{
  constexpr int    n_speeds = 200;
  constexpr double rpm_min = 1000.0, rpm_max = 20000.0, base_rpm = 16000.0;

  double seconds_since(const std::chrono::steady_clock::time_point t0)
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  double median(std::vector<double> v)
  {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  }

  std::vector<double> speeds()
  {
    std::vector<double> s(n_speeds);
    for (int i = 0; i < n_speeds; ++i)
      s[i] = rpm_min + (rpm_max - rpm_min) * i / (n_speeds - 1);
    return s;
  }

  struct Curve
  {
    std::vector<double> rms;
    std::vector<bool>   stable;
    int                 jumps = 0;
    long                steps = 0, rejected_steps = 0; // of the converged orbits' shooting
  };

  // Orbits at every speed, each predicted from the two before (the secant through them, or the
  // last orbit where the secant's Newton fails). Past a fold Newton fails from both: the motion
  // jumps as an up sweep does, time-marched in rounds of 25 periods until Newton converges from
  // its state to a stable orbit.
  // The contenders: the serial Hertz law, the FE force law on the table's ladder, and the FE
  // force law on a ladder made from the serial law itself (the same motion as the serial law:
  // what the FE law's evaluation costs, apart from the different motion of the FE ladder).
  enum class Law
  {
    serial_hertz,
    fe_map,
    fe_map_on_serial_ladder
  };
  const char *name(const Law law)
  {
    return law == Law::serial_hertz ? "serial-hertz" :
           law == Law::fe_map       ? "fe-map" :
                                      "fe-map on the serial law's ladder";
  }

  GearPairParameters pair_on(const Law law)
  {
    auto p = testing::contact_loss_pair();
    p.effects.mesh_force_law =
      law == Law::serial_hertz ? MeshForceLawKind::serial_hertz : MeshForceLawKind::fe_map;
    if (law == Law::fe_map_on_serial_ladder)
      {
        const double F0    = p.stiffness.ladder.nominal_load_N;
        p.stiffness.ladder = hertzgear::testing::serial_law_ladder(
          p.stiffness, hertzgear::testing::ladder_loads(F0),
          static_cast<unsigned>(p.stiffness.ladder.n_positions()), F0);
      }
    return with_shared_mesh_force_law(p);
  }

  Curve shooting_curve(const double rtol, const double newton,
                       const Law law = Law::serial_hertz)
  {
    const auto base = pair_on(law);
    Curve      c;
    ShootingSettings s;
    s.integrator.kind               = IntegratorKind::radau_iia;
    s.integrator.relative_tolerance = rtol;
    s.integrator.absolute_tolerance = 1e-13 * rtol / 1e-8;
    s.tolerance                     = newton;
    RunSettings analysis            = testing::run_settings(IntegratorKind::radau_iia, rtol,
                                                            s.integrator.absolute_tolerance, 1, 0, 100);
    std::vector<double> last, before; // the orbits at the two speeds before, on one branch
    for (const double rpm : speeds())
      {
        GearPairModel model(at_speed(base, base_rpm, rpm));
        if (last.empty())
          last = model.static_equilibrium_state();
        PeriodicOrbit orbit;
        bool          jumped = false;
        if (!before.empty())
          {
            std::vector<double> secant(last.size());
            for (std::size_t i = 0; i < last.size(); ++i)
              secant[i] = 2.0 * last[i] - before[i];
            orbit = find_periodic_orbit(model, secant, s);
          }
        if (!orbit.converged)
          orbit = find_periodic_orbit(model, last, s);
        if (!orbit.converged)
          {
            ++c.jumps;
            jumped = true;
            std::vector<double> state = last;
            for (int periods = 25; periods <= 400 && !(orbit.converged && orbit.stable); periods += 25)
              {
                auto settings = testing::run_settings(IntegratorKind::radau_iia, rtol,
                                                      s.integrator.absolute_tolerance, 26, 25, 1);
                state = simulate(model, settings, state).final_state;
                orbit = find_periodic_orbit(model, state, s);
              }
          }
        if (!orbit.converged)
          {
            std::fprintf(stderr, "no orbit at %g rpm: %s\n", rpm, orbit.failure.c_str());
            std::exit(3);
          }
        // The secant needs two orbits of one branch: none before the first, one after a jump.
        before = c.rms.empty() || jumped ? std::vector<double>{} : last;
        last   = orbit.state;
        c.rms.push_back(analyse_orbit(model, orbit, analysis).rms_dte_m);
        c.steps += orbit.stats.steps;
        c.rejected_steps += orbit.stats.rejected_steps;
        c.stable.push_back(orbit.stable);
      }
    return c;
  }

  Curve marching_curve(const int transient)
  {
    SweepModel m;
    m.parameters = testing::contact_loss_pair();
    m.speed_rpm  = base_rpm;
    m.run        = testing::run_settings(IntegratorKind::radau_iia, 1e-8, 1e-13, 1, 0, 100);
    m.initial.static_equilibrium = true;
    SweepSettings s;
    s.speed_min_rpm               = rpm_min;
    s.speed_max_rpm               = rpm_max;
    s.points                      = n_speeds;
    s.direction                   = SweepDirection::up;
    s.mode                        = SweepMode::continuation;
    s.periods_per_point           = transient + 5;
    s.transient_periods_per_point = transient;
    s.threads                     = 1;
    const auto r = sweep(m, s);
    Curve      c;
    for (const auto &row : r.rows)
      c.rms.push_back(row.summary.rms_dte_m);
    return c;
  }

  double largest_error(const Curve &c, const Curve &ref)
  {
    double e = 0.0;
    for (int i = 0; i < n_speeds; ++i)
      if (ref.stable[i])
        e = std::max(e, std::abs(c.rms[i] - ref.rms[i]) / ref.rms[i]);
    return e;
  }

  // One orbit at `rpm`, the scene's defaults, from the static equilibrium: median of `solves`.
  double one_orbit(const int solves, const double rpm, const Law law = Law::serial_hertz)
  {
    GearPairModel    model(at_speed(pair_on(law), base_rpm, rpm));
    ShootingSettings s;
    s.integrator.kind               = IntegratorKind::radau_iia;
    s.integrator.relative_tolerance = 1e-8;
    s.integrator.absolute_tolerance = 1e-13;
    s.tolerance                     = 1e-6;
    std::vector<double> times;
    PeriodicOrbit       orbit;
    for (int i = 0; i < solves; ++i)
      {
        const auto t0 = std::chrono::steady_clock::now();
        orbit = find_periodic_orbit(model, model.static_equilibrium_state(), s);
        times.push_back(seconds_since(t0));
      }
    std::printf("%s: one orbit at %g rpm: median %.3f ms over %d solves, %d Newton iterations, "
                "|mu|max %.2e, converged %d\n",
                name(law), rpm, 1e3 * median(times), solves, orbit.iterations,
                orbit.largest_multiplier_modulus, int(orbit.converged));
    return median(times);
  }

  // The three contenders in alternation: one orbit, then the shooting curve.
  void compare_laws(const int alternations)
  {
    constexpr int       n = 3;
    const Law           laws[n] = {Law::serial_hertz, Law::fe_map, Law::fe_map_on_serial_ladder};
    std::vector<double> orbit[n], curve[n];
    Curve               last[n];
    for (int a = 0; a < alternations; ++a)
      for (int i = 0; i < n; ++i)
        {
          orbit[i].push_back(one_orbit(20, 10000.0, laws[i]));
          const auto t0 = std::chrono::steady_clock::now();
          last[i]       = shooting_curve(1e-8, 1e-6, laws[i]);
          curve[i].push_back(seconds_since(t0));
          std::printf("  %s: %d-speed shooting curve: %.3f s\n", name(laws[i]), n_speeds,
                      curve[i].back());
        }
    const auto difference = [&](const int i) {
      double d = 0.0;
      for (int k = 0; k < n_speeds; ++k)
        d = std::max(d, std::abs(last[i].rms[k] - last[0].rms[k]) / last[0].rms[k]);
      return d;
    };
    for (int i = 1; i < n; ++i)
      std::printf("%s against serial-hertz (medians of %d): one orbit at 10000 rpm %.3f / %.3f ms, "
                  "ratio %.2f; %d-speed curve %.3f / %.3f s, ratio %.2f; largest RMS DTE "
                  "difference %.3e relative\n",
                  name(laws[i]), alternations, 1e3 * median(orbit[i]), 1e3 * median(orbit[0]),
                  median(orbit[i]) / median(orbit[0]), n_speeds, median(curve[i]),
                  median(curve[0]), median(curve[i]) / median(curve[0]), difference(i));
  }
} // namespace

int main(int argc, char **argv)
{
  // `orbit [solves] [rpm] [serial-hertz|fe-map]` times one orbit alone (for profiling, e.g.
  // under callgrind).
  if (argc > 1 && std::string(argv[1]) == "orbit")
    {
      const std::string law = argc > 4 ? argv[4] : "serial-hertz";
      one_orbit(argc > 2 ? std::max(1, std::atoi(argv[2])) : 50, argc > 3 ? std::atof(argv[3]) : 150.0,
                law == "fe-map"               ? Law::fe_map :
                law == "fe-map-serial-ladder" ? Law::fe_map_on_serial_ladder :
                                                Law::serial_hertz);
      return 0;
    }
  // `curve [law]`: the 200-speed shooting curve alone on one law (for instruction counts).
  if (argc > 1 && std::string(argv[1]) == "curve")
    {
      const std::string law = argc > 2 ? argv[2] : "serial-hertz";
      const Law         l   = law == "fe-map"               ? Law::fe_map :
                              law == "fe-map-serial-ladder" ? Law::fe_map_on_serial_ladder :
                                                              Law::serial_hertz;
      const auto t0 = std::chrono::steady_clock::now();
      const Curve c = shooting_curve(1e-8, 1e-6, l);
      std::printf("%s: %d-speed shooting curve %.3f s, %d jumps, %ld steps (%ld rejected) in "
                  "the shooting of its orbits\n", name(l), n_speeds, seconds_since(t0), c.jumps,
                  c.steps, c.rejected_steps);
      return 0;
    }
  if (argc > 1 && std::string(argv[1]) == "laws")
    {
      compare_laws(argc > 2 ? std::max(1, std::atoi(argv[2])) : 3);
      return 0;
    }
  const int alternations = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  std::printf("crowned paper pair (FE table), %d speeds %g-%g rpm, up\n", n_speeds, rpm_min, rpm_max);
  auto        t0  = std::chrono::steady_clock::now();
  const Curve ref = shooting_curve(1e-11, 1e-9);
  int n_stable = 0;
  for (const bool st : ref.stable)
    n_stable += st ? 1 : 0;
  std::printf("reference: shooting at rtol 1e-11, Newton 1e-9: %.2f s, %d of %d orbits stable, "
              "%d jumps\n", seconds_since(t0), n_stable, n_speeds, ref.jumps);

  t0                      = std::chrono::steady_clock::now();
  const Curve  shoot      = shooting_curve(1e-8, 1e-6);
  const double t_shoot    = seconds_since(t0);
  const double e_shoot    = largest_error(shoot, ref);
  std::printf("shooting, rtol 1e-8, Newton 1e-6: %.3f s, largest RMS error %.2e\n", t_shoot, e_shoot);

  int    chosen = 0;
  double e_chosen = 0.0;
  for (const int transient : {25, 50, 100, 125, 150, 175, 200, 300, 400})
    {
      t0                   = std::chrono::steady_clock::now();
      const Curve  c       = marching_curve(transient);
      const double t       = seconds_since(t0);
      const double e       = largest_error(c, ref);
      std::printf("time marching, %3d + 5 periods per speed: %.3f s, largest RMS error %.2e\n",
                  transient, t, e);
      if (!chosen && e <= e_shoot)
        {
          chosen   = transient;
          e_chosen = e;
        }
    }
  if (!chosen)
    {
      std::printf("no time-marching rung reaches the shooting accuracy %.2e: the ratio is a lower "
                  "bound against the 400-period rung\n", e_shoot);
      chosen = 400;
    }
  std::vector<double> ts, tm;
  for (int a = 0; a < alternations; ++a)
    {
      t0 = std::chrono::steady_clock::now();
      shooting_curve(1e-8, 1e-6);
      ts.push_back(seconds_since(t0));
      t0 = std::chrono::steady_clock::now();
      marching_curve(chosen);
      tm.push_back(seconds_since(t0));
    }
  std::printf("alternated %d times: shooting %.3f s, time marching (%d + 5 periods, error %.2e) "
              "%.3f s: shooting %.1f times faster\n",
              alternations, median(ts), chosen, e_chosen, median(tm), median(tm) / median(ts));

  one_orbit(50, 150.0);
  return 0;
}
