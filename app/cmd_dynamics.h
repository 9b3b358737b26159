#pragma once
// Pieces shared by the dynamics commands (dynamics, sweep, accuracy dynamics).
#include "app/command.h"
#include "app/dynamics_setup.h"
#include "app/run_directory.h"
#include "common/processes.h"
#include "common/progress.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace hertzgear
{
  // A command that runs one stage on its scene: `check(scene)` makes every check the stage would
  // make, before the command's start (CommandStart::begin, which locks --out); then with --out,
  // `stage(scene, &dir, timer)` writes into the run directory, finished with the timing and
  // `record(output)`; without, the output of `stage(scene, nullptr, timer)` goes to `print` and
  // the timing summary to stderr. Under mpirun a stage that is `collective` for its scene runs
  // on every rank (rank 0 writes), any other on rank 0 alone.
  template <typename Check, typename Stage, typename Print, typename Record>
  int run_stage_command(
    const CommandContext &ctx, const Check &check, const Stage &stage, const Print &print,
    const Record &record,
    const std::function<bool(const Scene &)> &collective = [](const Scene &) { return false; })
  {
    PhaseTimer  timer;
    const Scene scene = load_scene(ctx, timer);
    {
      PhaseTimer::Scope scope(timer, "checks");
      check(scene);
    }
    begin_on_out(ctx);
    if (!processes::is_root())
      {
        if (collective(scene))
          stage(scene, nullptr, timer);
        return 0;
      }
    if (ctx.out_dir.empty())
      {
        print(stage(scene, nullptr, timer));
        timer.print_summary(progress_stream());
      }
    else
      {
        RunDirectory dir(ctx.out_dir, scene, ctx.command_line);
        dir.finish(timer, record(stage(scene, &dir, timer))); // prints the timing summary
      }
    return 0;
  }

  // Every check of the dynamics stage of `scene` (its set-up: geometry, table, effects).
  void check_dynamics_inputs(const Scene &scene);
  // Every check of the response stage (`response`, or the sweep with Sweep/mode = shooting when
  // `speed_sweep`): the dynamics set-up, the parameter family and the continuation settings.
  void check_response_inputs(const Scene &scene, bool speed_sweep);
  // Every check of the sweep stage: Sweep/* (and --threads), then the response's or the
  // dynamics' checks, as Sweep/mode asks.
  void check_sweep_inputs(const Scene &scene, int n_threads);

  // The options of `hertzgear accuracy dynamics`: which integrators, and how far the ladder of
  // tolerances goes.
  struct AccuracyDynamicsOptions
  {
    std::vector<std::string> integrators; // empty: all
    double                   tightest_rtol = 1e-12;
  };
  int run_accuracy_dynamics(const CommandContext &ctx, const AccuracyDynamicsOptions &options);

  // The dynamics stage on a loaded scene: integrate, analyse and, when `dir` is given, write
  // timeseries.csv, poincare.csv, spectrum.csv, force_penetration.csv, impacts.csv and
  // summary.json into it (not used_parameters.prm / run.json: the caller finishes the run).
  // Returns the summary. Used by `hertzgear dynamics` and by the pipeline of `hertzgear run`.
  nlohmann::json run_dynamics_stage(const Scene &scene, const RunDirectory *dir, PhaseTimer &timer);

  struct SweepStageOutput
  {
    std::string    sweep_csv;  // what sweep.csv holds
    nlohmann::json integrator; // summed integrator statistics
  };
  // The speed sweep of Sweep/* (the engine is dynamics/sweep.h): writes sweep.csv and
  // bifurcation.csv into `dir` when given. `n_threads` 0 = all hardware threads. Collective under
  // mpirun (every rank calls it). Used by `hertzgear sweep` and `hertzgear run`.
  SweepStageOutput run_sweep_stage(const Scene &scene, const RunDirectory *dir, PhaseTimer &timer,
                                   int n_threads);

  struct ResponseStageOutput
  {
    std::string    csv;  // what response.csv holds
    nlohmann::json json; // what response.json holds
  };
  // The periodic orbits of Response/* followed by continuation (the engine is
  // dynamics/continuation.h): writes response.csv and response.json into `dir` when given. With
  // `speed_sweep` the parameter is the speed over Sweep/speed_min_rpm ... speed_max_rpm
  // (Sweep/mode = shooting). Used by `hertzgear response`, `hertzgear sweep` and `hertzgear run`.
  ResponseStageOutput run_response_stage(Scene scene, const RunDirectory *dir, PhaseTimer &timer,
                                         bool speed_sweep);
} // namespace hertzgear
