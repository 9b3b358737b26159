#include "common/input_file.h"

#include "common/errors.h"
#include "common/shown_text.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

namespace hertzgear
{
  namespace fs = std::filesystem;

  std::string read_input_file(const fs::path &file, const std::string &what, const std::uintmax_t max_bytes)
  {
    const std::string name = what + " " + file.string();
    std::error_code   ec;
    const auto        status = fs::status(file, ec); // stat(): opens nothing, so a FIFO cannot block
    HG_REQUIRE_INPUT(!ec || ec == std::errc::no_such_file_or_directory, name, ": ", ec.message());
    HG_REQUIRE_INPUT(fs::exists(status), name, ": no such file");
    HG_REQUIRE_INPUT(!fs::is_directory(status), name, ": is a directory, not a file");
    HG_REQUIRE_INPUT(fs::is_regular_file(status), name,
                     ": is not a regular file (a FIFO, device or socket)");
    const auto size = fs::file_size(file, ec);
    HG_REQUIRE_INPUT(!ec, name, ": ", ec.message());
    HG_REQUIRE_INPUT(size <= max_bytes, name, ": is ", size, " bytes, more than the ", max_bytes,
                     " bytes such a file can be");
    std::ifstream in(file, std::ios::binary);
    HG_REQUIRE_INPUT(in.good(), name, ": cannot be read (", std::strerror(errno), ")");
    std::ostringstream ss;
    ss << in.rdbuf();
    HG_REQUIRE_INPUT(!in.bad(), name, ": read error");
    return ss.str();
  }

  std::size_t json_nesting_depth(const std::string &text)
  {
    std::size_t depth = 0, deepest = 0;
    bool        in_string = false, escaped = false;
    for (const char c : text)
      if (in_string)
        {
          if (escaped)
            escaped = false;
          else if (c == '\\')
            escaped = true;
          else if (c == '"')
            in_string = false;
        }
      else if (c == '"')
        in_string = true;
      else if (c == '[' || c == '{')
        deepest = std::max(deepest, ++depth);
      else if ((c == ']' || c == '}') && depth > 0)
        --depth;
    return deepest;
  }

  nlohmann::json read_json_file(const fs::path &file, const std::string &what)
  {
    std::string text;
    {
      std::ifstream in(file, std::ios::binary);
      HG_REQUIRE_INPUT(in.good(), what, " ", file.string(), ": cannot be read (", std::strerror(errno), ")");
      std::ostringstream ss;
      ss << in.rdbuf();
      HG_REQUIRE_INPUT(!in.bad(), what, " ", file.string(), ": read error");
      text = ss.str();
    }
    // Converting a tree recurses once per level: a bound here keeps a hostile file from
    // exhausting the stack.
    const std::size_t depth = json_nesting_depth(text);
    HG_REQUIRE_INPUT(depth <= max_json_nesting, what, " ", file.string(), ": nested ", depth,
                     " levels deep, more than the ", max_json_nesting,
                     " levels such a file can have");
    try
      {
        // The keys of the objects open at this point of the parse.
        std::vector<std::set<std::string>> keys;
        const auto no_duplicates = [&](const int, const nlohmann::json::parse_event_t event,
                                       nlohmann::json &parsed) {
          using event_t = nlohmann::json::parse_event_t;
          if (event == event_t::object_start)
            keys.emplace_back();
          else if (event == event_t::object_end && !keys.empty())
            keys.pop_back();
          else if (event == event_t::key && !keys.empty() &&
                   !keys.back().insert(parsed.get<std::string>()).second)
            throw InputError(msg(what, " ", file.string(), ": the key \"", parsed.get<std::string>(),
                                 "\" appears twice in one object (which one is meant?)"));
          return true;
        };
        return nlohmann::json::parse(text, no_duplicates);
      }
    catch (const nlohmann::json::exception &e)
      {
        // nlohmann quotes the last token read whole, which may be a string of megabytes.
        throw InputError(msg(what, " ", file.string(), ": invalid JSON: ", shown(e.what(), 300)));
      }
  }
} // namespace hertzgear
