// SUNDIALS integrators (6.x API with SUNContext): ARKODE ERK, CVODE BDF with a dense Jacobian, IDA.
// Each locates the roots of the system's root functions, lets the system handle the event and
// re-initialises the integrator at the event time, so that no step straddles a contact
// transition (the right-hand side is only piecewise smooth there).
#include "common/errors.h"
#include "dynamics/integrator.h"

#include <arkode/arkode_arkstep.h>
#include <arkode/arkode_erkstep.h>
#include <cvode/cvode.h>
#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <chrono>
#include <cmath>

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
      double         jac[16];
      d->system->jacobian(t, N_VGetArrayPointer(y), jac);
      for (unsigned i = 0; i < n; ++i)
        for (unsigned j = 0; j < n; ++j)
          SM_ELEMENT_D(J, i, j) = jac[i * n + j];
      return all_finite(jac, n * n) ? 0 : 1;
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
               "Dynamics/integrator = cvode-bdf";
      return "check that the scene is physical (positive stiffness, damping c > 0 unless "
             "integrator = ida), or relax Dynamics/relative_tolerance";
    }

    // Common driver of the output/event loop. `advance(tout, t)` takes one call of the
    // SUNDIALS solve function and returns its flag; `is_root(flag)` and `restart(t)` as named.
    template <typename Advance, typename IsRoot, typename Restart, typename Harvest>
    void drive(OdeSystem &system, CallbackData &data, const std::string &name, const double t0,
               double *y, const double output_interval, const long n_outputs,
               const Observer &observer, Advance advance, IsRoot is_root, Restart restart,
               Harvest harvest, IntegratorStats &stats, const std::function<std::string(int)> &flag_name)
    {
      const unsigned   n_roots = system.n_roots();
      std::vector<int> directions(n_roots);
      if (observer)
        observer(t0, y);
      double t = t0;
      for (long out = 1; out <= n_outputs; ++out)
        {
          const double tout = t0 + out * output_interval;
          while (t < tout)
            {
              const int flag = advance(tout, t, directions.data());
              if (flag < 0)
                {
                  harvest();
                  throw NumericalError(msg(name, " failed at t = ", t, " s with ", flag_name(flag),
                                           " (", data.last_error, "); state ",
                                           system.describe_state(y), ". Remedy: ",
                                           remedy_for(name)));
                }
              check_state(system, t, y, name, remedy_for(name));
              if (is_root(flag))
                {
                  ++stats.events;
                  system.handle_event(t, y, directions.data());
                  // Counters restart with the integrator: collect them first.
                  harvest();
                  restart(t);
                }
              else
                break; // reached tout
            }
          if (observer)
            observer(tout, y);
          t = tout;
        }
      harvest();
    }

    class CvodeBdf : public Integrator
    {
    public:
      explicit CvodeBdf(const IntegratorSettings &s) : settings(s) { statistics.name = "cvode-bdf"; }

      void integrate(OdeSystem &system, const double t0, std::vector<double> &y0,
                     const double output_interval, const long n_outputs,
                     const Observer &observer) override
      {
        const auto     start = std::chrono::steady_clock::now();
        const unsigned n     = system.n_states();
        Context        context;
        Vector         y(n, context.ctx), atol(n, context.ctx);
        std::copy(y0.begin(), y0.end(), y.data());
        const auto a = system.absolute_tolerances(settings.absolute_tolerance);
        std::copy(a.begin(), a.end(), atol.data());
        CallbackData data{&system, {}};

        void *mem = CVodeCreate(CV_BDF, context.ctx);
        HG_REQUIRE_NUMERIC(mem != nullptr, "CVodeCreate failed");
        struct Free
        {
          void *&m;
          ~Free() { CVodeFree(&m); }
        } free_mem{mem};
        DenseSolver dense(n, y.v, context.ctx);
        auto        check = [](const int flag, const char *what) {
          HG_REQUIRE_NUMERIC(flag >= 0, what, " failed with flag ", flag);
        };
        check(CVodeInit(mem, rhs_callback, t0, y.v), "CVodeInit");
        check(CVodeSetUserData(mem, &data), "CVodeSetUserData");
        check(CVodeSetErrHandlerFn(mem, error_handler, &data), "CVodeSetErrHandlerFn");
        check(CVodeSVtolerances(mem, settings.relative_tolerance, atol.v), "CVodeSVtolerances");
        check(CVodeSetLinearSolver(mem, dense.LS, dense.A), "CVodeSetLinearSolver");
        if (system.has_jacobian())
          check(CVodeSetJacFn(mem, jacobian_callback), "CVodeSetJacFn");
        check(CVodeSetMaxNumSteps(mem, settings.max_steps_per_output), "CVodeSetMaxNumSteps");
        if (settings.max_order > 0)
          check(CVodeSetMaxOrd(mem, settings.max_order), "CVodeSetMaxOrd");
        check(CVodeSetStabLimDet(mem, settings.stability_limit_detection ? SUNTRUE : SUNFALSE),
              "CVodeSetStabLimDet");
        if (settings.max_step > 0.0)
          check(CVodeSetMaxStep(mem, settings.max_step), "CVodeSetMaxStep");
        if (system.n_roots() > 0)
          check(CVodeRootInit(mem, system.n_roots(), root_callback), "CVodeRootInit");

        auto harvest = [&]() {
          long steps = 0, etf = 0, ncf = 0, nfe = 0, nfe_ls = 0, nje = 0, nge = 0;
          CVodeGetNumSteps(mem, &steps);
          CVodeGetNumErrTestFails(mem, &etf);
          CVodeGetNumNonlinSolvConvFails(mem, &ncf);
          CVodeGetNumRhsEvals(mem, &nfe);
          CVodeGetNumLinRhsEvals(mem, &nfe_ls);
          CVodeGetNumJacEvals(mem, &nje);
          CVodeGetNumGEvals(mem, &nge);
          statistics.steps += steps - last.steps;
          statistics.rejected_steps += etf + ncf - last.rejected_steps;
          statistics.rhs_evals += nfe + nfe_ls - last.rhs_evals;
          statistics.jacobian_evals += nje - last.jacobian_evals;
          statistics.root_evals += nge - last.root_evals;
          last = {"", steps, etf + ncf, nfe + nfe_ls, nje, nge, 0, 0.0};
        };
        last = IntegratorStats{};
        drive(
          system, data, "cvode-bdf", t0, y.data(), output_interval, n_outputs, observer,
          [&](const double tout, double &t, int *dirs) {
            const int flag = CVode(mem, tout, y.v, &t, CV_NORMAL);
            if (flag == CV_ROOT_RETURN)
              CVodeGetRootInfo(mem, dirs);
            return flag;
          },
          [](const int flag) { return flag == CV_ROOT_RETURN; },
          [&](const double t) {
            check(CVodeReInit(mem, t, y.v), "CVodeReInit");
            last = IntegratorStats{};
          },
          harvest, statistics, [](int f) { return std::string(CVodeGetReturnFlagName(f)); });
        std::copy(y.data(), y.data() + n, y0.begin());
        statistics.wall_time_s +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      }

    private:
      IntegratorSettings settings;
      IntegratorStats    last;
    };

    class ArkodeErk : public Integrator
    {
    public:
      explicit ArkodeErk(const IntegratorSettings &s) : settings(s) { statistics.name = "arkode-erk"; }

      void integrate(OdeSystem &system, const double t0, std::vector<double> &y0,
                     const double output_interval, const long n_outputs,
                     const Observer &observer) override
      {
        const auto     start = std::chrono::steady_clock::now();
        const unsigned n     = system.n_states();
        Context        context;
        Vector         y(n, context.ctx), atol(n, context.ctx);
        std::copy(y0.begin(), y0.end(), y.data());
        const auto a = system.absolute_tolerances(settings.absolute_tolerance);
        std::copy(a.begin(), a.end(), atol.data());
        CallbackData data{&system, {}};

        void *mem = ERKStepCreate(rhs_callback, t0, y.v, context.ctx);
        HG_REQUIRE_NUMERIC(mem != nullptr, "ERKStepCreate failed");
        struct Free
        {
          void *&m;
          ~Free() { ERKStepFree(&m); }
        } free_mem{mem};
        auto check = [](const int flag, const char *what) {
          HG_REQUIRE_NUMERIC(flag >= 0, what, " failed with flag ", flag);
        };
        // Dormand-Prince 5(4): the explicit pair most readers know (MATLAB ode45, SciPy RK45).
        check(ERKStepSetTableNum(mem, ARKODE_DORMAND_PRINCE_7_4_5), "ERKStepSetTableNum");
        check(ERKStepSetUserData(mem, &data), "ERKStepSetUserData");
        check(ERKStepSetErrHandlerFn(mem, error_handler, &data), "ERKStepSetErrHandlerFn");
        check(ERKStepSVtolerances(mem, settings.relative_tolerance, atol.v), "ERKStepSVtolerances");
        check(ERKStepSetMaxNumSteps(mem, settings.max_steps_per_output), "ERKStepSetMaxNumSteps");
        if (settings.max_step > 0.0)
          check(ERKStepSetMaxStep(mem, settings.max_step), "ERKStepSetMaxStep");
        if (system.n_roots() > 0)
          check(ERKStepRootInit(mem, system.n_roots(), root_callback), "ERKStepRootInit");

        auto harvest = [&]() {
          long steps = 0, etf = 0, nfe = 0, nge = 0;
          ERKStepGetNumSteps(mem, &steps);
          ERKStepGetNumErrTestFails(mem, &etf);
          ERKStepGetNumRhsEvals(mem, &nfe);
          ERKStepGetNumGEvals(mem, &nge);
          statistics.steps += steps - last.steps;
          statistics.rejected_steps += etf - last.rejected_steps;
          statistics.rhs_evals += nfe - last.rhs_evals;
          statistics.root_evals += nge - last.root_evals;
          last = {"", steps, etf, nfe, 0, nge, 0, 0.0};
        };
        last = IntegratorStats{};
        drive(
          system, data, "arkode-erk", t0, y.data(), output_interval, n_outputs, observer,
          [&](const double tout, double &t, int *dirs) {
            const int flag = ERKStepEvolve(mem, tout, y.v, &t, ARK_NORMAL);
            if (flag == ARK_ROOT_RETURN)
              ERKStepGetRootInfo(mem, dirs);
            return flag;
          },
          [](const int flag) { return flag == ARK_ROOT_RETURN; },
          [&](const double t) {
            check(ERKStepReInit(mem, rhs_callback, t, y.v), "ERKStepReInit");
            last = IntegratorStats{};
          },
          harvest, statistics, [](int f) { return std::string(ERKStepGetReturnFlagName(f)); });
        std::copy(y.data(), y.data() + n, y0.begin());
        statistics.wall_time_s +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      }

    private:
      IntegratorSettings settings;
      IntegratorStats    last;
    };

    // Diagonally implicit RK (ARKODE ARKStep, implicit part only) with a dense Jacobian. Its
    // L-stable SDIRK/ESDIRK tables damp the lightly damped mesh mode instead of resolving it, which
    // BDF of order 3 to 5 cannot do near the imaginary axis.
    class ArkodeDirk : public Integrator
    {
    public:
      explicit ArkodeDirk(const IntegratorSettings &s) : settings(s) { statistics.name = "arkode-dirk"; }

      void integrate(OdeSystem &system, const double t0, std::vector<double> &y0,
                     const double output_interval, const long n_outputs,
                     const Observer &observer) override
      {
        const auto     start = std::chrono::steady_clock::now();
        const unsigned n     = system.n_states();
        Context        context;
        Vector         y(n, context.ctx), atol(n, context.ctx);
        std::copy(y0.begin(), y0.end(), y.data());
        const auto a = system.absolute_tolerances(settings.absolute_tolerance);
        std::copy(a.begin(), a.end(), atol.data());
        CallbackData data{&system, {}};

        void *mem = ARKStepCreate(nullptr, rhs_callback, t0, y.v, context.ctx);
        HG_REQUIRE_NUMERIC(mem != nullptr, "ARKStepCreate failed");
        struct Free
        {
          void *&m;
          ~Free() { ARKStepFree(&m); }
        } free_mem{mem};
        DenseSolver dense(n, y.v, context.ctx);
        auto        check = [](const int flag, const char *what) {
          HG_REQUIRE_NUMERIC(flag >= 0, what, " failed with flag ", flag);
        };
        check(ARKStepSetUserData(mem, &data), "ARKStepSetUserData");
        check(ARKStepSetErrHandlerFn(mem, error_handler, &data), "ARKStepSetErrHandlerFn");
        check(ARKStepSVtolerances(mem, settings.relative_tolerance, atol.v), "ARKStepSVtolerances");
        check(ARKStepSetLinearSolver(mem, dense.LS, dense.A), "ARKStepSetLinearSolver");
        if (system.has_jacobian())
          check(ARKStepSetJacFn(mem, jacobian_callback), "ARKStepSetJacFn");
        check(ARKStepSetOrder(mem, settings.max_order > 0 ? settings.max_order : 4), "ARKStepSetOrder");
        check(ARKStepSetMaxNumSteps(mem, settings.max_steps_per_output), "ARKStepSetMaxNumSteps");
        if (settings.max_step > 0.0)
          check(ARKStepSetMaxStep(mem, settings.max_step), "ARKStepSetMaxStep");
        if (system.n_roots() > 0)
          check(ARKStepRootInit(mem, system.n_roots(), root_callback), "ARKStepRootInit");

        auto harvest = [&]() {
          long steps = 0, etf = 0, ncf = 0, nfe = 0, nfi = 0, nfi_ls = 0, nje = 0, nge = 0;
          ARKStepGetNumSteps(mem, &steps);
          ARKStepGetNumErrTestFails(mem, &etf);
          ARKStepGetNumNonlinSolvConvFails(mem, &ncf);
          ARKStepGetNumRhsEvals(mem, &nfe, &nfi);
          ARKStepGetNumLinRhsEvals(mem, &nfi_ls);
          ARKStepGetNumJacEvals(mem, &nje);
          ARKStepGetNumGEvals(mem, &nge);
          statistics.steps += steps - last.steps;
          statistics.rejected_steps += etf + ncf - last.rejected_steps;
          statistics.rhs_evals += nfi + nfi_ls - last.rhs_evals;
          statistics.jacobian_evals += nje - last.jacobian_evals;
          statistics.root_evals += nge - last.root_evals;
          last = {"", steps, etf + ncf, nfi + nfi_ls, nje, nge, 0, 0.0};
        };
        last = IntegratorStats{};
        drive(
          system, data, "arkode-dirk", t0, y.data(), output_interval, n_outputs, observer,
          [&](const double tout, double &t, int *dirs) {
            const int flag = ARKStepEvolve(mem, tout, y.v, &t, ARK_NORMAL);
            if (flag == ARK_ROOT_RETURN)
              ARKStepGetRootInfo(mem, dirs);
            return flag;
          },
          [](const int flag) { return flag == ARK_ROOT_RETURN; },
          [&](const double t) {
            check(ARKStepReInit(mem, nullptr, rhs_callback, t, y.v), "ARKStepReInit");
            last = IntegratorStats{};
          },
          harvest, statistics, [](int f) { return std::string(ARKStepGetReturnFlagName(f)); });
        std::copy(y.data(), y.data() + n, y0.begin());
        statistics.wall_time_s +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      }

    private:
      IntegratorSettings settings;
      IntegratorStats    last;
    };

    class Ida : public Integrator
    {
    public:
      explicit Ida(const IntegratorSettings &s) : settings(s) { statistics.name = "ida"; }

      void integrate(OdeSystem &system, const double t0, std::vector<double> &y0,
                     const double output_interval, const long n_outputs,
                     const Observer &observer) override
      {
        const auto     start = std::chrono::steady_clock::now();
        const unsigned n     = system.n_states();
        Context        context;
        Vector         y(n, context.ctx), yp(n, context.ctx), atol(n, context.ctx),
          id(n, context.ctx);
        std::copy(y0.begin(), y0.end(), y.data());
        system.consistent_initial_derivative(t0, y.data(), yp.data());
        const auto a = system.absolute_tolerances(settings.absolute_tolerance);
        std::copy(a.begin(), a.end(), atol.data());
        const auto ids = system.differential_components();
        std::copy(ids.begin(), ids.end(), id.data());
        CallbackData data{&system, {}};

        void *mem = IDACreate(context.ctx);
        HG_REQUIRE_NUMERIC(mem != nullptr, "IDACreate failed");
        struct Free
        {
          void *&m;
          ~Free() { IDAFree(&m); }
        } free_mem{mem};
        DenseSolver dense(n, y.v, context.ctx);
        auto        check = [](const int flag, const char *what) {
          HG_REQUIRE_NUMERIC(flag >= 0, what, " failed with flag ", flag);
        };
        check(IDAInit(mem, residual_callback, t0, y.v, yp.v), "IDAInit");
        check(IDASetUserData(mem, &data), "IDASetUserData");
        check(IDASetErrHandlerFn(mem, error_handler, &data), "IDASetErrHandlerFn");
        check(IDASVtolerances(mem, settings.relative_tolerance, atol.v), "IDASVtolerances");
        check(IDASetLinearSolver(mem, dense.LS, dense.A), "IDASetLinearSolver");
        check(IDASetId(mem, id.v), "IDASetId");
        check(IDASetMaxNumSteps(mem, settings.max_steps_per_output), "IDASetMaxNumSteps");
        if (settings.max_order > 0)
          check(IDASetMaxOrd(mem, settings.max_order), "IDASetMaxOrd");
        if (settings.max_step > 0.0)
          check(IDASetMaxStep(mem, settings.max_step), "IDASetMaxStep");
        if (system.n_roots() > 0)
          check(IDARootInit(mem, system.n_roots(), ida_root_callback), "IDARootInit");

        auto harvest = [&]() {
          long steps = 0, etf = 0, ncf = 0, nre = 0, nre_ls = 0, nje = 0, nge = 0;
          IDAGetNumSteps(mem, &steps);
          IDAGetNumErrTestFails(mem, &etf);
          IDAGetNumNonlinSolvConvFails(mem, &ncf);
          IDAGetNumResEvals(mem, &nre);
          IDAGetNumLinResEvals(mem, &nre_ls);
          IDAGetNumJacEvals(mem, &nje);
          IDAGetNumGEvals(mem, &nge);
          statistics.steps += steps - last.steps;
          statistics.rejected_steps += etf + ncf - last.rejected_steps;
          statistics.rhs_evals += nre + nre_ls - last.rhs_evals;
          statistics.jacobian_evals += nje - last.jacobian_evals;
          statistics.root_evals += nge - last.root_evals;
          last = {"", steps, etf + ncf, nre + nre_ls, nje, nge, 0, 0.0};
        };
        last = IntegratorStats{};
        drive(
          system, data, "ida", t0, y.data(), output_interval, n_outputs, observer,
          [&](const double tout, double &t, int *dirs) {
            const int flag = IDASolve(mem, tout, &t, y.v, yp.v, IDA_NORMAL);
            if (flag == IDA_ROOT_RETURN)
              IDAGetRootInfo(mem, dirs);
            return flag;
          },
          [](const int flag) { return flag == IDA_ROOT_RETURN; },
          [&](const double t) {
            system.consistent_initial_derivative(t, y.data(), yp.data());
            check(IDAReInit(mem, t, y.v, yp.v), "IDAReInit");
            last = IntegratorStats{};
          },
          harvest, statistics, [](int f) { return std::string(IDAGetReturnFlagName(f)); });
        std::copy(y.data(), y.data() + n, y0.begin());
        statistics.wall_time_s +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      }

    private:
      IntegratorSettings settings;
      IntegratorStats    last;
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
