#include "app/pipeline.h"

#include "app/cmd_dynamics.h"
#include "app/command.h"
#include "app/dynamics_setup.h"
#include "app/meshing_setup.h"
#include "app/run_directory.h"
#include "app/scripts.h"
#include "app/stiffness_setup.h"
#include "common/atomic_file.h"
#include "common/errors.h"
#include "common/hash.h"
#include "common/processes.h"
#include "common/progress.h"
#include "stiffness/iso6336.h"

#include <algorithm>
#include <map>

namespace hertzgear
{
  namespace fs = std::filesystem;

  namespace
  {
    const std::vector<std::string> dynamics_artifacts = {
      "timeseries.csv", "poincare.csv", "spectrum.csv", "force_penetration.csv", "impacts.csv",
      "summary.json"};
    const std::vector<std::string> sweep_artifacts = {"sweep.csv", "bifurcation.csv"};

    bool stiffness_stage_needed(const Scene &scene) { return stiffness_source(scene).is_stage(); }

    // Stiffness/source = table: the dynamics stage copies the table (and the stiffness.csv of
    // the same stem beside it, when there is one) into the run directory, so that the run
    // directory records what drove the dynamics and the report can draw the stiffness.
    std::vector<std::pair<fs::path, std::string>> table_copies(const Scene &scene, const fs::path &out)
    {
      std::vector<std::pair<fs::path, std::string>> copies;
      if (scene.stiffness.source != "table")
        return copies;
      const fs::path table = scene.stiffness.table_file;
      std::error_code ec;
      if (fs::exists(out / "stiffness.json") && fs::equivalent(table, out / "stiffness.json", ec))
        return copies;
      copies.emplace_back(table, "stiffness.json");
      if (fs::path csv = fs::path(table).replace_extension(".csv"); fs::is_regular_file(csv))
        copies.emplace_back(csv, "stiffness.csv");
      return copies;
    }

    // The script the report stage runs (the same lookup as `hertzgear report`), or empty.
    fs::path report_script()
    {
      try
        {
          return find_script("hertzgear_report.py", "HERTZGEAR_REPORT_SCRIPT");
        }
      catch (const std::exception &)
        {
          return {}; // the report stage itself says what is missing
        }
    }

    // The modules the report script imports from beside it (hertzgear_report_lib/*.py), sorted:
    // the figures and the page come from them as much as from the script.
    std::vector<fs::path> report_modules(const fs::path &script)
    {
      std::vector<fs::path> modules;
      const fs::path        folder = script.parent_path() / "hertzgear_report_lib";
      if (fs::is_directory(folder))
        for (const auto &e : fs::directory_iterator(folder))
          if (e.is_regular_file() && e.path().extension() == ".py")
            modules.push_back(e.path());
      std::sort(modules.begin(), modules.end());
      return modules;
    }
  } // namespace

  std::string stage_scene_values(const Scene &scene, const std::string &stage)
  {
    // Geometry, materials and load shape the stiffness; the speed does not.
    const std::vector<std::string> geometry = {"Gear pair", "Material", "Operating"};
    if (stage == "stiffness")
      {
        auto prefixes = geometry;
        prefixes.push_back("Stiffness");
        // The FE force law asks the stage for its load ladder; no other effect reaches it.
        prefixes.push_back("Effects/mesh_force_law");
        std::vector<std::string> drop = {"Operating/speed_rpm", "Stiffness/Fourier"};
        if (!makes_load_ladder(scene))
          drop.push_back("Stiffness/load_ladder_percent");
        if (stiffness_source(scene).uses_fe())
          {
            prefixes.push_back("Mesh");
            prefixes.push_back("Output"); // write_fields: the FE stage's .vtu output
            drop.push_back("Output/report");
            drop.push_back("Output/timeseries_periods");
          }
        return scene_values_for(scene, prefixes, drop);
      }
    // The dynamics reads the gears (base radii, inertias), the operating point, the effects, the
    // stiffness section (source, exponent, Fourier coefficients) and its own settings.
    const std::vector<std::string> dynamics = {"Gear pair", "Material", "Operating", "Effects",
                                               "Stiffness", "Dynamics", "Output"};
    if (stage == "dynamics")
      return scene_values_for(scene, dynamics, {"Output/report"});
    if (stage == "sweep")
      {
        auto prefixes = dynamics;
        prefixes.push_back("Sweep");
        prefixes.push_back("Response");
        return scene_values_for(scene, prefixes, {"Output/report", "Output/timeseries_periods"});
      }
    if (stage == "report")
      return scene_values_for(scene, {""}, {});
    throw std::logic_error("unknown stage " + stage);
  }

