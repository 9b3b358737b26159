#include "app/pipeline.h"

#include "app/cmd_dynamics.h"
#include "app/command.h"
#include "app/run_directory.h"
#include "app/scripts.h"
#include "app/stiffness_setup.h"
#include "common/atomic_file.h"
#include "common/errors.h"
#include "common/hash.h"
#include "common/progress.h"

#include <hertzgear/version.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <map>
#include <sstream>

namespace hertzgear
{
  namespace fs = std::filesystem;

  namespace
  {
    constexpr const char *cache_folder    = ".hertzgear-cache";
    constexpr const char *manifest_schema = "hertzgear-cache/1";

    const std::vector<std::string> dynamics_artifacts = {
      "timeseries.csv", "poincare.csv", "spectrum.csv", "force_penetration.csv", "impacts.csv",
      "summary.json"};
    const std::vector<std::string> sweep_artifacts = {"sweep.csv", "bifurcation.csv"};

    bool stiffness_stage_needed(const Scene &scene) { return stiffness_source(scene).is_stage(); }

    // "Section/key = value" lines of `prefixes`, without the lines starting with one of `drop`.
    std::string values(const Scene &scene, const std::vector<std::string> &prefixes,
                       const std::vector<std::string> &drop)
    {
      std::istringstream in(scene_values_for(scene, prefixes));
      std::string        out;
      for (std::string line; std::getline(in, line);)
        if (std::none_of(drop.begin(), drop.end(),
                         [&](const std::string &d) { return line.rfind(d, 0) == 0; }))
          out += line + "\n";
      return out;
    }

    std::map<std::string, std::string> value_map(const std::string &lines)
    {
      std::map<std::string, std::string> m;
      std::istringstream                 in(lines);
      for (std::string line; std::getline(in, line);)
        {
          const auto eq = line.find(" = ");
          if (eq != std::string::npos)
            {
              std::string v = line.substr(eq + 3);
              v.erase(v.find_last_not_of(" \t") + 1);
              m[line.substr(0, eq)] = v;
            }
        }
      return m;
    }

    // The changed scene values between two manifests, as "key: old -> new" (at most a few).
    std::string changed_values(const std::string &before, const std::string &after)
    {
      const auto               a = value_map(before), b = value_map(after);
      std::vector<std::string> changes;
      for (const auto &[k, v] : b)
        if (const auto it = a.find(k); it == a.end() || it->second != v)
          changes.push_back(k + ": " + (it == a.end() ? std::string("(none)") : it->second) +
                            " -> " + v);
      for (const auto &[k, v] : a)
        if (!b.count(k))
          changes.push_back(k + ": " + v + " -> (none)");
      std::string out;
      for (std::size_t i = 0; i < changes.size() && i < 4; ++i)
        out += (i ? ", " : "") + changes[i];
      if (changes.size() > 4)
        out += msg(" and ", changes.size() - 4, " more");
      return out;
    }

    // The code that produced an artifact. A clean checkout is named by its version and git
    // revision; a build from modified sources ("-dirty") or without git ("unknown") keeps that
    // name through any number of edits, so its executable's content hash is added: a rebuilt
    // hertzgear then invalidates the cache instead of reusing results of other code.
    std::string code_version()
    {
      static const std::string code = [] {
        std::string       text = std::string(version) + " (git " + git_revision + ")";
        const std::string rev  = git_revision;
        if (rev.find("dirty") != std::string::npos || rev == "unknown" || rev.empty())
          {
            std::error_code ec;
            const fs::path  exe = fs::read_symlink("/proc/self/exe", ec);
            try
              {
                if (!ec)
                  text += " executable " + file_content_hash(exe);
              }
            catch (const std::exception &)
              {
                // No readable executable: the name alone (a clean build needs nothing more).
              }
          }
        return text;
      }();
      return code;
    }

    fs::path manifest_path(const fs::path &out, const std::string &stage)
    {
      return out / cache_folder / (stage + ".json");
    }

