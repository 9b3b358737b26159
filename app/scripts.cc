#include "app/scripts.h"

#include "common/errors.h"
#include "common/progress.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

#ifndef HERTZGEAR_INSTALL_DATADIR
#define HERTZGEAR_INSTALL_DATADIR "share"
#endif

namespace hertzgear
{
  namespace fs = std::filesystem;

  namespace
  {
    fs::path executable_path()
    {
      std::error_code ec;
      const fs::path  self = fs::read_symlink("/proc/self/exe", ec);
      return ec ? fs::path() : self;
    }
  } // namespace

  fs::path find_script(const std::string &name, const char *env_override)
  {
    std::vector<fs::path> candidates;
    if (env_override != nullptr)
      if (const char *env = std::getenv(env_override); env && *env)
        candidates.emplace_back(env);
    if (const fs::path exe = executable_path(); !exe.empty())
      candidates.push_back(exe.parent_path().parent_path() / HERTZGEAR_INSTALL_DATADIR /
                           "hertzgear" / "scripts" / name);
#ifdef HERTZGEAR_SOURCE_DIR
    candidates.push_back(fs::path(HERTZGEAR_SOURCE_DIR) / "scripts" / name);
#endif
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

  int run_process(const std::vector<std::string> &args)
  {
    std::vector<char *> argv;
    for (const auto &a : args)
      argv.push_back(const_cast<char *>(a.c_str()));
    argv.push_back(nullptr);
    std::cout.flush();
    std::cerr.flush();
    const pid_t pid = ::fork();
    if (pid < 0)
      throw std::runtime_error(msg("cannot start ", args[0], ": ", std::strerror(errno)));
    if (pid == 0)
      {
        ::execvp(argv[0], argv.data());
        std::fprintf(stderr, "hertzgear: error: cannot run %s: %s\n", argv[0], std::strerror(errno));
        ::_exit(127);
      }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0)
      if (errno != EINTR)
        throw std::runtime_error(msg("waiting for ", args[0], ": ", std::strerror(errno)));
    if (WIFEXITED(status))
      return WEXITSTATUS(status);
    return -1;
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
