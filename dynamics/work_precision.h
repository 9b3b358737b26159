#pragma once
// What accuracy costs in time, per integrator (`hertzgear accuracy dynamics`,
// docs/accuracy-dynamics.md): every integrator (radau-iia with each stage count) runs the same
// gear pair at a ladder of tolerances (fixed steps for rk4), and each run's RMS DTE, Poincaré
// points and peak mesh force are compared with a converged reference: radau-iia with 7 stages at
// rtol 1e-13 and an absolute tolerance of 1e-17 m, checked against 9 stages at the same
// tolerances (their difference is reported). When c = 0 makes the layer a DAE, only ida
// integrates it, and the reference is ida at rtol 1e-12.
#include "dynamics/analysis.h"
#include "dynamics/gear_pair_model.h"
#include "dynamics/integrator.h"
#include "dynamics/sweep.h"

#include <functional>
#include <string>
#include <vector>

namespace hertzgear::dynamics
{
  struct WorkPrecisionCase
  {
    IntegratorKind kind;
    double         rtol             = 0; // adaptive integrators
    int            steps_per_period = 0; // rk4
    int            stages           = 0; // radau-iia: 3, 5, 7, 9; 0 = by the tolerance
  };

  struct WorkPrecisionPoint
  {
    WorkPrecisionCase case_;
    bool              ok = false;
    std::string       status; // "ok" or why the run failed
    IntegratorStats   stats;
    double            rms_dte_m               = 0;
    double            rms_relative_error      = 0; // against the reference's RMS DTE
    double            poincare_max_error_m    = 0; // largest Poincaré point difference
    double            poincare_relative_error = 0; // of the reference's DTE range
    double            max_force_relative_error = 0; // peak mesh force (dynamic factor)
  };

  struct WorkPrecisionStudy
  {
    IntegratorStats                 reference_stats;
    SteadyStateSummary              reference_summary;
    std::string                     reference_name; // "radau-iia s=7 rtol 1e-13 atol 1e-17 m"
    // The reference against its check (radau-iia s = 9, same tolerances): RMS DTE relative,
    // largest Poincaré difference [m], peak force relative. NaN without a check (DAE).
    double                          check_rms_relative_difference  = 0;
    double                          check_poincare_max_difference_m = 0;
    double                          check_max_force_relative_difference = 0;
    std::vector<WorkPrecisionPoint> points;
  };

  // The ladder: cvode-bdf, ida, arkode-erk and radau-iia with s = 3, 5, 7 and 9 at rtol 1e-4 ...
  // `tightest_rtol` (a power of ten, at least 1e-12) and rk4 at 100 ... 30000 steps per period;
  // ida alone when `dae`. `integrators` (names, empty: all) selects among them.
  std::vector<WorkPrecisionCase> work_precision_cases(bool dae, double tightest_rtol = 1e-12,
                                                      const std::vector<std::string> &integrators = {});

  // Runs the reference and every case; `progress` is called after each case with its index.
  WorkPrecisionStudy
  work_precision(const GearPairParameters &parameters, const RunSettings &run,
                 const InitialState &initial, const std::vector<WorkPrecisionCase> &cases,
                 const std::function<void(std::size_t, const WorkPrecisionPoint &)> &progress = {});
} // namespace hertzgear::dynamics
