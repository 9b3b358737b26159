#include "dynamics/integrator.h"

#include "common/errors.h"
#include "common/names.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace hertzgear::dynamics
{
  // Defined in sundials_integrators.cc.
  std::unique_ptr<Integrator> make_arkode_erk(const IntegratorSettings &settings);
  std::unique_ptr<Integrator> make_cvode_bdf(const IntegratorSettings &settings);
  std::unique_ptr<Integrator> make_arkode_dirk(const IntegratorSettings &settings);
  std::unique_ptr<Integrator> make_ida(const IntegratorSettings &settings);
  // Defined in radau_integrator.cc.
  std::unique_ptr<Integrator> make_radau_iia(const IntegratorSettings &settings);

  namespace
  {
    const NameTable<IntegratorKind, 6> integrator_names = {
      {"rk4", IntegratorKind::rk4},
      {"arkode-erk", IntegratorKind::arkode_erk},
      {"arkode-dirk", IntegratorKind::arkode_dirk},
      {"cvode-bdf", IntegratorKind::cvode_bdf},
      {"ida", IntegratorKind::ida},
      {"radau-iia", IntegratorKind::radau_iia}};
  } // namespace

  IntegratorKind integrator_kind_from_name(const std::string &name)
  {
    return from_name(name, integrator_names, "integrator");
  }

  std::string integrator_name(const IntegratorKind kind) { return name_of(kind, integrator_names); }

  IntegratorStats &IntegratorStats::operator+=(const IntegratorStats &o)
  {
    steps += o.steps;
    rejected_steps += o.rejected_steps;
    rhs_evals += o.rhs_evals;
    jacobian_evals += o.jacobian_evals;
    root_evals += o.root_evals;
    events += o.events;
    wall_time_s += o.wall_time_s;
    return *this;
  }

  void check_state(const OdeSystem &system, const double t, const double *y,
                   const std::string &who, const std::string &remedy)
  {
    check_state(system, system.blow_up_bounds(), t, y, who, remedy);
  }

  void check_state(const OdeSystem &system, const std::vector<double> &bounds, const double t,
                   const double *y, const std::string &who, const std::string &remedy)
  {
    for (unsigned i = 0; i < system.n_states(); ++i)
      if (!std::isfinite(y[i]) || std::abs(y[i]) > bounds[i])
        throw NumericalError(msg(who, (std::isfinite(y[i]) ? " blew up" : " produced a NaN/inf"),
                                 " at t = ", t, " s: ", system.describe_state(y), ". Remedy: ",
                                 remedy));
  }

  namespace
  {
    // The paper's classical fourth-order Runge-Kutta with a fixed step. It does not locate
    // events: a root function that changes sign over a step is reported at the step's end.
    class RungeKutta4 : public Integrator
    {
    public:
      explicit RungeKutta4(const IntegratorSettings &settings) : settings(settings)
      {
        HG_REQUIRE_INPUT(settings.fixed_step > 0.0, "rk4 needs a positive fixed step");
        statistics.name = "rk4";
      }

      void integrate(OdeSystem &system, const double t0, std::vector<double> &y,
                     const double output_interval, const long n_outputs,
                     const Observer &observer) override
      {
        const auto     start = std::chrono::steady_clock::now();
        const unsigned n     = system.n_states();
        // Steps per output interval, rounded up so that output times are hit exactly.
        const long n_sub =
          std::max(1L, long(std::ceil(output_interval / settings.fixed_step - 1e-9)));
        const double h = output_interval / n_sub;
        const std::string remedy =
          msg("the fixed step h = ", h, " s is too large for this stiff system; use "
              "{integrator} = radau-iia (the default) or cvode-bdf, or more {steps_per_period}");
        const std::vector<double> bounds = system.blow_up_bounds();

        std::vector<double> k1(n), k2(n), k3(n), k4(n), tmp(n), y_old(n), f_end(n);
        // With a step observer, f at a step's end is needed for its Hermite polynomial, and is
        // the next step's k1 unless an event changed the state there.
        bool       k1_known = false;
        const auto hermite  = [&](const double t_a, const double h_step) -> DenseOutput {
          return [&, t_a, h_step](const double tt, double *u) {
            // Cubic Hermite basis in s = (tt - t_a) / h through y and f at both ends.
            const double s   = (tt - t_a) / h_step;
            const double h00 = (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s);
            const double h10 = s * (1.0 - s) * (1.0 - s);
            const double h01 = s * s * (3.0 - 2.0 * s);
            const double h11 = s * s * (s - 1.0);
            for (unsigned i = 0; i < n; ++i)
              u[i] = h00 * y_old[i] + h_step * h10 * k1[i] + h01 * y[i] + h_step * h11 * f_end[i];
          };
        };
        const unsigned      n_roots = system.n_roots();
        std::vector<double> g_old(n_roots), g_new(n_roots);
        std::vector<int>    directions(n_roots);
        if (n_roots)
          system.roots(t0, y.data(), g_old.data());

        if (observer)
          observer(t0, y.data());
        for (long out = 1; out <= n_outputs; ++out)
          {
            for (long s = 0; s < n_sub; ++s)
              {
                const double t = t0 + ((out - 1) * n_sub + s) * h;
                if (!k1_known)
                  {
                    system.rhs(t, y.data(), k1.data());
                    ++statistics.rhs_evals;
                  }
                k1_known = false;
                if (step_observer)
                  std::copy(y.begin(), y.end(), y_old.begin());
                for (unsigned i = 0; i < n; ++i)
                  tmp[i] = y[i] + 0.5 * h * k1[i];
                system.rhs(t + 0.5 * h, tmp.data(), k2.data());
                for (unsigned i = 0; i < n; ++i)
                  tmp[i] = y[i] + 0.5 * h * k2[i];
                system.rhs(t + 0.5 * h, tmp.data(), k3.data());
                for (unsigned i = 0; i < n; ++i)
                  tmp[i] = y[i] + h * k3[i];
                system.rhs(t + h, tmp.data(), k4.data());
                for (unsigned i = 0; i < n; ++i)
                  y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
                statistics.rhs_evals += 3;
                ++statistics.steps;
                check_state(system, bounds, t + h, y.data(), "rk4", remedy);
                if (step_observer)
                  {
                    // The polynomial through y_old, k1 = f(t, y_old) and y, f_end = f(t + h, y).
                    system.rhs(t + h, y.data(), f_end.data());
                    ++statistics.rhs_evals;
                    step_observer(t, t + h, hermite(t, h));
                    std::copy(f_end.begin(), f_end.end(), k1.begin());
                    k1_known = true;
                  }

                if (n_roots)
                  {
                    system.roots(t + h, y.data(), g_new.data());
                    ++statistics.root_evals;
                    bool any = false;
                    for (unsigned r = 0; r < n_roots; ++r)
                      {
                        directions[r] = 0;
                        if ((g_old[r] < 0.0 && g_new[r] >= 0.0) ||
                            (g_old[r] > 0.0 && g_new[r] <= 0.0))
                          {
                            directions[r] = g_new[r] > g_old[r] ? 1 : -1;
                            any           = true;
                          }
                      }
                    if (any)
                      {
                        ++statistics.events;
                        k1_known = false; // the event may change the state or the contact law
                        if (system.handle_event(t + h, y.data(), directions.data()))
                          system.roots(t + h, y.data(), g_new.data());
                      }
                    g_old = g_new;
                  }
              }
            if (observer)
              observer(t0 + out * output_interval, y.data());
          }
        statistics.wall_time_s +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      }

    private:
      IntegratorSettings settings;
    };
  } // namespace

  std::unique_ptr<Integrator> make_integrator(const IntegratorSettings &settings)
  {
    HG_REQUIRE_INPUT(settings.relative_tolerance > 0.0 && settings.absolute_tolerance > 0.0,
                     "integrator tolerances must be positive");
    switch (settings.kind)
      {
        case IntegratorKind::rk4:
          return std::make_unique<RungeKutta4>(settings);
        case IntegratorKind::arkode_erk:
          return make_arkode_erk(settings);
        case IntegratorKind::cvode_bdf:
          return make_cvode_bdf(settings);
        case IntegratorKind::arkode_dirk:
          return make_arkode_dirk(settings);
        case IntegratorKind::ida:
          return make_ida(settings);
        case IntegratorKind::radau_iia:
          return make_radau_iia(settings);
      }
    throw InputError("unknown integrator");
  }
} // namespace hertzgear::dynamics
