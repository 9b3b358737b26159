// Requirements on bad input across the commands (docs/architecture.md, "Errors and exit codes"):
// every case ends with exit code 2, a message that names the offending key, file or folder, and
// no folder or file left behind, and `hertzgear check` refuses the same case (on the same --out
// when the case is about the output place); a hostile table path (FIFO, device, directory, a file
// too large) ends at once; a folder in use by one hertzgear process is refused by the next one
// (run, stiffness, report) naming the process; the report names what no manifest of the run
// vouches for; an interrupted `stiffness` run leaves no mixed or partial table.
//
// 87 refused cases (exit code, named key or file, no folder left; `check` on each):
//   geometry (class 1) 12, helical pairs (1, 5) 18, tables (5) 18, output places (2) 9, scene text injection (8) 4,
//   scene files (3, 9) 5, values (3, 9) 5, arguments (2, 9) 4, JSON (8, 9) 3,
//   numerics (3, 4) 5, messages (9) 4 (two of them through `check` alone);
// and 16 further cases: check and run accept the same valid scenes (4) 3, a table at another
// load (5) 1, a folder in use (6) 5, the report's trust (7) 3, leftovers and durability (10) 4
// (leftover temporaries, a manifest that vouches for nothing, `stiffness` stopped by SIGINT and
// by SIGKILL). 103 cases in all; every class has at least three.
#include "tests/support/held_folder.h"
#include "tests/support/run_command.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <functional>
#include <fstream>
#include <fcntl.h>
#include <map>
#include <regex>
#include <sstream>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

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
  // A run with a stiffness stage: the paper's crowned pair with closed-form stiffness (no FE),
  // 60 mesh periods, no report.
  const std::string analytic_scene = scene_path("paper_crowned.prm") +
                                     " --set Stiffness/source=hertz-analytic"
                                     " --set Stiffness/positions_per_cycle=16 --set Dynamics/periods=60"
                                     " --set Dynamics/transient_periods=30 --set Output/report=false";
  // A closed-form stiffness scene for the `stiffness` command (no FE: a fraction of a second).
  const std::string iso_scene = scene_path("paper_uncrowned.prm") + " --set Stiffness/source=iso6336";
  const std::string table_scene = scene_path("paper_crowned_table.prm") +
                                  " --set Dynamics/periods=60 --set Dynamics/transient_periods=30"
                                  " --set Output/report=false";

  // Files the cases point at, made once.
  struct Fixtures
  {
    fs::path dir, fifo, big, not_json, string_value, negative, other_pair, newline_scene,
      hash_scene, regular_file, unknown_entry, unclosed, word_value, malformed_json, array_section,
      object_value;

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
      // Scene files that are no scenes.
      unknown_entry = dir / "unknown_entry.prm";
      std::ofstream(unknown_entry) << "subsection Stiffness\n  set frobnicate = 1\nend\n";
      unclosed = dir / "unclosed.prm";
      std::ofstream(unclosed) << "subsection Stiffness\n  set harmonics = 2\n";
      word_value = dir / "word_value.prm";
      std::ofstream(word_value) << "subsection Gear pair\n  subsection Pinion\n    set teeth = many\n"
                                   "  end\nend\n";
      malformed_json = dir / "malformed.json";
      std::ofstream(malformed_json) << R"({"Operating": {"torque_Nm": 100,)";
      array_section = dir / "array_section.json";
      std::ofstream(array_section) << R"({"Gear pair": [1, 2]})";
      object_value = dir / "object_value.json";
      // An object where an entry is expected ({"value": ...} is the entry form; this is not).
      std::ofstream(object_value) << R"({"Operating": {"torque_Nm": {"amount": 100}}})";
    }
  };

  const Fixtures &fixtures()
  {
    static const Fixtures f;
    return f;
  }

  // Requirement: `command` on DIR, which another process holds, exits 2 at once naming that
  // process and changes nothing in DIR.
  void expect_refused_while_held(const std::string &command, const fs::path &dir)
  {
    const HeldFolder held(dir);
    const auto       before = contents_below(dir);
    const auto       r      = run_hertzgear(command);
    EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.err;
    EXPECT_THAT(r.err, HasSubstr("the folder is in use by process " + held.pid)) << command;
    EXPECT_EQ(contents_below(dir), before) << command << ": changed a folder in use";
  }

  struct Case
  {
    std::string command;  // "run", "dynamics", "stiffness", "check"
    std::string scene;    // scene and --set arguments
    std::string named;    // what the message must name
    std::string out = ""; // --out; empty: a fresh folder that must not appear
    std::string reason = ""; // what the message must also say (the cause), if not empty
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
    EXPECT_THAT(r.err, HasSubstr(c.reason)) << what;
    EXPECT_FALSE(fs::exists(fresh)) << what << ": left a folder";
    // Refusal comes from the checks, before any work: far within a second for these scenes (a
    // generous bound that a hang on a FIFO or a read of /dev/zero would exceed by far; five times
    // as long in a sanitizer build, whose start-up alone takes seconds).
    EXPECT_LT(wall, 10.0 * HERTZGEAR_TIME_FACTOR) << what;
    // `check` agrees on every case (class 4): on the same scene, and on the same --out when the
    // case is about the output place (`check --out` writes the resolved scene there).
    const std::string check = "check " + c.scene + (c.out.empty() ? "" : " --out " + quoted(out));
    const auto        refused = run_hertzgear(check);
    EXPECT_EQ(refused.exit_code, 2) << check << "\n" << refused.err;
    EXPECT_THAT(refused.err, HasSubstr(c.named)) << check;
    EXPECT_THAT(refused.err, HasSubstr(c.reason)) << check;
    EXPECT_FALSE(fs::exists(fresh)) << check << ": left a folder";
  }
} // namespace

