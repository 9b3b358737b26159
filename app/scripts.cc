#include "app/scripts.h"

#include "common/child_process.h"
#include "common/errors.h"
#include "common/progress.h"

#include <cstdlib>
#include <stdexcept>
#include <unistd.h>

#ifndef HERTZGEAR_INSTALL_DATADIR
#define HERTZGEAR_INSTALL_DATADIR "share"
#endif

namespace hertzgear
{
  namespace fs = std::filesystem;

  std::vector<fs::path> bundled_locations(const char *env_override, const fs::path &installed,
                                          const fs::path &in_source)
  {
    std::vector<fs::path> candidates;
    if (env_override != nullptr)
      if (const char *env = std::getenv(env_override); env && *env)
        candidates.emplace_back(env);
    std::error_code ec;
    if (const fs::path exe = fs::read_symlink("/proc/self/exe", ec); !ec)
      {
        const fs::path share = exe.parent_path().parent_path() / HERTZGEAR_INSTALL_DATADIR / "hertzgear";
        candidates.push_back(installed.empty() ? share : share / installed);
      }
#ifdef HERTZGEAR_SOURCE_DIR
    candidates.push_back(fs::path(HERTZGEAR_SOURCE_DIR) / in_source);
#endif
    return candidates;
  }

  fs::path find_script(const std::string &name, const char *env_override)
  {
    const auto candidates =
      bundled_locations(env_override, fs::path("scripts") / name, fs::path("scripts") / name);
    for (const auto &c : candidates)
      if (fs::is_regular_file(c))
        return c;
    std::string searched;
    for (const auto &c : candidates)
      searched += "\n  " + c.string();
    throw std::runtime_error(msg("cannot find the script ", name, "; searched:", searched,
                                 env_override ? msg("\n(set ", env_override, " to its path)") :
                                                std::string()));
  }

  std::string find_python()
  {
    if (const char *env = std::getenv("HERTZGEAR_PYTHON"); env && *env)
      return env;
    for (const char *p : {"/usr/bin/python3", "/usr/local/bin/python3"})
      if (::access(p, X_OK) == 0)
        return p;
    return "python3"; // looked up on PATH by execvp
  }

  bool draw_figure(const std::string &script, const std::vector<std::string> &args)
  {
    std::vector<std::string> argv;
    try
      {
        argv = {find_python(), find_script(script).string()};
      }
    catch (const std::runtime_error &e)
      {
        progress_line("figure", std::string("warning: no figure: ") + e.what());
        return false;
      }
    argv.insert(argv.end(), args.begin(), args.end());
    const int status = run_process(argv);
    if (status != 0)
      {
        std::string command;
        for (const auto &a : argv)
          command += (command.empty() ? "" : " ") + a;
        progress_line("figure", "warning: the figure could not be drawn (" + command +
                                  " exited with " + std::to_string(status) + ")");
      }
    return status == 0;
  }
} // namespace hertzgear
