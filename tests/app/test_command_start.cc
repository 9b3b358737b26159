// Requirements on the start of every command (app/command.h, CommandStart; docs/architecture.md,
// "Under mpirun"):
// - every command that writes into a folder takes the folder's lock at its start, after its
//   checks and before it computes: a second process on the folder stops there with exit 2
//   naming the holder, and changes nothing;
// - the lock file is never followed through a symbolic link, and a lock path that is not a
//   regular file is refused;
// - a command refused after its start leaves no folder it made;
// - under `mpirun -np 2` every command behaves as it does serially: on a free folder it succeeds
//   on both ranks, on a busy folder and on bad input every rank ends with exit 2, one message,
//   within seconds (a hang guard turns a rank that waits forever into a failure).
// The MPI cases run by ctest as app.command_start_mpi2 (HERTZGEAR_TEST_MPI=1, mpirun allowed as
// root); elsewhere they are skipped.
#include "tests/support/held_folder.h"
#include "tests/support/run_command.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <fcntl.h>
#include <fstream>
#include <map>
#include <regex>
#include <sys/file.h>
#include <thread>
#include <functional>
#include <unistd.h>

using namespace hertzgear::testing;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

namespace
{
  std::string quoted(const fs::path &p) { return "'" + p.string() + "'"; }

  // Seconds a command of these tests may take before the guard stops it: the slowest case (the
  // coarse 2D FE run on two ranks) takes a few seconds on two cores; a hang takes for ever.
  const int guard_s = 120 * HERTZGEAR_TIME_FACTOR;

  // Fast scenes: the scene's own Fourier stiffness, 40 mesh periods, no report.
  const std::string fourier_scene = scene_path("paper_crowned_fourier.prm") +
                                    " --set Dynamics/periods=40 --set Dynamics/transient_periods=20"
                                    " --set Output/report=false";
  const std::string sweep_settings = " --set Sweep/points=3 --set Sweep/speed_min_rpm=100"
                                     " --set Sweep/speed_max_rpm=300 --set Sweep/periods_per_point=12"
                                     " --set Sweep/transient_periods_per_point=6 --set Sweep/mode=independent";
  const std::string response_settings = " --set Response/parameter=speed_rpm"
                                        " --set Sweep/speed_min_rpm=12000 --set Sweep/speed_max_rpm=12400";
  // The FE stage at its coarsest (2D, Q1, level 0, 5 positions).
  const std::string fe_scene = scene_path("paper_uncrowned.prm") +
                               " --set Stiffness/fe_level=0 --set Stiffness/fe_degree=1"
                               " --set Stiffness/positions_per_cycle=5 --set Stiffness/harmonics=2"
                               " --set Output/write_fields=false --set Output/report=false"
                               " --set Dynamics/periods=40 --set Dynamics/transient_periods=20";

  std::size_t occurrences(const std::string &text, const std::string &what)
  {
    std::size_t n = 0;
    for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size()))
      ++n;
    return n;
  }

  // The commands that write into a folder, each on a valid scene, with the artifact that shows
  // it ran. `report` takes the folder of a finished run (made by the caller).
  struct Command
  {
    std::string name, arguments, artifact;
  };
  std::vector<Command> writing_commands()
  {
    return {{"dynamics", "dynamics " + fourier_scene, "summary.json"},
            {"sweep", "sweep " + fourier_scene + sweep_settings + " --threads 1", "sweep.csv"},
            {"response", "response " + fourier_scene + response_settings, "response.json"},
            {"stiffness", "stiffness " + scene_path("paper_uncrowned.prm") + " --set Stiffness/source=iso6336",
             "stiffness.json"},
            {"run", "run " + fourier_scene, "summary.json"},
            {"check", "check " + fourier_scene, "used_parameters.prm"}};
  }

  std::string launcher_mpi() { return "timeout -s KILL " + std::to_string(guard_s) + " mpirun -np 2 --oversubscribe"; }
  std::string launcher_serial() { return "timeout -s KILL " + std::to_string(guard_s); }

  bool mpi_enabled() { return std::getenv("HERTZGEAR_TEST_MPI") != nullptr; }

  // Requirement: `arguments --out DIR` on DIR, which another process holds, exits 2 within the
  // guard naming the holder once, and changes nothing in DIR.
  void expect_refused_while_held(const std::string &arguments, const fs::path &dir,
                                 const std::string &launcher)
  {
    const HeldFolder held(dir);
    const auto       before = contents_below(dir);
    const auto       start  = std::chrono::steady_clock::now();
    const auto       r      = run_hertzgear(arguments + " --out " + quoted(dir), launcher);
    const double     took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(r.exit_code, 2) << arguments << "\n" << r.err;
    EXPECT_EQ(occurrences(r.err, "the folder is in use by process " + held.pid), 1u)
      << arguments << "\n" << r.err;
    EXPECT_EQ(contents_below(dir), before) << arguments << ": changed a folder in use";
    // Refused at the start, before the stage computes: the slowest of these commands computes
    // for several seconds, its refusal takes the start-up of the program (and of MPI) only.
    EXPECT_LT(took, 30.0 * HERTZGEAR_TIME_FACTOR) << arguments;
  }
} // namespace

