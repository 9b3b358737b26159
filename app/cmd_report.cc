// `hertzgear report DIR [--out REPORT_DIR]`: figures and an HTML page from the artifacts of a run.
//
//   hertzgear report results/paper_crowned          -> results/paper_crowned/report/index.html
//
// The figures are drawn by scripts/hertzgear_report.py (matplotlib, Agg backend). This command
// finds the script (installed under <prefix>/share/hertzgear/scripts/, or in the source tree of a
// build), runs it with a Python 3 that has matplotlib, and maps its exit status: 0 success,
// 2 bad input (no such directory, no artifact), anything else 1.
#include "app/command.h"
#include "common/errors.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>
#include <sys/wait.h>
#include <unistd.h>

namespace hertzgear
{
  namespace fs = std::filesystem;

  namespace
  {
    constexpr const char *script_name = "hertzgear_report.py";

#ifndef HERTZGEAR_INSTALL_DATADIR
#define HERTZGEAR_INSTALL_DATADIR "share"
#endif

    fs::path executable_path()
    {
      std::error_code ec;
      const fs::path  self = fs::read_symlink("/proc/self/exe", ec);
      return ec ? fs::path() : self;
    }

    // The report script: $HERTZGEAR_REPORT_SCRIPT, then the install prefix of this executable
    // (<prefix>/bin/hertzgear -> <prefix>/share/hertzgear/scripts/), then the source tree the
    // program was built from.
    fs::path find_report_script()
    {
      std::vector<fs::path> candidates;
      if (const char *env = std::getenv("HERTZGEAR_REPORT_SCRIPT"); env && *env)
        candidates.emplace_back(env);
      if (const fs::path exe = executable_path(); !exe.empty())
        candidates.push_back(exe.parent_path().parent_path() / HERTZGEAR_INSTALL_DATADIR /
                             "hertzgear" / "scripts" / script_name);
#ifdef HERTZGEAR_SOURCE_DIR
      candidates.push_back(fs::path(HERTZGEAR_SOURCE_DIR) / "scripts" / script_name);
#endif
      for (const auto &c : candidates)
        if (fs::is_regular_file(c))
          return c;
      std::string searched;
      for (const auto &c : candidates)
        searched += "\n  " + c.string();
      throw std::runtime_error(msg("cannot find the report script ", script_name,
                                   "; searched:", searched,
                                   "\n(set HERTZGEAR_REPORT_SCRIPT to its path)"));
    }

    // Debian's python3 carries python3-matplotlib; a python3 found first on PATH (a virtual
    // environment, pyenv) often does not. $HERTZGEAR_PYTHON overrides both.
    std::string find_python()
    {
      if (const char *env = std::getenv("HERTZGEAR_PYTHON"); env && *env)
        return env;
      for (const char *p : {"/usr/bin/python3", "/usr/local/bin/python3"})
        if (::access(p, X_OK) == 0)
          return p;
      return "python3"; // looked up on PATH by execvp
    }

    // Run argv[0] with the given arguments, inheriting stdout/stderr; returns its exit status,
    // or -1 when it could not start or died of a signal.
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
          std::fprintf(stderr, "hertzgear: error: cannot run %s: %s\n", argv[0],
                       std::strerror(errno));
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

    int run_report(const CommandContext &ctx, const std::string &run_dir)
    {
      HG_REQUIRE_INPUT(ctx.overrides.empty(),
                       "report reads finished artifacts and takes no --set (got \"",
                       ctx.overrides.front(), "\"); set scene values when the run is made");
      return write_report(run_dir, ctx.out_dir);
    }
  } // namespace

  int write_report(const fs::path &run_dir, const fs::path &report_dir)
  {
    HG_REQUIRE_INPUT(fs::is_directory(run_dir), "the run directory ", run_dir.string(),
                     " does not exist or is not a directory");
    const fs::path           script = find_report_script();
    std::vector<std::string> args   = {find_python(), script.string(), run_dir.string()};
    if (!report_dir.empty())
      {
        args.push_back("--out");
        args.push_back(report_dir.string());
      }
    const int status = run_process(args);
    switch (status)
      {
        case 0:
          return exit_success;
        case 2:
          return exit_bad_input; // the script has printed what was wrong with the input
        case 127:
          std::cerr << "hertzgear: error: could not run " << args[0]
                    << " (install python3 and python3-matplotlib, or set HERTZGEAR_PYTHON)"
                    << std::endl;
          return exit_other;
        default:
          std::cerr << "hertzgear: error: the report script " << script.string()
                    << (status < 0 ? std::string(" was killed")
                                   : " failed with status " + std::to_string(status))
                    << std::endl;
          return exit_other;
      }
  }

  void add_report_command(CommandRegistry &registry)
  {
    auto      run_dir = std::make_shared<std::string>();
    CLI::App *report  = registry.add_command(
      {"report",
       "Write DIR/report/index.html with figures of the artifacts in a run directory "
       "(--out puts the report elsewhere)",
       false, false},
      [run_dir](const CommandContext &ctx) { return run_report(ctx, *run_dir); });
    report->add_option("dir", *run_dir, "Run directory holding the artifacts (CSV, JSON, .prm)")
      ->required();
  }
} // namespace hertzgear
