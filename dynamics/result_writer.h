#pragma once
// The text forms of the dynamics' results, next to their types: the CSV tables and JSON summaries
// that `hertzgear dynamics`, `sweep`, `response` and `accuracy dynamics` write (units in the
// column names and keys; docs/dynamics.md). app/ decides where they go.
#include "dynamics/analysis.h"
#include "dynamics/continuation.h"
#include "dynamics/gear_pair_model.h"
#include "dynamics/sweep.h"
#include "dynamics/work_precision.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace hertzgear::dynamics
{
  // A number as the dynamics' CSV files write it: 12 significant digits.
  std::string csv_number(double v);

  // summary.json: the steady-state summary `s` of `result` on `model`, with `model_description`
  // (what the caller records about how the model was set up) under "model".
  nlohmann::json summary_json(const GearPairModel &model, const SimulationResult &result,
                              const SteadyStateSummary &s, const nlohmann::json &model_description);

  // The tables of one simulation. timeseries.csv and force_penetration.csv hold the last
  // `last_periods` mesh periods of the steady window (all of it when 0 or more).
  std::string timeseries_csv(const SimulationResult &result, int last_periods);
  std::string poincare_csv(const SimulationResult &result);
  std::string spectrum_csv(const SimulationResult &result);
  std::string force_penetration_csv(const SimulationResult &result, int last_periods);
  std::string impacts_csv(const SimulationResult &result);

  // sweep.csv: one row per sweep point.
  std::string sweep_csv(const std::vector<SweepRow> &rows);
  // bifurcation.csv: the Poincare points of the independent runs when `independent`, else those
  // of the continuation chains.
  std::string bifurcation_csv(const std::vector<SweepRow> &rows, bool independent);

  // response.csv: one row per periodic orbit; `column` names the continuation parameter.
  std::string response_csv(const ContinuationResult &result, const std::string &column);
  // response.json without the scene's part: parameter, orbits solved, integrator statistics,
  // branches with their end reasons, bifurcation points (the parameter under `column`).
  nlohmann::json response_json(const ContinuationResult &result, const std::string &column,
                               double wall_time_s);

  // accuracy_dynamics.csv: one row per case of the study.
  std::string work_precision_csv(const WorkPrecisionStudy &study);
  // The reference of the study and its check, for run.json.
  nlohmann::json work_precision_reference_json(const WorkPrecisionStudy &study);
} // namespace hertzgear::dynamics