TEST(CommandStart, EveryWritingCommandRefusesABusyFolderAtItsStart)
{
  // Requirement: each command that writes into --out takes the folder's lock at its start: a
  // second process stops with exit 2 before computing, and the first one's files stay.
  for (const auto &c : writing_commands())
    {
      const fs::path dir = fresh_temp_dir("start_busy_" + c.name);
      fs::create_directories(dir);
      std::ofstream(dir / "summary.json") << "{\"from\": \"the first run\"}\n";
      expect_refused_while_held(c.arguments, dir, launcher_serial());
      fs::remove_all(dir);
    }
}

TEST(CommandStart, TwoOverlappingRunsOfOneCommandCannotBothWrite)
{
  // Requirement: while a `sweep` (`dynamics`, `response`) run computes into a folder, a second
  // run of the same command on that folder exits 2 at its start naming the first, and the first
  // ends normally with its artifacts. The first run is given work for several seconds; the
  // second starts as soon as the first holds the lock (its number in the lock file).
  const std::vector<Command> long_runs = {
    {"sweep", "sweep " + fourier_scene + " --threads 1 --set Sweep/points=80 --set Sweep/speed_min_rpm=100"
              " --set Sweep/speed_max_rpm=20000 --set Sweep/periods_per_point=200"
              " --set Sweep/transient_periods_per_point=100 --set Sweep/mode=independent", "sweep.csv"},
    {"dynamics", "dynamics " + fourier_scene + " --set Dynamics/periods=12000 --set Output/timeseries_periods=5",
     "summary.json"},
    {"response", "response " + fourier_scene + " --set Response/parameter=speed_rpm"
                 " --set Sweep/speed_min_rpm=1000 --set Sweep/speed_max_rpm=20000"
                 " --set Response/relative_tolerance=1e-11 --set Response/newton_tolerance=1e-9"
                 " --set Response/step_max=0.002 --set Response/max_points_per_branch=20000",
     "response.json"}};
  for (const auto &c : long_runs)
    {
      const fs::path dir = fresh_temp_dir("start_overlap_" + c.name);
      const fs::path rc_file = dir.string() + ".rc", err_file = dir.string() + ".err";
      fs::remove(rc_file);
      const std::string first = "(" + launcher_serial() + " '" + std::string(HERTZGEAR_EXE) + "' " +
                                c.arguments + " --out " + quoted(dir) + " >/dev/null 2>'" +
                                err_file.string() + "'; echo $? >'" + rc_file.string() + "') &";
      ASSERT_EQ(std::system(first.c_str()), 0);
      // The first run at work: its process number in the lock file.
      const auto wait_for = [](const std::function<bool()> &ready, const double seconds) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        while (!ready() && std::chrono::steady_clock::now() < until)
          std::this_thread::sleep_for(std::chrono::milliseconds(20));
        return ready();
      };
      ASSERT_TRUE(wait_for([&] { return fs::exists(dir / ".hertzgear.lock") &&
                                        !slurp(dir / ".hertzgear.lock").empty(); },
                           guard_s))
        << c.name << ": the first run never took its folder";
      const std::string holder = slurp(dir / ".hertzgear.lock");
      const auto        second = run_hertzgear(c.arguments + " --out " + quoted(dir));
      const bool        first_running = !fs::exists(rc_file);
      EXPECT_EQ(second.exit_code, 2) << c.name << "\n" << second.err;
      EXPECT_THAT(second.err, HasSubstr("the folder is in use by process " + holder)) << c.name;
      EXPECT_TRUE(first_running) << c.name << ": the first run ended before the second was refused;"
                                    " give it more work";
      ASSERT_TRUE(wait_for([&] { return fs::exists(rc_file) && !slurp(rc_file).empty(); }, guard_s));
      EXPECT_EQ(std::stoi(slurp(rc_file)), 0) << c.name << "\n" << slurp(err_file);
      EXPECT_TRUE(fs::exists(dir / c.artifact)) << c.name;
      fs::remove(rc_file);
      fs::remove(err_file);
      fs::remove_all(dir);
    }
}

