#include "dynamics/sweep.h"

#include "common/errors.h"
#include "common/names.h"
#include "common/processes.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>

namespace hertzgear::dynamics
{
  namespace
  {
    const NameTable<SweepDirection, 3> direction_names = {
      {"up", SweepDirection::up}, {"down", SweepDirection::down}, {"both", SweepDirection::both}};
    const NameTable<SweepMode, 3> mode_names = {{"continuation", SweepMode::continuation},
                                                {"independent", SweepMode::independent},
                                                {"both", SweepMode::both}};
    const NameTable<SweepBranch, 3> branch_names = {{"up", SweepBranch::up},
                                                    {"down", SweepBranch::down},
                                                    {"independent", SweepBranch::independent}};
  } // namespace

  SweepDirection sweep_direction_from_name(const std::string &name)
  {
    return from_name(name, direction_names, "direction");
  }

  SweepMode sweep_mode_from_name(const std::string &name) { return from_name(name, mode_names, "mode"); }

  std::string sweep_branch_name(const SweepBranch branch) { return name_of(branch, branch_names); }

  void check_sweep_settings(const SweepSettings &s)
  {
    if (s.points < 1)
      throw ParameterError("points", msg(s.points, " must be at least 1"));
    if (s.points == 1 && s.speed_max_rpm != s.speed_min_rpm)
      throw ParameterError("speed_max_rpm", msg(s.speed_max_rpm, " must equal {speed_min_rpm} = ",
                                                s.speed_min_rpm, " for a sweep of one point"));
    if (s.points > 1 && !(s.speed_max_rpm > s.speed_min_rpm))
      throw ParameterError("speed_max_rpm", msg(s.speed_max_rpm, " must exceed {speed_min_rpm} = ",
                                                s.speed_min_rpm));
    if (!(s.speed_min_rpm > 0.0))
      throw ParameterError("speed_min_rpm", msg(s.speed_min_rpm, " must be > 0"));
    if (s.transient_periods_per_point < 0)
      throw ParameterError("transient_periods_per_point",
                           msg(s.transient_periods_per_point, " must be >= 0"));
    if (s.periods_per_point <= s.transient_periods_per_point)
      throw ParameterError("periods_per_point",
                           msg(s.periods_per_point, " must exceed {transient_periods_per_point} = ",
                               s.transient_periods_per_point));
    if (s.threads < 0)
      throw ParameterError("threads", msg(s.threads, " must be >= 0 (0: all hardware threads)"));
  }

  std::vector<double> sweep_speeds(const SweepSettings &s)
  {
    std::vector<double> speeds(static_cast<std::size_t>(std::max(s.points, 0)), s.speed_min_rpm);
    for (int i = 1; i < s.points; ++i)
      speeds[i] = s.speed_min_rpm + (s.speed_max_rpm - s.speed_min_rpm) * i / (s.points - 1);
    return speeds;
  }

  std::vector<double> InitialState::of(const GearPairModel &model) const
  {
    if (static_equilibrium)
      return model.static_equilibrium_state();
    return model.state(dte_m, dte_rate_m_per_s, penetration_m);
  }

  GearPairParameters at_speed(const GearPairParameters &parameters,
                              const double speed_rpm_of_parameters, const double speed_rpm)
  {
    GearPairParameters p = parameters;
    p.mesh_frequency_rad_per_s *= speed_rpm / speed_rpm_of_parameters;
    return p;
  }

  namespace
  {
    // A continuation chain (up or down) is one sequential job; every independent point is its
    // own job.
    struct Job
    {
      SweepBranch      branch = SweepBranch::independent;
      std::vector<int> points; // indices into the speeds, in the order they run
    };

    std::vector<Job> make_jobs(const SweepSettings &s)
    {
      std::vector<Job> jobs;
      const bool continuation = s.mode != SweepMode::independent;
      if (continuation && s.direction != SweepDirection::down)
        {
          jobs.push_back({SweepBranch::up, {}});
          for (int i = 0; i < s.points; ++i)
            jobs.back().points.push_back(i);
        }
      if (continuation && s.direction != SweepDirection::up)
        {
          jobs.push_back({SweepBranch::down, {}});
          for (int i = s.points - 1; i >= 0; --i)
            jobs.back().points.push_back(i);
        }
      if (s.mode != SweepMode::continuation)
        for (int i = 0; i < s.points; ++i)
          jobs.push_back({SweepBranch::independent, {i}});
      return jobs;
    }

    // ---- Rows and statistics between ranks (as JSON text) ----

    // This rank's rows by job, its statistics and its failure, as one text.
    std::string rank_part(const std::vector<std::vector<SweepRow>> &rows,
                          const IntegratorStats &stats, const std::exception_ptr &failure)
    {
      nlohmann::json mine = {{"rows", nlohmann::json::array()}, {"stats", stats}};
      for (std::size_t j = 0; j < rows.size(); ++j)
        for (const auto &r : rows[j])
          mine["rows"].push_back({{"job", j},
                                  {"speed_rpm", r.speed_rpm},
                                  {"branch", static_cast<int>(r.branch)},
                                  {"summary", r.summary},
                                  {"poincare", r.poincare_dte_m}});
      if (failure)
        try
          {
            std::rethrow_exception(failure);
          }
        catch (const std::exception &e)
          {
            mine["error"] = {{"code", exit_code_of(e)}, {"what", e.what()}};
          }
      return mine.dump();
    }

