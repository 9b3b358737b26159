// SUNDIALS integrators (6.x API with SUNContext): ARKODE ERK, CVODE BDF with a dense Jacobian, IDA.
// Each locates the roots of the system's root functions, lets the system handle the event and
// re-initialises the integrator at the event time, so that no step straddles a contact
// transition (the right-hand side is only piecewise smooth there).
#include "common/errors.h"
#include "dynamics/integrator.h"

#include <boost/math/tools/toms748_solve.hpp>

#include <arkode/arkode_arkstep.h>
#include <arkode/arkode_erkstep.h>
#include <cvode/cvode.h>
#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

namespace hertzgear::dynamics
{
  namespace
  {
    // RAII holders for the SUNDIALS objects.
    struct Context
    {
      SUNContext ctx = nullptr;
      Context()
      {
        HG_REQUIRE_NUMERIC(SUNContext_Create(nullptr, &ctx) == 0, "SUNContext_Create failed");
      }
      ~Context() { SUNContext_Free(&ctx); }
    };

    struct Vector
    {
      N_Vector v = nullptr;
      Vector(const unsigned n, SUNContext ctx) : v(N_VNew_Serial(n, ctx))
      {
        HG_REQUIRE_NUMERIC(v != nullptr, "N_VNew_Serial failed");
      }
      ~Vector() { N_VDestroy(v); }
      double *data() { return N_VGetArrayPointer(v); }
    };

    struct DenseSolver
    {
      SUNMatrix       A  = nullptr;
      SUNLinearSolver LS = nullptr;
      DenseSolver(const unsigned n, N_Vector y, SUNContext ctx)
        : A(SUNDenseMatrix(n, n, ctx)), LS(SUNLinSol_Dense(y, A, ctx))
      {
        HG_REQUIRE_NUMERIC(A && LS, "cannot create the dense linear solver");
      }
      ~DenseSolver()
      {
        SUNLinSolFree(LS);
        SUNMatDestroy(A);
      }
    };

    // What the C callbacks get as user data.
    struct CallbackData
    {
      OdeSystem  *system = nullptr;
      std::string last_error; // from the SUNDIALS error handler
    };

    bool all_finite(const double *v, const unsigned n)
    {
      for (unsigned i = 0; i < n; ++i)
        if (!std::isfinite(v[i]))
          return false;
      return true;
    }

    // Right-hand side; a non-finite value is a recoverable failure (the step is retried smaller).
    int rhs_callback(realtype t, N_Vector y, N_Vector y_dot, void *user_data)
    {
      auto *d = static_cast<CallbackData *>(user_data);
      d->system->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(y_dot));
      return all_finite(N_VGetArrayPointer(y_dot), d->system->n_states()) ? 0 : 1;
    }

    int root_callback(realtype t, N_Vector y, realtype *g, void *user_data)
    {
      auto *d = static_cast<CallbackData *>(user_data);
      d->system->roots(t, N_VGetArrayPointer(y), g);
      return 0;
    }

    int ida_root_callback(realtype t, N_Vector y, N_Vector, realtype *g, void *user_data)
    {
      return root_callback(t, y, g, user_data);
    }

    // SUNDIALS dense matrices are column-major; OdeSystem::jacobian is row-major.
    int jacobian_callback(realtype t, N_Vector y, N_Vector, SUNMatrix J, void *user_data, N_Vector,
                          N_Vector, N_Vector)
    {
      auto          *d = static_cast<CallbackData *>(user_data);
      const unsigned n = d->system->n_states();
      // Any state dimension (the gear pair's 2 or 3, and 12 with its sensitivities).
      thread_local std::vector<double> jac;
      jac.resize(std::size_t(n) * n);
      d->system->jacobian(t, N_VGetArrayPointer(y), jac.data());
      for (unsigned i = 0; i < n; ++i)
        for (unsigned j = 0; j < n; ++j)
          SM_ELEMENT_D(J, i, j) = jac[i * n + j];
      return all_finite(jac.data(), n * n) ? 0 : 1;
    }

    int residual_callback(realtype t, N_Vector y, N_Vector y_dot, N_Vector r, void *user_data)
    {
      auto *d = static_cast<CallbackData *>(user_data);
      d->system->residual(t, N_VGetArrayPointer(y), N_VGetArrayPointer(y_dot),
                          N_VGetArrayPointer(r));
      return all_finite(N_VGetArrayPointer(r), d->system->n_states()) ? 0 : 1;
    }

