#pragma once
// Run the `hertzgear` program in a test and capture its exit code, stdout and stderr.
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>

namespace hertzgear::testing
{
  struct CommandResult
  {
    int         exit_code = -1;
    std::string out;
    std::string err;
  };

  inline std::string slurp(const std::filesystem::path &p)
  {
    std::ifstream     in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }

  // `arguments` is appended to the executable path as shell text (quote what needs quoting);
  // `launcher` (e.g. "mpirun -np 2 --oversubscribe") is put in front of the executable.
  inline CommandResult run_hertzgear(const std::string &arguments, const std::string &launcher = "")
  {
#ifdef HERTZGEAR_EXE
    const std::filesystem::path dir = std::filesystem::temp_directory_path();
    static int                  counter = 0;
    const std::string           tag = std::to_string(::getpid()) + "_" + std::to_string(counter++);
    const auto out = dir / ("hg_out_" + tag), err = dir / ("hg_err_" + tag);
    const std::string cmd = launcher + (launcher.empty() ? "" : " ") + "'" + HERTZGEAR_EXE + "' " +
                            arguments + " >'" +
                            out.string() + "' 2>'" + err.string() + "' </dev/null";
    const int     status = std::system(cmd.c_str());
    CommandResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out       = slurp(out);
    r.err       = slurp(err);
    std::filesystem::remove(out);
    std::filesystem::remove(err);
    return r;
#else
    (void)arguments;
    (void)launcher;
    return {};
#endif
  }

  inline std::string scene_path(const std::string &name)
  {
    return std::string(HERTZGEAR_SOURCE_DIR) + "/data/scenes/" + name;
  }

  // An empty temporary folder for `name`, one per build tree (told apart by the folder of the
  // test executable), so that the suites of two builds (a sanitizer build beside the normal one)
  // can run at the same time without removing each other's folders.
  inline std::filesystem::path fresh_temp_dir(const std::string &name)
  {
    std::error_code ec;
    const auto      exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    const auto      tree = std::hash<std::string>{}(exe.parent_path().string()) % 1000000;
    const auto      dir  = std::filesystem::temp_directory_path() /
                     ("hertzgear_test_" + std::to_string(tree) + "_" + name);
    std::filesystem::remove_all(dir);
    return dir;
  }
} // namespace hertzgear::testing
