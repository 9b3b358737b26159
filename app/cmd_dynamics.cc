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
#include "app/run_directory.h"
#include "common/errors.h"
#include "common/processes.h"
#include "common/progress.h"
#include "dynamics/sweep.h"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <sstream>

namespace hertzgear
{
  using namespace dynamics;

  nlohmann::json summary_json(const DynamicsSetup &setup, const GearPairModel &model,
                              const SimulationResult &result, const SteadyStateSummary &s)
  {
    nlohmann::json j;
    j["rms_dte_um"]                 = 1e6 * s.rms_dte_m;
    j["rms_dte_fluctuation_um"]     = 1e6 * s.rms_dte_fluctuation_m;
    j["mean_dte_um"]                = 1e6 * s.mean_dte_m;
    j["min_dte_um"]                 = 1e6 * s.min_dte_m;
    j["max_dte_um"]                 = 1e6 * s.max_dte_m;
    j["mean_mesh_force_N"]          = s.mean_force_N;
    j["static_force_N"]             = s.static_force_N;
    j["max_mesh_force_N"]           = s.max_force_N;
    j["min_mesh_force_N"]           = s.min_force_N;
    j["dynamic_factor"]             = s.dynamic_factor;
    j["contact_loss_fraction"]      = s.contact_loss_fraction;
    j["contact_losses_per_period"]  = s.contact_losses_per_period;
    j["backside_impacts"]           = s.backside_impacts;
    j["period_multiplicity"]        = s.period_multiplicity;
    // How the period was decided (dynamics/analysis.h, detect_period): "period-k", "not settled"
    // (with the nearest period, the contraction per mesh period and the distance from it relative
    // to the DTE scale, all estimated from the Poincare section) or "aperiodic".
    j["period_status"]              = s.period_status;
    j["period_candidate"]           = s.period_candidate;
    j["period_contraction_per_period"] = s.period_contraction;
    j["period_distance_relative"]   = s.period_distance;
    j["max_penetration_um"]         = 1e6 * s.max_penetration_m;
    // "dense output": the extremes above (DTE, mesh force, penetration, dynamic factor) are
    // maxima of the integrator's interpolant inside every step; "samples": of the samples only.
    j["extremes_from"]              = s.extremes_from;
    j["impacts"]                    = s.n_impacts;
    // The mean of the loop integrals of F d(delta) over the impacts: the contact damping's
    // dissipation when k_h is constant under load, else with the stiffness variation's work.
    j["mean_loop_work_per_impact_J"] = s.mean_loop_work_per_impact_J;
    j["state_dimension"]            = model.n_states();
    j["effects"]                    = model.parameters().effects.describe();
    j["equivalent_mass_kg"]         = model.parameters().equivalent_mass_kg;
    j["steady_periods"]             = result.steady_periods;
    j["mesh_period_s"]              = result.mesh_period_s;
    j["model"]                      = setup.describe();
    j["integrator"]                 = nlohmann::json(result.stats);
    j["wall_time_s"]                = result.stats.wall_time_s;
    return j;
  }

  std::string csv_number(const double v)
  {
    std::ostringstream os;
    os.precision(12);
    os << v;
    return os.str();
  }

  namespace
  {
    void write_dynamics_artifacts(const RunDirectory &dir, const Scene &scene,
                                  const SimulationResult &result, const nlohmann::json &summary)
    {
      const auto &s      = result.steady;
      const int   S      = result.samples_per_period;
      const int   n_last = scene.output.timeseries_periods;
      const std::size_t first =
        (n_last > 0 && n_last < result.steady_periods) ? s.size() - 1 - std::size_t(n_last) * S : 0;
      dir.write_text("timeseries.csv", [&]() {
        std::ostringstream os;
        os << "time_s,dte_um,dte_rate_m_per_s,penetration_um,mesh_force_N,contact\n";
        for (std::size_t i = first; i < s.size(); ++i)
          os << csv_number(s[i].t_s) << ',' << csv_number(1e6 * s[i].dte_m) << ','
             << csv_number(s[i].dte_rate_m_per_s) << ',' << csv_number(1e6 * s[i].penetration_m)
             << ',' << csv_number(s[i].force_N) << ',' << s[i].contact << '\n';
        return os.str();
      }());
      dir.write_text("poincare.csv", [&]() {
        std::ostringstream os;
        os << "period,time_s,dte_um,dte_rate_m_per_s\n";
        for (std::size_t i = 0; i < result.poincare.size(); ++i)
          os << i << ',' << csv_number(result.poincare[i].t_s) << ','
             << csv_number(1e6 * result.poincare[i].dte_m) << ','
             << csv_number(result.poincare[i].dte_rate_m_per_s) << '\n';
        return os.str();
      }());
      dir.write_text("spectrum.csv", [&]() {
        std::ostringstream os;
        os << "frequency_Hz,mesh_order,amplitude_um\n";
        for (const auto &l : dte_spectrum(result))
          os << csv_number(l.frequency_Hz) << ',' << csv_number(l.mesh_order) << ','
             << csv_number(1e6 * l.amplitude_m) << '\n';
        return os.str();
      }());
      dir.write_text("force_penetration.csv", [&]() {
        // The loops of the written time window, and the energy of every closed loop (impact).
        std::ostringstream os;
        os << "time_s,penetration_um,mesh_force_N,contact\n";
        for (std::size_t i = first; i < s.size(); ++i)
          os << csv_number(s[i].t_s) << ',' << csv_number(1e6 * s[i].penetration_m) << ','
             << csv_number(s[i].force_N) << ',' << s[i].contact << '\n';
        return os.str();
      }());
      dir.write_text("impacts.csv", [&]() {
        std::ostringstream os;
        os << "start_s,end_s,max_force_N,max_penetration_um,loop_work_J\n";
        for (const auto &l : force_penetration_loops(result))
          os << csv_number(l.start_s) << ',' << csv_number(l.end_s) << ','
             << csv_number(l.max_force_N) << ',' << csv_number(1e6 * l.max_penetration_m) << ','
             << csv_number(l.loop_work_J) << '\n';
        return os.str();
      }());
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
      summary = summary_json(setup, model, result, analyse(model, result));
    }
    progress_line("dynamics",
                  msg("rms DTE ", summary["rms_dte_um"].get<double>(), " um, mean force ",
                      summary["mean_mesh_force_N"].get<double>(), " N (F0 ",
                      summary["static_force_N"].get<double>(), " N), period ",
                      summary["period_multiplicity"].get<int>(), ", steps ",
                      result.stats.steps, ", rhs evals ", result.stats.rhs_evals, ", events ",
                      result.stats.events));
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
        ctx, run_dynamics_stage,
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