    void error_handler(int, const char *module, const char *function, char *message,
                       void *user_data)
    {
      static_cast<CallbackData *>(user_data)->last_error =
        msg(module, "/", function, ": ", message);
    }

    std::string remedy_for(const std::string &name)
    {
      if (name == "arkode-erk")
        return "the explicit integrator is limited by the stiffness of the Hertzian layer; use "
               "{integrator} = radau-iia (the default) or cvode-bdf";
      return "check that the scene is physical (positive stiffness, damping c > 0 unless "
             "integrator = ida), or relax {relative_tolerance}";
    }

    // Common driver of the output/event loop. The solver takes one internal step per call
    // (ONE_STEP mode), so that every step is seen: `advance(tout, t, directions)` takes it, leaves
    // the solution at its end (or at a located root) in y and t, and returns the solve function's
    // flag; `interpolate(t, out)` evaluates the solver's interpolant of the last step (its dense
    // output, valid back to the step's start). Output samples are taken from that interpolant, as
    // the solver's NORMAL mode does. The solver checks the root functions at the step's ends; as
    // in NORMAL mode they are also checked at the output times inside the step, so that two
    // roots within one step (a short contact, or a short loss of it) are found when an output
    // time separates them: the first is located on the interpolant (TOMS 748, to the solver's
    // root tolerance 100 u (|t| + |h|)) and treated as the solver's own root return. At a root,
    // the samples before it are taken before the event changes the state and `restart(t)`
    // re-initialises the solver there.
    template <typename Advance, typename Interpolate, typename IsRoot, typename Restart,
              typename Harvest>
    void drive(OdeSystem &system, CallbackData &data, const std::string &name, const double t0,
               double *y, const double output_interval, const long n_outputs,
               const Observer &observer, const StepObserver &step_observer,
               const long max_steps_per_output, Advance advance, Interpolate interpolate,
               IsRoot is_root, Restart restart, Harvest harvest, IntegratorStats &stats,
               const std::function<std::string(int)> &flag_name)
    {
      const unsigned      n       = system.n_states();
      const unsigned      n_roots = system.n_roots();
      std::vector<int>    directions(n_roots);
      std::vector<double> y_out(n), y_probe(n);
      // The root functions at the last point checked (the step's start or an output time).
      std::vector<double> g_ref(n_roots), g_probe(n_roots);
      double              t_ref = t0;
      if (n_roots)
        system.roots(t0, y, g_ref.data());
      const DenseOutput   dense = [&](const double tt, double *u) { interpolate(tt, u); };
      if (observer)
        observer(t0, y);
      double t          = t0; // the time of y
      double t_reported = t0; // where the last step report ended
      long   out        = 1;
      long   steps      = 0;  // since the last output sample
      // The samples up to t from the last step's interpolant.
      const auto sample_until = [&](const double t_end) {
        for (; out <= n_outputs && t0 + out * output_interval <= t_end; ++out)
          {
            const double tout = t0 + out * output_interval;
            if (tout == t)
              std::copy(y, y + n, y_out.begin());
            else
              interpolate(tout, y_out.data());
            if (observer)
              observer(tout, y_out.data());
            steps = 0;
          }
      };
      const double t_final = t0 + n_outputs * output_interval;
      while (out <= n_outputs)
        {
          const double tout = t0 + out * output_interval;
          if (++steps > max_steps_per_output)
            {
              harvest();
              throw NumericalError(msg(name, " took more than ", max_steps_per_output,
                                       " steps before t = ", tout, " s, at t = ", t, " s; state ",
                                       system.describe_state(y), ". Remedy: ", remedy_for(name)));
            }
          const int flag = advance(tout, t, directions.data());
          if (flag < 0)
            {
              harvest();
              throw NumericalError(msg(name, " failed at t = ", t, " s with ", flag_name(flag), " (",
                                       data.last_error, "); state ", system.describe_state(y),
                                       ". Remedy: ", remedy_for(name)));
            }
          check_state(system, t, y, name, remedy_for(name));
          bool found_root = is_root(flag);
          if (n_roots && !found_root)
            {
              // The output times inside the step (the solver checked its ends).
              for (long k = out; k <= n_outputs && t0 + k * output_interval < t; ++k)
                {
                  const double tk = t0 + k * output_interval;
                  interpolate(tk, y_probe.data());
                  system.roots(tk, y_probe.data(), g_probe.data());
                  ++stats.root_evals;
                  double t_root = tk;
                  int    i_root = -1;
                  for (unsigned i = 0; i < n_roots; ++i)
                    if (g_ref[i] * g_probe[i] < 0.0)
                      {
                        const auto g_i = [&](const double tt) {
                          interpolate(tt, y_probe.data());
                          std::vector<double> g(n_roots);
                          system.roots(tt, y_probe.data(), g.data());
                          ++stats.root_evals;
                          return g[i];
                        };
                        const double   t_tol = 100.0 * std::numeric_limits<double>::epsilon() *
                                             (std::abs(t) + (t - t_ref));
                        std::uintmax_t iterations = 100;
                        const auto     bracket    = boost::math::tools::toms748_solve(
                          g_i, t_ref, tk, g_ref[i], g_probe[i],
                          [t_tol](const double a, const double b) { return b - a <= t_tol; },
                          iterations);
                        if (bracket.second < t_root || i_root < 0)
                          {
                            t_root = bracket.second; // past the root, as the solver's root return
                            i_root = int(i);
                          }
                      }
                  if (i_root >= 0)
                    {
                      interpolate(t_root, y);
                      system.roots(t_root, y, g_probe.data());
                      for (unsigned i = 0; i < n_roots; ++i)
                        directions[i] = g_ref[i] * g_probe[i] < 0.0 || int(i) == i_root
                                          ? (g_ref[i] < 0.0 ? 1 : -1)
                                          : 0;
                      t          = t_root;
                      found_root = true;
                      break;
                    }
                  g_ref = g_probe;
                  t_ref = tk;
                }
            }
          // The part of the step within this call's range (the next call restarts at t_final).
          if (step_observer && std::min(t, t_final) > t_reported)
            step_observer(t_reported, std::min(t, t_final), dense);
          t_reported = t;
          sample_until(t);
          if (found_root)
            {
              ++stats.events;
              system.handle_event(t, y, directions.data());
              // Counters restart with the integrator: collect them first.
              harvest();
              restart(t);
            }
          if (n_roots)
            {
              system.roots(t, y, g_ref.data());
              ++stats.root_evals;
              t_ref = t;
            }
        }
      // The state at the last output time (the last step may have passed it).
      if (t != t_final)
        std::copy(y_out.begin(), y_out.end(), y);
      harvest();
    }
    void check_flag(const int flag, const char *what)
    {
      HG_REQUIRE_NUMERIC(flag >= 0, what, " failed with flag ", flag);
    }