    // Artifacts (relative paths) of a stage that wrote whole folders: every regular file below.
    std::vector<std::string> files_below(const fs::path &out, const std::string &folder)
    {
      std::vector<std::string> names;
      if (fs::is_directory(out / folder))
        for (const auto &e : fs::recursive_directory_iterator(out / folder))
          if (e.is_regular_file() && !is_temporary_artifact(e.path()))
            names.push_back(fs::relative(e.path(), out).generic_string());
      std::sort(names.begin(), names.end());
      return names;
    }

    // Empty when the cached stage is valid, else why it must run.
    std::string invalid_reason(const fs::path &out, const std::string &stage, const StageKey &key)
    {
      const fs::path m = manifest_path(out, stage);
      if (!fs::exists(m))
        return "no cached result";
      nlohmann::json j;
      try
        {
          std::ifstream in(m);
          j = nlohmann::json::parse(in);
        }
      catch (const std::exception &)
        {
          return "its cache manifest is unreadable";
        }
      if (j.value("schema", "") != manifest_schema || j.value("stage", "") != stage)
        return "its cache manifest is of another kind";
      if (j.value("key", "") != key.key())
        {
          if (j.value("code", "") != key.code)
            return "hertzgear changed (" + j.value("code", "") + " -> " + key.code + ")";
          if (j.value("scene_values", "") != key.scene_values)
            return "scene values it reads changed: " +
                   changed_values(j.value("scene_values", ""), key.scene_values);
          // Name the inputs whose content changed (or that are new or gone).
          std::map<std::string, std::string> before;
          if (j.contains("inputs") && j.at("inputs").is_object())
            for (const auto &[name, hash] : j.at("inputs").items())
              if (hash.is_string())
                before[name] = hash.get<std::string>();
          std::vector<std::string> changed;
          for (const auto &[name, hash] : key.inputs)
            {
              const auto it = before.find(name);
              if (it == before.end())
                {
                  changed.push_back(name + " (new)");
                  continue;
                }
              if (it->second != hash)
                changed.push_back(name);
              before.erase(it);
            }
          for (const auto &[name, hash] : before)
            changed.push_back(name + " (gone)");
          std::string list;
          for (std::size_t i = 0; i < changed.size() && i < 4; ++i)
            list += (i ? ", " : "") + changed[i];
          if (changed.size() > 4)
            list += msg(" and ", changed.size() - 4, " more");
          return list.empty() ? std::string("an input artifact changed") :
                                "input changed: " + list;
        }
      for (const auto &a : j.at("artifacts"))
        {
          const fs::path p = out / a.at("path").get<std::string>();
          if (!fs::is_regular_file(p))
            return "artifact " + a.at("path").get<std::string>() + " is missing";
          if (fs::file_size(p) != a.at("size_bytes").get<std::uintmax_t>() ||
              file_content_hash(p) != a.at("content_hash").get<std::string>())
            return "artifact " + a.at("path").get<std::string>() +
                   " does not match its recorded hash (corrupt or truncated)";
        }
      return "";
    }

    void write_manifest(const fs::path &out, const std::string &stage, const StageKey &key,
                        const std::vector<std::string> &artifacts, const double wall_time_s)
    {
      nlohmann::json a = nlohmann::json::array();
      for (const auto &name : artifacts)
        {
          const fs::path p = out / name;
          if (!fs::is_regular_file(p))
            throw std::runtime_error("stage " + stage + " did not write its artifact " + name);
          a.push_back({{"path", name},
                       {"size_bytes", fs::file_size(p)},
                       {"content_hash", file_content_hash(p)}});
        }
      nlohmann::json inputs = nlohmann::json::object();
      for (const auto &[name, hash] : key.inputs)
        inputs[name] = hash;
      const nlohmann::json j = {{"schema", manifest_schema},
                                {"stage", stage},
                                {"key", key.key()},
                                {"code", key.code},
                                {"scene_values", key.scene_values},
                                {"inputs", inputs},
                                {"artifacts", a},
                                {"wall_time_s", wall_time_s}};
      write_file_atomically(manifest_path(out, stage), j.dump(2) + "\n");
    }

