#include "common/stage_cache.h"

#include "common/atomic_file.h"
#include "common/errors.h"
#include "common/hash.h"
#include "common/progress.h"

#include <hertzgear/version.h>

#include <nlohmann/json.hpp>

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
    constexpr const char *parameters_key  = "used_parameters_hash";

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

    // The cache folder's name is reserved and its content disposable: anything else under that
    // name (a regular file, a link, a FIFO) is removed, the link itself and not its target, with
    // a progress line, so that the manifests can be written and never land outside the folder.
    void reclaim_cache_folder(const fs::path &out)
    {
      const fs::path  folder = out / cache_folder;
      std::error_code ec;
      const auto      status = fs::symlink_status(folder, ec);
      if (ec || !fs::exists(status) || fs::is_directory(status))
        return;
      const char *kind = fs::is_symlink(status)      ? "symbolic link" :
                         fs::is_regular_file(status) ? "regular file" :
                                                       "special file";
      fs::remove(folder);
      progress_line("run", msg(folder.string(), " was a ", kind,
                               ", not the cache folder: removed (the name is reserved for the "
                               "cache of hertzgear run, whose content is disposable)"));
    }
  } // namespace

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
    // A manifest vouches only for what it lists: one that lists nothing (or names a place outside
    // the run folder) vouches for nothing.
    if (!j.contains("artifacts") || !j.at("artifacts").is_array() || j.at("artifacts").empty())
      return "its cache manifest lists no artifacts";
    for (const auto &a : j.at("artifacts"))
      {
        const fs::path relative = a.at("path").get<std::string>();
        if (relative.is_absolute() ||
            std::any_of(relative.begin(), relative.end(), [](const fs::path &part) { return part == ".."; }))
          return "its cache manifest names " + relative.string() + ", outside the run folder";
        const fs::path p = out / relative;
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
                      const std::vector<std::string> &artifacts, const double wall_time_s,
                      const std::string &parameters_hash)
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
                              {parameters_key, parameters_hash},
                              {"wall_time_s", wall_time_s}};
    write_file_atomically(manifest_path(out, stage), j.dump(2) + "\n");
  }

  void record_parameters_hash(const fs::path &out, const std::string &stage,
                              const std::string &parameters_hash)
  {
    const fs::path m = manifest_path(out, stage);
    nlohmann::json j = nlohmann::json::parse(slurp_file(m));
    if (j.value(parameters_key, "") == parameters_hash)
      return;
    j[parameters_key] = parameters_hash;
    write_file_atomically(m, j.dump(2) + "\n");
  }

  // Leftover temporaries of an interrupted write (never trusted, removed before a run).
  void remove_partial_files(const fs::path &out)
  {
    if (!fs::is_directory(out))
      return;
    // Files and folders (the fields of an FE run are written as a folder under a temporary name).
    std::vector<fs::path> partial;
    for (auto it = fs::recursive_directory_iterator(out); it != fs::recursive_directory_iterator(); ++it)
      if (is_temporary_artifact(it->path()))
        {
          partial.push_back(it->path());
          if (it->is_directory())
            it.disable_recursion_pending();
        }
    for (const auto &p : partial)
      fs::remove_all(p);
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


  std::string StageKey::key() const
  {
    std::string text = "code\n" + code + "\nscene\n" + scene_values + "inputs\n";
    for (const auto &[name, hash] : inputs)
      text += name + " " + hash + "\n";
    return hash_hex(text);
  }

  std::string file_content_hash(const fs::path &file) { return hash_hex(slurp_file(file)); }


  CachedStage run_cached_stage(const fs::path &out, const std::string &stage, const StageKey &key,
                               const std::string                               &rerun_reason,
                               const std::string                               &parameters_hash,
                               const std::function<std::vector<std::string>()> &run)
  {
    reclaim_cache_folder(out);
    CachedStage  c;
    StageOutcome &o          = c.outcome;
    o.stage                  = stage;
    const std::string reason = rerun_reason.empty() ? invalid_reason(out, stage, key) : rerun_reason;
    const auto        start  = std::chrono::steady_clock::now();
    o.ran                    = !reason.empty();
    if (!o.ran)
      {
        o.reason = "cached: key and every artifact hash match";
        std::ifstream        in(manifest_path(out, stage));
        const nlohmann::json manifest = nlohmann::json::parse(in);
        for (const auto &a : manifest.at("artifacts"))
          c.artifacts.push_back(a.at("path").get<std::string>());
        record_parameters_hash(out, stage, parameters_hash); // now this run's artifacts
        progress_line("run", stage + ": reused (" + o.reason + ")");
      }
    else
      {
        o.reason = reason;
        progress_line("run", stage + ": runs (" + reason + ")");
        fs::remove(manifest_path(out, stage)); // no manifest while the stage is under way
        c.artifacts = run();
      }
    o.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (o.ran)
      write_manifest(out, stage, key, c.artifacts, o.wall_time_s, // last: the stage is done
                     parameters_hash);
    return c;
  }
} // namespace hertzgear