    // Counters since the last (re)initialisation, as the SUNDIALS solver reports them.
    struct Counters
    {
      long steps = 0, rejected = 0, rhs = 0, jacobians = 0, roots = 0;
    };

    // What the four SUNDIALS integrators share: state and tolerance vectors, the event loop of
    // drive(), restarts, statistics accumulated across restarts, and freeing the solver memory
    // also when the integration throws. A solver adds its creation and settings, one advance
    // call, its re-initialisation, its counters and its flag names.
    class SundialsIntegrator : public Integrator
    {
    public:
      SundialsIntegrator(const IntegratorSettings &s, const std::string &name) : settings(s)
      {
        statistics.name = name;
      }

      void integrate(OdeSystem &system, const double t0, std::vector<double> &y0,
                     const double output_interval, const long n_outputs,
                     const Observer &observer) final
      {
        const auto     start = std::chrono::steady_clock::now();
        const unsigned n     = system.n_states();
        Context        context;
        Vector         y(n, context.ctx), atol(n, context.ctx);
        std::copy(y0.begin(), y0.end(), y.data());
        const auto a = system.absolute_tolerances(settings.absolute_tolerance);
        std::copy(a.begin(), a.end(), atol.data());
        CallbackData data{&system, {}};
        struct Release // the solver memory goes before the context, also on a throw
        {
          SundialsIntegrator &self;
          ~Release() { self.release(); }
        } release_at_exit{*this};
        create(system, context.ctx, t0, y.v, atol.v, data);

        Counters last;
        auto     harvest = [&]() {
          const Counters c = counters();
          statistics.steps += c.steps - last.steps;
          statistics.rejected_steps += c.rejected - last.rejected;
          statistics.rhs_evals += c.rhs - last.rhs;
          statistics.jacobian_evals += c.jacobians - last.jacobians;
          statistics.root_evals += c.roots - last.roots;
          last = c;
        };
        Vector dky(n, context.ctx);
        drive(
          system, data, statistics.name, t0, y.data(), output_interval, n_outputs, observer,
          step_observer, settings.max_steps_per_output,
          [&](const double tout, double &t, int *dirs) { return advance(tout, t, y.v, dirs); },
          [&](const double t, double *u) {
            check_flag(dense_output(t, dky.v), "the dense output (GetDky)");
            std::copy(dky.data(), dky.data() + n, u);
          },
          [&](const int flag) { return is_root(flag); },
          [&](const double t) {
            reinit(system, t, y.v);
            last = Counters{};
          },
          harvest, statistics, [&](const int flag) { return flag_name(flag); });
        std::copy(y.data(), y.data() + n, y0.begin());
        statistics.wall_time_s +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      }

