#include "dynamics/periodic_orbit.h"

#include "common/errors.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hertzgear::dynamics
{
  namespace
  {
    // Phi_dot = J Phi for n x n matrices (J row-major, Phi column-major); N > 0: n == N known at
    // compile time.
    template <unsigned N>
    void jacobian_times_phi(const double *J, const double *Phi, double *Phi_dot, const unsigned n_rt)
    {
      const unsigned n = N > 0 ? N : n_rt;
      for (unsigned j = 0; j < n; ++j)
        for (unsigned i = 0; i < n; ++i)
          {
            double s = 0.0;
            for (unsigned k = 0; k < n; ++k)
              s += J[i * n + k] * Phi[k + j * n];
            Phi_dot[i + j * n] = s;
          }
    }
  } // namespace

  SensitivitySystem::SensitivitySystem(OdeSystem &base_system, std::vector<double> scales)
    : base(base_system), n(base_system.n_states()), scale(std::move(scales))
  {
    HG_REQUIRE_INPUT(n <= 8, "sensitivities: at most 8 states, the system has ", n);
    HG_REQUIRE_INPUT(scale.size() == n, "sensitivities: ", scale.size(), " scales for ", n,
                     " states");
    for (const double s : scale)
      HG_REQUIRE_INPUT(s > 0.0, "sensitivities: the state scales must be positive");
  }

  void SensitivitySystem::base_jacobian(const double t, const double *y, double *J) const
  {
    if (base.has_jacobian())
      {
        base.jacobian(t, y, J);
        return;
      }
    // Central differences, step 1e-6 of each component's scale (error ~1e-12 of the scale).
    std::vector<double> yp(y, y + n), fp(n), fm(n);
    for (unsigned j = 0; j < n; ++j)
      {
        const double h = 1e-6 * scale[j];
        yp[j]          = y[j] + h;
        base.rhs(t, yp.data(), fp.data());
        yp[j] = y[j] - h;
        base.rhs(t, yp.data(), fm.data());
        yp[j] = y[j];
        for (unsigned i = 0; i < n; ++i)
          J[i * n + j] = (fp[i] - fm[i]) / (2 * h);
      }
  }

  void SensitivitySystem::rhs(const double t, const double *y, double *y_dot)
  {
    double J[64];
    if (base.has_jacobian())
      base.rhs_and_jacobian(t, y, y_dot, J);
    else
      {
        base.rhs(t, y, y_dot);
        base_jacobian(t, y, J);
      }
    // Phi' = J Phi (Phi column-major: Phi_kj at k + j n), unrolled for the pair's 2 and 3 states.
    if (n == 3)
      jacobian_times_phi<3>(J, y + n, y_dot + n, n);
    else if (n == 2)
      jacobian_times_phi<2>(J, y + n, y_dot + n, n);
    else
      jacobian_times_phi<0>(J, y + n, y_dot + n, n);
  }

  void SensitivitySystem::jacobian(const double t, const double *y, double *jac) const
  {
    const unsigned N = n_states();
    std::fill(jac, jac + std::size_t(N) * N, 0.0);
    double J[64];
    base_jacobian(t, y, J);
    for (unsigned i = 0; i < n; ++i)
      for (unsigned k = 0; k < n; ++k)
        {
          jac[i * N + k] = J[i * n + k];
          for (unsigned j = 0; j < n; ++j) // d(Phi_ij)'/d(Phi_kj) = J_ik: block j is J
            jac[(n + i + j * n) * N + (n + k + j * n)] = J[i * n + k];
        }
  }

  std::vector<double> SensitivitySystem::absolute_tolerances(const double displacement_tolerance) const
  {
    std::vector<double> a = base.absolute_tolerances(displacement_tolerance);
    a.resize(n_states());
    for (unsigned i = 0; i < n; ++i)
      for (unsigned j = 0; j < n; ++j)
        a[n + i + j * n] = a[i] / scale[j];
    return a;
  }

  std::vector<double> SensitivitySystem::blow_up_bounds() const
  {
    std::vector<double> b = base.blow_up_bounds();
    b.resize(n_states(), 1e200);
    return b;
  }

  void SensitivitySystem::one_side(const double t, const double *y, const unsigned r, const int side,
                                   const double *grad, double *f) const
  {
    // The step v with grad . v = 1 that moves least in the scaled norm.
    double gs2 = 0.0;
    for (unsigned i = 0; i < n; ++i)
      gs2 += grad[i] * grad[i] * scale[i] * scale[i];
    const unsigned      nr = base.n_roots();
    std::vector<double> g(nr), v(n), y0(y, y + n), g0(nr), gv(nr);
    base.roots(t, y, g.data());
    for (unsigned i = 0; i < n; ++i)
      {
        v[i] = scale[i] * scale[i] * grad[i] / gs2;
        y0[i] -= g[r] * v[i]; // on the surface
      }
    // The two points must lie on this side of surface r and on no other surface's far side: where
    // another switching lies within the offset (two switchings a picosecond apart, as where a
    // contact closes and its layer's own root changes sign at once), the offset shrinks to a
    // quarter of the distance to it along v, so that f is that of the zone between them.
    double eps = 1e-7 * std::sqrt(gs2);
    base.roots(t, y0.data(), g0.data());
    {
      std::vector<double> yv(y0);
      for (unsigned i = 0; i < n; ++i)
        yv[i] += side * eps * v[i];
      base.roots(t, yv.data(), gv.data());
    }
    for (unsigned k = 0; k < nr; ++k)
      {
        const double slope = (gv[k] - g0[k]) / eps; // dg_k along side * v (linear in a zone)
        if (k == r || slope == 0.0 || (g0[k] != 0.0 && g0[k] * slope > 0.0))
          continue; // moving away from surface k (or along it)
        if (g0[k] != 0.0)
          eps = std::min(eps, 0.25 * std::abs(g0[k] / slope));
      }
    eps = std::max(eps, 1e-13 * std::sqrt(gs2));
    std::vector<double> ya(y0), yb(y0), fa(n), fb(n);
    for (unsigned i = 0; i < n; ++i)
      {
        ya[i] += side * eps * v[i];
        yb[i] += side * 2 * eps * v[i];
      }
    base.rhs(t, ya.data(), fa.data());
    base.rhs(t, yb.data(), fb.data());
    for (unsigned i = 0; i < n; ++i)
      f[i] = 2 * fa[i] - fb[i];
  }

  bool SensitivitySystem::handle_event(const double t, double *y, const int *directions)
  {
    const unsigned nr = base.n_roots();
    unsigned       r  = nr;
    for (unsigned i = 0; i < nr && r == nr; ++i)
      if (directions[i] != 0)
        r = i;
    if (r == nr || base.root_seam(t, y, r))
      return base.handle_event(t, y, directions);
    const int dir = directions[r];

    // grad(g_r) and dg_r/dt by central differences; the root functions are linear in the state
    // within a zone and smooth in t, so these are exact to rounding.
    std::vector<double> gp(nr), gm(nr), yp(y, y + n), grad(n);
    for (unsigned i = 0; i < n; ++i)
      {
        const double h = 1e-6 * scale[i];
        yp[i]          = y[i] + h;
        base.roots(t, yp.data(), gp.data());
        yp[i] = y[i] - h;
        base.roots(t, yp.data(), gm.data());
        yp[i]   = y[i];
        grad[i] = (gp[r] - gm[r]) / (2 * h);
      }
    const double tau = 1e-6 * scale[0] / scale[1]; // a millionth of the state's time scale
    base.roots(t + tau, y, gp.data());
    base.roots(t - tau, y, gm.data());
    const double g_t = (gp[r] - gm[r]) / (2 * tau);

    std::vector<double> f_minus(n), f_plus(n);
    one_side(t, y, r, -dir, grad.data(), f_minus.data());
    const bool changed = base.handle_event(t, y, directions);
    one_side(t, y, r, dir, grad.data(), f_plus.data());

    double g_dot = g_t, g_size = std::abs(g_t);
    for (unsigned i = 0; i < n; ++i)
      {
        g_dot += grad[i] * f_minus[i];
        g_size += std::abs(grad[i] * f_minus[i]);
      }
    min_crossing = std::min(min_crossing, g_size > 0 ? std::abs(g_dot) / g_size : 0.0);
    ++n_events;
    if (g_dot == 0.0)
      return changed; // grazing: no finite saltation matrix (smallest_crossing_speed() = 0)

    // Phi <- S Phi with S = I + (f+ - f-) grad^T / g_dot.
    double *Phi = y + n;
    for (unsigned j = 0; j < n; ++j)
      {
        double gPhi = 0.0;
        for (unsigned k = 0; k < n; ++k)
          gPhi += grad[k] * Phi[k + j * n];
        for (unsigned i = 0; i < n; ++i)
          Phi[i + j * n] += (f_plus[i] - f_minus[i]) * gPhi / g_dot;
      }
    return true;
  }

  FlowWithSensitivity flow_with_sensitivity(OdeSystem &system, const std::vector<double> &scales,
                                            Integrator &integrator, const double t0,
                                            const std::vector<double> &y0, const double duration)
  {
    SensitivitySystem   aug(system, scales);
    const unsigned      n = system.n_states();
    std::vector<double> Y(aug.n_states(), 0.0);
    std::copy(y0.begin(), y0.end(), Y.begin());
    for (unsigned i = 0; i < n; ++i)
      Y[n + i + i * n] = 1.0;
    integrator.integrate(aug, t0, Y, duration, 1, [](double, const double *) {});
    FlowWithSensitivity out;
    out.y.assign(Y.begin(), Y.begin() + n);
    out.jacobian.resize(n, n);
    for (unsigned i = 0; i < n; ++i)
      for (unsigned j = 0; j < n; ++j)
        out.jacobian(i, j) = Y[n + i + j * n];
    out.events = aug.events();
    return out;
  }

  IntegratorSettings sensitivity_integrator(IntegratorSettings settings)
  {
    // Radau IIA's periodic starting values serve a motion integrated over many periods; a flow
    // over one period has no period before it, and keeping its steps costs more than its
    // arithmetic at 12 states.
    settings.periodic_start = false;
    // The steps of a flow over one period are set by the error test on the state and its
    // sensitivities (the mesh mode is resolved while Phi decays), not by an output grid, so a
    // higher order pays: below rtol 1e-7 radau-iia takes 7 stages instead of the 5 of its
    // default (docs/accuracy-dynamics.md, "Stages of a flow with sensitivities").
    if (settings.kind == IntegratorKind::radau_iia && settings.stages == 0 &&
        settings.relative_tolerance < 1e-7)
      settings.stages = 7;
    return settings;
  }

  void check_shooting_settings(const ShootingSettings &s)
  {
    if (s.integrator.kind == IntegratorKind::rk4)
      throw ParameterError("integrator", "rk4 cannot serve the shooting method: it does not locate "
                                         "the switching events the saltation matrices need; take "
                                         "radau-iia, cvode-bdf, arkode-erk, arkode-dirk or ida");
    if (s.period_multiple < 1 || s.period_multiple > 64)
      throw ParameterError("period_multiple", msg(s.period_multiple, " is outside 1 ... 64"));
    if (s.segments < 1 || s.segments > 64)
      throw ParameterError("segments", msg(s.segments, " is outside 1 ... 64"));
    if (!(s.tolerance > 0.0 && s.tolerance < 1e-2))
      throw ParameterError("tolerance", msg(s.tolerance, " is outside (0, 1e-2)"));
    if (s.max_iterations < 1)
      throw ParameterError("max_iterations", msg(s.max_iterations, " must be at least 1"));
  }

  std::vector<std::complex<double>> floquet_multipliers(const Eigen::MatrixXd &M)
  {
    Eigen::EigenSolver<Eigen::MatrixXd> es(M, false);
    std::vector<std::complex<double>>   mu;
    for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i)
      mu.push_back(es.eigenvalues()(i));
    std::stable_sort(mu.begin(), mu.end(), [](const auto &a, const auto &b) {
      return std::abs(a) > std::abs(b) || (std::abs(a) == std::abs(b) && a.imag() > b.imag());
    });
    return mu;
  }

  namespace
  {
    // The residual and Jacobian of multiple shooting at the unknowns X = (x_0 ... x_{m-1}):
    // R_i = phi_i(x_i) - x_{i+1 mod m}, in scaled variables.
    struct ShootingEvaluation
    {
      Eigen::VectorXd              R;    // scaled
      Eigen::MatrixXd              J;    // scaled
      std::vector<Eigen::MatrixXd> Phi;  // unscaled segment Jacobians
      double                       norm = 0.0; // max |R_i|
      long                         events = 0;
    };

    ShootingEvaluation evaluate_shooting(GearPairModel &model, Integrator &integrator,
                                         const std::vector<double> &scale, std::vector<double> &X,
                                         const int m, const double segment, const bool chain)
    {
      const unsigned     n = model.n_states();
      ShootingEvaluation ev;
      ev.R = Eigen::VectorXd::Zero(n * m);
      ev.J = Eigen::MatrixXd::Zero(n * m, n * m);
      for (int i = 0; i < m; ++i)
        {
          std::vector<double> xi(X.begin() + i * n, X.begin() + (i + 1) * n);
          const auto flow = flow_with_sensitivity(model, scale, integrator, i * segment, xi, segment);
          const int  next = (i + 1) % m;
          if (chain && next != 0) // the first evaluation starts every segment where the last ended
            std::copy(flow.y.begin(), flow.y.end(), X.begin() + next * n);
          for (unsigned a = 0; a < n; ++a)
            {
              ev.R(i * n + a) = (flow.y[a] - X[next * n + a]) / scale[a];
              for (unsigned b = 0; b < n; ++b)
                ev.J(i * n + a, i * n + b) += flow.jacobian(a, b) * scale[b] / scale[a];
              ev.J(i * n + a, next * n + a) -= 1.0;
            }
          ev.Phi.push_back(flow.jacobian);
          ev.events += flow.events;
        }
      ev.norm = ev.R.lpNorm<Eigen::Infinity>();
      return ev;
    }
  } // namespace

  PeriodicOrbit find_periodic_orbit(GearPairModel &model, const std::vector<double> &guess,
                                    const ShootingSettings &settings)
  {
    check_shooting_settings(settings);
    const unsigned n = model.n_states();
    HG_REQUIRE_INPUT(guess.size() == n, "the orbit's starting guess has ", guess.size(),
                     " components, the model ", n);
    const int    m       = settings.segments;
    const double period  = settings.period_multiple * model.mesh_period();
    const double segment = period / m;
    const auto   scale   = model.state_scales();
    auto         integrator = make_integrator(sensitivity_integrator(settings.integrator));

    PeriodicOrbit orbit;
    orbit.t0_s            = 0.0;
    orbit.period_s        = period;
    orbit.period_multiple = settings.period_multiple;

    std::vector<double> X(n * m, 0.0);
    std::copy(guess.begin(), guess.end(), X.begin());
    std::vector<double> X_prev;
    Eigen::VectorXd     step_prev;
    double              norm_prev = 0.0, lambda = 1.0;
    bool                first = true;
    auto fail = [&](const std::string &why) {
      orbit.converged = false;
      orbit.failure   = why;
      orbit.state.assign(X.begin(), X.begin() + n);
      orbit.stats = integrator->stats();
      return orbit;
    };

    for (int it = 0; it < settings.max_iterations;)
      {
        ShootingEvaluation ev;
        try
          {
            ev = evaluate_shooting(model, *integrator, scale, X, m, segment, first);
          }
        catch (const NumericalError &e)
          {
            if (first || lambda < 1.0 / 256)
              return fail(msg("the integration failed: ", e.what()));
            lambda *= 0.5; // a trial step too far: back off
            for (std::size_t i = 0; i < X.size(); ++i)
              X[i] = X_prev[i] + lambda * step_prev(i) * scale[i % n];
            continue;
          }
        if (!first && !(ev.norm < norm_prev * (1.0 - 1e-4 * lambda)) && ev.norm > settings.tolerance)
          {
            if (lambda < 1.0 / 256)
              return fail(msg("Newton's method does not reduce the residual (", norm_prev,
                              " of the state scale after ", it, " iterations)"));
            lambda *= 0.5;
            for (std::size_t i = 0; i < X.size(); ++i)
              X[i] = X_prev[i] + lambda * step_prev(i) * scale[i % n];
            continue;
          }
        first = false;
        ++it;
        Eigen::PartialPivLU<Eigen::MatrixXd> lu(ev.J);
        const Eigen::VectorXd step = lu.solve(-ev.R);
        if (!step.allFinite())
          {
            // An iterate that flies through the backlash for the whole period without a
            // switching event carries no mesh force: its period map is a free flight, whose
            // monodromy has the block [[1, kT], [0, 1]] in (x, x'), a double multiplier at +1
            // (met from rough starts in a chaotic region, tests/dynamics/test_chaotic_region.cc).
            bool free_flight = ev.events == 0 && model.n_roots() > 0;
            for (int i = 0; i < m && free_flight; ++i)
              free_flight = model.mesh_state(i * segment, X.data() + i * n).contact == 0;
            if (free_flight)
              return fail(msg("the shooting Jacobian is singular: the iterate after ", it - 1,
                              " Newton step", it - 1 == 1 ? "" : "s",
                              " flies through the backlash without contact for the whole period, "
                              "a free flight with a double Floquet multiplier at +1; start from "
                              "a state in contact"));
            return fail("the shooting Jacobian is singular (a Floquet multiplier at +1: a fold or "
                        "a branch point)");
          }
        const double correction = step.lpNorm<Eigen::Infinity>();
        X_prev                  = X;
        step_prev               = step;
        norm_prev               = ev.norm;
        lambda                  = 1.0;
        for (std::size_t i = 0; i < X.size(); ++i)
          X[i] += step(i) * scale[i % n];
        orbit.iterations = it;
        orbit.correction = correction;
        orbit.residual   = ev.norm;
        if (correction < settings.tolerance)
          {
            Eigen::MatrixXd M = Eigen::MatrixXd::Identity(n, n);
            for (int i = 0; i < m; ++i)
              M = ev.Phi[i] * M;
            orbit.converged  = true;
            orbit.state.assign(X.begin(), X.begin() + n);
            orbit.monodromy  = M;
            orbit.multipliers = floquet_multipliers(M);
            orbit.largest_multiplier_modulus = std::abs(orbit.multipliers.front());
            orbit.stable     = orbit.largest_multiplier_modulus < 1.0;
            orbit.events_per_period = ev.events;
            orbit.stats      = integrator->stats();
            return orbit;
          }
      }
    return fail(msg("Newton's method did not converge in ", settings.max_iterations,
                    " iterations (last scaled correction ", orbit.correction, ", tolerance ",
                    settings.tolerance, ")"));
  }

  SteadyStateSummary analyse_orbit(GearPairModel &model, const PeriodicOrbit &orbit,
                                   const RunSettings &run)
  {
    HG_REQUIRE_INPUT(orbit.converged, "no periodic orbit to analyse");
    RunSettings settings       = run;
    settings.periods           = orbit.period_multiple;
    settings.transient_periods = 0;
    const auto result          = simulate(model, settings, orbit.state);
    SteadyStateSummary s       = analyse(model, result);
    s.period_multiplicity      = orbit.period_multiple;
    s.period_status            = msg("period-", orbit.period_multiple);
    s.period_candidate         = orbit.period_multiple;
    s.period_contraction       = std::pow(orbit.largest_multiplier_modulus, 1.0 / orbit.period_multiple);
    s.period_distance          = orbit.correction;
    return s;
  }
} // namespace hertzgear::dynamics