  std::vector<std::pair<std::string, std::string>> planned_stages(const Scene &scene)
  {
    std::vector<std::pair<std::string, std::string>> stages;
    const auto &src    = scene.stiffness.source;
    const auto &source = stiffness_source(scene);
    if (source.is_stage())
      stages.emplace_back("stiffness", "Stiffness/source = " + src + ": " + source.summary());
    stages.emplace_back("dynamics",
                        src == "table" ?
                          "on the stiffness table " + scene.stiffness.table_file.lexically_normal().string() +
                            " (Stiffness/source = table: no meshing, no FE)" :
                        src == "fourier" ?
                          std::string("on the Fourier coefficients of the scene (Stiffness/source = "
                                      "fourier: no meshing, no FE)") :
                          std::string("on the stiffness table of the stiffness stage"));
    if (scene.sweep.enabled)
      stages.emplace_back("sweep", scene.sweep.mode == "shooting" ?
                                     msg("Sweep/enabled = true, Sweep/mode = shooting: periodic "
                                         "orbits followed from ", scene.sweep.speed_min_rpm, " to ",
                                         scene.sweep.speed_max_rpm, " rpm") :
                                     msg("Sweep/enabled = true: ", scene.sweep.points,
                                         " speeds from ", scene.sweep.speed_min_rpm, " to ",
                                         scene.sweep.speed_max_rpm, " rpm"));
    if (scene.output.report)
      stages.emplace_back("report", "Output/report = true: report/index.html");
    return stages;
  }

  namespace
  {
    // One run of the pipeline: its stages in order, each run or reused from the cache.
    class PipelineRun
    {
    public:
      PipelineRun(const Scene &scene, const fs::path &out, const std::string &command_line,
                  const PipelineOptions &options)
        : scene(scene), out(out), command_line(command_line), options(options),
          dir(out, scene, command_line), code(code_version()), dynamics_scene(scene)
      {
        // The scene the dynamics and sweep see: the stiffness stage's table when there is one.
        if (stiffness_stage_needed(scene))
          {
            dynamics_scene.stiffness.source     = "table";
            dynamics_scene.stiffness.table_file = fs::absolute(out / "stiffness.json");
          }
      }

      std::vector<StageOutcome> run()
      {
        const auto plan = planned_stages(scene);
        if (!processes::is_root())
          {
            follow(plan);
            return {};
          }
        announce(plan);
        dir.lock(); // held since the command's start: a second run stopped there
        remove_partial_files(out);
        // The report reads the scene values; written first, it is not an artifact of any stage,
        // but every manifest of this run records its hash, which ties it to the artifacts.
        dir.write_text("used_parameters.prm", scene.used_parameters_prm);
        parameters_hash = file_content_hash(out / "used_parameters.prm");
        for (const auto &[stage, why] : plan)
          run_stage(stage);
        finish();
        return outcomes;
      }

    private:
      const Scene            &scene;
      const fs::path          out;
      const std::string       command_line;
      const PipelineOptions   options;
      PhaseTimer              timer;
      RunDirectory            dir;
      const std::string       code;
      Scene                   dynamics_scene;
      std::vector<StageOutcome> outcomes;
      std::string             parameters_hash; // of this run's used_parameters.prm
      // Content hashes of the artifacts so far, inputs of later stages.
      std::vector<std::pair<std::string, std::string>> produced;

