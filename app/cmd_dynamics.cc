// `hertzgear dynamics SCENE --out DIR` and `hertzgear sweep SCENE --out DIR`.
//
//   hertzgear dynamics data/scenes/paper_crowned_fourier.prm --out runs/crowned
//   hertzgear sweep data/scenes/paper_crowned_fourier.prm --out runs/sweep --threads 2
//   mpirun -np 2 hertzgear sweep data/scenes/paper_crowned_fourier.prm --out runs/sweep
//
// dynamics writes timeseries.csv, poincare.csv, spectrum.csv, force_penetration.csv and
// summary.json; sweep writes sweep.csv and bifurcation.csv. Both add used_parameters.prm and
// run.json. Progress lines and the timing summary go to stderr.
#include "app/cmd_dynamics.h"
#include "app/command.h"
#include "app/dynamics_setup.h"
#include "app/meshing_setup.h"
#include "app/run_directory.h"
#include "app/scene_keys.h"
#include "common/errors.h"
#include "common/processes.h"
#include "common/progress.h"
#include "dynamics/result_writer.h"
#include "dynamics/sweep.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>

namespace hertzgear
{
  using namespace dynamics;

  namespace
  {
    void write_dynamics_artifacts(const RunDirectory &dir, const Scene &scene,
                                  const SimulationResult &result, const nlohmann::json &summary)
    {
      const int last_periods = scene.output.timeseries_periods;
      dir.write_text("timeseries.csv", timeseries_csv(result, last_periods));
      dir.write_text("poincare.csv", poincare_csv(result));
      dir.write_text("spectrum.csv", spectrum_csv(result));
      dir.write_text("force_penetration.csv", force_penetration_csv(result, last_periods));
      dir.write_text("impacts.csv", impacts_csv(result));
      dir.write_json("summary.json", summary);
    }
  } // namespace

  nlohmann::json run_dynamics_stage(const Scene &scene, const RunDirectory *dir, PhaseTimer &timer)
  {
    DynamicsSetup setup;
    {
      PhaseTimer::Scope scope(timer, "setup");
      setup = make_dynamics_setup(scene);
    }
    GearPairModel model(setup.parameters);
    progress_line("dynamics",
                  msg("state dimension ", model.n_states(), ", ", model.parameters().effects.describe(),
                      ", m_e = ", setup.parameters.equivalent_mass_kg, " kg, F0 = ",
                      setup.parameters.static_force_N, " N, c = ",
                      setup.parameters.damping_N_s_per_m, " N s/m, integrator ",
                      scene.dynamics.integrator));
    SimulationResult result;
    {
      PhaseTimer::Scope scope(timer, "integrate");
      const auto        start = std::chrono::steady_clock::now();
      result = simulate(model, setup.run, initial_state(scene, model), [&](int done, int total) {
        progress_line("dynamics",
                      msg("period ", done, "/", total, "  (",
                          std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
                            .count(),
                          " s)"));
      });
    }
    nlohmann::json summary;
    {
      PhaseTimer::Scope scope(timer, "analysis");
      summary = summary_json(model, result, analyse(model, result), setup.describe());
      // A helical pair's normal mesh force F / cos(beta_b) has the axial component F tan(beta_b)
      // (F along the transverse line of action, docs/dynamics.md, "Helical pairs"): the load on
      // the shafts' thrust bearings, from the same steady window.
      const double beta_b = make_pair(scene).base_helix_angle_rad();
      if (beta_b != 0)
        {
          const double t = std::tan(beta_b);
          summary["axial_force"] = {{"mean_N", t * summary["mean_mesh_force_N"].get<double>()},
                                    {"max_N", t * summary["max_mesh_force_N"].get<double>()},
                                    {"min_N", t * summary["min_mesh_force_N"].get<double>()},
                                    {"static_N", t * summary["static_force_N"].get<double>()},
                                    {"base_helix_angle_deg", beta_b * 180 / M_PI}};
        }
    }
    progress_line("dynamics",
                  msg("rms DTE ", summary["rms_dte_um"].get<double>(), " um, mean force ",
                      summary["mean_mesh_force_N"].get<double>(), " N (F0 ",
                      summary["static_force_N"].get<double>(), " N), period ",
                      summary["period_multiplicity"].get<int>(), ", steps ",
                      result.stats.steps, ", rhs evals ", result.stats.rhs_evals, ", events ",
                      result.stats.events));
    if (summary["force_law"]["extrapolated"].get<bool>())
      progress_line("dynamics",
                    msg("warning: the mesh force reaches ", summary["max_mesh_force_N"].get<double>(),
                        " N, above the force law's data (",
                        summary["force_law"]["tabulated_force_limit_N"].get<double>(),
                        " N, the load ladder's top), in ",
                        100.0 * summary["force_law"]["extrapolated_fraction"].get<double>(),
                        " % of the steady window: the FE law extrapolates there; a higher top of "
                        "Stiffness/load_ladder_percent covers it"));
    if (dir)
      {
        PhaseTimer::Scope scope(timer, "write");
        write_dynamics_artifacts(*dir, scene, result, summary);
      }
    return summary;
  }