    protected:
      // Create the solver memory for `system` from (t0, y) and apply the settings.
      virtual void        create(OdeSystem &system, SUNContext ctx, double t0, N_Vector y,
                                 N_Vector atol, CallbackData &data)          = 0;
      // One internal step of the solve function (ONE_STEP mode; tout sets the direction and the
      // first step's size); fills the root directions on a root return.
      virtual int         advance(double tout, double &t, N_Vector y, int *directions) = 0;
      // The interpolant of the last step at t (the solver's GetDky with k = 0).
      virtual int         dense_output(double t, N_Vector y) const                  = 0;
      virtual bool        is_root(int flag) const                             = 0;
      // Restart at t from y after an event.
      virtual void        reinit(OdeSystem &system, double t, N_Vector y)     = 0;
      virtual Counters    counters() const                                    = 0;
      virtual std::string flag_name(int flag) const                           = 0;
      // Free the solver memory and everything created with the context.
      virtual void        release()                                           = 0;

      IntegratorSettings           settings;
      void                        *mem = nullptr;
      std::unique_ptr<DenseSolver> dense;
    };

    class CvodeBdf final : public SundialsIntegrator
    {
    public:
      explicit CvodeBdf(const IntegratorSettings &s) : SundialsIntegrator(s, "cvode-bdf") {}

    private:
      void create(OdeSystem &system, SUNContext ctx, const double t0, N_Vector y, N_Vector atol,
                  CallbackData &data) override
      {
        mem = CVodeCreate(CV_BDF, ctx);
        HG_REQUIRE_NUMERIC(mem != nullptr, "CVodeCreate failed");
        dense = std::make_unique<DenseSolver>(system.n_states(), y, ctx);
        check_flag(CVodeInit(mem, rhs_callback, t0, y), "CVodeInit");
        check_flag(CVodeSetUserData(mem, &data), "CVodeSetUserData");
        check_flag(CVodeSetErrHandlerFn(mem, error_handler, &data), "CVodeSetErrHandlerFn");
        check_flag(CVodeSVtolerances(mem, settings.relative_tolerance, atol), "CVodeSVtolerances");
        check_flag(CVodeSetLinearSolver(mem, dense->LS, dense->A), "CVodeSetLinearSolver");
        if (system.has_jacobian())
          check_flag(CVodeSetJacFn(mem, jacobian_callback), "CVodeSetJacFn");
        check_flag(CVodeSetMaxNumSteps(mem, settings.max_steps_per_output), "CVodeSetMaxNumSteps");
        if (settings.max_order > 0)
          check_flag(CVodeSetMaxOrd(mem, settings.max_order), "CVodeSetMaxOrd");
        check_flag(CVodeSetStabLimDet(mem, settings.stability_limit_detection ? SUNTRUE : SUNFALSE),
                   "CVodeSetStabLimDet");
        if (settings.max_step > 0.0)
          check_flag(CVodeSetMaxStep(mem, settings.max_step), "CVodeSetMaxStep");
        if (system.n_roots() > 0)
          check_flag(CVodeRootInit(mem, system.n_roots(), root_callback), "CVodeRootInit");
      }
      int advance(const double tout, double &t, N_Vector y, int *directions) override
      {
        const int flag = CVode(mem, tout, y, &t, CV_ONE_STEP);
        if (flag == CV_ROOT_RETURN)
          CVodeGetRootInfo(mem, directions);
        return flag;
      }
      int  dense_output(const double t, N_Vector y) const override
      {
        return CVodeGetDky(mem, t, 0, y);
      }
      bool is_root(const int flag) const override { return flag == CV_ROOT_RETURN; }
      void reinit(OdeSystem &, const double t, N_Vector y) override
      {
        check_flag(CVodeReInit(mem, t, y), "CVodeReInit");
      }
      Counters counters() const override
      {
        long steps = 0, etf = 0, ncf = 0, nfe = 0, nfe_ls = 0, nje = 0, nge = 0;
        CVodeGetNumSteps(mem, &steps);
        CVodeGetNumErrTestFails(mem, &etf);
        CVodeGetNumNonlinSolvConvFails(mem, &ncf);
        CVodeGetNumRhsEvals(mem, &nfe);
        CVodeGetNumLinRhsEvals(mem, &nfe_ls);
        CVodeGetNumJacEvals(mem, &nje);
        CVodeGetNumGEvals(mem, &nge);
        return {steps, etf + ncf, nfe + nfe_ls, nje, nge};
      }
      std::string flag_name(const int flag) const override { return CVodeGetReturnFlagName(flag); }
      void        release() override
      {
        if (mem)
          CVodeFree(&mem);
        dense.reset();
      }
    };