    // Leftover temporaries of an interrupted write (never trusted, removed before a run).
    void remove_partial_files(const fs::path &out)
    {
      if (!fs::is_directory(out))
        return;
      std::vector<fs::path> partial;
      for (const auto &e : fs::recursive_directory_iterator(out))
        if (e.is_regular_file() && is_temporary_artifact(e.path()))
          partial.push_back(e.path());
      for (const auto &p : partial)
        fs::remove(p);
    }

    std::string slurp_file(const fs::path &file)
    {
      std::ifstream in(file, std::ios::binary);
      if (!in)
        throw std::runtime_error("cannot read " + file.string());
      std::ostringstream ss;
      ss << in.rdbuf();
      return ss.str();
    }

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

  std::string StageKey::key() const
  {
    std::string text = "code\n" + code + "\nscene\n" + scene_values + "inputs\n";
    for (const auto &[name, hash] : inputs)
      text += name + " " + hash + "\n";
    return hash_hex(text);
  }

  std::string file_content_hash(const fs::path &file) { return hash_hex(slurp_file(file)); }

  std::string stage_scene_values(const Scene &scene, const std::string &stage)
  {
    // Geometry, materials and load shape the stiffness; the speed does not.
    const std::vector<std::string> geometry = {"Gear pair", "Material", "Operating"};
    if (stage == "stiffness")
      {
        auto prefixes = geometry;
        prefixes.push_back("Stiffness");
        std::vector<std::string> drop = {"Operating/speed_rpm", "Stiffness/Fourier"};
        if (stiffness_source(scene).uses_fe())
          {
            prefixes.push_back("Mesh");
            prefixes.push_back("Output"); // write_fields: the FE stage's .vtu output
            drop.push_back("Output/report");
            drop.push_back("Output/timeseries_periods");
          }
        return values(scene, prefixes, drop);
      }
    // The dynamics reads the gears (base radii, inertias), the operating point, the effects, the
    // stiffness section (source, exponent, Fourier coefficients) and its own settings.
    const std::vector<std::string> dynamics = {"Gear pair", "Material", "Operating", "Effects",
                                               "Stiffness", "Dynamics", "Output"};
    if (stage == "dynamics")
      return values(scene, dynamics, {"Output/report"});
    if (stage == "sweep")
      {
        auto prefixes = dynamics;
        prefixes.push_back("Sweep");
        return values(scene, prefixes, {"Output/report", "Output/timeseries_periods"});
      }
    if (stage == "report")
      return values(scene, {""}, {});
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
      stages.emplace_back("sweep", msg("Sweep/enabled = true: ", scene.sweep.points, " speeds from ",
                                       scene.sweep.speed_min_rpm, " to ", scene.sweep.speed_max_rpm,
                                       " rpm"));
    if (scene.output.report)
      stages.emplace_back("report", "Output/report = true: report/index.html");
    return stages;
  }