TEST(CommandStart, ASymbolicLinkInTheLocksPlaceIsNeverFollowed)
{
  // Requirement: when DIR/.hertzgear.lock is a symbolic link, `run` and `report` refuse with exit
  // 2 naming the lock file, and the file the link points at is left untouched; a folder in the
  // lock's place is refused too.
  const fs::path base   = fresh_temp_dir("start_symlink");
  const fs::path target = base / "precious.txt";
  fs::create_directories(base / "run");
  std::ofstream(target) << "precious content\n";
  fs::create_symlink(target, base / "run" / ".hertzgear.lock");
  const auto r = run_hertzgear("run " + fourier_scene + " --out " + quoted(base / "run"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr(".hertzgear.lock is a symbolic link"));
  EXPECT_EQ(slurp(target), "precious content\n");
  const auto rep = run_hertzgear("report " + quoted(base / "run"));
  EXPECT_EQ(rep.exit_code, 2) << rep.err;
  EXPECT_THAT(rep.err, HasSubstr(".hertzgear.lock is a symbolic link"));
  EXPECT_EQ(slurp(target), "precious content\n");
  EXPECT_TRUE(fs::is_symlink(base / "run" / ".hertzgear.lock"));

  fs::create_directories(base / "dir_lock" / ".hertzgear.lock");
  const auto d = run_hertzgear("dynamics " + fourier_scene + " --out " + quoted(base / "dir_lock"));
  EXPECT_EQ(d.exit_code, 2) << d.err;
  EXPECT_THAT(d.err, HasSubstr(".hertzgear.lock is a folder"));
  fs::remove_all(base);
}

TEST(CommandStart, ACommandRefusedAfterItsStartLeavesNoFolder)
{
  // Requirement: a command that fails after its start (the lock made the folder) and wrote
  // nothing leaves no folder behind: here `response` whose Newton iteration finds no orbit
  // (exit 3, a numerical failure of the computation, found after the start), and `stiffness`
  // with a closed-form source on an impossible pair (exit 2, refused before the start).
  const fs::path base = fresh_temp_dir("start_leftover");
  const fs::path out  = base / "a" / "b";
  auto r = run_hertzgear("response " + fourier_scene +
                         " --set Response/relative_tolerance=1e-4 --set Response/newton_tolerance=1e-3"
                         " --set Dynamics/initial_state=given --set Dynamics/initial_dte_um=5000"
                         " --set Dynamics/periods=2 --set Dynamics/transient_periods=1"
                         " --set Sweep/speed_min_rpm=15000 --set Sweep/speed_max_rpm=16000 --out " +
                         quoted(out));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_FALSE(fs::exists(base)) << "the folders the command made stay";
  r = run_hertzgear("stiffness " + scene_path("paper_uncrowned.prm") +
                    " --set Stiffness/source=iso6336 --set \"Gear pair/Pinion/tip_radius_mm=39.5\" --out " +
                    quoted(out));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("Gear pair/Pinion/tip_radius_mm"));
  EXPECT_FALSE(fs::exists(base));
}

// ---- Under mpirun -np 2 ----