    class ArkodeErk final : public SundialsIntegrator
    {
    public:
      explicit ArkodeErk(const IntegratorSettings &s) : SundialsIntegrator(s, "arkode-erk") {}

    private:
      void create(OdeSystem &system, SUNContext ctx, const double t0, N_Vector y, N_Vector atol,
                  CallbackData &data) override
      {
        mem = ERKStepCreate(rhs_callback, t0, y, ctx);
        HG_REQUIRE_NUMERIC(mem != nullptr, "ERKStepCreate failed");
        // Dormand-Prince 5(4): the explicit pair most readers know (MATLAB ode45, SciPy RK45).
        check_flag(ERKStepSetTableNum(mem, ARKODE_DORMAND_PRINCE_7_4_5), "ERKStepSetTableNum");
        check_flag(ERKStepSetUserData(mem, &data), "ERKStepSetUserData");
        check_flag(ERKStepSetErrHandlerFn(mem, error_handler, &data), "ERKStepSetErrHandlerFn");
        check_flag(ERKStepSVtolerances(mem, settings.relative_tolerance, atol),
                   "ERKStepSVtolerances");
        check_flag(ERKStepSetMaxNumSteps(mem, settings.max_steps_per_output),
                   "ERKStepSetMaxNumSteps");
        if (settings.max_step > 0.0)
          check_flag(ERKStepSetMaxStep(mem, settings.max_step), "ERKStepSetMaxStep");
        if (system.n_roots() > 0)
          check_flag(ERKStepRootInit(mem, system.n_roots(), root_callback), "ERKStepRootInit");
      }
      int advance(const double tout, double &t, N_Vector y, int *directions) override
      {
        const int flag = ERKStepEvolve(mem, tout, y, &t, ARK_ONE_STEP);
        if (flag == ARK_ROOT_RETURN)
          ERKStepGetRootInfo(mem, directions);
        return flag;
      }
      int  dense_output(const double t, N_Vector y) const override
      {
        return ERKStepGetDky(mem, t, 0, y);
      }
      bool is_root(const int flag) const override { return flag == ARK_ROOT_RETURN; }
      void reinit(OdeSystem &, const double t, N_Vector y) override
      {
        check_flag(ERKStepReInit(mem, rhs_callback, t, y), "ERKStepReInit");
      }
      Counters counters() const override
      {
        long steps = 0, etf = 0, nfe = 0, nge = 0;
        ERKStepGetNumSteps(mem, &steps);
        ERKStepGetNumErrTestFails(mem, &etf);
        ERKStepGetNumRhsEvals(mem, &nfe);
        ERKStepGetNumGEvals(mem, &nge);
        return {steps, etf, nfe, 0, nge};
      }
      std::string flag_name(const int flag) const override { return ERKStepGetReturnFlagName(flag); }
      void        release() override
      {
        if (mem)
          ERKStepFree(&mem);
      }
    };

