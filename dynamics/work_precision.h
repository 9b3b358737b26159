#pragma once
// What accuracy costs in time, per integrator (`hertzgear accuracy dynamics`,
// docs/accuracy-dynamics.md): every integrator runs the same gear pair at a ladder of tolerances
// (fixed steps for rk4), and each run's RMS DTE and Poincaré points are compared with a reference
// run at rtol 1e-12 (cvode-bdf, or ida when c = 0 makes the layer a DAE).
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
  };

  struct WorkPrecisionStudy
  {
    IntegratorStats                 reference_stats;
    SteadyStateSummary              reference_summary;
    std::vector<WorkPrecisionPoint> points;
  };

  // The ladder: cvode-bdf, radau-iia, ida and arkode-erk at rtol 1e-4 ... 1e-10 and rk4 at 100 ...
  // 30000 steps per period; ida alone when `dae`.
  std::vector<WorkPrecisionCase> work_precision_cases(bool dae);

  // Runs the reference and every case; `progress` is called after each case with its index.
  WorkPrecisionStudy
  work_precision(const GearPairParameters &parameters, const RunSettings &run,
                 const InitialState &initial,
                 const std::function<void(std::size_t, const WorkPrecisionPoint &)> &progress = {});
} // namespace hertzgear::dynamics
