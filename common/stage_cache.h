#pragma once
// The cache of a staged run (`hertzgear run`, docs/architecture.md "The pipeline and its cache"):
// DIR/.hertzgear-cache/<stage>.json records the stage's key (the scene values it read, the code
// version, the content hashes of its input artifacts) and every artifact with its size and FNV-1a
// hash, and the content hash of the run's used_parameters.prm (the report draws the scene values
// from that file beside the artifacts: the hash ties them to one run). It is written atomically
// after the artifacts and removed before a stage runs, so an interrupted stage never leaves a
// manifest behind; a stage is reused only when its key matches and every artifact verifies.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace hertzgear
{
  // Cache key material of one stage: the scene values it reads (one "Section/key = value" line
  // each), the code version and the content hashes of its input artifacts.
  struct StageKey
  {
    std::string                                      scene_values;
    std::string                                      code;
    std::vector<std::pair<std::string, std::string>> inputs; // name, content hash
    std::string                                      key() const;
  };

  // The code that produced an artifact: version and git revision, and for a build from modified
  // sources the content hash of the executable, so that a rebuilt hertzgear invalidates the cache.
  std::string code_version();

  // FNV-1a 64 hex of a file's content; throws std::runtime_error when it cannot be read.
  std::string file_content_hash(const std::filesystem::path &file);
  // A file's content; throws std::runtime_error when it cannot be read.
  std::string slurp_file(const std::filesystem::path &file);

  // DIR/.hertzgear-cache/<stage>.json
  std::filesystem::path manifest_path(const std::filesystem::path &out, const std::string &stage);
  // Artifacts (relative paths) of a stage that wrote whole folders: every regular file below.
  std::vector<std::string> files_below(const std::filesystem::path &out, const std::string &folder);
  // Empty when the cached stage is valid, else why it must run.
  std::string invalid_reason(const std::filesystem::path &out, const std::string &stage,
                             const StageKey &key);
  // The manifest of a finished stage (written last, atomically); `parameters_hash` is the content
  // hash of the used_parameters.prm of the run that wrote the artifacts.
  void write_manifest(const std::filesystem::path &out, const std::string &stage, const StageKey &key,
                      const std::vector<std::string> &artifacts, double wall_time_s,
                      const std::string &parameters_hash);
  // A reused stage belongs to the run that reuses it: its manifest is rewritten (atomically) to
  // record this run's used_parameters.prm hash, when it records another.
  void record_parameters_hash(const std::filesystem::path &out, const std::string &stage,
                              const std::string &parameters_hash);
  // Leftover temporaries of an interrupted write (never trusted, removed before a run).
  void remove_partial_files(const std::filesystem::path &out);

  // What one stage of a cached run did (run.json records it, keys as the member names).
  struct StageOutcome
  {
    std::string stage;
    bool        ran = false;
    std::string reason;      // why it ran, or why its cached artifacts were reused
    double      wall_time_s = 0;
  };
  NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(StageOutcome, stage, ran, reason, wall_time_s)

  struct CachedStage
  {
    StageOutcome             outcome;
    std::vector<std::string> artifacts; // relative to the run directory
  };

  // One stage of a cached run into `out`: reused when its manifest verifies under `key` and
  // `rerun_reason` is empty (its manifest then records `parameters_hash`, the hash of this run's
  // used_parameters.prm); else its manifest is removed, `run` runs the stage and returns its
  // artifacts, and the new manifest is written last. Says which on the progress stream.
  CachedStage run_cached_stage(const std::filesystem::path &out, const std::string &stage,
                               const StageKey &key, const std::string &rerun_reason,
                               const std::string &parameters_hash,
                               const std::function<std::vector<std::string>()> &run);
} // namespace hertzgear