      void announce(const std::vector<std::pair<std::string, std::string>> &plan) const
      {
        std::string list;
        for (const auto &[name, why] : plan)
          list += (list.empty() ? "" : " -> ") + name;
        progress_line("run", "stages of " +
                               (scene.file.empty() ? std::string("the default scene") :
                                                     scene.file.string()) +
                               ": " + list + "  (into " + out.string() + ")");
        for (const auto &[name, why] : plan)
          progress_line("run", "  " + name + ": " + why);
      }

      StageKey key_of(const std::string &stage) const
      {
        StageKey key;
        key.code         = code;
        key.scene_values = stage_scene_values(scene, stage);
        if (stage == "dynamics" || stage == "sweep")
          {
            if (stiffness_stage_needed(scene))
              key.inputs.emplace_back("stiffness.json", file_content_hash(out / "stiffness.json"));
            else if (scene.stiffness.source == "table" || scene.effects.ste_excitation == "table")
              key.inputs.emplace_back(scene.stiffness.table_file.string(),
                                      file_content_hash(scene.stiffness.table_file));
          }
        if (stage == "report")
          {
            key.inputs = produced;
            const fs::path script = report_script();
            if (!script.empty() && fs::is_regular_file(script))
              {
                key.inputs.emplace_back("report script", file_content_hash(script));
                for (const fs::path &py : report_modules(script))
                  key.inputs.emplace_back("report module " + py.filename().string(),
                                          file_content_hash(py));
              }
          }
        return key;
      }

      // Under mpirun the stiffness stage with an FE source and the sweep over speeds share their
      // work among the ranks; the other stages run on rank 0.
      bool collective(const std::string &stage) const
      {
        return processes::count() > 1 &&
               ((stage == "stiffness" && stiffness_source(scene).uses_fe()) ||
                (stage == "sweep" && scene.sweep.mode != "shooting"));
      }

      // The other ranks' part of the run: rank 0 says for each collective stage whether it runs
      // (its cache decides) and every rank runs it then; rank 0 alone writes.
      void follow(const std::vector<std::pair<std::string, std::string>> &plan)
      {
        for (const auto &[stage, why] : plan)
          if (collective(stage) && processes::broadcast("") == "run")
            {
              if (stage == "stiffness")
                write_stiffness(scene, dir, scene.output.write_fields, timer);
              else
                run_sweep_stage(dynamics_scene, nullptr, timer, options.sweep_threads);
            }
      }

      void run_stage(const std::string &stage)
      {
        bool       told = false; // whether the other ranks know that the stage runs
        const auto c = run_cached_stage(out, stage, key_of(stage), options.force ? "--force" : "",
                                        parameters_hash, [&] {
                                          if (collective(stage))
                                            told = !processes::broadcast("run").empty();
                                          execute(stage);
                                          return artifacts_of(stage);
                                        });
        if (collective(stage) && !told)
          processes::broadcast("reused");
        if (!c.outcome.ran)
          timer.add(stage + " (cached)", c.outcome.wall_time_s);
        for (const auto &a : c.artifacts)
          if (stage != "report")
            produced.emplace_back(a, file_content_hash(out / a));
        outcomes.push_back(c.outcome);
      }

      void execute(const std::string &stage)
      {
        if (stage == "stiffness")
          write_stiffness(scene, dir, scene.output.write_fields, timer);
        else if (stage == "dynamics")
          {
            run_dynamics_stage(dynamics_scene, &dir, timer);
            for (const auto &[from, to] : table_copies(scene, out))
              dir.write_text(to, slurp_file(from));
          }
        else if (stage == "sweep")
          run_sweep_stage(dynamics_scene, &dir, timer, options.sweep_threads);
        else if (stage == "report")
          {
            // The page header reads run.json: record this run's stages so far (the final
            // run.json, with the report's own time, follows at the end).
            nlohmann::json provisional = provenance(scene);
            provisional["command"]     = command_line;
            provisional["stage"]       = "run";
            provisional["pipeline"]    = stages_json();
            dir.write_json("run.json", provisional);
            PhaseTimer::Scope scope(timer, "report");
            const int         status = write_report(out);
            if (status != 0)
              throw std::runtime_error(msg("the report failed with exit code ", status));
          }
      }

