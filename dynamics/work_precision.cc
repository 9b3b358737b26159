#include "dynamics/work_precision.h"

#include "common/errors.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hertzgear::dynamics
{
  namespace
  {
    struct Run
    {
      bool               ok = false;
      std::string        status;
      SimulationResult   result;
      SteadyStateSummary summary;
    };

    Run run_case(const GearPairParameters &parameters, const RunSettings &settings,
                 const InitialState &initial, const WorkPrecisionCase &c,
                 const double absolute_tolerance = 0.0)
    {
      Run           o;
      GearPairModel model(parameters);
      RunSettings   run  = settings;
      run.integrator.kind   = c.kind;
      run.integrator.stages = c.stages;
      if (c.kind == IntegratorKind::rk4)
        run.steps_per_period = c.steps_per_period;
      else
        {
          run.integrator.relative_tolerance = c.rtol;
          // Absolute tolerance tied to the relative one on the scale of the displacements, so
          // that one knob moves the accuracy (the reference gives its own).
          run.integrator.absolute_tolerance =
            absolute_tolerance > 0.0 ? absolute_tolerance
                                     : c.rtol * 1e-2 * model.characteristic_displacement();
        }
      try
        {
          o.result  = simulate(model, run, initial.of(model));
          o.summary = analyse(model, o.result);
          o.ok      = true;
          o.status  = "ok";
        }
      catch (const NumericalError &e)
        {
          o.status = std::string("failed: ") + e.what();
        }
      return o;
    }

    double max_poincare_difference(const SimulationResult &a, const SimulationResult &b)
    {
      double d = 0.0;
      for (std::size_t j = 0; j < std::min(a.poincare.size(), b.poincare.size()); ++j)
        d = std::max(d, std::abs(a.poincare[j].dte_m - b.poincare[j].dte_m));
      return d;
    }
  } // namespace

  std::vector<WorkPrecisionCase> work_precision_cases(const bool dae, const double tightest_rtol,
                                                      const std::vector<std::string> &integrators)
  {
    HG_REQUIRE_INPUT(tightest_rtol >= 1e-12 && tightest_rtol <= 1e-4,
                     "the tightest tolerance of the ladder must lie in [1e-12, 1e-4], not ",
                     tightest_rtol);
    const auto wanted = [&](const IntegratorKind kind) {
      return integrators.empty() || std::find(integrators.begin(), integrators.end(),
                                              integrator_name(kind)) != integrators.end();
    };
    std::vector<double> rtols;
    for (int e = 4; e <= 12 && std::pow(10.0, -e) >= tightest_rtol * (1.0 - 1e-9); ++e)
      rtols.push_back(std::pow(10.0, -e));
    std::vector<WorkPrecisionCase> cases;
    for (const auto kind : {IntegratorKind::cvode_bdf, IntegratorKind::ida, IntegratorKind::arkode_erk})
      if ((!dae || kind == IntegratorKind::ida) && wanted(kind))
        for (const double rtol : rtols)
          cases.push_back({kind, rtol, 0, 0});
    if (!dae && wanted(IntegratorKind::radau_iia))
      for (const int s : {3, 5, 7, 9})
        for (const double rtol : rtols)
          cases.push_back({IntegratorKind::radau_iia, rtol, 0, s});
    if (!dae && wanted(IntegratorKind::rk4))
      for (const int n : {100, 300, 1000, 3000, 10000, 30000})
        cases.push_back({IntegratorKind::rk4, 0.0, n, 0});
    return cases;
  }

  WorkPrecisionStudy
  work_precision(const GearPairParameters &parameters, const RunSettings &run,
                 const InitialState &initial, const std::vector<WorkPrecisionCase> &cases,
                 const std::function<void(std::size_t, const WorkPrecisionPoint &)> &progress)
  {
    const bool         dae = parameters.damping_N_s_per_m == 0.0;
    WorkPrecisionStudy study;
    // The reference: Radau IIA of order 13 at rtol 1e-13, checked against order 17 (its error
    // estimate is of order s, the solution's 2s - 1, so two orders that agree far below the
    // ladder's errors are converged); 1e-17 m absolute, where the layer's force k_h |delta|^n is
    // far below rounding. ida for the DAE, which radau-iia does not integrate.
    const double ref_atol = 1e-17;
    const Run    reference =
      dae ? run_case(parameters, run, initial, {IntegratorKind::ida, 1e-12, 0, 0})
          : run_case(parameters, run, initial, {IntegratorKind::radau_iia, 1e-13, 0, 7}, ref_atol);
    HG_REQUIRE_NUMERIC(reference.ok, "the reference run failed: ", reference.status);
    study.reference_name = dae ? "ida rtol 1e-12" : "radau-iia s=7 rtol 1e-13 atol 1e-17 m";
    const auto &ref      = reference.summary;
    study.check_rms_relative_difference = study.check_poincare_max_difference_m =
      study.check_max_force_relative_difference = std::numeric_limits<double>::quiet_NaN();
    if (!dae)
      {
        const Run check =
          run_case(parameters, run, initial, {IntegratorKind::radau_iia, 1e-13, 0, 9}, ref_atol);
        HG_REQUIRE_NUMERIC(check.ok, "the reference's check run failed: ", check.status);
        study.check_rms_relative_difference =
          std::abs(check.summary.rms_dte_m - ref.rms_dte_m) / ref.rms_dte_m;
        study.check_poincare_max_difference_m = max_poincare_difference(check.result, reference.result);
        study.check_max_force_relative_difference =
          std::abs(check.summary.max_force_N - ref.max_force_N) / ref.max_force_N;
      }
    study.reference_stats   = reference.result.stats;
    study.reference_summary = reference.summary;
    const double ref_scale  = std::max(ref.max_dte_m - ref.min_dte_m, std::abs(ref.mean_dte_m));
    for (std::size_t i = 0; i < cases.size(); ++i)
      {
        const Run          o = run_case(parameters, run, initial, cases[i]);
        WorkPrecisionPoint p;
        p.case_  = cases[i];
        p.ok     = o.ok;
        p.status = o.status;
        p.stats  = o.result.stats;
        p.rms_dte_m = p.rms_relative_error = p.poincare_max_error_m = p.max_force_relative_error =
          std::numeric_limits<double>::quiet_NaN();
        if (o.ok)
          {
            p.rms_dte_m            = o.summary.rms_dte_m;
            p.rms_relative_error   = std::abs(o.summary.rms_dte_m - ref.rms_dte_m) / ref.rms_dte_m;
            p.poincare_max_error_m = max_poincare_difference(o.result, reference.result);
            p.max_force_relative_error =
              std::abs(o.summary.max_force_N - ref.max_force_N) / ref.max_force_N;
          }
        p.poincare_relative_error = p.poincare_max_error_m / ref_scale;
        study.points.push_back(p);
        if (progress)
          progress(i, p);
      }
    return study;
  }
} // namespace hertzgear::dynamics
