#include "dynamics/analysis.h"

#include "common/errors.h"

#include <boost/math/tools/minima.hpp>
#include <fftw3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace hertzgear::dynamics
{
  namespace
  {
    // The extremes of the steady window located on the integrator's dense output. Per step, the
    // quantities q = x, -x, F, -F, |delta| of the model's mesh state on the interpolated state
    // are evaluated at n_sub + 1 equally spaced points; where the largest of them could exceed
    // the largest found so far, the bracket of the two neighbouring points is searched by
    // Brent's method (Boost.Math) for the maximum of the interpolant. "Could exceed": near a
    // smooth maximum a quadratic through three points spaced d apart, with second difference
    // D2 = q_{j-1} - 2 q_j + q_{j+1}, rises at most |D2| / 8 above its middle point; a step is
    // searched when its best point lies within |D2| (eight times that) of the running extreme.
    // In a periodic motion that is about one step per mesh period and quantity. The located
    // maxima are the interpolant's to rounding: Brent's method stops at 2^-26 of the bracket,
    // where the quadratic fall-off of a smooth maximum is 2^-52 of the curvature term.
    class ExtremeLocator
    {
    public:
      ExtremeLocator(const GearPairModel &model, const double t_start)
        : model(model), t_start(t_start), y(model.n_states())
      {
        best.fill(-std::numeric_limits<double>::infinity());
      }

      void step(double ta, const double tb, const DenseOutput &y_at)
      {
        ta = std::max(ta, t_start);
        if (!(tb > ta))
          return;
        std::array<std::array<double, n_q>, n_sub + 1> q;
        std::array<double, n_sub + 1>                  t;
        for (int j = 0; j <= n_sub; ++j)
          {
            t[j] = j == n_sub ? tb : ta + (tb - ta) * j / n_sub;
            q[j] = evaluate(t[j], y_at);
            for (int k = 0; k < n_q; ++k)
              record(k, q[j][k], t[j]);
          }
        for (int k = 0; k < n_q; ++k)
          {
            int j_best = 0;
            for (int j = 1; j <= n_sub; ++j)
              if (q[j][k] > q[j_best][k])
                j_best = j;
            const int    m  = std::clamp(j_best, 1, n_sub - 1); // middle of the curvature triple
            const double d2 = std::abs(q[m - 1][k] - 2.0 * q[m][k] + q[m + 1][k]);
            if (q[j_best][k] + d2 < best[k])
              continue;
            if (monotone_into_end(q, k, j_best))
              continue;
            const double a = t[std::max(j_best - 1, 0)], b = t[std::min(j_best + 1, n_sub)];
            // On the bracket's own coordinate s in [0, 1]: Boost's tolerance is relative to the
            // abscissa, and 2^-26 of t would be far coarser than 2^-26 of the bracket.
            const auto minus_q = [&](const double s_) {
              return -evaluate(a + s_ * (b - a), y_at)[k];
            };
            std::uintmax_t iterations = max_iterations;
            const auto     r          = boost::math::tools::brent_find_minima(
              minus_q, 0.0, 1.0, std::numeric_limits<double>::digits / 2, iterations);
            record(k, -r.second, a + r.first * (b - a));
          }
      }

      bool any() const { return best[0] > -std::numeric_limits<double>::infinity(); }

      SteadyExtremes result() const
      {
        SteadyExtremes e;
        e.max_dte_m         = best[0];
        e.t_max_dte_s       = where[0];
        e.min_dte_m         = -best[1];
        e.t_min_dte_s       = where[1];
        e.max_force_N       = best[2];
        e.t_max_force_s     = where[2];
        e.min_force_N       = -best[3];
        e.t_min_force_s     = where[3];
        e.max_penetration_m = best[4];
        e.t_max_penetration_s = where[4];
        return e;
      }

    private:
      static constexpr int n_q = 5, n_sub = 4;
      // Brent's method on 26 bits of the bracket converges in about 15-25 evaluations.
      static constexpr std::uintmax_t max_iterations = 100;

      std::array<double, n_q> evaluate(const double t, const DenseOutput &y_at)
      {
        y_at(t, y.data());
        const MeshState ms = model.mesh_state(t, y.data());
        return {ms.dte_m, -ms.dte_m, ms.force_N, -ms.force_N, std::abs(ms.penetration_m)};
      }

      // True when the largest point is an end of the step and q runs into it monotonically, so
      // that the bracket's maximum is that end point, already recorded. The slope at the end is
      // estimated by the quadratic through the three points nearest it; it must keep its sign
      // with the third difference as margin (a turning point between two points and a return
      // above the end needs a third difference of the slope's size).
      static bool monotone_into_end(const std::array<std::array<double, n_q>, n_sub + 1> &q,
                                    const int k, const int j_best)
      {
        if (j_best == n_sub)
          {
            const auto  &a  = q[n_sub][k], &b = q[n_sub - 1][k], &c = q[n_sub - 2][k];
            const double d1 = a - b, d2 = a - 2.0 * b + c;
            const double d3 = a - 3.0 * b + 3.0 * c - q[n_sub - 3][k];
            return d1 + 0.5 * d2 > std::abs(d3);
          }
        if (j_best == 0)
          {
            const double d1 = q[1][k] - q[0][k], d2 = q[2][k] - 2.0 * q[1][k] + q[0][k];
            const double d3 = q[3][k] - 3.0 * q[2][k] + 3.0 * q[1][k] - q[0][k];
            return -(d1 - 0.5 * d2) > std::abs(d3);
          }
        return false;
      }
      static_assert(n_sub >= 3, "the end slopes take four points");

      void record(const int k, const double value, const double t)
      {
        if (value > best[k])
          {
            best[k]  = value;
            where[k] = t;
          }
      }

      // A copy: the model keeps its time coefficients in a store, and probing it at other times
      // must not change, even at rounding level, what the integrator's right-hand side sees.
      const GearPairModel     model;
      double                  t_start;
      std::vector<double>     y;
      std::array<double, n_q> best{}, where{};
    };
  } // namespace

  SimulationResult simulate(GearPairModel &model, const RunSettings &settings,
                            std::vector<double> y, const ProgressCallback &progress)
  {
    HG_REQUIRE_INPUT(settings.periods > settings.transient_periods,
                     "{periods} (", settings.periods, ") must exceed {transient_periods} (",
                     settings.transient_periods, ")");
    HG_REQUIRE_INPUT(settings.samples_per_period >= 1, "samples_per_period must be >= 1");
    HG_REQUIRE_INPUT(y.size() == model.n_states(), "initial state has ", y.size(),
                     " components, the model ", model.n_states());
    const double T  = model.mesh_period();
    const int    S  = settings.samples_per_period;
    IntegratorSettings is = settings.integrator;
    if (is.kind == IntegratorKind::rk4)
      is.fixed_step = T / settings.steps_per_period;
    auto integrator = make_integrator(is);
    ExtremeLocator extremes(model, settings.transient_periods * T);
    if (settings.dense_extremes)
      integrator->set_step_observer(
        [&](const double ta, const double tb, const DenseOutput &y_at) {
          if (tb > settings.transient_periods * T)
            extremes.step(ta, tb, y_at);
        });

    SimulationResult result;
    result.mesh_period_s      = T;
    result.samples_per_period = S;
    result.steady_periods     = settings.periods - settings.transient_periods;
    result.steady.reserve(std::size_t(result.steady_periods) * S + 1);

    const long first_steady = long(settings.transient_periods) * S;
    long       index        = 0;
    bool       skip_first   = false;
    auto       observer     = [&](const double t, const double *state) {
      if (skip_first)
        {
          skip_first = false; // the chunk's start repeats the previous chunk's end
          return;
        }
      if (index >= first_steady)
        {
          const MeshState ms = model.mesh_state(t, state);
          result.steady.push_back({t, ms.dte_m, ms.dte_rate_m_per_s, ms.penetration_m, ms.force_N,
                                   ms.contact});
          if ((index - first_steady) % S == 0)
            result.poincare.push_back({t, state[0], state[1]});
        }
      ++index;
    };

    // Chunks of about a tenth of the run, for progress lines.
    const int chunk = std::max(1, settings.periods / 10);
    for (int done = 0; done < settings.periods;)
      {
        const int n = std::min(chunk, settings.periods - done);
        integrator->integrate(model, done * T, y, T / S, long(n) * S, observer);
        skip_first = true;
        done += n;
        if (progress)
          progress(done, settings.periods);
      }
    result.final_state = y;
    result.relative_tolerance = settings.integrator.relative_tolerance;
    result.has_dense_extremes = extremes.any();
    if (result.has_dense_extremes)
      result.dense_extremes = extremes.result();
    result.stats       = integrator->stats();
    return result;
  }

  PeriodDetection detect_period(const std::vector<PoincarePoint> &p, const double x_scale,
                                const double v_scale, const double tol, const int max_k)
  {
    PeriodDetection out;
    out.tolerance = tol;
    // Differences far below the tolerance are equal: the logarithm is floored there, so that
    // rounding-level differences neither break the fit nor count as a trend.
    const double floor = 1e-3 * tol;
    double       best_distance = std::numeric_limits<double>::infinity();
    bool         any_checked   = false;
    for (int k = 1; k <= max_k; ++k)
      {
        const int n_check = 2 * k + 8;
        if (int(p.size()) < n_check + k)
          break;
        any_checked = true;
        std::vector<double> d(n_check);
        for (int i = 0; i < n_check; ++i)
          {
            const int j = int(p.size()) - n_check - k + i;
            d[i]        = std::max(std::abs(p[j + k].dte_m - p[j].dte_m) / x_scale,
                                   std::abs(p[j + k].dte_rate_m_per_s - p[j].dte_rate_m_per_s) / v_scale);
          }
        // log d_i = a + i log r by least squares; the residual says whether there is a trend.
        double si = 0, sl = 0, sii = 0, sil = 0;
        for (int i = 0; i < n_check; ++i)
          {
            const double l = std::log(std::max(d[i], floor));
            si += i;
            sl += l;
            sii += double(i) * i;
            sil += i * l;
          }
        const double slope = (n_check * sil - si * sl) / (n_check * sii - si * si);
        const double icept = (sl - slope * si) / n_check;
        double       rss   = 0.0;
        for (int i = 0; i < n_check; ++i)
          {
            const double e = std::log(std::max(d[i], floor)) - icept - slope * i;
            rss += e * e;
          }
        // A geometric trend when the differences follow C r^i within about 30 %.
        const bool   trend  = std::sqrt(rss / n_check) <= 0.25;
        const double r      = std::exp(slope);
        const double d_last = d.back();
        double       max_d  = 0.0;
        for (const double v : d)
          max_d = std::max(max_d, v);
        double distance = max_d; // no trend: the differences themselves
        if (trend && max_d > floor)
          {
            const double rk = std::pow(r, k);
            distance = rk < 1.0 ? d_last * rk / (1.0 - rk) : std::numeric_limits<double>::infinity();
          }
        if (d_last <= tol && distance <= tol)
          {
            out.multiplicity = k;
            out.candidate    = k;
            out.contraction  = trend && max_d > floor ? r : 0.0;
            out.distance     = distance;
            out.status       = "period-" + std::to_string(k);
            return out;
          }
        if (trend && r < 1.0 && distance < best_distance)
          {
            best_distance   = distance;
            out.candidate   = k;
            out.contraction = r;
            out.distance    = distance;
          }
      }
    out.status = !any_checked ? "too few periods" : out.candidate > 0 ? "not settled" : "aperiodic";
    return out;
  }

  double period_settle_tolerance(const double relative_tolerance)
  {
    return std::max(1e3 * relative_tolerance, 1e-12);
  }

  int period_multiplicity(const std::vector<PoincarePoint> &p, const double x_scale,
                          const double v_scale, const double relative_tolerance, const int max_k)
  {
    return detect_period(p, x_scale, v_scale, relative_tolerance, max_k).multiplicity;
  }

  std::vector<ImpactLoop> force_penetration_loops(const SimulationResult &r)
  {
    // A contact episode is a run of samples with force-carrying contact between samples without.
    // Its loop is closed through the neighbouring separated samples (F = 0 there).
    std::vector<ImpactLoop> loops;
    const auto             &s = r.steady;
    std::size_t             i = 0;
    while (i < s.size() && s[i].contact != 0)
      ++i; // an episode already under way at the window's start is not a whole loop
    while (i < s.size())
      {
        while (i < s.size() && s[i].contact == 0)
          ++i;
        if (i >= s.size())
          break;
        const std::size_t begin = i - 1; // separated sample before
        while (i < s.size() && s[i].contact != 0)
          ++i;
        if (i >= s.size())
          break; // not closed within the window
        const std::size_t end = i; // separated sample after
        ImpactLoop        loop;
        loop.start_s = s[begin + 1].t_s;
        loop.end_s   = s[end - 1].t_s;
        for (std::size_t j = begin; j < end; ++j)
          {
            loop.loop_work_J += 0.5 * (s[j].force_N + s[j + 1].force_N) *
                                        (s[j + 1].penetration_m - s[j].penetration_m);
            loop.max_force_N = std::max(loop.max_force_N, std::abs(s[j + 1].force_N));
            loop.max_penetration_m =
              std::max(loop.max_penetration_m, std::abs(s[j + 1].penetration_m));
          }
        loops.push_back(loop);
      }
    return loops;
  }

  SteadyStateSummary analyse(const GearPairModel &model, const SimulationResult &r)
  {
    SteadyStateSummary sum;
    sum.static_force_N = model.parameters().static_force_N;
    const auto &s      = r.steady;
    HG_REQUIRE_NUMERIC(s.size() >= 2, "no steady samples to analyse");
    // Whole periods: the last sample repeats the phase of the first, leave it out of the means.
    const std::size_t n = s.size() - 1;
    double            sum_x = 0, sum_x2 = 0, sum_f = 0;
    sum.min_dte_m = sum.max_dte_m = s[0].dte_m;
    sum.min_force_N = sum.max_force_N = s[0].force_N;
    std::size_t n_lost = 0, n_losses = 0;
    for (std::size_t i = 0; i < n; ++i)
      {
        sum_x += s[i].dte_m;
        sum_x2 += s[i].dte_m * s[i].dte_m;
        sum_f += s[i].force_N;
        sum.min_dte_m         = std::min(sum.min_dte_m, s[i].dte_m);
        sum.max_dte_m         = std::max(sum.max_dte_m, s[i].dte_m);
        sum.max_force_N       = std::max(sum.max_force_N, s[i].force_N);
        sum.min_force_N       = std::min(sum.min_force_N, s[i].force_N);
        sum.max_penetration_m = std::max(sum.max_penetration_m, std::abs(s[i].penetration_m));
        n_lost += s[i].contact == 0;
        if (i > 0 && s[i - 1].contact != 0 && s[i].contact == 0)
          ++n_losses;
        if (i > 0 && s[i - 1].contact != -1 && s[i].contact == -1)
          ++sum.backside_impacts;
      }
    // The extremes between the samples, from the dense output.
    sum.extremes_from = r.has_dense_extremes ? "dense output" : "samples";
    if (r.has_dense_extremes)
      {
        const SteadyExtremes &e = r.dense_extremes;
        sum.min_dte_m           = std::min(sum.min_dte_m, e.min_dte_m);
        sum.max_dte_m           = std::max(sum.max_dte_m, e.max_dte_m);
        sum.min_force_N         = std::min(sum.min_force_N, e.min_force_N);
        sum.max_force_N         = std::max(sum.max_force_N, e.max_force_N);
        sum.max_penetration_m   = std::max(sum.max_penetration_m, e.max_penetration_m);
      }
    const double limit = model.mesh_force_law().tabulated_force_limit();
    if (std::isfinite(limit))
      {
        sum.tabulated_force_limit_N = limit;
        sum.extrapolated_fraction =
          double(std::count_if(s.begin(), s.begin() + std::ptrdiff_t(n),
                               [&](const Sample &x) { return std::abs(x.force_N) > limit; })) /
          double(n);
        sum.force_law_extrapolated = std::max(sum.max_force_N, -sum.min_force_N) > limit;
      }
    sum.mean_dte_m            = sum_x / n;
    sum.rms_dte_m             = std::sqrt(sum_x2 / n);
    sum.rms_dte_fluctuation_m =
      std::sqrt(std::max(0.0, sum_x2 / n - sum.mean_dte_m * sum.mean_dte_m));
    sum.mean_force_N              = sum_f / n;
    sum.dynamic_factor            = sum.static_force_N > 0 ? sum.max_force_N / sum.static_force_N : 0;
    sum.contact_loss_fraction     = double(n_lost) / n;
    sum.contact_losses_per_period = double(n_losses) / r.steady_periods;
    double max_rate = 0.0;
    for (const auto &sample : s)
      max_rate = std::max(max_rate, std::abs(sample.dte_rate_m_per_s));
    // Scales of the periodicity test: the peak-to-peak motion, but at least 1 % of the DTE level
    // (and that over a mesh period for the rate). A motion that barely varies (constant stiffness)
    // would otherwise give a tolerance below the integrator's own error, rtol |x|, and read as
    // aperiodic.
    const double level   = std::max(std::abs(sum.max_dte_m), std::abs(sum.min_dte_m));
    const double x_scale = std::max(sum.max_dte_m - sum.min_dte_m, 1e-2 * level);
    const double v_scale = std::max(max_rate, x_scale / r.mesh_period_s);
    const PeriodDetection period = detect_period(
      r.poincare, x_scale, v_scale,
      period_settle_tolerance(r.relative_tolerance > 0.0 ? r.relative_tolerance : 1e-8));
    sum.period_multiplicity = period.multiplicity;
    sum.period_status       = period.status;
    sum.period_candidate    = period.candidate;
    sum.period_contraction  = period.contraction;
    sum.period_distance     = period.distance;
    const auto loops              = force_penetration_loops(r);
    sum.n_impacts                 = loops.size();
    for (const auto &l : loops)
      sum.mean_loop_work_per_impact_J += l.loop_work_J / loops.size();
    return sum;
  }

  std::vector<SpectrumLine> dte_spectrum(const SimulationResult &r)
  {
    const int n = int(r.steady.size()) - 1; // whole periods
    std::vector<SpectrumLine> lines;
    if (n < 2)
      return lines;
    std::vector<double> in(n);
    double              mean = 0;
    for (int i = 0; i < n; ++i)
      mean += r.steady[i].dte_m / n;
    for (int i = 0; i < n; ++i)
      in[i] = r.steady[i].dte_m - mean;
    std::vector<fftw_complex> out(n / 2 + 1);
    fftw_plan plan = fftw_plan_dft_r2c_1d(n, in.data(), out.data(), FFTW_ESTIMATE);
    fftw_execute(plan);
    fftw_destroy_plan(plan);
    const double dt = r.mesh_period_s / r.samples_per_period;
    const double df = 1.0 / (n * dt);
    for (int j = 0; j <= n / 2; ++j)
      {
        const double scale = (j == 0 || 2 * j == n) ? 1.0 / n : 2.0 / n;
        lines.push_back({j * df, j * df * r.mesh_period_s,
                         scale * std::hypot(out[j][0], out[j][1])});
      }
    return lines;
  }
} // namespace hertzgear::dynamics
