#pragma once
// Atomic artifact writes: content goes to a temporary file in the destination directory, is
// flushed, and is renamed over the destination only when complete. An interrupted or failed
// write never leaves a half-written artifact under the final name.
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace hertzgear
{
  // Write `content` to `path` atomically. Throws std::runtime_error on I/O failure.
  void write_file_atomically(const std::filesystem::path &path, const std::string &content);

  // Stream into a temporary file, then rename. If `writer` throws, the temporary is removed and
  // the destination is left untouched.
  void write_file_atomically(const std::filesystem::path &path,
                             const std::function<void(std::ostream &)> &writer);

  // For producers that write files themselves (gmsh, deal.II's DataOut): call `producer` with a
  // temporary path in the destination directory, then rename it to `path`.
  void produce_file_atomically(const std::filesystem::path &path,
                               const std::function<void(const std::filesystem::path &)> &producer);

  // The temporary name used for `path` (same directory, so rename is atomic on POSIX).
  std::filesystem::path temporary_path_for(const std::filesystem::path &path);

  // True for names produced by temporary_path_for (lets a later run recognise leftovers).
  bool is_temporary_artifact(const std::filesystem::path &path);
} // namespace hertzgear