  namespace
  {
    int run_dynamics(const CommandContext &ctx)
    {
      return run_stage_command(
        ctx, check_dynamics_inputs, run_dynamics_stage,
        [](const nlohmann::json &summary) { std::cout << summary.dump(2) << std::endl; },
        [](const nlohmann::json &) { return nlohmann::json{{"stage", "dynamics"}}; });
    }

    // The sweep's plain inputs from Sweep/* and --threads.
    SweepSettings sweep_settings(const Scene &scene, const int n_threads)
    {
      const auto   &w = scene.sweep;
      SweepSettings s;
      s.speed_min_rpm               = w.speed_min_rpm;
      s.speed_max_rpm               = w.speed_max_rpm;
      s.points                      = w.points;
      s.direction                   = sweep_direction_from_name(w.direction);
      s.mode                        = sweep_mode_from_name(w.mode);
      s.periods_per_point           = w.periods_per_point;
      s.transient_periods_per_point = w.transient_periods_per_point;
      s.threads                     = std::max(0, n_threads); // < 0 as 0, as --threads did
      return s;
    }

    // Sweep/* (and --threads) as the sweep's settings, checked.
    SweepSettings checked_sweep_settings(const Scene &scene, const int n_threads)
    {
      try
        {
          SweepSettings settings = sweep_settings(scene, n_threads);
          check_sweep_settings(settings);
          return settings;
        }
      catch (const ParameterError &e)
        {
          // The field as its scene key, or --threads.
          throw InputError(keyed_message(e, [](const std::string &field) {
            return field == "threads" ? std::string("--threads") : "Sweep/" + field;
          }));
        }
    }

    // "[sweep] rank 1: up point 3/8  2928.57 rpm  rms DTE 108.99 um  period 1  (0.4 s)"
    void sweep_progress_line(const SweepPointDone &p)
    {
      progress_line("sweep", msg(p.n_ranks > 1 ? msg("rank ", p.rank, ": ") : std::string(),
                                 sweep_branch_name(p.row.branch), " point ", p.done, "/", p.total,
                                 "  ", p.row.speed_rpm, " rpm  rms DTE ",
                                 1e6 * p.row.summary.rms_dte_m, " um  period ",
                                 p.row.summary.period_multiplicity, "  (", p.elapsed_s, " s)"));
    }
  } // namespace

  void check_dynamics_inputs(const Scene &scene) { make_dynamics_setup(scene); }

  void check_sweep_inputs(const Scene &scene, const int n_threads)
  {
    if (scene.sweep.mode == "shooting")
      {
        check_response_inputs(scene, true);
        return;
      }
    checked_sweep_settings(scene, n_threads);
    check_dynamics_inputs(scene);
  }

