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


#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <iostream>
#include <mutex>
#include <numeric>
#include <sstream>
#include <thread>

namespace hertzgear
{
  using namespace dynamics;

  nlohmann::json integrator_json(const IntegratorStats &s)
  {
    return {{"name", s.name},
            {"steps", s.steps},
            {"rejected_steps", s.rejected_steps},
            {"rhs_evals", s.rhs_evals},
            {"jacobian_evals", s.jacobian_evals},
            {"root_evals", s.root_evals},
            {"events", s.events},
            {"wall_time_s", s.wall_time_s}};
  }

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
    j["max_penetration_um"]         = 1e6 * s.max_penetration_m;
    j["impacts"]                    = s.n_impacts;
    j["mean_energy_dissipated_per_impact_J"] = s.mean_energy_per_impact_J;
    j["state_dimension"]            = model.n_states();
    j["effects"]                    = model.parameters().effects.describe();
    j["equivalent_mass_kg"]         = model.parameters().equivalent_mass_kg;
    j["steady_periods"]             = result.steady_periods;
    j["mesh_period_s"]              = result.mesh_period_s;
    j["model"]                      = setup.describe();
    j["integrator"]                 = integrator_json(result.stats);
    j["wall_time_s"]                = result.stats.wall_time_s;
    return j;
  }

  namespace
  {
    std::string csv_number(const double v)
    {
      std::ostringstream os;
      os.precision(12);
      os << v;
      return os.str();
    }

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
        os << "start_s,end_s,max_force_N,max_penetration_um,energy_dissipated_J\n";
        for (const auto &l : force_penetration_loops(result))
          os << csv_number(l.start_s) << ',' << csv_number(l.end_s) << ','
             << csv_number(l.max_force_N) << ',' << csv_number(1e6 * l.max_penetration_m) << ','
             << csv_number(l.energy_dissipated_J) << '\n';
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
      PhaseTimer timer;
      Scene      scene;
      {
        PhaseTimer::Scope scope(timer, "scene");
        scene = load_scene(ctx.scene_file, ctx.overrides);
      }
      if (ctx.out_dir.empty())
        {
          std::cout << run_dynamics_stage(scene, nullptr, timer).dump(2) << std::endl;
          timer.print_summary(progress_stream());
        }
      else
        {
          RunDirectory dir(ctx.out_dir, scene, ctx.command_line);
          run_dynamics_stage(scene, &dir, timer);
          dir.finish(timer, {{"stage", "dynamics"}}); // prints the timing summary
        }
      return 0;
    }

    struct SweepRow
    {
      double              speed_rpm = 0;
      std::string         direction;
      SteadyStateSummary  summary;
      std::vector<double> poincare_dte_m;
    };

    // Under mpirun: every rank sends the rows of its jobs (and its failure, if any) to all ranks,
    // so that each rank ends with the whole table, or all of them with the same error.
    void gather_sweep_rows(std::exception_ptr &failure,
                           std::vector<std::vector<SweepRow>> &rows, IntegratorStats &stats)
    {
      nlohmann::json mine = {{"rows", nlohmann::json::array()}};
      for (std::size_t j = 0; j < rows.size(); ++j)
        for (const auto &r : rows[j])
          mine["rows"].push_back({{"job", j},
                                  {"speed_rpm", r.speed_rpm},
                                  {"direction", r.direction},
                                  {"rms", r.summary.rms_dte_m},
                                  {"min", r.summary.min_dte_m},
                                  {"max", r.summary.max_dte_m},
                                  {"dynamic_factor", r.summary.dynamic_factor},
                                  {"contact_loss_fraction", r.summary.contact_loss_fraction},
                                  {"period", r.summary.period_multiplicity},
                                  {"poincare", r.poincare_dte_m}});
      mine["stats"] = integrator_json(stats);
      if (failure)
        try
          {
            std::rethrow_exception(failure);
          }
        catch (const std::exception &e)
          {
            mine["error"] = {{"code", exit_code_of(e)}, {"what", e.what()}};
          }
      const auto all = processes::all_gather(mine.dump());
      for (auto &job_rows : rows)
        job_rows.clear();
      stats = IntegratorStats{};
      for (std::size_t r = 0; r < all.size(); ++r)
        {
          const auto part = nlohmann::json::parse(all[r]);
          if (part.contains("error") && !failure)
            {
              const std::string what = msg("sweep rank ", r, ": ", part["error"]["what"].get<std::string>());
              try
                {
                  throw_for_exit_code(part["error"]["code"].get<int>(), what);
                }
              catch (...)
                {
                  failure = std::current_exception();
                }
            }
          for (const auto &row : part["rows"])
            {
              SweepRow x;
              x.speed_rpm                           = row["speed_rpm"];
              x.direction                           = row["direction"];
              x.summary.rms_dte_m                   = row["rms"];
              x.summary.min_dte_m                   = row["min"];
              x.summary.max_dte_m                   = row["max"];
              x.summary.dynamic_factor              = row["dynamic_factor"];
              x.summary.contact_loss_fraction       = row["contact_loss_fraction"];
              x.summary.period_multiplicity         = row["period"];
              x.poincare_dte_m                      = row["poincare"].get<std::vector<double>>();
              rows[row["job"].get<std::size_t>()].push_back(x);
            }
          const auto &st = part["stats"];
          IntegratorStats s;
          s.name           = st["name"];
          s.steps          = st["steps"];
          s.rejected_steps = st["rejected_steps"];
          s.rhs_evals      = st["rhs_evals"];
          s.jacobian_evals = st["jacobian_evals"];
          s.root_evals     = st["root_evals"];
          s.events         = st["events"];
          s.wall_time_s    = st["wall_time_s"];
          stats += s;
          if (stats.name.empty())
            stats.name = s.name;
        }
    }
  } // namespace

  SweepStageOutput run_sweep_stage(const Scene &scene, const RunDirectory *dir, PhaseTimer &timer,
                                   const int n_threads_requested)
  {
      const auto &w = scene.sweep;
      HG_REQUIRE_INPUT(w.speed_max_rpm > w.speed_min_rpm, "Sweep/speed_max_rpm (", w.speed_max_rpm,
                       ") must exceed Sweep/speed_min_rpm (", w.speed_min_rpm, ")");
      HG_REQUIRE_INPUT(w.periods_per_point > w.transient_periods_per_point,
                       "Sweep/periods_per_point must exceed Sweep/transient_periods_per_point");
      DynamicsSetup base = make_dynamics_setup(scene);
      base.run.periods           = w.periods_per_point;
      base.run.transient_periods = w.transient_periods_per_point;
      std::vector<double> speeds(w.points);
      for (int i = 0; i < w.points; ++i)
        speeds[i] = w.speed_min_rpm + (w.speed_max_rpm - w.speed_min_rpm) * i / (w.points - 1);

      // Jobs: a continuation chain (up or down) is one sequential job; every independent point
      // is its own job. Under mpirun job j runs on rank j mod (number of ranks); on each rank the
      // jobs run on threads. Rank 0 gathers the rows and writes the tables.
      struct Job
      {
        std::string      direction;
        std::vector<int> points; // indices into speeds, in order
      };
      std::vector<Job> jobs;
      const bool continuation = w.mode != "independent", independent = w.mode != "continuation";
      if (continuation && w.direction != "down")
        {
          jobs.push_back({"up", {}});
          for (int i = 0; i < w.points; ++i)
            jobs.back().points.push_back(i);
        }
      if (continuation && w.direction != "up")
        {
          jobs.push_back({"down", {}});
          for (int i = w.points - 1; i >= 0; --i)
            jobs.back().points.push_back(i);
        }
      if (independent)
        for (int i = 0; i < w.points; ++i)
          jobs.push_back({"independent", {i}});

      const auto rank    = static_cast<std::size_t>(processes::rank());
      const auto n_ranks = static_cast<std::size_t>(processes::count());
      std::vector<std::size_t> my_jobs;
      int                      n_points = 0;
      for (std::size_t j = 0; j < jobs.size(); ++j)
        if (j % n_ranks == rank)
          {
            my_jobs.push_back(j);
            n_points += int(jobs[j].points.size());
          }
      std::vector<std::vector<SweepRow>> rows(jobs.size());
      std::atomic<std::size_t>           next_job{0};
      std::atomic<int>                   done{0};
      std::mutex                         mutex;
      std::exception_ptr                 failure;
      IntegratorStats                    total_stats;
      const auto                         start = std::chrono::steady_clock::now();

      auto worker = [&]() {
        for (std::size_t k = next_job++; k < my_jobs.size(); k = next_job++)
          {
            const std::size_t j = my_jobs[k];
            try
              {
                std::vector<double> y;
                for (const int i : jobs[j].points)
                  {
                    const DynamicsSetup setup = at_speed(base, speeds[i]);
                    GearPairModel       model(setup.parameters);
                    if (y.empty())
                      y = initial_state(scene, model);
                    const SimulationResult r = simulate(model, setup.run, y);
                    if (jobs[j].direction != "independent")
                      y = r.final_state; // continuation: the next speed starts here
                    SweepRow row{speeds[i], jobs[j].direction, analyse(model, r), {}};
                    for (const auto &p : r.poincare)
                      row.poincare_dte_m.push_back(p.dte_m);
                    rows[j].push_back(row);
                    std::lock_guard<std::mutex> lock(mutex);
                    total_stats += r.stats;
                    progress_line("sweep",
                                  msg(n_ranks > 1 ? msg("rank ", rank, ": ") : std::string(),
                                      jobs[j].direction, " point ", ++done, "/", n_points, "  ",
                                      speeds[i], " rpm  rms DTE ", 1e6 * row.summary.rms_dte_m,
                                      " um  period ", row.summary.period_multiplicity, "  (",
                                      std::chrono::duration<double>(
                                        std::chrono::steady_clock::now() - start)
                                        .count(),
                                      " s)"));
                  }
              }
            catch (...)
              {
                std::lock_guard<std::mutex> lock(mutex);
                if (!failure)
                  failure = std::current_exception();
                next_job = my_jobs.size();
              }
          }
      };
      {
        PhaseTimer::Scope scope(timer, "integrate");
        // Default: the hardware threads shared among the ranks.
        const int n_threads = std::max(
          1, std::min<int>(n_threads_requested > 0 ?
                             n_threads_requested :
                             int(std::thread::hardware_concurrency() / n_ranks),
                           my_jobs.size()));
        std::vector<std::thread> threads;
        for (int t = 0; t < n_threads; ++t)
          threads.emplace_back(worker);
        for (auto &t : threads)
          t.join();
      }
      if (n_ranks > 1)
        gather_sweep_rows(failure, rows, total_stats);
      if (failure)
        std::rethrow_exception(failure);

      std::ostringstream sweep_csv, bifurcation_csv;
      sweep_csv << "speed_rpm,direction,rms_dte_um,min_dte_um,max_dte_um,dynamic_factor,"
                   "contact_loss_fraction,period_multiplicity\n";
      bifurcation_csv << "speed_rpm,poincare_dte_um\n";
      // Bifurcation points from the independent runs when there are any, else from all chains.
      for (const auto &job_rows : rows)
        for (const auto &r : job_rows)
          {
            sweep_csv << csv_number(r.speed_rpm) << ',' << r.direction << ','
                      << csv_number(1e6 * r.summary.rms_dte_m) << ','
                      << csv_number(1e6 * r.summary.min_dte_m) << ','
                      << csv_number(1e6 * r.summary.max_dte_m) << ','
                      << csv_number(r.summary.dynamic_factor) << ','
                      << csv_number(r.summary.contact_loss_fraction) << ','
                      << r.summary.period_multiplicity << '\n';
            if (independent == (r.direction == "independent"))
              for (const double x : r.poincare_dte_m)
                bifurcation_csv << csv_number(r.speed_rpm) << ',' << csv_number(1e6 * x) << '\n';
          }
      if (dir)
        {
          PhaseTimer::Scope scope(timer, "write");
          dir->write_text("sweep.csv", sweep_csv.str());
          dir->write_text("bifurcation.csv", bifurcation_csv.str());
        }
      return {sweep_csv.str(), integrator_json(total_stats)};
    }

  namespace
  {
    int run_sweep(const CommandContext &ctx, const int n_threads_requested)
    {
      PhaseTimer timer;
      Scene      scene;
      {
        PhaseTimer::Scope scope(timer, "scene");
        scene = load_scene(ctx.scene_file, ctx.overrides);
      }
      // Under mpirun only rank 0 writes; the other ranks compute their share of the points.
      if (!processes::is_root())
        run_sweep_stage(scene, nullptr, timer, n_threads_requested);
      else if (ctx.out_dir.empty())
        {
          std::cout << run_sweep_stage(scene, nullptr, timer, n_threads_requested).sweep_csv;
          timer.print_summary(progress_stream());
        }
      else
        {
          RunDirectory dir(ctx.out_dir, scene, ctx.command_line);
          const auto out = run_sweep_stage(scene, &dir, timer, n_threads_requested);
          dir.finish(timer, {{"stage", "sweep"}, {"integrator", out.integrator}});
        }
      return 0;
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
    registry.add_command({"dynamics", "Work-precision table of the dynamics integrators "
                                      "against a reference run at rtol 1e-12"},
                         run_accuracy_dynamics, accuracy);
  }
} // namespace hertzgear
