#include "dynamics/continuation.h"

#include "common/errors.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hertzgear::dynamics
{
  std::string bifurcation_name(const Bifurcation b)
  {
    switch (b)
      {
        case Bifurcation::none:
          return "";
        case Bifurcation::fold:
          return "fold";
        case Bifurcation::period_doubling:
          return "period-doubling";
        case Bifurcation::neimark_sacker:
          return "neimark-sacker";
        case Bifurcation::corner_turn:
          return "corner-turn";
      }
    return "?";
  }

  void check_continuation_settings(const ContinuationSettings &s)
  {
    check_shooting_settings(s.shooting);
    if (!(s.lambda_max > s.lambda_min))
      throw ParameterError("lambda_max", msg(s.lambda_max, " must exceed {lambda_min} (", s.lambda_min, ")"));
    if (!(s.lambda_start >= s.lambda_min && s.lambda_start <= s.lambda_max))
      throw ParameterError("lambda_start", msg(s.lambda_start, " lies outside {lambda_min} ... {lambda_max} (",
                                               s.lambda_min, " ... ", s.lambda_max, ")"));
    if (s.direction != 1 && s.direction != -1)
      throw ParameterError("direction", msg(s.direction, " must be +1 or -1"));
    if (!(s.step_min > 0 && s.step_min <= s.step_initial && s.step_initial <= s.step_max && s.step_max <= 0.5))
      throw ParameterError("step_initial", msg(s.step_initial, " must lie in {step_min} ... {step_max} (",
                                               s.step_min, " ... ", s.step_max, "), 0 < step_min, step_max <= 0.5"));
    if (s.max_points < 2)
      throw ParameterError("max_points", msg(s.max_points, " must be at least 2"));
    if (s.corrector_iterations < 2)
      throw ParameterError("corrector_iterations", msg(s.corrector_iterations, " must be at least 2"));
    if (s.max_branches < 1)
      throw ParameterError("max_branches", msg(s.max_branches, " must be at least 1"));
    if (!(s.fold_multiplier_tolerance > 0.0 && s.fold_multiplier_tolerance < 0.5))
      throw ParameterError("fold_multiplier_tolerance",
                           msg(s.fold_multiplier_tolerance, " is outside (0, 0.5)"));
  }

  namespace
  {
    using Vec = Eigen::VectorXd;
    using Mat = Eigen::MatrixXd;

    // G(u, l) and its derivatives at one point.
    struct Evaluation
    {
      bool        ok = false;
      std::string error;
      Vec         G;
      Mat         Gu, M;
      Vec         Gl;
      long        events = 0;
    };

    struct Corrected
    {
      bool        ok = false;
      std::string error;
      Vec         z;
      Evaluation  ev; // at the last iterate before the final (converged) correction
      int         iterations = 0;
    };

    double sign_of(const double v) { return (v > 0) - (v < 0); }

    // A sign change of the tangent's parameter component between two values both below this is
    // rounding on a branch that runs at constant parameter (a linear system's period-2 branch
    // leaves its period doubling that way), not a fold.
    constexpr double fold_noise = 1e-6;

    // Test functions of the multipliers: period doubling and Neimark-Sacker.
    double period_doubling_test(const std::vector<std::complex<double>> &mu)
    {
      std::complex<double> p = 1.0;
      for (const auto &m : mu)
        p *= m + 1.0;
      return p.real();
    }
    double neimark_sacker_test(const std::vector<std::complex<double>> &mu)
    {
      std::complex<double> p = 1.0;
      for (std::size_t i = 0; i < mu.size(); ++i)
        for (std::size_t j = i + 1; j < mu.size(); ++j)
          p *= mu[i] * mu[j] - 1.0;
      return p.real();
    }
    // How far the multiplier nearest +1 lies from it.
    double distance_to_one(const std::vector<std::complex<double>> &mu)
    {
      double d = std::numeric_limits<double>::infinity();
      for (const auto &m : mu)
        d = std::min(d, std::abs(m - 1.0));
      return d;
    }

    // A complex pair on the unit circle (not a real pair whose product is 1).
    bool has_complex_pair_near_unit_circle(const std::vector<std::complex<double>> &mu)
    {
      for (const auto &m : mu)
        if (std::abs(m.imag()) > 1e-6 && std::abs(std::abs(m) - 1.0) < 1e-3)
          return true;
      return false;
    }

    class BranchFollower
    {
    public:
      BranchFollower(const ParameterFamily &f, const ContinuationSettings &s, std::vector<double> sc,
                     ContinuationResult &r)
        : family(f), cs(s), scale(std::move(sc)), n(unsigned(scale.size())), result(r)
      {}

      double lambda_of(const double l) const { return cs.lambda_min + l * (cs.lambda_max - cs.lambda_min); }
      double l_of(const double lambda) const { return (lambda - cs.lambda_min) / (cs.lambda_max - cs.lambda_min); }

      Evaluation evaluate(const Vec &z, const int k)
      {
        Evaluation ev;
        try
          {
            std::vector<double> x(n);
            for (unsigned i = 0; i < n; ++i)
              x[i] = z(i) * scale[i];
            GearPairModel model(family.at(lambda_of(z(n))));
            auto          integrator = make_integrator(sensitivity_integrator(cs.shooting.integrator));
            const auto    flow = flow_with_sensitivity(model, scale, *integrator, 0.0, x,
                                                       k * model.mesh_period());
            ev.G.resize(n);
            ev.Gu.resize(n, n);
            for (unsigned i = 0; i < n; ++i)
              {
                ev.G(i) = (flow.y[i] - x[i]) / scale[i];
                for (unsigned j = 0; j < n; ++j)
                  ev.Gu(i, j) = flow.jacobian(i, j) * scale[j] / scale[i] - (i == j ? 1.0 : 0.0);
              }
            ev.M      = flow.jacobian;
            ev.events = flow.events;
            // dG/dl by a forward difference of 1e-6 of the range (the corrector converges with
            // any good approximation; the branch is fixed by G alone).
            const double h = 1e-6;
            GearPairModel model_h(family.at(lambda_of(z(n) + h)));
            std::vector<double> y = x;
            integrator->integrate(model_h, 0.0, y, k * model_h.mesh_period(), 1,
                                  [](double, const double *) {});
            ev.Gl.resize(n);
            for (unsigned i = 0; i < n; ++i)
              ev.Gl(i) = ((y[i] - x[i]) / scale[i] - ev.G(i)) / h;
            result.stats += integrator->stats();
            ev.ok = ev.G.allFinite() && ev.Gu.allFinite() && ev.Gl.allFinite();
            if (!ev.ok)
              ev.error = "the period map is not finite";
          }
        catch (const NumericalError &e)
          {
            ev.ok    = false;
            ev.error = e.what();
          }
        catch (const InputError &e) // a parameter the family cannot take (a speed <= 0, ...)
          {
            ev.ok    = false;
            ev.error = e.what();
          }
        return ev;
      }

      Mat bordered(const Evaluation &ev, const Vec &tau) const
      {
        Mat A(n + 1, n + 1);
        A.topLeftCorner(n, n) = ev.Gu;
        A.topRightCorner(n, 1) = ev.Gl;
        A.bottomRows(1)        = tau.transpose();
        return A;
      }

      // Newton on G = 0, tau . (z - z_pred) = 0.
      // Newton on the bordered system from z_pred until its update is below `tolerance` (0: the
      // shooting's Newton tolerance).
      Corrected correct(const Vec &z_pred, const Vec &tau, const int k, const int max_iterations,
                        const double tolerance = 0.0)
      {
        const double tol = tolerance > 0.0 ? tolerance : cs.shooting.tolerance;
        Corrected c;
        c.z = z_pred;
        for (int it = 1; it <= max_iterations; ++it)
          {
            c.ev = evaluate(c.z, k);
            ++result.orbits_solved;
            if (!c.ev.ok)
              {
                c.error = c.ev.error;
                return c;
              }
            Vec rhs(n + 1);
            rhs.head(n) = -c.ev.G;
            rhs(n)      = -tau.dot(c.z - z_pred);
            const Vec dz = bordered(c.ev, tau).partialPivLu().solve(rhs);
            if (!dz.allFinite())
              {
                c.error = "the bordered Jacobian is singular";
                return c;
              }
            c.z += dz;
            c.iterations = it;
            if (dz.lpNorm<Eigen::Infinity>() < tol)
              {
                c.ok = true;
                return c;
              }
          }
        c.error = msg("the corrector did not converge in ", max_iterations, " iterations");
        return c;
      }

      // The unit tangent at a corrected point, oriented along `previous`.
      Vec tangent(const Evaluation &ev, const Vec &previous) const
      {
        Vec rhs = Vec::Zero(n + 1);
        rhs(n)  = 1.0;
        Vec t   = bordered(ev, previous).partialPivLu().solve(rhs);
        return t / t.norm();
      }

      ContinuationPoint make_point(const Vec &z, const Evaluation &ev, const int k, const int branch,
                                   const double s, const int iterations)
      {
        ContinuationPoint p;
        p.lambda          = lambda_of(z(n));
        p.branch          = branch;
        p.period_multiple = k;
        p.arclength       = s;
        p.state.resize(n);
        for (unsigned i = 0; i < n; ++i)
          p.state[i] = z(i) * scale[i];
        p.multipliers          = floquet_multipliers(ev.M);
        p.stable               = std::abs(p.multipliers.front()) < 1.0;
        p.corrector_iterations = iterations;
        p.events_per_period    = ev.events;
        PeriodicOrbit orbit;
        orbit.converged                  = true;
        orbit.state                      = p.state;
        orbit.period_multiple            = k;
        orbit.multipliers                = p.multipliers;
        orbit.largest_multiplier_modulus = std::abs(p.multipliers.front());
        GearPairModel model(family.at(p.lambda));
        orbit.period_s = k * model.mesh_period();
        p.summary      = analyse_orbit(model, orbit, cs.analysis);
        return p;
      }

      struct Tests
      {
        double fold = 0, pd = 0, ns = 0;
      };
      Tests tests_of(const Evaluation &ev, const Vec &tau) const
      {
        const auto mu = floquet_multipliers(ev.M);
        return {tau(n), period_doubling_test(mu), neimark_sacker_test(mu)};
      }

      // Locates the sign change of one test between s = 0 (z0) and s = h by bisection on the step
      // length along tau0, to location_tolerance h. Returns false, with the reason in `error`,
      // when a corrector fails on the way: the last point corrected is not the bifurcation.
      bool locate(const Vec &z0, const Vec &tau0, const double h, const int k, const Bifurcation which,
                  const double sign0, Corrected &at, Vec &tau_at, double &s_at, std::string &error)
      {
        double lo = 0.0, hi = h;
        bool   have = false;
        for (int i = 0; i < 60 && hi - lo > cs.location_tolerance * h; ++i)
          {
            const double s = 0.5 * (lo + hi);
            Corrected    c = correct(z0 + s * tau0, tau0, k, cs.corrector_iterations + 4,
                                     location_newton_tolerance());
            if (!c.ok)
              {
                error = c.error;
                return false;
              }
            const Vec   t    = tangent(c.ev, tau0);
            const Tests te   = tests_of(c.ev, t);
            const double v   = which == Bifurcation::fold            ? te.fold :
                               which == Bifurcation::period_doubling ? te.pd :
                                                                       te.ns;
            at     = c;
            tau_at = t;
            s_at   = s;
            have   = true;
            (sign_of(v) == sign0 ? lo : hi) = s;
          }
        return have;
      }

      // The Newton tolerance of the points a bisection visits: a tenth of the branch's, not below
      // ten times the period map's integration tolerance (check_continuation_settings' rule for
      // the branch). The speed of a fold is as accurate as its orbits: at the default 1e-6 the
      // folds of the crowned table found from either end of the range differed by up to 1.4e-8
      // (relative), at 1e-7 by 1.2e-9.
      double location_newton_tolerance() const
      {
        return std::max(0.1 * cs.shooting.tolerance,
                        10.0 * cs.shooting.integrator.relative_tolerance);
      }

      // Whether the corrected point lies within max_correction steps h of its predictor: the
      // corrector moves across the tangent by about the branch's curvature times h^2 / 2, and a
      // point much farther is on another branch (a step of 0.013 once landed 0.23 away).
      static bool near_predictor(const Corrected &c, const Vec &predicted, const double h)
      {
        return (c.z - predicted).norm() <= max_correction * h;
      }
      static constexpr double max_correction = 3.0;
      // Steps this short are those of a corner (pass_corner's shortest).
      double corner_step() const { return 100.0 * cs.step_min; }

      // At a corner of the branch the corrector fails for every small step: Newton's iterates
      // alternate between the two sides of the kink of the period map. Steps of 100 ... 10^5
      // times the minimum, with more iterations, start beyond the kink, in the smooth part.
      bool pass_corner(const Vec &z, const Vec &tau, const int k, Corrected &c, Vec &tau1, double &h)
      {
        for (h = corner_step(); h <= std::min(1e5 * cs.step_min, cs.step_max); h *= 10)
          {
            c = correct(z + h * tau, tau, k, 3 * cs.corrector_iterations);
            if (!c.ok)
              continue;
            // Beyond a corner the tangent is oriented along the secant from the last point, the
            // way the branch was travelled (the old tangent may point back along the new piece).
            const Vec secant = c.z - z;
            if (secant.dot(tau) <= 0.0)
              continue;
            tau1 = tangent(c.ev, secant / secant.norm());
            return true;
          }
        return false;
      }

      // Follows one branch from its corrected start z (tangent tau) until it leaves the range,
      // reaches max_points or its step collapses.
      void follow(ContinuationBranch &branch, Vec z, Evaluation ev, Vec tau, int iterations,
                  const ContinuationProgress &progress)
      {
        const int k  = branch.period_multiple;
        double    h  = cs.step_initial, s = 0.0;
        auto      push = [&](const ContinuationPoint &p) {
          branch.points.push_back(p);
          if (progress)
            progress(branch, branch.points.back());
        };
        push(make_point(z, ev, k, branch.id, s, iterations));
        Tests t0 = tests_of(ev, tau);
        while (int(branch.points.size()) < cs.max_points)
          {
            Corrected c = correct(z + h * tau, tau, k, cs.corrector_iterations);
            Vec       tau1;
            bool      accept = c.ok, passed_corner = false;
            if (accept)
              {
                tau1 = tangent(c.ev, tau);
                // A turn of more than ~25 degrees in one step, or a corrected point farther from
                // the predictor than the step is long, may have jumped to another branch.
                accept = tau1.dot(tau) > 0.9 && near_predictor(c, z + h * tau, h);
              }
            if (!accept)
              {
                h *= 0.5;
                double h_corner = 0.0;
                if (h < cs.step_min && pass_corner(z, tau, k, c, tau1, h_corner))
                  {
                    // A corner of the branch (a grazing contact: the period map is continuous
                    // but its derivative jumps), passed with a step from beyond it.
                    ++branch.corners;
                    h             = h_corner;
                    accept        = true;
                    passed_corner = true;
                  }
              }
            if (!accept)
              {
                if (h < cs.step_min)
                  {
                    branch.end_reason = msg("the continuation step collapsed below its minimum ",
                                            cs.step_min, " at ", family.name, " = ",
                                            lambda_of(z(n)), (c.ok ? "" : ": " + c.error));
                    branch.ended_in_failure = true;
                    return;
                  }
                continue;
              }
            const Tests t1 = tests_of(c.ev, tau1);
            // Bifurcations inside the step, located and recorded in arclength order.
            struct Found
            {
              double            s;
              ContinuationPoint p;
            };
            std::vector<Found> found;
            bool retry_shorter = false;
            const std::pair<Bifurcation, std::pair<double, double>> checks[] = {
              {Bifurcation::fold, {t0.fold, t1.fold}},
              {Bifurcation::period_doubling, {t0.pd, t1.pd}},
              {Bifurcation::neimark_sacker, {t0.ns, t1.ns}}};
            for (const auto &[which, values] : checks)
              if (sign_of(values.first) != sign_of(values.second) && values.first != 0.0 &&
                  (which != Bifurcation::fold ||
                   std::max(std::abs(values.first), std::abs(values.second)) > fold_noise))
                {
                  Corrected   at;
                  Vec         tau_at;
                  double      s_at = 0;
                  std::string error;
                  const auto  between = [&] {
                    return msg(family.name, " = ", lambda_of(z(n)), " and ", lambda_of(c.z(n)));
                  };
                  // A switching that appears or vanishes inside the step: the branch has a corner
                  // there (the period map's derivative jumps).
                  const bool corner_inside = branch.points.back().events_per_period != c.ev.events;
                  const bool located =
                    locate(z, tau, h, k, which, sign_of(values.first), at, tau_at, s_at, error);
                  // A step that spans the turning point too coarsely (its corrected points jump
                  // from one side of a fold to the other, so that the bisection closes on that jump,
                  // or a corrector fails on the way) is taken again, shorter, down to the steps of
                  // a corner; only then is what it found classified below. A step that passed a
                  // corner is not retaken: every shorter one failed, and retaking it passed the
                  // same corner with the same step again, without end.
                  const bool shorter = h > corner_step() && !passed_corner;
                  if (!located && shorter)
                    {
                      retry_shorter = true;
                      break;
                    }
                  if (!located && !(which == Bifurcation::fold && corner_inside && at.ok))
                    {
                      branch.notes.push_back({which, lambda_of(z(n)), lambda_of(c.z(n)),
                                              msg("a ", which == Bifurcation::fold ? "turning point" :
                                                                                    bifurcation_name(which),
                                                  " between ", between(), " could not be located (",
                                                  error, "): not reported")});
                      continue;
                    }
                  // (A turning point at a corner, where the corrector fails at the kink itself, is
                  // reported at the last point corrected beside it.)
                  auto p = make_point(at.z, at.ev, k, branch.id, s + s_at, at.iterations);
                  if (which == Bifurcation::neimark_sacker &&
                      !has_complex_pair_near_unit_circle(p.multipliers))
                    continue; // a real pair with product 1: no torus
                  p.bifurcation = which;
                  if (which == Bifurcation::fold &&
                      distance_to_one(p.multipliers) > cs.fold_multiplier_tolerance && shorter)
                    {
                      retry_shorter = true;
                      break;
                    }
                  if (which == Bifurcation::fold &&
                      distance_to_one(p.multipliers) > cs.fold_multiplier_tolerance)
                    {
                      // No multiplier at 1: a turning point at a corner when a switching appears
                      // or vanishes across the step; else the period map is not accurate enough.
                      if (corner_inside)
                        p.bifurcation = Bifurcation::corner_turn;
                      else
                        {
                          branch.notes.push_back({which, p.lambda, p.lambda,
                            msg("the parameter turns back at ", family.name, " = ", p.lambda,
                                " where no Floquet multiplier is 1 (the nearest lies ",
                                distance_to_one(p.multipliers), " from it) and the switchings per "
                                "period do not change: not reported as a fold; the period map is "
                                "not integrated accurately enough for the Newton tolerance "
                                "(tighten {shooting_relative_tolerance})")});
                          continue;
                        }
                    }
                  found.push_back({s_at, p});
                }
            if (retry_shorter)
              {
                h *= 0.5;
                continue;
              }
            std::sort(found.begin(), found.end(), [](const Found &a, const Found &b) { return a.s < b.s; });
            // A fold the branch has passed before: the continuation came back onto its own path
            // (where a turning point could not be located, its corrected points may follow the
            // old piece back instead of the new one) and would only repeat it. The same orbit:
            // the speed within 1e-5 and the state within 1e-3 relative (a fold found twice on a
            // coarse period map differs by ~1e-7 relative; two folds of different orbits at the
            // same speed differ in the state by the orbits' difference).
            for (const auto &f : found)
              {
                if (f.p.bifurcation != Bifurcation::fold)
                  continue;
                for (std::size_t i = 0; i < branch.points.size(); ++i)
                  {
                    const auto &q = branch.points[i];
                    if (q.bifurcation != Bifurcation::fold ||
                        std::abs(q.lambda - f.p.lambda) > 1e-5 * std::abs(q.lambda))
                      continue;
                    double d2 = 0.0, q2 = 0.0;
                    for (std::size_t m = 0; m < q.state.size(); ++m)
                      {
                        d2 += (q.state[m] - f.p.state[m]) * (q.state[m] - f.p.state[m]);
                        q2 += q.state[m] * q.state[m];
                      }
                    if (d2 > 1e-6 * q2)
                      continue;
                    const bool after_unlocated =
                      !branch.notes.empty() &&
                      branch.notes.back().text.find("could not be located") != std::string::npos;
                    branch.end_reason =
                      msg("the branch came back onto its own path: the fold at ", family.name, " = ",
                          f.p.lambda, " is the one it passed at point ", i,
                          after_unlocated ? msg(", after a turning point near ", family.name, " = ",
                                                branch.notes.back().lambda_from,
                                                " that could not be located") :
                                            std::string(),
                          "; the period map is not integrated accurately enough for this branch "
                          "(tighten {shooting_relative_tolerance})");
                    branch.ended_in_failure = true;
                    return;
                  }
              }
            for (const auto &f : found)
              push(f.p);

            const double l1 = c.z(n);
            if (l1 > 1.0 || l1 < 0.0)
              {
                // The end of the range: the point at l = 1 (or 0) exactly.
                Vec e       = Vec::Zero(n + 1);
                e(n)        = 1.0;
                Vec z_end   = z + h * tau;
                z_end(n)    = l1 > 1.0 ? 1.0 : 0.0;
                Corrected c_end = correct(z_end, e, k, cs.corrector_iterations + 4);
                if (c_end.ok)
                  push(make_point(c_end.z, c_end.ev, k, branch.id, s + h, c_end.iterations));
                branch.end_reason = msg("reached ", family.name, " = ", lambda_of(l1 > 1.0 ? 1.0 : 0.0));
                return;
              }
            s += h;
            push(make_point(c.z, c.ev, k, branch.id, s, c.iterations));
            z   = c.z;
            tau = tau1;
            t0  = t1;
            // Step control by the corrector's effort.
            if (c.iterations <= 2)
              h = std::min(2.0 * h, cs.step_max);
            else if (c.iterations <= 3)
              h = std::min(1.3 * h, cs.step_max);
            else if (c.iterations >= 5)
              h *= 0.6;
          }
        branch.end_reason = msg("reached the limit of ", cs.max_points, " points");
      }

      const ParameterFamily      &family;
      const ContinuationSettings &cs;
      std::vector<double>          scale;
      unsigned                     n;
      ContinuationResult          &result;
    };
  } // namespace

  ContinuationResult continue_periodic_orbits(const ParameterFamily &family,
                                              const std::vector<double> &guess,
                                              const ContinuationSettings &settings,
                                              const ContinuationProgress &progress)
  {
    check_continuation_settings(settings);
    GearPairModel start_model(family.at(settings.lambda_start));
    const auto    first = find_periodic_orbit(start_model, guess, settings.shooting);
    if (!first.converged)
      throw NumericalError(msg("no periodic orbit found at ", family.name, " = ",
                               settings.lambda_start, ": ", first.failure));
    ContinuationResult result;
    result.stats += first.stats;
    const auto     scale = start_model.state_scales();
    const unsigned n     = unsigned(scale.size());
    BranchFollower follower(family, settings, scale, result);

    Vec z(n + 1);
    for (unsigned i = 0; i < n; ++i)
      z(i) = first.state[i] / scale[i];
    z(n) = follower.l_of(settings.lambda_start);
    const int k = settings.shooting.period_multiple;
    // The start, corrected on the bordered system with the parameter held.
    Vec e  = Vec::Zero(n + 1);
    e(n)   = 1.0;
    auto c = follower.correct(z, e, k, settings.corrector_iterations + 4);
    if (!c.ok)
      throw NumericalError(msg("no periodic orbit found at ", family.name, " = ",
                               settings.lambda_start, ": ", c.error));
    Vec tau = follower.tangent(c.ev, settings.direction * e);

    ContinuationBranch main;
    main.id              = 0;
    main.period_multiple = k;
    main.start_lambda    = settings.lambda_start;
    result.branches.push_back(main);
    follower.follow(result.branches.back(), c.z, c.ev, tau, c.iterations, progress);

    // Period-doubled branches from every period doubling found, breadth first.
    for (std::size_t b = 0; b < result.branches.size() && settings.follow_period_doubling; ++b)
      {
        const auto pds = [&] {
          std::vector<ContinuationPoint> v;
          for (const auto &p : result.branches[b].points)
            if (p.bifurcation == Bifurcation::period_doubling)
              v.push_back(p);
          return v;
        }();
        for (const auto &pd : pds)
          {
            if (int(result.branches.size()) >= settings.max_branches)
              break;
            ContinuationBranch child;
            child.id              = int(result.branches.size());
            child.period_multiple = 2 * result.branches[b].period_multiple;
            child.parent          = result.branches[b].id;
            child.start_lambda    = pd.lambda;
            // The eigenvector of the multiplier nearest -1, scaled.
            Vec           zp(n + 1);
            for (unsigned i = 0; i < n; ++i)
              zp(i) = pd.state[i] / scale[i];
            zp(n)         = follower.l_of(pd.lambda);
            const auto ev = follower.evaluate(zp, result.branches[b].period_multiple);
            if (!ev.ok)
              continue;
            Eigen::EigenSolver<Mat> es(ev.M);
            Eigen::Index best = 0;
            for (Eigen::Index i = 1; i < es.eigenvalues().size(); ++i)
              if (std::abs(es.eigenvalues()(i) + 1.0) < std::abs(es.eigenvalues()(best) + 1.0))
                best = i;
            Vec v = Vec::Zero(n + 1);
            for (unsigned i = 0; i < n; ++i)
              v(i) = es.eigenvectors()(i, best).real() / scale[i];
            v /= v.norm();
            const double eps = 1e-3;
            auto cc = follower.correct(zp + eps * v, v, child.period_multiple,
                                       settings.corrector_iterations + 4);
            result.branches.push_back(child);
            if (!cc.ok)
              {
                result.branches.back().end_reason =
                  msg("the period-", child.period_multiple, " branch could not be started at ",
                      family.name, " = ", pd.lambda, ": ", cc.error);
                result.branches.back().ended_in_failure = true;
                continue;
              }
            Vec t = follower.tangent(cc.ev, v);
            follower.follow(result.branches.back(), cc.z, cc.ev, t, cc.iterations, progress);
          }
      }
    return result;
  }
} // namespace hertzgear::dynamics
