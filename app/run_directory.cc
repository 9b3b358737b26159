#include "app/run_directory.h"

#include "common/errors.h"

#include "common/atomic_file.h"

#include <hertzgear/version.h>

#include <chrono>
#include <ctime>

namespace hertzgear
{
  namespace fs = std::filesystem;

  nlohmann::json provenance(const Scene &scene)
  {
    return {{"hertzgear_version", version},
            {"git_revision", git_revision},
            {"scene_file", scene.file.string()},
            {"scene_hash", scene.hash}};
  }

  RunDirectory::RunDirectory(fs::path directory, const Scene &scene, std::string command_line)
    : directory(std::move(directory)), scene(scene), command_line(std::move(command_line))
  {}

  void RunDirectory::lock() const
  {
    // Every command takes its folders at its start (CommandStart::begin, app/command.h), before
    // it computes: a write into a folder not taken there is a command that skipped the rule.
    if (!FolderLock::held_here(directory))
      throw std::logic_error("RunDirectory: " + directory.string() +
                             " was not taken at the command's start (CommandStart::begin)");
  }

  void RunDirectory::write_text(const std::string &name, const std::string &content) const
  {
    lock();
    write_file_atomically(directory / name, content);
  }

  void RunDirectory::write_json(const std::string &name, const nlohmann::json &value) const
  {
    write_text(name, value.dump(2) + "\n");
  }

  void RunDirectory::finish(const PhaseTimer &timer, const nlohmann::json &extra) const
  {
    write_text("used_parameters.prm", scene.used_parameters_prm);
    nlohmann::json run = provenance(scene);
    run["command"]     = command_line;
    const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    char              stamp[32];
    std::strftime(stamp, sizeof(stamp), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    run["finished_utc"]   = stamp;
    nlohmann::json stages = nlohmann::json::array();
    for (const auto &[phase, seconds] : timer.phases())
      stages.push_back({{"stage", phase}, {"wall_time_s", seconds}});
    run["stage_timings"] = stages;
    run["wall_time_s"]   = timer.total_seconds();
    run.update(extra);
    write_json("run.json", run);
    timer.print_summary(progress_stream());
  }
} // namespace hertzgear