    // Diagonally implicit RK (ARKODE ARKStep, implicit part only) with a dense Jacobian. Its
    // L-stable SDIRK/ESDIRK tables damp the lightly damped mesh mode instead of resolving it, which
    // BDF of order 3 to 5 cannot do near the imaginary axis.
    class ArkodeDirk final : public SundialsIntegrator
    {
    public:
      explicit ArkodeDirk(const IntegratorSettings &s) : SundialsIntegrator(s, "arkode-dirk") {}

    private:
      void create(OdeSystem &system, SUNContext ctx, const double t0, N_Vector y, N_Vector atol,
                  CallbackData &data) override
      {
        mem = ARKStepCreate(nullptr, rhs_callback, t0, y, ctx);
        HG_REQUIRE_NUMERIC(mem != nullptr, "ARKStepCreate failed");
        dense = std::make_unique<DenseSolver>(system.n_states(), y, ctx);
        check_flag(ARKStepSetUserData(mem, &data), "ARKStepSetUserData");
        check_flag(ARKStepSetErrHandlerFn(mem, error_handler, &data), "ARKStepSetErrHandlerFn");
        check_flag(ARKStepSVtolerances(mem, settings.relative_tolerance, atol),
                   "ARKStepSVtolerances");
        check_flag(ARKStepSetLinearSolver(mem, dense->LS, dense->A), "ARKStepSetLinearSolver");
        if (system.has_jacobian())
          check_flag(ARKStepSetJacFn(mem, jacobian_callback), "ARKStepSetJacFn");
        check_flag(ARKStepSetOrder(mem, settings.max_order > 0 ? settings.max_order : 4),
                   "ARKStepSetOrder");
        check_flag(ARKStepSetMaxNumSteps(mem, settings.max_steps_per_output),
                   "ARKStepSetMaxNumSteps");
        if (settings.max_step > 0.0)
          check_flag(ARKStepSetMaxStep(mem, settings.max_step), "ARKStepSetMaxStep");
        if (system.n_roots() > 0)
          check_flag(ARKStepRootInit(mem, system.n_roots(), root_callback), "ARKStepRootInit");
        // The stage equations are solved to 0.01 of the error tolerance (ARKODE's default is 0.1):
        // with 0.1, the error of the Poincare points across back-side impacts grew from 4e-8 um
        // at rtol 1e-10 to 1.2e-6 um at 1e-12; with 0.01 it stays below 4e-7 um (measured in
        // tests/dynamics/test_switching_convergence.cc).
        check_flag(ARKStepSetNonlinConvCoef(mem, 0.01), "ARKStepSetNonlinConvCoef");
      }
      int advance(const double tout, double &t, N_Vector y, int *directions) override
      {
        const int flag = ARKStepEvolve(mem, tout, y, &t, ARK_ONE_STEP);
        if (flag == ARK_ROOT_RETURN)
          ARKStepGetRootInfo(mem, directions);
        return flag;
      }
      int  dense_output(const double t, N_Vector y) const override
      {
        return ARKStepGetDky(mem, t, 0, y);
      }
      bool is_root(const int flag) const override { return flag == ARK_ROOT_RETURN; }
      void reinit(OdeSystem &, const double t, N_Vector y) override
      {
        check_flag(ARKStepReInit(mem, nullptr, rhs_callback, t, y), "ARKStepReInit");
      }
      Counters counters() const override
      {
        long steps = 0, etf = 0, ncf = 0, nfe = 0, nfi = 0, nfi_ls = 0, nje = 0, nge = 0;
        ARKStepGetNumSteps(mem, &steps);
        ARKStepGetNumErrTestFails(mem, &etf);
        ARKStepGetNumNonlinSolvConvFails(mem, &ncf);
        ARKStepGetNumRhsEvals(mem, &nfe, &nfi);
        ARKStepGetNumLinRhsEvals(mem, &nfi_ls);
        ARKStepGetNumJacEvals(mem, &nje);
        ARKStepGetNumGEvals(mem, &nge);
        return {steps, etf + ncf, nfi + nfi_ls, nje, nge};
      }
      std::string flag_name(const int flag) const override { return ARKStepGetReturnFlagName(flag); }
      void        release() override
      {
        if (mem)
          ARKStepFree(&mem);
        dense.reset();
      }
    };

    // IDA on the residual form F(t, y, y') = 0: the DAE when c = 0 (the penetration equation is
    // then algebraic), and the same model as a residual otherwise.
    class Ida final : public SundialsIntegrator
    {
    public:
      explicit Ida(const IntegratorSettings &s) : SundialsIntegrator(s, "ida") {}