  SweepStageOutput run_sweep_stage(const Scene &scene, const RunDirectory *dir, PhaseTimer &timer,
                                   const int n_threads_requested)
  {
    if (scene.sweep.mode == "shooting")
      {
        const auto out = run_response_stage(scene, dir, timer, true);
        return {out.csv, out.json["integrator"]};
      }
    const SweepSettings settings = checked_sweep_settings(scene, n_threads_requested);
    const DynamicsSetup setup    = make_dynamics_setup(scene);
    const SweepModel    model{setup.parameters, setup.speed_rpm, setup.run, initial_state(scene)};
    SweepResult         result;
    {
      PhaseTimer::Scope scope(timer, "integrate");
      result = dynamics::sweep(model, settings, sweep_progress_line);
    }
    const auto extrapolated = std::count_if(result.rows.begin(), result.rows.end(), [](const auto &r) {
      return r.summary.force_law_extrapolated;
    });
    if (extrapolated > 0)
      progress_line("sweep", msg("warning: at ", extrapolated, " of ", result.rows.size(),
                                 " points the mesh force goes above the force law's data (",
                                 result.rows.front().summary.tabulated_force_limit_N,
                                 " N, the load ladder's top): the FE law extrapolates there "
                                 "(column extrapolated_fraction); a higher top of "
                                 "Stiffness/load_ladder_percent covers them"));
    const std::string csv = sweep_csv(result.rows);
    if (dir)
      {
        PhaseTimer::Scope scope(timer, "write");
        dir->write_text("sweep.csv", csv);
        dir->write_text("bifurcation.csv",
                        bifurcation_csv(result.rows, settings.mode != SweepMode::continuation));
      }
    return {csv, nlohmann::json(result.stats)};
  }

  namespace
  {
    int run_sweep(const CommandContext &ctx, const int n_threads_requested)
    {
      const auto stage = [n_threads_requested](const Scene &scene, const RunDirectory *dir,
                                               PhaseTimer &timer) {
        return run_sweep_stage(scene, dir, timer, n_threads_requested);
      };
      // Under mpirun every rank computes its share of the speeds (rank 0 writes); the shooting
      // sweep, one continuation, runs on rank 0.
      return run_stage_command(
        ctx,
        [n_threads_requested](const Scene &scene) { check_sweep_inputs(scene, n_threads_requested); },
        stage, [](const SweepStageOutput &out) { std::cout << out.sweep_csv; },
        [](const SweepStageOutput &out) {
          return nlohmann::json{{"stage", "sweep"}, {"integrator", out.integrator}};
        },
        [](const Scene &scene) { return scene.sweep.mode != "shooting"; });
    }
  } // namespace

  void add_dynamics_commands(CommandRegistry &registry)
  {
    CLI::App *dyn = registry.add_command(
      {"dynamics", "Integrate the gear-pair dynamics of a scene and analyse its steady state"},
      run_dynamics);
    auto      threads = std::make_shared<int>(0);
    CLI::App *sweep   = registry.add_command(
      {"sweep", "Speed sweep of the dynamics (continuation up/down and independent points)"},
      [threads](const CommandContext &ctx) { return run_sweep(ctx, *threads); });
    sweep->add_option("--threads", *threads,
                      "Threads for the sweep jobs (0 = all hardware threads)");
    CLI::App *accuracy = command_group(*dyn->get_parent(), "accuracy",
                                       "Work-precision studies: error versus time");
    auto      options = std::make_shared<AccuracyDynamicsOptions>();
    CLI::App *acc_dyn = registry.add_command(
      {"dynamics", "Work-precision table of the dynamics integrators against a converged "
                   "reference (radau-iia, 7 and 9 stages at rtol 1e-13)"},
      [options](const CommandContext &ctx) { return run_accuracy_dynamics(ctx, *options); },
      accuracy);
    acc_dyn->add_option("--integrators", options->integrators,
                        "Only these integrators (comma-separated names; default all)")
      ->delimiter(',');
    acc_dyn->add_option("--tightest-rtol", options->tightest_rtol,
                        "The ladder runs rtol 1e-4 down to this power of ten (1e-12 .. 1e-4)");
  }
} // namespace hertzgear