  std::vector<StageOutcome> run_pipeline(const Scene &scene, const fs::path &out,
                                         const std::string &command_line,
                                         const PipelineOptions &options)
  {
    PhaseTimer   timer;
    RunDirectory dir(out, scene, command_line);
    const auto   plan = planned_stages(scene);
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
    remove_partial_files(out);
    // The report reads the scene values; written first, it is not an artifact of any stage.
    dir.write_text("used_parameters.prm", scene.used_parameters_prm);

    const std::string         code = code_version();
    std::vector<StageOutcome> outcomes;
    // Content hashes of the artifacts so far, inputs of later stages.
    std::vector<std::pair<std::string, std::string>> produced;

    // The scene the dynamics and sweep see: the stiffness stage's table when there is one.
    Scene dynamics_scene = scene;
    if (stiffness_stage_needed(scene))
      {
        dynamics_scene.stiffness.source     = "table";
        dynamics_scene.stiffness.table_file = fs::absolute(out / "stiffness.json");
      }

    for (const auto &[stage, why] : plan)
      {
        StageKey key;
        key.code         = code;
        key.scene_values = stage_scene_values(scene, stage);
        if (stage == "dynamics" || stage == "sweep")
          {
            if (stiffness_stage_needed(scene))
              key.inputs.emplace_back("stiffness.json", file_content_hash(out / "stiffness.json"));
            else if (scene.stiffness.source == "table" ||
                     scene.effects.ste_excitation == "table")
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

        StageOutcome o;
        o.stage                  = stage;
        const std::string reason = options.force ? "--force" : invalid_reason(out, stage, key);
        std::vector<std::string> artifacts;
        const auto               start = std::chrono::steady_clock::now();
        if (reason.empty())
          {
            o.ran    = false;
            o.reason = "cached: key and every artifact hash match";
            std::ifstream        in(manifest_path(out, stage));
            const nlohmann::json manifest = nlohmann::json::parse(in);
            for (const auto &a : manifest.at("artifacts"))
              artifacts.push_back(a.at("path").get<std::string>());
            progress_line("run", stage + ": reused (" + o.reason + ")");
          }
        else
          {
            o.ran    = true;
            o.reason = reason;
            progress_line("run", stage + ": runs (" + reason + ")");
            fs::remove(manifest_path(out, stage)); // no manifest while the stage is under way
            if (stage == "stiffness")
              {
                write_stiffness(scene, dir, scene.output.write_fields, timer);
              }
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
                provisional["pipeline"]    = nlohmann::json::array();
                for (const auto &p : outcomes)
                  provisional["pipeline"].push_back({{"stage", p.stage},
                                                     {"ran", p.ran},
                                                     {"reason", p.reason},
                                                     {"wall_time_s", p.wall_time_s}});
                dir.write_json("run.json", provisional);
                PhaseTimer::Scope scope(timer, "report");
                const int         status = write_report(out);
                if (status != 0)
                  throw std::runtime_error(msg("the report failed with exit code ", status));
              }
          }
        if (o.ran)
          {
            if (stage == "stiffness")
              {
                artifacts = {"stiffness.csv", "stiffness.json"};
                for (const auto &m : files_below(out, "mesh"))
                  artifacts.push_back(m);
                for (const auto &f : files_below(out, "fields"))
                  artifacts.push_back(f);
              }
            else if (stage == "dynamics")
              {
                artifacts = dynamics_artifacts;
                for (const auto &[from, to] : table_copies(scene, out))
                  artifacts.push_back(to);
              }
            else if (stage == "sweep")
              artifacts = sweep_artifacts;
            else if (stage == "report")
              artifacts = files_below(out, "report");
          }
        o.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (o.ran)
          write_manifest(out, stage, key, artifacts, o.wall_time_s); // last: the stage is done
        else
          timer.add(stage + " (cached)", o.wall_time_s);
        for (const auto &a : artifacts)
          if (stage != "report")
            produced.emplace_back(a, file_content_hash(out / a));
        outcomes.push_back(o);
      }

    nlohmann::json stages = nlohmann::json::array();
    std::string    ran, reused;
    for (const auto &o : outcomes)
      {
        stages.push_back(
          {{"stage", o.stage}, {"ran", o.ran}, {"reason", o.reason}, {"wall_time_s", o.wall_time_s}});
        std::string &list = o.ran ? ran : reused;
        list += (list.empty() ? "" : ", ") + o.stage;
      }
    progress_line("run", "ran: " + (ran.empty() ? std::string("nothing") : ran) +
                           "; reused: " + (reused.empty() ? std::string("nothing") : reused));
    dir.finish(timer, {{"stage", "run"}, {"pipeline", stages}});
    return outcomes;
  }
} // namespace hertzgear