    private:
      void create(OdeSystem &system, SUNContext ctx, const double t0, N_Vector y, N_Vector atol,
                  CallbackData &data) override
      {
        const unsigned n = system.n_states();
        yp = std::make_unique<Vector>(n, ctx);
        Vector id(n, ctx);
        system.consistent_initial_derivative(t0, N_VGetArrayPointer(y), yp->data());
        const auto ids = system.differential_components();
        std::copy(ids.begin(), ids.end(), id.data());

        mem = IDACreate(ctx);
        HG_REQUIRE_NUMERIC(mem != nullptr, "IDACreate failed");
        dense = std::make_unique<DenseSolver>(n, y, ctx);
        check_flag(IDAInit(mem, residual_callback, t0, y, yp->v), "IDAInit");
        check_flag(IDASetUserData(mem, &data), "IDASetUserData");
        check_flag(IDASetErrHandlerFn(mem, error_handler, &data), "IDASetErrHandlerFn");
        check_flag(IDASVtolerances(mem, settings.relative_tolerance, atol), "IDASVtolerances");
        check_flag(IDASetLinearSolver(mem, dense->LS, dense->A), "IDASetLinearSolver");
        check_flag(IDASetId(mem, id.v), "IDASetId");
        check_flag(IDASetMaxNumSteps(mem, settings.max_steps_per_output), "IDASetMaxNumSteps");
        if (settings.max_order > 0)
          check_flag(IDASetMaxOrd(mem, settings.max_order), "IDASetMaxOrd");
        if (settings.max_step > 0.0)
          check_flag(IDASetMaxStep(mem, settings.max_step), "IDASetMaxStep");
        if (system.n_roots() > 0)
          check_flag(IDARootInit(mem, system.n_roots(), ida_root_callback), "IDARootInit");
      }
      int advance(const double tout, double &t, N_Vector y, int *directions) override
      {
        const int flag = IDASolve(mem, tout, &t, y, yp->v, IDA_ONE_STEP);
        if (flag == IDA_ROOT_RETURN)
          IDAGetRootInfo(mem, directions);
        return flag;
      }
      int  dense_output(const double t, N_Vector y) const override
      {
        return IDAGetDky(mem, t, 0, y);
      }
      bool is_root(const int flag) const override { return flag == IDA_ROOT_RETURN; }
      void reinit(OdeSystem &system, const double t, N_Vector y) override
      {
        system.consistent_initial_derivative(t, N_VGetArrayPointer(y), yp->data());
        check_flag(IDAReInit(mem, t, y, yp->v), "IDAReInit");
      }
      Counters counters() const override
      {
        long steps = 0, etf = 0, ncf = 0, nre = 0, nre_ls = 0, nje = 0, nge = 0;
        IDAGetNumSteps(mem, &steps);
        IDAGetNumErrTestFails(mem, &etf);
        IDAGetNumNonlinSolvConvFails(mem, &ncf);
        IDAGetNumResEvals(mem, &nre);
        IDAGetNumLinResEvals(mem, &nre_ls);
        IDAGetNumJacEvals(mem, &nje);
        IDAGetNumGEvals(mem, &nge);
        return {steps, etf + ncf, nre + nre_ls, nje, nge};
      }
      std::string flag_name(const int flag) const override { return IDAGetReturnFlagName(flag); }
      void        release() override
      {
        if (mem)
          IDAFree(&mem);
        dense.reset();
        yp.reset();
      }

      std::unique_ptr<Vector> yp; // y'
    };
  } // namespace

  std::unique_ptr<Integrator> make_arkode_erk(const IntegratorSettings &s)
  {
    return std::make_unique<ArkodeErk>(s);
  }
  std::unique_ptr<Integrator> make_cvode_bdf(const IntegratorSettings &s)
  {
    return std::make_unique<CvodeBdf>(s);
  }
  std::unique_ptr<Integrator> make_arkode_dirk(const IntegratorSettings &s)
  {
    return std::make_unique<ArkodeDirk>(s);
  }
  std::unique_ptr<Integrator> make_ida(const IntegratorSettings &s)
  {
    return std::make_unique<Ida>(s);
  }
} // namespace hertzgear::dynamics
