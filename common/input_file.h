#pragma once
// Reading a file the user named (a stiffness table, a scene): only a regular file is opened, and
// only up to a size limit, so that a FIFO, a device or a directory ends at once with a message
// instead of hanging or reading until memory runs out.
#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <filesystem>
#include <string>

namespace hertzgear
{
  // The whole content of `file`. Throws InputError "<what> <file>: <reason>" when it does not
  // exist, is not a regular file (directory, FIFO, device, socket), is larger than max_bytes or
  // cannot be read.
  std::string read_input_file(const std::filesystem::path &file, const std::string &what,
                              std::uintmax_t max_bytes);

  // The deepest nesting of arrays and objects in JSON text (0 for a scalar), counted by a scan
  // that converts nothing, so that it can bound the nesting before any recursive step runs.
  std::size_t json_nesting_depth(const std::string &text);

  // The nesting a JSON file the user names may have: a scene nests 4 levels (section,
  // subsection, key, {"value": ...}), a stiffness table 3.
  constexpr std::size_t max_json_nesting = 64;

  // The JSON text of `file`, read strictly: nested at most max_json_nesting levels deep (a
  // deeper file is refused naming its depth before it is parsed), and a key twice in one object,
  // which nlohmann would silently keep the last of, is refused naming it. Throws InputError
  // "<what> <file>: ..." for too deep a nesting, a duplicate key or invalid JSON.
  nlohmann::json read_json_file(const std::filesystem::path &file, const std::string &what);
} // namespace hertzgear