// Class 1: impossible gears are refused whatever the stiffness source, naming the scene keys to
// change and the cause.
TEST(BadInput, ImpossibleGearsAreRefusedWithEveryStiffnessSource)
{
  struct Gears
  {
    std::string set, key, reason;
  };
  for (const std::string &scene : {fourier_scene, table_scene})
    for (const auto &[set, key, reason] : std::vector<Gears>{
           {"--set 'Gear pair/Pinion/tip_radius_mm=45'", "Gear pair/Pinion/tip_radius_mm", "pointed tip"},
           {"--set 'Gear pair/Pinion/teeth=8' --set 'Gear pair/Pinion/bore_radius_mm=2' "
            "--set 'Gear pair/Pinion/profile_shift_coefficient=-1'",
            "Gear pair/Pinion/profile_shift_coefficient", "undercut"},
           {"--set 'Gear pair/Gear/addendum_coefficient=2' --set 'Gear pair/Gear/tip_radius_mm=0'",
            "Gear pair/Gear/addendum_coefficient", "pointed tip"},
           {"--set 'Gear pair/Pinion/tip_relief_um=20' --set 'Gear pair/Pinion/tip_relief_length_mm=40'",
            "Gear pair/Pinion/tip_relief_length_mm", "tip relief length"},
           {"--set 'Gear pair/Pinion/lead_end_relief_um=5' "
            "--set 'Gear pair/Pinion/lead_end_relief_length_mm=15'",
            "Gear pair/Pinion/lead_end_relief_length_mm", "lead end relief length"},
           {"--set Operating/mesh_misalignment_um=200", "Operating/mesh_misalignment_um", "misalignment"},
           {"--set Operating/center_distance_mm=85.2 --set Operating/backlash_mm=0",
            "Operating/center_distance_mm", "jams the pair"}})
      expect_refused({"run", scene + " " + set, key, "", reason});
}

// Class 1: the helix keys of a pair (docs/scenes.md): a helix angle outside [0, 45) deg, equal
// hands on a helical external pair and different helix angles are refused by every command that
// reads the pair, `geometry` included, naming the key and the cause.
TEST(BadInput, ImpossibleHelicalPairsAreRefusedNamingTheHelixKey)
{
  const std::string helical = scene_path("paper_helical.prm");
  struct Helix
  {
    std::string set, key, reason;
  };
  for (const std::string command : {"geometry", "run"})
    for (const auto &[set, key, reason] : std::vector<Helix>{
           {"--set 'Gear pair/Pinion/helix_angle_deg=45' --set 'Gear pair/Gear/helix_angle_deg=45'",
            "Gear pair/Pinion/helix_angle_deg", "outside [0, 45) deg"},
           {"--set 'Gear pair/Gear/helix_angle_deg=50'", "Gear pair/Gear/helix_angle_deg", "not allowed"},
           {"--set 'Gear pair/Pinion/helix_angle_deg=-5'", "Gear pair/Pinion/helix_angle_deg", "not allowed"},
           {"--set 'Gear pair/Gear/hand=right'", "Gear pair/Gear/hand", "needs opposite hands"},
           {"--set 'Gear pair/Gear/helix_angle_deg=10'", "Gear pair/Gear/helix_angle_deg",
            "share one helix angle"}})
      expect_refused({command, helical + " " + set, key, "", reason});
}

