#pragma once
// The speed sweep of the gear-pair model: evenly spaced pinion speeds run as continuation chains
// (up and/or down, each point starting from the last state of the one before) and/or as
// independent points (each from the initial state), every point analysed in its steady state.
// The chains and the independent points are jobs: under mpirun job j runs on rank
// j mod (number of ranks), on each rank the jobs run on threads, and every rank ends with all
// the rows (common/processes.h). Plain inputs, SI units except the speeds (rpm).
#include "dynamics/analysis.h"
#include "dynamics/gear_pair_model.h"
#include "dynamics/integrator.h"

#include <functional>
#include <string>
#include <vector>

namespace hertzgear::dynamics
{
  enum class SweepDirection
  {
    up,
    down,
    both
  };

  enum class SweepMode
  {
    continuation,
    independent,
    both
  };

  SweepDirection sweep_direction_from_name(const std::string &name); // up | down | both
  SweepMode      sweep_mode_from_name(const std::string &name); // continuation | independent | both

  struct SweepSettings
  {
    double         speed_min_rpm = 100.0;
    double         speed_max_rpm = 10000.0;
    int            points        = 50; // speeds from min to max inclusive; 1: min = max
    SweepDirection direction     = SweepDirection::both; // of the continuation chains
    SweepMode      mode          = SweepMode::both;
    int            periods_per_point           = 300; // mesh periods integrated per point
    int            transient_periods_per_point = 200; // of which discarded before the analysis
    int            threads                     = 0;   // per rank; 0 = hardware threads / ranks
  };

  // Throws ParameterError naming the field of SweepSettings that is out of range.
  void check_sweep_settings(const SweepSettings &settings);

  // The speeds of the sweep in increasing order [rpm].
  std::vector<double> sweep_speeds(const SweepSettings &settings);

  // Where every run that does not continue from another starts.
  struct InitialState
  {
    bool   static_equilibrium = true; // the model's static equilibrium; else the values below
    double dte_m              = 0.0;
    double dte_rate_m_per_s   = 0.0;
    double penetration_m      = 0.0; // dynamic Hertzian layer only

    std::vector<double> of(const GearPairModel &model) const;
  };

  // The gear pair at one reference speed, and how each point is integrated (the periods of
  // RunSettings are replaced by those of SweepSettings).
  struct SweepModel
  {
    GearPairParameters parameters;
    double             speed_rpm = 0.0; // the pinion speed `parameters` describe
    RunSettings        run;
    InitialState       initial;
  };

  // `parameters`, which describe the pair at `speed_rpm_of_parameters`, at another pinion speed:
  // the mesh frequency scales with the speed, nothing else changes.
  GearPairParameters at_speed(const GearPairParameters &parameters, double speed_rpm_of_parameters,
                              double speed_rpm);

  // Which run a row belongs to.
  enum class SweepBranch
  {
    up,
    down,
    independent
  };
  std::string sweep_branch_name(SweepBranch branch); // up | down | independent

  struct SweepRow
  {
    double              speed_rpm = 0.0;
    SweepBranch         branch    = SweepBranch::independent;
    SteadyStateSummary  summary;
    std::vector<double> poincare_dte_m; // the DTE of the Poincare section of the steady window
  };

  struct SweepResult
  {
    // The up chain (increasing speed), then the down chain (decreasing speed), then the
    // independent points (increasing speed), as far as the settings ask for them.
    std::vector<SweepRow> rows;
    IntegratorStats       stats; // summed over all points and ranks
  };

  // One point done on this rank. Called from the worker threads, one call at a time.
  struct SweepPointDone
  {
    int             rank    = 0;
    int             n_ranks = 1;
    int             done    = 0; // points done on this rank, this one included
    int             total   = 0; // points on this rank
    const SweepRow &row;
    double          elapsed_s = 0.0; // since the sweep started
  };
  using SweepProgress = std::function<void(const SweepPointDone &point)>;

  // Runs the sweep. Collective under mpirun: every rank calls it with the same inputs and gets
  // the same result, or the same error (the first failure, with its rank in the text, thrown as
  // the type of its exit code).
  SweepResult sweep(const SweepModel &model, const SweepSettings &settings,
                    const SweepProgress &progress = {});
} // namespace hertzgear::dynamics