      std::vector<std::string> artifacts_of(const std::string &stage) const
      {
        std::vector<std::string> artifacts;
        if (stage == "stiffness")
          {
            artifacts = {"stiffness.csv", "stiffness.json"};
            for (const auto *file : {"stiffness_map.csv", "contact_pattern.csv"})
              if (fs::exists(out / file))
                artifacts.push_back(file);
            for (const auto *folder : {"mesh", "fields"})
              for (const auto &f : files_below(out, folder))
                artifacts.push_back(f);
          }
        else if (stage == "dynamics")
          {
            artifacts = dynamics_artifacts;
            for (const auto &[from, to] : table_copies(scene, out))
              artifacts.push_back(to);
          }
        else if (stage == "sweep")
          artifacts = scene.sweep.mode == "shooting" ?
                        std::vector<std::string>{"response.csv", "response.json"} :
                        sweep_artifacts;
        else if (stage == "report")
          artifacts = files_below(out, "report");
        return artifacts;
      }

      nlohmann::json stages_json() const { return outcomes; }

      void finish() const
      {
        std::string ran, reused;
        for (const auto &o : outcomes)
          {
            std::string &list = o.ran ? ran : reused;
            list += (list.empty() ? "" : ", ") + o.stage;
          }
        progress_line("run", "ran: " + (ran.empty() ? std::string("nothing") : ran) +
                               "; reused: " + (reused.empty() ? std::string("nothing") : reused));
        dir.finish(timer, {{"stage", "run"}, {"pipeline", stages_json()}});
      }
    };
  } // namespace

  void check_run_inputs(const Scene &scene)
  {
    const meshing::PairKinematics pair = make_pair(scene);
    check_stiffness_input(scene);
    const auto &source = stiffness_source(scene);
    if (!source.is_stage())
      make_dynamics_setup(scene); // reads the table: every check of the dynamics
    else
      {
        // The table is the stiffness stage's: what the dynamics checks without it, and whether
        // the stage's table will hold what the effects need.
        check_dynamics_scene(scene);
        HG_REQUIRE_INPUT(scene.effects.ste_excitation != "table" || source.tabulates_unloaded_ste(),
                         "Effects/ste_excitation = table needs the unloaded STE in the stiffness "
                         "table, which Stiffness/source = ", source.name(),
                         " does not compute (the fem source does); set Effects/ste_excitation = "
                         "off or take the STE from a table with Stiffness/source = table");
      }
    if (scene.sweep.enabled && scene.sweep.mode == "shooting")
      check_response_scene(scene, true); // the sweep stage's Response/* checks
    warn_implausible_load(scene, pair);
  }

  void warn_implausible_load(const Scene &scene, const meshing::PairKinematics &pair)
  {
    const auto s = stiffness::nominal_contact_stress(pair, scene.pinion_material,
                                                     scene.gear_material, scene.operating.torque_Nm);
    if (s.sigma_H0_MPa > stiffness::implausible_contact_stress_MPa)
      progress_line("check",
                    msg("warning: Operating/torque_Nm = ", scene.operating.torque_Nm,
                        " gives a nominal contact stress sigma_H0 = ", s.sigma_H0_MPa,
                        " MPa (ISO 6336-2; specific load F_t/b = ", s.specific_load_N_per_mm,
                        " N/mm), above the ", stiffness::implausible_contact_stress_MPa,
                        " MPa that no gear steel carries even under static load: the results "
                        "are those of linear elasticity far outside a gear's range"));
  }

  std::vector<StageOutcome> run_pipeline(const Scene &scene, const fs::path &out,
                                         const std::string &command_line,
                                         const PipelineOptions &options)
  {
    return PipelineRun(scene, out, command_line, options).run();
  }
} // namespace hertzgear