TEST(CommandStartMpi, EveryCommandSucceedsOnBothRanksOnAFreeFolder)
{
  // Requirement: on a free folder each command ends with exit 0 on both ranks (no hang, no rank
  // refused by the other's lock) and writes its artifacts once; `run` with an FE stage and `run`
  // with a sweep share their collective stages between the ranks.
  if (!mpi_enabled())
    GTEST_SKIP() << "set HERTZGEAR_TEST_MPI=1 (ctest app.command_start_mpi2)";
  std::vector<Command> commands = writing_commands();
  commands.push_back({"run_fe", "run " + fe_scene, "stiffness.json"});
  commands.push_back({"run_sweep", "run " + fourier_scene + " --set Sweep/enabled=true" + sweep_settings,
                      "sweep.csv"});
  commands.push_back({"stiffness_fe", "stiffness " + fe_scene, "stiffness.json"});
  for (const auto &c : commands)
    {
      const fs::path dir = fresh_temp_dir("start_mpi_free_" + c.name);
      const auto     r   = run_hertzgear(c.arguments + " --out " + quoted(dir), launcher_mpi());
      EXPECT_EQ(r.exit_code, 0) << c.name << "\n" << r.err;
      EXPECT_TRUE(fs::exists(dir / c.artifact)) << c.name;
      EXPECT_EQ(occurrences(r.err, "in use by process"), 0u) << c.name << "\n" << r.err;
      if (c.name == "run_fe")
        {
          // The report of that run, on two ranks: one process draws.
          const auto rep = run_hertzgear("report " + quoted(dir), launcher_mpi());
          EXPECT_EQ(rep.exit_code, 0) << rep.err;
          EXPECT_TRUE(fs::exists(dir / "report" / "index.html"));
        }
      fs::remove_all(dir);
    }
}

TEST(CommandStartMpi, EveryCommandOnABusyFolderEndsAllRanksWithOneMessage)
{
  // Requirement: on a folder another process holds, every command under mpirun ends all ranks
  // with exit 2 and the holder named once, within seconds, and changes nothing; the FE `run` and
  // `stiffness` too (they used to wait in a collective call for the rank that was refused).
  if (!mpi_enabled())
    GTEST_SKIP() << "set HERTZGEAR_TEST_MPI=1 (ctest app.command_start_mpi2)";
  std::vector<Command> commands = writing_commands();
  commands.push_back({"run_fe", "run " + fe_scene, ""});
  commands.push_back({"stiffness_fe", "stiffness " + fe_scene, ""});
  for (const auto &c : commands)
    {
      const fs::path dir = fresh_temp_dir("start_mpi_busy_" + c.name);
      fs::create_directories(dir);
      std::ofstream(dir / "summary.json") << "{}\n";
      expect_refused_while_held(c.arguments, dir, launcher_mpi());
      fs::remove_all(dir);
    }
  // The report: a run folder in use.
  const fs::path dir = fresh_temp_dir("start_mpi_busy_report");
  ASSERT_EQ(run_hertzgear("dynamics " + fourier_scene + " --out " + quoted(dir)).exit_code, 0);
  const HeldFolder held(dir);
  const auto       r = run_hertzgear("report " + quoted(dir), launcher_mpi());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(occurrences(r.err, "in use by process " + held.pid), 1u) << r.err;
  EXPECT_FALSE(fs::exists(dir / "report"));
  fs::remove_all(dir);
}

TEST(CommandStartMpi, BadInputEndsAllRanksWithOneMessageAndNoFolder)
{
  // Requirement: bad input under mpirun ends every rank with exit 2 and one message naming the
  // key, and leaves no folder, as it does serially.
  if (!mpi_enabled())
    GTEST_SKIP() << "set HERTZGEAR_TEST_MPI=1 (ctest app.command_start_mpi2)";
  const std::string bad = " --set Operating/torque_Nm=-5";
  for (auto c : writing_commands())
    {
      const fs::path dir = fresh_temp_dir("start_mpi_bad_" + c.name);
      const auto     r   = run_hertzgear(c.arguments + bad + " --out " + quoted(dir), launcher_mpi());
      EXPECT_EQ(r.exit_code, 2) << c.name << "\n" << r.err;
      EXPECT_EQ(occurrences(r.err, "hertzgear: input error:"), 1u) << c.name << "\n" << r.err;
      EXPECT_THAT(r.err, HasSubstr("Operating/torque_Nm")) << c.name;
      EXPECT_FALSE(fs::exists(dir)) << c.name;
    }
  // The FE stage's own refusal (an impossible pair) and a missing report folder.
  const fs::path dir = fresh_temp_dir("start_mpi_bad_fe");
  auto r = run_hertzgear("run " + fe_scene + " --set \"Gear pair/Pinion/tip_radius_mm=39.5\" --out " + quoted(dir),
                         launcher_mpi());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(occurrences(r.err, "hertzgear: input error:"), 1u) << r.err;
  EXPECT_FALSE(fs::exists(dir));
  r = run_hertzgear("report " + quoted(dir), launcher_mpi());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(occurrences(r.err, "hertzgear: input error:"), 1u) << r.err;
}