// Class 1: a helical pair asked of a stage that cannot serve it gets that stage's refusal from
// the command line (exit 2, the key named, no folder): the stiffness command with every
// closed-form stiffness source (naming the helix angle), the FE source and `run` with the 2D
// model (naming Stiffness/fe_dimension), a 3D mesh with too few layers for its twist, and the
// dynamics on a spur pair's table.
TEST(BadInput, HelicalScenesAreRefusedByTheStagesThatCannotServeThem)
{
  const std::string helical = scene_path("paper_helical.prm");
  const std::string beta    = "Gear pair/Pinion/helix_angle_deg";
  const std::string refused = "helical pairs are not supported by ";
  for (const auto &[set, reason] : std::vector<std::pair<std::string, std::string>>{
         {"--set Stiffness/source=iso6336", refused + "the closed-form stiffness sources yet"},
         {"--set Stiffness/source=hertz-analytic", refused + "the closed-form stiffness sources yet"},
         {"--set Stiffness/source=potential-energy", refused + "the closed-form stiffness sources yet"}})
    expect_refused({"stiffness", helical + " " + set, beta, "", reason});
  // The FE source takes a helical pair in 3D only (the scene's own dimension).
  for (const std::string command : {"stiffness", "run"})
    expect_refused({command, helical + " --set Stiffness/fe_dimension=2", "Stiffness/fe_dimension = 2",
                    "", "cannot represent a helical pair"});
  // Too few layers along the face for the twist: the FE stage refuses before any work.
  expect_refused({"stiffness", helical + " --set Mesh/face_width_layers=2", "Mesh/face_width_layers",
                  "", "cannot carry the helix"});
  // The count it names carries both bodies: at 32.5 deg with 16 layers the pinion needs 18 and the
  // gear 20, and the refusal names the gear's 20 (not a count that the next run refuses again).
  expect_refused({"stiffness",
                  helical + " --set 'Gear pair/Pinion/helix_angle_deg=32.5' --set 'Gear pair/Gear/helix_angle_deg=32.5'"
                            " --set Mesh/face_width_layers=16",
                  "Mesh/face_width_layers", "", "set Mesh/face_width_layers >= 20"});
  // The mesher builds helical 3D bodies (tests/meshing/test_mesh.cc), but not with fewer layers
  // along the face than the twist needs (docs/geometry.md, "Meshes"): it names the key and the
  // count that carries both bodies (the gear's 8; the pinion would take 7).
  const fs::path mesh_out = fresh_temp_dir("bad_input_mesh_" + this_test()) / "mesh";
  const auto     mesh     = run_hertzgear("mesh " + helical +
                                  " --set Stiffness/fe_dimension=3 --set Mesh/face_width_layers=2 --out " +
                                  quoted(mesh_out));
  EXPECT_EQ(mesh.exit_code, 2) << mesh.err;
  EXPECT_THAT(mesh.err, HasSubstr("cannot carry the helix"));
  EXPECT_THAT(mesh.err, HasSubstr("set Mesh/face_width_layers >= 8"));
  EXPECT_FALSE(fs::exists(mesh_out)) << "mesh: left a folder";
  // A table records no helix angle for a spur pair: it is a spur table, and serves no helical pair.
  const fs::path spur_table = fs::path(HERTZGEAR_SOURCE_DIR) / "data" / "stiffness" / "paper_uncrowned.json";
  expect_refused({"dynamics",
                  helical + " --set Stiffness/source=table --set Stiffness/table_file=" + quoted(spur_table),
                  "Stiffness/table_file", "Gear pair/Pinion/helix_angle_deg 0 (table) / 15 (scene)"});
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
      const std::string scene = command == "stiffness" ? iso_scene : fourier_scene;
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

// Classes 3 and 9: scene files that cannot be read as scenes, refused before any folder, naming
// the file and the line or key.
TEST(BadInput, SceneFilesThatAreNoScenesNameTheFileAndTheLine)
{
  const auto &f = fixtures();
  for (const auto &[scene, named] : std::vector<std::pair<fs::path, std::string>>{
         {"/nonexistent/scene.prm", "/nonexistent/scene.prm"},
         {f.dir, f.dir.string()},
         {f.unknown_entry, "frobnicate"},
         {f.unclosed, "unclosed.prm"},
         {f.word_value, "\"many\""}})
    expect_refused({"run", quoted(scene), named});
}

// Classes 3 and 9: values out of their range or no numbers, named with their key.
TEST(BadInput, ValuesOutOfRangeAreRefusedNamingTheKey)
{
  for (const auto &[set, named] : std::vector<std::pair<std::string, std::string>>{
         {"Dynamics/damping_ratio=-1", "damping_ratio"},
         {"Operating/torque_Nm=nan", "torque_Nm"},
         {"Operating/speed_rpm=inf", "speed_rpm"},
         {"Operating/torque_Nm=1e400", "torque_Nm"},
         {"'Gear pair/Pinion/teeth=2.5'", "teeth"}})
    expect_refused({"run", fourier_scene + " --set " + set, named});
}

// Classes 2 and 9: command-line arguments that make no run.
TEST(BadInput, ArgumentsThatMakeNoRunNameTheArgument)
{
  expect_refused({"run", fourier_scene + " --set Dynamics/periods", "Dynamics/periods"});
  expect_refused({"run", fourier_scene + " --set Nowhere/key=1", "Nowhere"});
  expect_refused({"run", fourier_scene + " --frobnicate", "--frobnicate"});
  expect_refused({"dynamics", fourier_scene + " --set Dynamics/nonexistent_key=3", "nonexistent_key"});
}

// Classes 8 and 9: JSON scenes of the wrong shape.
TEST(BadInput, JsonScenesOfTheWrongShapeNameTheFileAndTheKey)
{
  const auto &f = fixtures();
  expect_refused({"run", quoted(f.malformed_json), "malformed.json"});
  expect_refused({"run", quoted(f.array_section), "Gear pair"});
  expect_refused({"run", quoted(f.object_value), "torque_Nm"});
}

// Classes 3 and 4: numerical settings a run would only fail on late (after it made its folder,
// before the checks learnt them) are refused up front by `run` and by `check` alike.
TEST(BadInput, NumericalSettingsThatCannotRunAreRefusedUpFront)
{
  for (const auto &[set, named] : std::vector<std::pair<std::string, std::string>>{
         {"Dynamics/damping_ratio=0", "Dynamics/integrator"},
         {"Dynamics/relative_tolerance=0", "relative_tolerance"},
         {"Dynamics/periods=0", "periods"},
         {"Dynamics/transient_periods=100", "transient_periods"}})
    expect_refused({"run", fourier_scene + " --set " + set, named});
  expect_refused({"stiffness",
                  scene_path("paper_uncrowned.prm") +
                    " --set Stiffness/positions_per_cycle=3 --set Stiffness/harmonics=4",
                  "positions_per_cycle"});
}

TEST(BadInput, CheckAndRunAcceptTheSameValidScenes)
{
  // Requirement (class 4): `check` accepts what `run` accepts: both pass the valid scenes the
  // cases above start from.
  for (const std::string &scene : {fourier_scene, table_scene, analytic_scene})
    {
      const fs::path dir   = fresh_temp_dir("bad_input_valid_" + this_test());
      const auto     check = run_hertzgear("check " + scene);
      const auto     run   = run_hertzgear("run " + scene + " --set Output/report=false --out " + quoted(dir));
      EXPECT_EQ(check.exit_code, 0) << scene << "\n" << check.err;
      EXPECT_EQ(run.exit_code, 0) << scene << "\n" << run.err;
    }
}

// Class 6: two runs on one folder.
TEST(BadInput, AFolderInUseIsRefusedNamingTheProcess)
{
  // Requirement: a run on a folder whose lock another process holds exits 2 at once, naming that
  // process, and writes nothing there; once the lock is free the run proceeds.
  const fs::path dir = fresh_temp_dir("bad_input_held");
  expect_refused_while_held("run " + fourier_scene + " --out " + quoted(dir), dir);
  EXPECT_FALSE(fs::exists(dir / "used_parameters.prm"));
  const auto r = run_hertzgear("run " + fourier_scene + " --out " + quoted(dir));
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(BadInput, TheStiffnessCommandRefusesAFolderInUse)
{
  // Requirement: `stiffness` takes the folder as `run` does: into a folder another process holds
  // it exits 2 naming that process, and leaves the folder's files as they were.
  const fs::path dir = fresh_temp_dir("bad_input_held_stiffness");
  ASSERT_EQ(run_hertzgear("stiffness " + iso_scene + " --out " + quoted(dir)).exit_code, 0);
  expect_refused_while_held("stiffness " + iso_scene + " --set Operating/torque_Nm=300 --out " +
                              quoted(dir),
                            dir);
}

TEST(BadInput, TheReportRefusesAFolderInUse)
{
  // Requirement: the report of a folder that a run is writing into would draw the run's old
  // artifacts beside its new ones: `report` exits 2 naming the process that holds the folder and
  // writes no report; once the folder is free it draws the report.
  const fs::path dir = fresh_temp_dir("bad_input_held_report");
  ASSERT_EQ(run_hertzgear("run " + fourier_scene + " --out " + quoted(dir)).exit_code, 0);
  expect_refused_while_held("report " + quoted(dir), dir);
  EXPECT_FALSE(fs::exists(dir / "report"));
  const auto r = run_hertzgear("report " + quoted(dir));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "report" / "index.html"));
}

