// Requirements on bad input across the commands (docs/architecture.md, "Errors and exit codes"):
// every case ends with exit code 2, a message that names the offending key, file or folder, and
// no folder or file left behind; `hertzgear check` refuses the same scene; a hostile table path
// (FIFO, device, directory, a file too large) ends within a second; two runs on one folder do not
// race: the second stops at once with the lock message and the first's results verify.
#include "tests/support/run_command.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <fstream>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>
#include <thread>

using namespace hertzgear::testing;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

namespace
{
  std::string quoted(const fs::path &p) { return "'" + p.string() + "'"; }

  // ctest runs the tests of this file in parallel processes: each gets its own folders.
  std::string this_test() { return ::testing::UnitTest::GetInstance()->current_test_info()->name(); }

  // A fast scene: the scene's own Fourier stiffness, 60 mesh periods, no report.
  const std::string fourier_scene = scene_path("paper_crowned_fourier.prm") +
                                    " --set Dynamics/periods=60 --set Dynamics/transient_periods=30"
                                    " --set Output/report=false";
  const std::string table_scene = scene_path("paper_crowned_table.prm") +
                                  " --set Dynamics/periods=60 --set Dynamics/transient_periods=30"
                                  " --set Output/report=false";

  // Files the cases point at, made once.
  struct Fixtures
  {
    fs::path dir, fifo, big, not_json, string_value, negative, other_pair, newline_scene,
      hash_scene, regular_file;

    Fixtures()
    {
      dir = fresh_temp_dir("bad_input_fixtures_" + this_test());
      fs::create_directories(dir);
      fifo = dir / "fifo.json";
      ::mkfifo(fifo.c_str(), 0644);
      big = dir / "big.json"; // sparse: 65 MiB that occupy nothing
      std::ofstream(big).close();
      fs::resize_file(big, 65u << 20);
      not_json = dir / "not_json.json";
      std::ofstream(not_json) << "this is not a table";
      const auto table = nlohmann::json::parse(slurp(fs::path(HERTZGEAR_SOURCE_DIR) / "data" /
                                                     "stiffness" / "paper_crowned.json"));
      auto string_table                      = table;
      string_table["k_rest_N_per_m"]["mean"] = "large";
      string_value                           = dir / "string_value.json";
      std::ofstream(string_value) << string_table.dump();
      auto negative_table                      = table;
      negative_table["k_rest_N_per_m"]["mean"] = -1.0e8;
      negative_table["samples"].erase("k_rest_N_per_m");
      negative = dir / "negative.json";
      std::ofstream(negative) << negative_table.dump();
      auto other                      = table;
      other["pair"]["pinion"]["teeth"] = 20;
      other["pair"]["gear"]["teeth"]   = 40;
      other_pair                       = dir / "other_pair.json";
      std::ofstream(other_pair) << other.dump();
      // JSON scenes whose strings would inject text into the .prm form.
      newline_scene = dir / "newline.json";
      std::ofstream(newline_scene)
        << R"({"Gear pair": {"Pinion": {"teeth": "23\nend\nend\nsubsection Operating\nset speed_rpm = 999"}}})";
      hash_scene = dir / "hash.json";
      std::ofstream(hash_scene) << R"({"Stiffness": {"table_file": "data/stiffness/paper_crowned.json#x"}})";
      regular_file = dir / "a_file";
      std::ofstream(regular_file) << "x";
    }
  };

  const Fixtures &fixtures()
  {
    static const Fixtures f;
    return f;
  }

  struct Case
  {
    std::string command;  // "run", "dynamics", "stiffness", "check"
    std::string scene;    // scene and --set arguments
    std::string named;    // what the message must name
    std::string out = ""; // --out; empty: a fresh folder that must not appear
  };

