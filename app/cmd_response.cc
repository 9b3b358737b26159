// `hertzgear response SCENE --out DIR`: the periodic orbits of the gear pair found by shooting
// and followed over a parameter (Response/parameter: speed, torque or damping ratio) by
// pseudo-arclength continuation, with their Floquet multipliers, stability and bifurcations
// (dynamics/continuation.h, docs/dynamics.md). Writes response.csv (one row per orbit) and
// response.json (branches, their end reasons, the bifurcation points, statistics), plus
// used_parameters.prm and run.json. Also the sweep stage of `hertzgear sweep` / `run` when
// Sweep/mode = shooting (then in speed over the sweep's range).
//
//   hertzgear response data/scenes/paper_crowned_table.prm --out runs/response
#include "app/cmd_dynamics.h"
#include "app/command.h"
#include "app/dynamics_setup.h"
#include "app/run_directory.h"
#include "app/scene_keys.h"
#include "common/errors.h"
#include "common/progress.h"
#include "dynamics/continuation.h"
#include "dynamics/result_writer.h"

#include <chrono>
#include <iostream>

namespace hertzgear
{
  using namespace dynamics;

  namespace
  {
    // "[response] branch 0 (period 1) point 12  15143.6 rpm  rms DTE 91.65 um  stable
    //  |mu|max 0.9935  fold  (0.4 s)"
    void response_progress_line(const ResponseFamily &family, const ContinuationBranch &b,
                                const ContinuationPoint &p, const double elapsed_s)
    {
      progress_line("response",
                    msg("branch ", b.id, " (period ", b.period_multiple, ") point ",
                        b.points.size(), "  ", family.column, " ", p.lambda, "  rms DTE ",
                        1e6 * p.summary.rms_dte_m, " um  ", p.stable ? "stable" : "unstable",
                        "  |mu|max ", std::abs(p.multipliers.front()),
                        p.bifurcation != Bifurcation::none ? "  " + bifurcation_name(p.bifurcation) : "",
                        "  (", elapsed_s, " s)"));
    }
  } // namespace

  namespace
  {
    // What the response stage starts from, every check made.
    struct ResponseStart
    {
      DynamicsSetup        setup;
      ResponseFamily       family;
      ContinuationSettings settings;
    };

    ResponseStart response_start(Scene scene, const bool speed_sweep)
    {
      if (speed_sweep)
        scene.response.parameter = "speed_rpm";
      ResponseStart s;
      s.setup    = make_dynamics_setup(scene);
      s.family   = response_family(scene, s.setup);
      s.settings = continuation_settings(scene, s.setup, s.family); // checked
      return s;
    }
  } // namespace

  void check_response_inputs(const Scene &scene, const bool speed_sweep)
  {
    response_start(scene, speed_sweep);
  }

  ResponseStageOutput run_response_stage(Scene scene, const RunDirectory *dir, PhaseTimer &timer,
                                         const bool speed_sweep)
  {
    if (speed_sweep)
      scene.response.parameter = "speed_rpm";
    ResponseStart prepared;
    {
      PhaseTimer::Scope scope(timer, "setup");
      prepared = response_start(scene, speed_sweep);
    }
    const ResponseFamily       &family   = prepared.family;
    const ContinuationSettings &settings = prepared.settings;
    GearPairModel start_model(settings.lambda_start == family.min ? family.family.at(family.min) :
                                                                    family.family.at(family.max));
    progress_line("response", msg("periodic orbits in ", family.column, " from ",
                                  settings.lambda_start, " towards ",
                                  settings.direction > 0 ? family.max : family.min,
                                  ": shooting with ", scene.dynamics.integrator, " at rtol ",
                                  settings.shooting.integrator.relative_tolerance, ", Newton tolerance ",
                                  settings.shooting.tolerance, ", state dimension ",
                                  start_model.n_states(), ", ",
                                  start_model.parameters().effects.describe()));
    ContinuationResult result;
    const auto         start = std::chrono::steady_clock::now();
    const auto         elapsed = [&] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    {
      PhaseTimer::Scope scope(timer, "continuation");
      result = continue_periodic_orbits(
        family.family, initial_state(scene, start_model), settings,
        [&](const ContinuationBranch &b, const ContinuationPoint &p) {
          response_progress_line(family, b, p, elapsed());
        });
    }
    int n_points = 0;
    for (auto &b : result.branches)
      {
        b.end_reason = with_scene_keys(b.end_reason); // the library's {field}s as scene keys
        for (auto &note : b.notes)
          {
            note.text = with_scene_keys(note.text);
            progress_line("response", msg("warning: branch ", b.id, ": ", note.text));
          }
        n_points += int(b.points.size());
        progress_line("response", msg(b.ended_in_failure ? "warning: " : "", "branch ", b.id,
                                      " (period ", b.period_multiple, ", ", b.points.size(),
                                      " orbits) ends: ", b.end_reason));
      }
    auto json         = response_json(result, family.column, elapsed());
    json["scene_key"] = family.key;
    json["range"]     = {family.min, family.max};
    // Which model the orbits are of (the report labels the curves of compared runs with it).
    json["effects"]        = start_model.parameters().effects.describe();
    json["mesh_force_law"] = dynamics::mesh_force_law_name(start_model.parameters().effects.mesh_force_law);
    progress_line("response", msg(n_points, " orbits on ", result.branches.size(), " branches, ",
                                  json["bifurcations"].size(), " bifurcations, ",
                                  result.orbits_solved, " Newton iterations, ", elapsed(), " s"));
    if (json["force_law"]["extrapolated_orbits"].get<int>() > 0)
      progress_line("response",
                    msg("warning: on ", json["force_law"]["extrapolated_orbits"].get<int>(),
                        " orbits the mesh force goes above the force law's data (",
                        json["force_law"]["tabulated_force_limit_N"].get<double>(),
                        " N, the load ladder's top): the FE law extrapolates there; a higher top "
                        "of Stiffness/load_ladder_percent covers them"));
    ResponseStageOutput out{response_csv(result, family.column), json};
    if (dir)
      {
        PhaseTimer::Scope scope(timer, "write");
        dir->write_text("response.csv", out.csv);
        dir->write_json("response.json", out.json);
      }
    return out;
  }

  namespace
  {
    int run_response(const CommandContext &ctx)
    {
      return run_stage_command(
        ctx, [](const Scene &scene) { check_response_inputs(scene, false); },
        [](const Scene &scene, const RunDirectory *dir, PhaseTimer &timer) {
          return run_response_stage(scene, dir, timer, false);
        },
        [](const ResponseStageOutput &out) { std::cout << out.csv; },
        [](const ResponseStageOutput &) { return nlohmann::json{{"stage", "response"}}; });
    }
  } // namespace

  void add_response_command(CommandRegistry &registry)
  {
    registry.add_command({"response", "Periodic orbits by shooting, followed in speed, torque or "
                                      "damping by arclength continuation, with their stability "
                                      "and bifurcations (Response/*)"},
                         run_response);
  }
} // namespace hertzgear
