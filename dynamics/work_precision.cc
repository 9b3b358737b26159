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
                 const InitialState &initial, const WorkPrecisionCase &c)
    {
      Run           o;
      GearPairModel model(parameters);
      RunSettings   run  = settings;
      run.integrator.kind = c.kind;
      if (c.kind == IntegratorKind::rk4)
        run.steps_per_period = c.steps_per_period;
      else
        {
          run.integrator.relative_tolerance = c.rtol;
          // Absolute tolerance tied to the relative one on the scale of the displacements, so
          // that one knob moves the accuracy.
          run.integrator.absolute_tolerance = c.rtol * 1e-2 * model.characteristic_displacement();
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
  } // namespace

  std::vector<WorkPrecisionCase> work_precision_cases(const bool dae)
  {
    std::vector<WorkPrecisionCase> cases;
    for (const auto kind : {IntegratorKind::cvode_bdf, IntegratorKind::radau_iia, IntegratorKind::ida,
                            IntegratorKind::arkode_erk})
      {
        if (dae && kind != IntegratorKind::ida)
          continue;
        for (const double rtol : {1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10})
          cases.push_back({kind, rtol, 0});
      }
    if (!dae)
      for (const int n : {100, 300, 1000, 3000, 10000, 30000})
        cases.push_back({IntegratorKind::rk4, 0.0, n});
    return cases;
  }

  WorkPrecisionStudy
  work_precision(const GearPairParameters &parameters, const RunSettings &run,
                 const InitialState &initial,
                 const std::function<void(std::size_t, const WorkPrecisionPoint &)> &progress)
  {
    const bool dae = parameters.damping_N_s_per_m == 0.0;
    const Run  reference =
      run_case(parameters, run, initial, {dae ? IntegratorKind::ida : IntegratorKind::cvode_bdf, 1e-12, 0});
    HG_REQUIRE_NUMERIC(reference.ok, "the reference run at rtol 1e-12 failed: ", reference.status);
    WorkPrecisionStudy study;
    study.reference_stats   = reference.result.stats;
    study.reference_summary = reference.summary;
    const auto  &ref_p      = reference.result.poincare;
    const auto  &ref        = reference.summary;
    const double ref_scale  = std::max(ref.max_dte_m - ref.min_dte_m, std::abs(ref.mean_dte_m));
    const auto   cases      = work_precision_cases(dae);
    for (std::size_t i = 0; i < cases.size(); ++i)
      {
        const Run          o = run_case(parameters, run, initial, cases[i]);
        WorkPrecisionPoint p;
        p.case_  = cases[i];
        p.ok     = o.ok;
        p.status = o.status;
        p.stats  = o.result.stats;
        p.rms_dte_m = p.rms_relative_error = p.poincare_max_error_m =
          std::numeric_limits<double>::quiet_NaN();
        if (o.ok)
          {
            p.rms_dte_m            = o.summary.rms_dte_m;
            p.rms_relative_error   = std::abs(o.summary.rms_dte_m - ref.rms_dte_m) / ref.rms_dte_m;
            p.poincare_max_error_m = 0.0;
            for (std::size_t j = 0; j < std::min(ref_p.size(), o.result.poincare.size()); ++j)
              p.poincare_max_error_m =
                std::max(p.poincare_max_error_m, std::abs(o.result.poincare[j].dte_m - ref_p[j].dte_m));
          }
        p.poincare_relative_error = p.poincare_max_error_m / ref_scale;
        study.points.push_back(p);
        if (progress)
          progress(i, p);
      }
    return study;
  }
} // namespace hertzgear::dynamics