TEST(BadInput, ALockFileLeftByAnEndedProcessDoesNotBlock)
{
  // Requirement: the lock is the kernel's flock, not the file: a .hertzgear.lock that an ended
  // process left (its number inside, no holder) does not stop a run, which takes the folder.
  const fs::path dir = fresh_temp_dir("bad_input_ended_lock");
  fs::create_directories(dir);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0)
    {
      const int         fd  = ::open((dir / ".hertzgear.lock").c_str(), O_RDWR | O_CREAT, 0644);
      const std::string pid = std::to_string(::getpid());
      const bool ok = fd >= 0 && ::flock(fd, LOCK_EX) == 0 && ::write(fd, pid.data(), pid.size()) > 0;
      ::_exit(ok ? 0 : 1); // ends holding the lock: the kernel releases it, the file stays
    }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  ASSERT_EQ(slurp(dir / ".hertzgear.lock"), std::to_string(child));
  const auto r = run_hertzgear("run " + fourier_scene + " --out " + quoted(dir));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "summary.json"));
  EXPECT_NE(slurp(dir / ".hertzgear.lock"), std::to_string(child)) << "the run did not take the folder";
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
  const auto r = run_hertzgear("stiffness " + iso_scene + " --out " + quoted(dir));
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

TEST(BadInput, TheReportWarnsWhenTheParametersAreOfAnotherRun)
{
  // Requirement: the report shows the scene values of used_parameters.prm beside the results only
  // when the manifests of the stages that wrote them record that file's hash. Here the folder
  // holds the parameters of a run with another damping ratio, as a run stopped right after it
  // wrote them leaves them: the page and stderr warn, naming the file, the stages and the results.
  // A complete run of that scene reruns the dynamics and re-records the reused stiffness stage
  // under its parameters: then every manifest records the same parameters.
  const fs::path    dir    = fresh_temp_dir("bad_input_report_parameters");
  const fs::path    other  = fresh_temp_dir("bad_input_report_parameters_other");
  const std::string damped = analytic_scene + " --set Dynamics/damping_ratio=0.03";
  ASSERT_EQ(run_hertzgear("run " + analytic_scene + " --out " + quoted(dir)).exit_code, 0);
  ASSERT_EQ(run_hertzgear("check " + damped + " --out " + quoted(other)).exit_code, 0);
  const auto recorded = [&](const std::string &stage) {
    return nlohmann::json::parse(slurp(dir / ".hertzgear-cache" / (stage + ".json")))
      .at("used_parameters_hash")
      .get<std::string>();
  };
  fs::copy_file(other / "used_parameters.prm", dir / "used_parameters.prm",
                fs::copy_options::overwrite_existing);
  const auto r = run_hertzgear("report " + quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string warning = "used_parameters.prm is not the scene of the run that wrote the "
                              "artifacts of the stage(s) dynamics, stiffness";
  EXPECT_THAT(r.err, HasSubstr("warning: " + warning));
  const std::string page = slurp(dir / "report" / "index.html");
  EXPECT_THAT(page, HasSubstr(warning));
  EXPECT_THAT(page, HasSubstr("Not covered by a verified cache manifest"));
  EXPECT_THAT(page, HasSubstr("summary.json"));

  const std::string first = recorded("stiffness");
  const auto        again = run_hertzgear("run " + damped + " --out " + quoted(dir));
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_THAT(again.err, HasSubstr("stiffness: reused"));
  EXPECT_NE(recorded("stiffness"), first) << "the reused stiffness stage keeps the first run's record";
  EXPECT_EQ(recorded("stiffness"), recorded("dynamics"));
}

TEST(BadInput, TheReportWarnsOnARunFolderWithoutManifests)
{
  // Requirement: a `hertzgear run` folder whose cache manifests are gone vouches for nothing: the
  // report says so and names every result it draws as untrusted. A folder of a single command
  // (`dynamics`), which never has manifests, is drawn without that warning.
  const fs::path dir = fresh_temp_dir("bad_input_report_no_manifest");
  ASSERT_EQ(run_hertzgear("run " + fourier_scene + " --out " + quoted(dir)).exit_code, 0);
  fs::remove_all(dir / ".hertzgear-cache");
  const auto r = run_hertzgear("report " + quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("warning: This folder was written by `hertzgear run` but holds no cache manifest"));
  const std::string page = slurp(dir / "report" / "index.html");
  EXPECT_THAT(page, HasSubstr(".hertzgear-cache/ is missing"));
  for (const char *result : {"summary.json", "timeseries.csv", "poincare.csv"})
    EXPECT_THAT(page, HasSubstr(result)) << result;
  EXPECT_THAT(page, HasSubstr("Not covered by a verified cache manifest"));

  const fs::path single = fresh_temp_dir("bad_input_report_single_command");
  ASSERT_EQ(run_hertzgear("dynamics " + fourier_scene + " --out " + quoted(single)).exit_code, 0);
  const auto s = run_hertzgear("report " + quoted(single));
  ASSERT_EQ(s.exit_code, 0) << s.err;
  EXPECT_THAT(s.err, ::testing::Not(HasSubstr("warning:")));
  EXPECT_THAT(slurp(single / "report" / "index.html"), ::testing::Not(HasSubstr("Not covered by")));
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
// Class 10: an interrupted `stiffness` command, as Run.InterruptedRunLeavesNothingTrusted for `run`.
namespace
{
  // The paper's uncrowned pair in 2D at FE level 0 with its fields: under a second of FE.
  // A coarse FE stiffness run of the uncrowned pair with `positions` mesh positions; `extra`
  // further --set arguments.
  std::string fe_scene(const int positions, const std::string &extra = "")
  {
    return scene_path("paper_uncrowned.prm") +
           " --set Stiffness/fe_level=0 --set Stiffness/harmonics=1 --set Output/write_fields=true"
           " --set Stiffness/positions_per_cycle=" +
           std::to_string(positions) + extra;
  }

  std::size_t count_of(const std::string &text, const std::string &what)
  {
    std::size_t n = 0;
    for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
      ++n;
    return n;
  }

  // What a stiffness folder must be at any instant: a stiffness.json under its final name is
  // complete and has its stiffness.csv beside it with the same mesh positions; fields beside it
  // hold exactly its positions; a run.json beside it is of the same scene. Returns the number of
  // positions of the table, 0 when there is none.
  std::size_t expect_stiffness_folder_consistent(const fs::path &dir, const std::string &when)
  {
    if (!fs::exists(dir / "stiffness.json"))
      return 0;
    nlohmann::json table;
    EXPECT_NO_THROW(table = nlohmann::json::parse(slurp(dir / "stiffness.json")))
      << when << ": stiffness.json is not complete JSON";
    if (!table.is_object())
      return 0;
    const auto phases = table.at("samples").at("mesh_phase").get<std::vector<double>>();
    // stiffness.csv: a header and one complete row per position of the same table.
    std::istringstream       csv(slurp(dir / "stiffness.csv"));
    std::vector<std::string> rows;
    for (std::string line; std::getline(csv, line);)
      if (!line.empty() && line[0] != '#')
        rows.push_back(line);
    EXPECT_EQ(rows.size(), phases.size() + 1) << when << ": stiffness.csv is not the table's";
    for (std::size_t i = 1; i < rows.size() && i <= phases.size(); ++i)
      {
        const auto comma = rows[i].find(',');
        // The CSV prints 10 significant digits; phases lie in [0, 1).
        EXPECT_NEAR(std::stod(rows[i].substr(comma + 1)), phases[i - 1], 1e-9)
          << when << ": row " << i << " of stiffness.csv";
        EXPECT_EQ(count_of(rows[i], ","), count_of(rows[0], ",")) << when << ": cut row " << i;
      }
    // Fields beside the table: one data set per position of this table, never of another.
    for (const char *pvd : {"pinion.pvd", "gear.pvd"})
      if (fs::exists(dir / "fields" / pvd))
        {
          const std::string text = slurp(dir / "fields" / pvd);
          EXPECT_EQ(count_of(text, "<DataSet"), phases.size()) << when << ": fields/" << pvd
                                                               << " belong to another table";
          EXPECT_THAT(text, HasSubstr("</VTKFile>")) << when << ": fields/" << pvd << " is cut";
        }
    if (fs::exists(dir / "used_parameters.prm"))
      {
        std::smatch       m;
        const std::string prm = slurp(dir / "used_parameters.prm");
        EXPECT_TRUE(std::regex_search(prm, m, std::regex(R"(positions_per_cycle\s*=\s*(\d+))")) &&
                    std::stoul(m[1]) == phases.size())
          << when << ": used_parameters.prm is of another run than stiffness.json";
      }
    if (fs::exists(dir / "run.json"))
      {
        EXPECT_EQ(nlohmann::json::parse(slurp(dir / "run.json")).at("scene_hash"), table.at("scene_hash"))
          << when << ": run.json is of another run than stiffness.json";
      }
    return phases.size();
  }

  void complete_stiffness_run(const fs::path &dir, const int positions, const std::string &extra = "")
  {
    const auto r = run_hertzgear("stiffness " + fe_scene(positions, extra) + " --out " + quoted(dir));
    EXPECT_EQ(r.exit_code, 0) << r.err;
  }

  // Starts `hertzgear stiffness` into `dir`, sends it `signal` as soon as `reached(dir)` holds
  // (polled every millisecond), and returns whether the signal stopped it (false: the run ended
  // first, with exit code 0 asserted).
  bool stiffness_run_stopped_when(const fs::path &dir, const int positions, const std::string &extra,
                                  const int signal, const std::function<bool(const fs::path &)> &reached)
  {
    const std::string command = "exec '" + std::string(HERTZGEAR_EXE) + "' stiffness " +
                                fe_scene(positions, extra) + " --out " + quoted(dir) + " >/dev/null 2>&1";
    const pid_t child = ::fork();
    if (child == 0)
      {
        ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char *>(nullptr));
        ::_exit(127);
      }
    EXPECT_GT(child, 0);
    int status = 0;
    while (::waitpid(child, &status, WNOHANG) == 0)
      {
        if (reached(dir))
          {
            ::kill(child, signal);
            ::waitpid(child, &status, 0);
            break;
          }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    if (WIFSIGNALED(status))
      return true;
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status;
    return false;
  }

  bool fields_under_way(const fs::path &dir)
  {
    std::error_code ec;
    for (const auto &e : fs::directory_iterator(dir, ec))
      if (e.path().filename().string().rfind(".fields.hg-partial", 0) == 0)
        return true;
    return false;
  }

  // The files of mesh/ below `dir` with their content.
  std::map<std::string, std::string> meshes_below(const fs::path &dir)
  {
    std::map<std::string, std::string> meshes;
    for (const auto &[file, content] : contents_below(dir))
      if (file.rfind("mesh/", 0) == 0)
        meshes[file] = content;
    return meshes;
  }

  // Requirement: a `stiffness` run stopped by `signal` leaves no partial file under a final name
  // and no new table beside the old fields or meshes (or the old used_parameters.prm and
  // run.json), nor new meshes beside the old table, and the next run removes the temporaries it
  // left. The stopped runs mesh thinner teeth (more backlash) than the first, so that their
  // meshes differ from its meshes. The runs are stopped at two measured points,
  // not after a time, so that a loaded machine changes nothing: while the FE stage writes the
  // fields (hidden .fields.hg-partial-* folder present: the old files must all stand), and as
  // soon as the old stiffness.json is gone (the commit of the new files has begun: the kill lands
  // in the commit or, on a slow poll, after it). Each outcome is checked, not assumed.
  void expect_stopped_stiffness_runs_leave_no_mix(const int signal)
  {
    const fs::path dir = fresh_temp_dir("bad_input_stiffness_" + std::to_string(signal));
    // The old table has 5 positions, its fields and meshes; the stopped runs compute 7 on other
    // meshes.
    const int         old_positions = 5, new_positions = 7;
    const std::string other_meshes  = " --set Operating/backlash_mm=0.2";
    complete_stiffness_run(dir, old_positions);
    ASSERT_EQ(expect_stiffness_folder_consistent(dir, "first run"), std::size_t(old_positions));
    const auto old_files  = contents_below(dir);
    const auto old_meshes = meshes_below(dir);
    ASSERT_FALSE(old_meshes.empty());

    ASSERT_TRUE(stiffness_run_stopped_when(dir, new_positions, other_meshes, signal, fields_under_way))
      << "the run ended before its fields were written";
    EXPECT_EQ(expect_stiffness_folder_consistent(dir, "stopped in the FE stage"),
              std::size_t(old_positions));
    // Every old file stands unchanged, the meshes included (the new ones are made in hidden
    // folders).
    for (const auto &[file, content] : old_files)
      {
        if (file != ".hertzgear.lock") // holds the process number of the last run
          {
            EXPECT_EQ(slurp(dir / file), content) << file << " changed before the commit";
          }
      }

    const bool stopped =
      stiffness_run_stopped_when(dir, new_positions, other_meshes, signal,
                                 [](const fs::path &d) { return !fs::exists(d / "stiffness.json"); });
    const std::size_t n = expect_stiffness_folder_consistent(dir, stopped ? "stopped in the commit" :
                                                                            "ended before the stop");
    if (!stopped)
      {
        EXPECT_EQ(n, std::size_t(new_positions)) << "a completed run holds its own table";
      }
    // The old meshes leave before the new table comes: the new table never stands beside them.
    if (n == std::size_t(new_positions))
      {
        for (const auto &[file, content] : meshes_below(dir))
          EXPECT_NE(content, old_meshes.at(file)) << file << ": an old mesh beside the new table";
      }

    complete_stiffness_run(dir, new_positions, other_meshes);
    EXPECT_EQ(expect_stiffness_folder_consistent(dir, "last run"), std::size_t(new_positions));
    EXPECT_TRUE(fs::exists(dir / "fields" / "pinion.pvd"));
    const auto new_meshes = meshes_below(dir);
    EXPECT_EQ(new_meshes.size(), old_meshes.size()) << "the last run's meshes are not all there";
    for (const auto &[file, content] : new_meshes)
      EXPECT_NE(content, old_meshes.at(file)) << file << " is not the last run's mesh";
    for (const auto &e : fs::recursive_directory_iterator(dir))
      EXPECT_THAT(e.path().filename().string(), ::testing::Not(HasSubstr("hg-partial")))
        << "a temporary of a stopped run is left: " << e.path();
  }
} // namespace

TEST(BadInput, AStiffnessRunStoppedBySigintLeavesNoMixedTable)
{
  expect_stopped_stiffness_runs_leave_no_mix(SIGINT);
}

TEST(BadInput, AStiffnessRunStoppedBySigkillLeavesNoMixedTable)
{
  expect_stopped_stiffness_runs_leave_no_mix(SIGKILL);
}