    // A ParameterError of SweepSettings as an InputError about the scene key (or --threads).
    InputError sweep_input_error(const ParameterError &e)
    {
      const auto key_of = [](const std::string &field) {
        return field == "threads" ? std::string("--threads") : "Sweep/" + field;
      };
      std::string text = e.text();
      for (std::size_t open = text.find('{'); open != std::string::npos; open = text.find('{', open))
        {
          const std::size_t close = text.find('}', open);
          if (close == std::string::npos)
            break;
          const std::string key = key_of(text.substr(open + 1, close - open - 1));
          text.replace(open, close - open + 1, key);
          open += key.size();
        }
      return InputError(key_of(e.parameter()) + " = " + text);
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

    std::string sweep_csv_text(const std::vector<SweepRow> &rows)
    {
      std::ostringstream os;
      os << "speed_rpm,direction,rms_dte_um,min_dte_um,max_dte_um,dynamic_factor,"
            "contact_loss_fraction,period_multiplicity,extremes_from\n";
      for (const auto &r : rows)
        os << csv_number(r.speed_rpm) << ',' << sweep_branch_name(r.branch) << ','
           << csv_number(1e6 * r.summary.rms_dte_m) << ','
           << csv_number(1e6 * r.summary.min_dte_m) << ','
           << csv_number(1e6 * r.summary.max_dte_m) << ','
           << csv_number(r.summary.dynamic_factor) << ','
           << csv_number(r.summary.contact_loss_fraction) << ','
           << r.summary.period_multiplicity << ',' << r.summary.extremes_from << '\n';
      return os.str();
    }

    // The Poincare points of the independent runs when there are any, else those of the chains.
    std::string bifurcation_csv_text(const std::vector<SweepRow> &rows, const bool independent)
    {
      std::ostringstream os;
      os << "speed_rpm,poincare_dte_um\n";
      for (const auto &r : rows)
        if (independent == (r.branch == SweepBranch::independent))
          for (const double x : r.poincare_dte_m)
            os << csv_number(r.speed_rpm) << ',' << csv_number(1e6 * x) << '\n';
      return os.str();
    }
  } // namespace

  SweepStageOutput run_sweep_stage(const Scene &scene, const RunDirectory *dir, PhaseTimer &timer,
                                   const int n_threads_requested)
  {
    if (scene.sweep.mode == "shooting")
      {
        const auto out = run_response_stage(scene, dir, timer, true);
        return {out.csv, out.json["integrator"]};
      }
    SweepSettings settings;
    try
      {
        settings = sweep_settings(scene, n_threads_requested);
        check_sweep_settings(settings);
      }
    catch (const ParameterError &e)
      {
        throw sweep_input_error(e);
      }
    const DynamicsSetup setup = make_dynamics_setup(scene);
    const SweepModel    model{setup.parameters, setup.speed_rpm, setup.run, initial_state(scene)};
    SweepResult         result;
    {
      PhaseTimer::Scope scope(timer, "integrate");
      result = dynamics::sweep(model, settings, sweep_progress_line);
    }
    const std::string sweep_csv = sweep_csv_text(result.rows);
    if (dir)
      {
        PhaseTimer::Scope scope(timer, "write");
        dir->write_text("sweep.csv", sweep_csv);
        dir->write_text("bifurcation.csv",
                        bifurcation_csv_text(result.rows, settings.mode != SweepMode::continuation));
      }
    return {sweep_csv, nlohmann::json(result.stats)};
  }

  namespace
  {
    int run_sweep(const CommandContext &ctx, const int n_threads_requested)
    {
      const auto stage = [n_threads_requested](const Scene &scene, const RunDirectory *dir,
                                               PhaseTimer &timer) {
        return run_sweep_stage(scene, dir, timer, n_threads_requested);
      };
      // Under mpirun only rank 0 writes; the other ranks compute their share of the points.
      if (!processes::is_root())
        {
          PhaseTimer timer;
          stage(load_scene(ctx, timer), nullptr, timer);
          return 0;
        }
      return run_stage_command(
        ctx, stage, [](const SweepStageOutput &out) { std::cout << out.sweep_csv; },
        [](const SweepStageOutput &out) {
          return nlohmann::json{{"stage", "sweep"}, {"integrator", out.integrator}};
        });
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
