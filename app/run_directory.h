#pragma once
// A run directory: results, `used_parameters.prm` and `run.json` (version, git revision, scene
// hash, command, stage timings). Every file is written atomically. The directory is made and
// locked at the command's start (CommandStart::begin), after the scene has been validated, so bad
// input leaves nothing behind.
#include "app/scene.h"
#include "common/folder_lock.h"
#include "common/progress.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace hertzgear
{
  class RunDirectory
  {
  public:
    RunDirectory(std::filesystem::path directory, const Scene &scene, std::string command_line);

    const std::filesystem::path &path() const { return directory; }

    // Checks that this process holds the folder (taken at the command's start by
    // CommandStart::begin); every write checks it too. Throws std::logic_error otherwise.
    void lock() const;

    // Atomically write `content` to directory/name (sub-folders are created as needed).
    void write_text(const std::string &name, const std::string &content) const;
    void write_json(const std::string &name, const nlohmann::json &value) const;

    // Write used_parameters.prm and run.json with the timings of `timer`; `extra` is merged into
    // run.json (stage-specific metadata).
    void finish(const PhaseTimer &timer, const nlohmann::json &extra = nlohmann::json::object()) const;

  private:
    std::filesystem::path            directory;
    const Scene                     &scene;
    std::string                      command_line;
  };

  // Metadata every artifact carries: version, git revision, scene hash.
  nlohmann::json provenance(const Scene &scene);
} // namespace hertzgear
