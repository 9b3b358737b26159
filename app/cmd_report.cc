// `hertzgear report DIR [--out REPORT_DIR] [--compare OTHER_DIR]...`: figures and an HTML page
// from the artifacts of a run.
//
//   hertzgear report results/paper_crowned          -> results/paper_crowned/report/index.html
//   hertzgear report results/response-fe --compare results/response-serial
//                                  (the periodic orbits of both runs on one response figure)
//
// The figures are drawn by scripts/hertzgear_report.py (matplotlib, Agg backend). This command
// finds the script (installed under <prefix>/share/hertzgear/scripts/, or in the source tree of a
// build), runs it with a Python 3 that has matplotlib, and maps its exit status: 0 success,
// 2 bad input (no such directory, no artifact, an artifact that cannot be parsed, a report folder
// that cannot be written), anything else 1. The script prints its own one-line message for 1 and
// 2; this command adds one only for a status the script does not give (killed, no interpreter).
#include "app/command.h"
#include "app/run_directory.h"
#include "app/scripts.h"
#include "common/child_process.h"
#include "common/errors.h"
#include "common/folder_lock.h"
#include "common/processes.h"

#include <unistd.h>

#include <iostream>
#include <string>
#include <vector>

namespace hertzgear
{
  namespace fs = std::filesystem;

  namespace
  {
    constexpr const char *script_name = "hertzgear_report.py";

    int run_report(const CommandContext &ctx, const std::string &run_dir,
                   const std::vector<std::string> &compared)
    {
      HG_REQUIRE_INPUT(ctx.overrides.empty(),
                       "report reads finished artifacts and takes no --set (got \"",
                       ctx.overrides.front(), "\"); set scene values when the run is made");
      // Before the lock, which would make the folder.
      HG_REQUIRE_INPUT(fs::is_directory(run_dir), "the run directory ", run_dir,
                       " does not exist or is not a directory");
      for (const auto &other : compared)
        HG_REQUIRE_INPUT(fs::is_directory(other), "--compare ", other,
                         ": the run directory does not exist or is not a directory");
      // A run that writes into the folder would have the report draw its old artifacts beside
      // its new ones: the report holds the folder's lock, as a run does, and stops with exit 2
      // while another process holds it. A folder this user cannot write into (shipped results)
      // is read without it: no hertzgear run of this user writes there. A report put elsewhere
      // (--out) holds that folder too.
      std::vector<std::pair<fs::path, std::string>> folders;
      if (::access(run_dir.c_str(), W_OK) == 0)
        folders.emplace_back(run_dir, "the run directory");
      if (!ctx.out_dir.empty())
        folders.emplace_back(ctx.out_dir, "--out");
      ctx.start->begin(folders);
      if (!processes::is_root())
        return 0; // one process draws
      std::vector<fs::path> others(compared.begin(), compared.end());
      return write_report(run_dir, ctx.out_dir, others);
    }
  } // namespace

  int write_report(const fs::path &run_dir, const fs::path &report_dir,
                   const std::vector<fs::path> &compared)
  {
    HG_REQUIRE_INPUT(fs::is_directory(run_dir), "the run directory ", run_dir.string(),
                     " does not exist or is not a directory");
    const fs::path           script = find_script(script_name, "HERTZGEAR_REPORT_SCRIPT");
    std::vector<std::string> args   = {find_python(), script.string(), run_dir.string()};
    if (!report_dir.empty())
      {
        args.push_back("--out");
        args.push_back(report_dir.string());
      }
    for (const auto &other : compared)
      {
        args.push_back("--compare");
        args.push_back(other.string());
      }
    const int status = run_process(args);
    switch (status)
      {
        case 0:
          return exit_success;
        case 2:
          return exit_bad_input; // the script has printed what was wrong with the input
        case 1:
          return exit_other; // the script has printed what failed ("report script failed: ...")
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
    auto      run_dir  = std::make_shared<std::string>();
    auto      compared = std::make_shared<std::vector<std::string>>();
    CLI::App *report  = registry.add_command(
      {"report",
       "Write DIR/report/index.html with figures of the artifacts in a run directory "
       "(--out puts the report elsewhere)",
       false, false},
      [run_dir, compared](const CommandContext &ctx) { return run_report(ctx, *run_dir, *compared); });
    report->add_option("dir", *run_dir, "Run directory holding the artifacts (CSV, JSON, .prm)")
      ->required();
    report->add_option("--compare", *compared,
                       "Another run's folder whose periodic orbits (response.csv) the response "
                       "figure draws beside this run's, e.g. the other mesh force law (repeatable)");
  }
} // namespace hertzgear