  void expect_refused(const Case &c)
  {
    const fs::path fresh = fresh_temp_dir("bad_input_out_" + this_test()) / "run";
    const fs::path out   = c.out.empty() ? fresh : fs::path(c.out);
    const auto     t0    = std::chrono::steady_clock::now();
    const auto     r     = run_hertzgear(c.command + " " + c.scene + " --out " + quoted(out));
    const double   wall  = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::string what = c.command + " " + c.scene + " --out " + out.string();
    EXPECT_EQ(r.exit_code, 2) << what << "\n" << r.err;
    EXPECT_THAT(r.err, HasSubstr(c.named)) << what;
    EXPECT_FALSE(fs::exists(fresh)) << what << ": left a folder";
    // Refusal comes from the checks, before any work: far within a second for these scenes (a
    // generous bound that a hang on a FIFO or a read of /dev/zero would exceed by far).
    EXPECT_LT(wall, 10.0) << what;
    if (c.out.empty())
      {
        const auto check = run_hertzgear("check " + c.scene);
        EXPECT_EQ(check.exit_code, 2) << "check " << c.scene << "\n" << check.err;
        EXPECT_THAT(check.err, HasSubstr(c.named)) << "check " << c.scene;
      }
  }
} // namespace

// Class 1: impossible gears are refused whatever the stiffness source.
TEST(BadInput, ImpossibleGearsAreRefusedWithEveryStiffnessSource)
{
  for (const std::string &scene : {fourier_scene, table_scene})
    for (const auto &[set, named] : std::vector<std::pair<std::string, std::string>>{
           {"--set 'Gear pair/Pinion/tip_radius_mm=45'", "pointed tip"},
           {"--set 'Gear pair/Pinion/teeth=8' --set 'Gear pair/Pinion/bore_radius_mm=2' "
            "--set 'Gear pair/Pinion/profile_shift_coefficient=-1'",
            "undercut"},
           {"--set 'Gear pair/Gear/addendum_coefficient=2' --set 'Gear pair/Gear/tip_radius_mm=0'",
            "pointed tip"},
           {"--set 'Gear pair/Pinion/tip_relief_um=20' --set 'Gear pair/Pinion/tip_relief_length_mm=40'",
            "tip relief length"},
           {"--set 'Gear pair/Pinion/lead_end_relief_um=5' "
            "--set 'Gear pair/Pinion/lead_end_relief_length_mm=15'",
            "lead end relief length"},
           {"--set Operating/mesh_misalignment_um=200", "Operating/mesh_misalignment_um"}})
      expect_refused({"run", scene + " " + set, named});
}

// Classes 2 and 5: table files are opened only as regular files of bounded size, tied to their
// pair, and every refusal names Stiffness/table_file.
TEST(BadInput, HostileOrForeignTablesAreRefusedNamingTheKey)
{
  const auto &f = fixtures();
  for (const auto &[file, named] : std::vector<std::pair<fs::path, std::string>>{
         {"/nonexistent/table.json", "no such file"},
         {f.fifo, "not a regular file"},
         {"/dev/zero", "not a regular file"},
         {f.dir, "is a directory"},
         {f.big, "more than the"},
         {f.not_json, "not_json.json"},
         {f.string_value, "string_value.json"},
         {f.negative, "negative.json"},
         {f.other_pair, "computed for another pair"}})
    {
      expect_refused({"run", table_scene + " --set Stiffness/table_file=" + quoted(file), named});
      expect_refused(
        {"dynamics", table_scene + " --set Stiffness/table_file=" + quoted(file), "Stiffness/table_file"});
    }
}

TEST(BadInput, ATableAtAnotherLoadRunsWithAWarning)
{
  // Requirement: a table is tied to the load it was computed at: another torque is allowed (the
  // dynamics may be run at another load on purpose) but said.
  const fs::path out = fresh_temp_dir("bad_input_load");
  const auto     r   = run_hertzgear("dynamics " + table_scene + " --set Operating/torque_Nm=2100 --out " +
                                 quoted(out));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("warning: the stiffness table"));
  EXPECT_THAT(r.err, HasSubstr("was computed at a mesh load of"));
}

// Class 2: output places that cannot hold a run folder.
TEST(BadInput, OutputPlacesThatCannotHoldARunNameTheFolderAndTheReason)
{
  const auto &f = fixtures();
  for (const std::string command : {"run", "dynamics", "stiffness"})
    {
      const std::string scene = command == "stiffness" ? scene_path("paper_uncrowned.prm") +
                                                           " --set Stiffness/source=iso6336" :
                                                         fourier_scene;
      expect_refused({command, scene, "is a file, not a folder", f.regular_file.string()});
      expect_refused({command, scene, "Not a directory", (f.regular_file / "x").string()});
      expect_refused({command, scene, "cannot create the folder", "/proc/hertzgear_run"});
    }
}