    // Under mpirun: every rank sends the rows of its jobs (and its failure, if any) to all ranks,
    // so that each rank ends with the whole table, or all of them with the same error.
    void gather_rows(std::exception_ptr &failure, std::vector<std::vector<SweepRow>> &rows,
                     IntegratorStats &stats)
    {
      const auto all = processes::all_gather(rank_part(rows, stats, failure));
      for (auto &job_rows : rows)
        job_rows.clear();
      stats = IntegratorStats{};
      for (std::size_t r = 0; r < all.size(); ++r)
        {
          const auto part = nlohmann::json::parse(all[r]);
          if (part.contains("error") && !failure)
            try
              {
                throw_for_exit_code(part["error"]["code"].get<int>(),
                                    msg("sweep rank ", r, ": ",
                                        part["error"]["what"].get<std::string>()));
              }
            catch (...)
              {
                failure = std::current_exception();
              }
          for (const auto &row : part["rows"])
            rows[row["job"].get<std::size_t>()].push_back(
              {row["speed_rpm"].get<double>(), static_cast<SweepBranch>(row["branch"].get<int>()),
               row["summary"].get<SteadyStateSummary>(), row["poincare"].get<std::vector<double>>()});
          const IntegratorStats s = part["stats"].get<IntegratorStats>();
          stats += s;
          if (stats.name.empty())
            stats.name = s.name;
        }
    }

    // ---- The jobs of this rank on threads ----

    class SweepRun
    {
    public:
      SweepRun(const SweepModel &sweep_model, const SweepSettings &settings,
               const SweepProgress &on_point)
        : model(sweep_model), pair(with_shared_mesh_force_law(sweep_model.parameters)),
          progress(on_point), speeds(sweep_speeds(settings)),
          jobs(make_jobs(settings)), rows(jobs.size()), rank(processes::rank()),
          n_ranks(processes::count()), run(sweep_model.run)
      {
        run.periods           = settings.periods_per_point;
        run.transient_periods = settings.transient_periods_per_point;
        // Job j runs on rank j mod (number of ranks).
        for (std::size_t j = 0; j < jobs.size(); ++j)
          if (int(j % std::size_t(n_ranks)) == rank)
            {
              my_jobs.push_back(j);
              n_points += int(jobs[j].points.size());
            }
      }

      void run_on_threads(const int n_threads_requested)
      {
        // Default: the hardware threads shared among the ranks.
        const int n_threads = std::max(
          1, std::min<int>(n_threads_requested > 0 ?
                             n_threads_requested :
                             int(std::thread::hardware_concurrency() / unsigned(n_ranks)),
                           int(my_jobs.size())));
        std::vector<std::thread> threads;
        for (int t = 0; t < n_threads; ++t)
          threads.emplace_back([this]() { work(); });
        for (auto &t : threads)
          t.join();
      }

      SweepResult finish()
      {
        if (n_ranks > 1)
          {
            gather_rows(failure, rows, stats);
            if (failure)
              processes::mark_failure_shared(); // every rank has it from the gather
          }
        if (failure)
          std::rethrow_exception(failure);
        SweepResult result;
        for (auto &job_rows : rows)
          for (auto &row : job_rows)
            result.rows.push_back(std::move(row));
        result.stats = stats;
        return result;
      }

    private:
      // Takes the next job of this rank until there is none left or a job failed.
      void work()
      {
        for (std::size_t k = next_job++; k < my_jobs.size(); k = next_job++)
          try
            {
              run_job(my_jobs[k]);
            }
          catch (...)
            {
              std::lock_guard<std::mutex> lock(mutex);
              if (!failure)
                failure = std::current_exception();
              next_job = my_jobs.size();
            }
      }

      // The points of job j in order; a chain starts each point from the last state.
      void run_job(const std::size_t j)
      {
        const Job          &job = jobs[j];
        std::vector<double> y;
        for (const int i : job.points)
          {
            GearPairModel gear_pair(at_speed(pair, model.speed_rpm, speeds[i]));
            if (y.empty())
              y = model.initial.of(gear_pair);
            const SimulationResult r = simulate(gear_pair, run, y);
            if (job.branch != SweepBranch::independent)
              y = r.final_state; // continuation: the next speed starts here
            SweepRow row{speeds[i], job.branch, analyse(gear_pair, r), {}};
            for (const auto &p : r.poincare)
              row.poincare_dte_m.push_back(p.dte_m);
            rows[j].push_back(row);
            point_done(rows[j].back(), r.stats);
          }
      }

      void point_done(const SweepRow &row, const IntegratorStats &point_stats)
      {
        std::lock_guard<std::mutex> lock(mutex);
        stats += point_stats;
        ++done;
        if (progress)
          progress({rank, n_ranks, done, n_points, row,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
      }

      const SweepModel                   &model;
      const GearPairParameters            pair; // the model's, with the force law its points share
      const SweepProgress                &progress;
      const std::vector<double>           speeds;
      const std::vector<Job>              jobs;
      std::vector<std::vector<SweepRow>>  rows; // by job
      const int                           rank, n_ranks;
      RunSettings                         run;
      std::vector<std::size_t>            my_jobs;
      int                                 n_points = 0, done = 0;
      std::atomic<std::size_t>            next_job{0};
      std::mutex                          mutex;
      std::exception_ptr                  failure;
      IntegratorStats                     stats;
      const std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    };
  } // namespace

  SweepResult sweep(const SweepModel &model, const SweepSettings &settings,
                    const SweepProgress &progress)
  {
    check_sweep_settings(settings);
    SweepRun run(model, settings, progress);
    run.run_on_threads(settings.threads);
    return run.finish();
  }
} // namespace hertzgear::dynamics