// Class 8: scene text cannot inject entries or cut values.
TEST(BadInput, SceneStringsCannotInjectEntriesOrComments)
{
  const auto &f = fixtures();
  expect_refused({"run", quoted(f.newline_scene), "control character 0x0a"});
  expect_refused({"run", quoted(f.hash_scene), "contains '#'"});
  expect_refused({"run", fourier_scene + " --set 'Stiffness/table_file=a#b'", "'#'"});
  expect_refused({"dynamics", quoted(f.newline_scene), "\"teeth\""});
}

// Class 6: two runs on one folder.
TEST(BadInput, AFolderInUseIsRefusedNamingTheProcess)
{
  // Requirement: a run on a folder whose lock another process holds exits 2 at once, naming that
  // process, and writes nothing there; once the lock is free the run proceeds.
  const fs::path dir = fresh_temp_dir("bad_input_held");
  fs::create_directories(dir);
  const int      fd  = ::open((dir / ".hertzgear.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX), 0);
  const std::string pid = std::to_string(::getpid());
  ASSERT_EQ(::pwrite(fd, pid.data(), pid.size(), 0), static_cast<ssize_t>(pid.size()));
  const auto refused = run_hertzgear("run " + fourier_scene + " --out " + quoted(dir));
  EXPECT_EQ(refused.exit_code, 2) << refused.err;
  EXPECT_THAT(refused.err, HasSubstr("the folder is in use by process " + pid));
  EXPECT_FALSE(fs::exists(dir / "used_parameters.prm"));
  ::close(fd);
  const auto r = run_hertzgear("run " + fourier_scene + " --out " + quoted(dir));
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(BadInput, ASecondRunOnAFolderInUseStopsAndTheFirstsResultsVerify)
{
  // Requirement: while one run writes into a folder, a second run on it exits 2 with the lock
  // message, and the first run completes with results its manifests verify (a third run reuses
  // every stage).
  const fs::path    dir        = fresh_temp_dir("bad_input_lock");
  const std::string long_scene = scene_path("paper_crowned_fourier.prm") +
                                 " --set Dynamics/periods=4000 --set Dynamics/transient_periods=30"
                                 " --set Output/report=false";
  std::thread first([&] {
    const auto r = run_hertzgear("run " + long_scene + " --out " + quoted(dir));
    EXPECT_EQ(r.exit_code, 0) << r.err;
  });
  // used_parameters.prm is the first file a run writes, after it has taken the folder; the
  // 4 000 periods take seconds after it.
  for (int i = 0; i < 1000 && !fs::exists(dir / "used_parameters.prm"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const auto second = run_hertzgear("run " + fourier_scene + " --out " + quoted(dir));
  first.join();
  EXPECT_EQ(second.exit_code, 2) << second.err;
  EXPECT_THAT(second.err, HasSubstr("is in use by process"));
  const auto again = run_hertzgear("run " + long_scene + " --out " + quoted(dir));
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_THAT(again.err, HasSubstr("ran: nothing"));
}

// Class 10: leftovers and what a manifest vouches for.
TEST(BadInput, TheStiffnessCommandRemovesTheLeftoversOfAnInterruptedRun)
{
  // Requirement: temporaries an interrupted `stiffness` run left (files and a fields folder under
  // their hidden .hg-partial names) are removed by the next run on the folder.
  const fs::path dir = fresh_temp_dir("bad_input_leftovers");
  fs::create_directories(dir / ".fields.hg-partial-1-0");
  std::ofstream(dir / ".fields.hg-partial-1-0" / "pinion_0000.vtu") << "partial";
  std::ofstream(dir / ".stiffness.csv.hg-partial-1-1") << "partial";
  const auto r = run_hertzgear("stiffness " + scene_path("paper_uncrowned.prm") +
                               " --set Stiffness/source=iso6336 --out " + quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const auto &e : fs::recursive_directory_iterator(dir))
    EXPECT_THAT(e.path().filename().string(), ::testing::Not(HasSubstr("hg-partial"))) << e.path();
  EXPECT_TRUE(fs::exists(dir / "stiffness.json"));
}

TEST(BadInput, AManifestThatListsNoArtifactsIsNotTrusted)
{
  // Requirement: a stage is reused only when its manifest lists its artifacts and they verify; a
  // manifest edited to list none (or a path outside the folder) makes the stage run again.
  const fs::path dir = fresh_temp_dir("bad_input_manifest");
  ASSERT_EQ(run_hertzgear("run " + fourier_scene + " --out " + quoted(dir)).exit_code, 0);
  const fs::path manifest = dir / ".hertzgear-cache" / "dynamics.json";
  for (const nlohmann::json &artifacts :
       {nlohmann::json::array(),
        nlohmann::json::array({{{"path", "../elsewhere.csv"}, {"size_bytes", 1}, {"content_hash", "x"}}})})
    {
      auto j         = nlohmann::json::parse(slurp(manifest));
      j["artifacts"] = artifacts;
      std::ofstream(manifest) << j.dump();
      const auto r = run_hertzgear("run " + fourier_scene + " --out " + quoted(dir));
      ASSERT_EQ(r.exit_code, 0) << r.err;
      EXPECT_THAT(r.err, HasSubstr(artifacts.empty() ? "lists no artifacts" : "outside the run folder"));
      EXPECT_THAT(r.err, HasSubstr("ran: dynamics"));
    }
}

// Class 7: the report marks what no verified manifest covers.
TEST(BadInput, TheReportMarksArtifactsNoVerifiedManifestCovers)
{
  // Requirement: in a `hertzgear run` folder, an artifact that no cache manifest vouches for (here
  // a summary.json replaced after the run, as an interrupted or concurrent run could leave it)
  // is named on the report page as untrusted; an untouched run has no such note.
  const fs::path dir = fresh_temp_dir("bad_input_report_trust");
  ASSERT_EQ(run_hertzgear("run " + scene_path("paper_crowned_fourier.prm") +
                          " --set Dynamics/periods=60 --set Dynamics/transient_periods=30 --out " + quoted(dir))
              .exit_code,
            0);
  EXPECT_THAT(slurp(dir / "report" / "index.html"), ::testing::Not(HasSubstr("Not covered by a verified")));
  std::ofstream(dir / "summary.json") << R"({"rms_dte_um": 1.0})";
  // The half-drawn report of an interrupted report stage (it is drawn beside report/ and swapped
  // in whole): removed, and never shown.
  fs::create_directories(dir / ".report.hg-partial-new-1");
  std::ofstream(dir / ".report.hg-partial-new-1" / "index.html") << "half";
  const auto r = run_hertzgear("report " + quoted(dir));
  EXPECT_FALSE(fs::exists(dir / ".report.hg-partial-new-1"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(slurp(dir / "report" / "index.html"),
              HasSubstr("Not covered by a verified cache manifest of this run folder"));
  EXPECT_THAT(slurp(dir / "report" / "index.html"), HasSubstr("summary.json"));
}

// Class 9: messages name the key, the file and the reason, once.
TEST(BadInput, MessagesNameTheKeyTheFileAndTheReasonOnce)
{
  const fs::path dir = fresh_temp_dir("bad_input_messages");
  fs::create_directories(dir);
  const fs::path duplicate = dir / "duplicate.json";
  std::ofstream(duplicate) << R"({"Gear pair": {"Pinion": {"teeth": 23, "teeth": 24}}})";
  expect_refused({"run", quoted(duplicate), "the key \"teeth\" appears twice"});
  expect_refused({"run", fourier_scene + " --set Operating/center_distance_mm=100 --set Operating/backlash_mm=0",
                  "centre distance 100 mm: the gears do not mesh"});
  const auto r = run_hertzgear("check " + quoted(duplicate));
  EXPECT_EQ(r.err.find("scene file"), r.err.rfind("scene file")) << "named twice: " << r.err;
  // A 60 000-character key is shown shortened with its length; bytes that are no text as \xNN.
  const auto long_key = run_hertzgear("check " + fourier_scene + " --set 'Stiffness/" +
                                      std::string(60000, 'k') + "=1'");
  EXPECT_EQ(long_key.exit_code, 2);
  EXPECT_THAT(long_key.err, HasSubstr("(60000 characters)"));
  EXPECT_LT(long_key.err.size(), 1000u) << "the key is echoed whole";
  const auto binary =
    run_hertzgear("check " + fourier_scene + " --set \"$(printf 'Stiffness/ab\\001c=1')\"");
  EXPECT_EQ(binary.exit_code, 2);
  EXPECT_THAT(binary.err, HasSubstr("ab\\x01c"));
}
