// Requirements on the checks that run before anything is written (docs/architecture.md, "Errors
// and exit codes", "The pipeline and its cache", "Stiffness table schema"; docs/user-guide.md):
// a scene nested deeper than a JSON file may be is refused naming its depth before it is
// converted; a value longer than a scene value may be is refused naming its key, and messages
// quote long values cut; `check` and `run` share one validation path, so that what a stage would
// refuse later (the Response values of a shooting sweep, a table without the unloaded STE an
// effect needs, misalignment in the 2D FE model) is refused by both with exit code 2 and no
// folder; a file that takes the reserved name of the run cache is replaced; a table made with
// other micro-geometry is refused naming the key; an implausible load warns without changing
// the exit code.
#include "tests/support/run_command.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <string>
#include <vector>

using namespace hertzgear::testing;
using ::testing::HasSubstr;
using ::testing::Not;
namespace fs = std::filesystem;

namespace
{
  std::string quoted(const fs::path &p) { return "'" + p.string() + "'"; }

  std::string this_test() { return ::testing::UnitTest::GetInstance()->current_test_info()->name(); }

  // A bundled scene with 60 mesh periods and no report (seconds per run), and `extra` settings.
  std::string fast(const std::string &scene, const std::string &extra = "")
  {
    return scene_path(scene) + " --set Dynamics/periods=60 --set Dynamics/transient_periods=30" +
           " --set Output/report=false" + extra;
  }
  // The crowned pair on the scene's own Fourier stiffness, on a closed-form stiffness stage (no
  // FE), and the uncrowned pair on its shipped FE table.
  const std::string fourier_scene  = fast("paper_crowned_fourier.prm");
  const std::string analytic_scene = fast("paper_crowned.prm", " --set Stiffness/source=hertz-analytic"
                                                               " --set Stiffness/positions_per_cycle=16");
  const std::string table_scene    = fast("paper_uncrowned_table.prm");

  // `check` and `run` on `scene` both end with exit code 2, name `named` (and `reason`), leave no
  // output folder and print a short message. Returns run's stderr.
  std::string expect_refused_by_check_and_run(const std::string &scene, const std::string &named,
                                              const std::string &reason = "")
  {
    std::string err;
    for (const std::string command : {"check", "run"})
      {
        const fs::path out  = fresh_temp_dir("early_" + this_test()) / "run";
        const auto     r    = run_hertzgear(command + " " + scene + " --out " + quoted(out));
        const std::string what = command + " " + scene;
        EXPECT_EQ(r.exit_code, 2) << what << "\n" << r.err;
        EXPECT_THAT(r.err, HasSubstr(named)) << what;
        EXPECT_THAT(r.err, HasSubstr(reason)) << what;
        EXPECT_FALSE(fs::exists(out)) << what << ": left a folder";
        EXPECT_FALSE(fs::exists(out.parent_path())) << what << ": left a folder";
        err = r.err;
      }
    return err;
  }

  // A JSON scene whose top level nests `depth` objects: {"Operating": {"a": {"a": ... 1 ...}}}.
  fs::path deep_json_scene(const fs::path &dir, const std::size_t depth)
  {
    fs::create_directories(dir);
    const fs::path file = dir / ("deep_" + std::to_string(depth) + ".json");
    std::ofstream  out(file);
    out << "{\"Operating\": ";
    for (std::size_t i = 1; i < depth; ++i)
      out << "{\"a\": ";
    out << "1";
    for (std::size_t i = 0; i < depth; ++i)
      out << "}";
    return file;
  }
} // namespace

// 1. Deep JSON.
TEST(EarlyChecks, ADeeplyNestedJsonSceneIsRefusedNamingItsDepth)
{
  // Requirement: a JSON scene nested 30 000 or 100 000 levels deep (which overflowed the stack
  // of the recursive conversion) is refused with exit code 2, naming its depth and the limit,
  // before any conversion, by `check` and `run`, with no folder left.
  const fs::path dir = fresh_temp_dir("early_deep_json");
  for (const std::size_t depth : {30000u, 100000u})
    {
      const fs::path scene = deep_json_scene(dir, depth);
      const auto     err   = expect_refused_by_check_and_run(
        quoted(scene), "nested " + std::to_string(depth) + " levels deep", "more than the 64 levels");
      EXPECT_LT(err.size(), 1000u) << err;
    }
  // A nesting within the limit is read as before: the unknown subsection is named.
  const auto r = run_hertzgear("check " + quoted(deep_json_scene(dir, 5)));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("no subsection \"a\""));
}

TEST(EarlyChecks, ADeeplyNestedStiffnessTableIsRefusedNamingTheKey)
{
  // Requirement: a stiffness table nested deeper than a table may be is refused naming
  // Stiffness/table_file and its depth (exit 2, no folder).
  const fs::path dir   = fresh_temp_dir("early_deep_table");
  const fs::path table = deep_json_scene(dir, 30000);
  expect_refused_by_check_and_run(table_scene + " --set Stiffness/table_file=" + quoted(table),
                                  "Stiffness/table_file", "nested 30000 levels deep");
}

// 2. Value sizes.
TEST(EarlyChecks, AValueOfMegabytesIsRefusedWithAShortMessageNamingTheKey)
{
  // Requirement: a scene value longer than 16 384 characters (from a .prm file, a .json file or
  // --set) is refused with exit code 2 before conversion; the message names the key and the
  // length and stays short (under 1 kB: the value is not echoed).
  const fs::path dir = fresh_temp_dir("early_long_value");
  fs::create_directories(dir);
  const std::string five_mb(5u << 20, '1');
  const fs::path    prm = dir / "long.prm";
  std::ofstream(prm) << "subsection Operating\n  set torque_Nm = " << five_mb << "\nend\n";
  const fs::path json = dir / "long.json";
  std::ofstream(json) << nlohmann::json{{"Operating", {{"torque_Nm", five_mb}}}}.dump();
  for (const auto &[scene, key] : std::vector<std::pair<fs::path, std::string>>{
         {prm, "Operating/torque_Nm"}, {json, "\"torque_Nm\""}})
    {
      const auto err = expect_refused_by_check_and_run(quoted(scene), key,
                                                       std::to_string(five_mb.size()) + " characters");
      EXPECT_LT(err.size(), 1000u) << "the value is echoed: " << err.substr(0, 2000);
    }
  // One argument of a command line holds at most 128 KiB (Linux's MAX_ARG_STRLEN): a --set value
  // of 120 000 characters is the longest a test can pass.
  const std::string long_set(120000, '1');
  const auto err = expect_refused_by_check_and_run(fourier_scene + " --set Operating/torque_Nm=" + long_set,
                                                   "Operating/torque_Nm", "120000 characters long");
  EXPECT_LT(err.size(), 1000u) << "the value is echoed: " << err.substr(0, 2000);
}

TEST(EarlyChecks, LongValuesAreQuotedCut)
{
  // Requirement: a value within the length limit but refused for its content is quoted cut to
  // its first characters with its length, not whole.
  const std::string value = std::string(10000, 'x');
  const auto        r = run_hertzgear("check " + fourier_scene + " --set Dynamics/integrator=" + value);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("Dynamics/integrator"));
  EXPECT_THAT(r.err, HasSubstr("(10000 characters)"));
  EXPECT_LT(r.err.size(), 1000u) << r.err.substr(0, 2000);
}

// 3. One validation path.
TEST(EarlyChecks, ResponseValuesOfAShootingSweepAreCheckedBeforeAnyFolder)
{
  // Requirement: with Sweep/enabled = true and Sweep/mode = shooting, the Response/* checks of
  // the sweep stage (Newton tolerance at least 10 rtol, an integrator that can shoot) run in
  // `check` and before `run` makes its folder, also when the table comes from a stiffness stage.
  const std::string shooting = " --set Sweep/enabled=true --set Sweep/mode=shooting";
  for (const std::string &scene : {fourier_scene, analytic_scene})
    {
      expect_refused_by_check_and_run(scene + shooting +
                                        " --set Response/relative_tolerance=1e-8"
                                        " --set Response/newton_tolerance=1e-8",
                                      "Response/newton_tolerance = 1e-08",
                                      "must be at least 10 Response/relative_tolerance");
      expect_refused_by_check_and_run(scene + shooting + " --set Dynamics/integrator=rk4",
                                      "Dynamics/integrator = rk4", "cannot serve the shooting method");
    }
  // Without the sweep the same values are no error of `check` (the response command alone reads
  // them).
  const auto r = run_hertzgear("check " + fourier_scene + " --set Dynamics/integrator=rk4");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(EarlyChecks, SteExcitationWithoutUnloadedSteIsRefusedBeforeAnyFolder)
{
  // Requirement: Effects/ste_excitation = table with a table that holds no unloaded STE, or with
  // a stiffness stage whose source does not compute it, is refused by `check` and by `run`
  // before any folder, naming the key.
  const fs::path dir = fresh_temp_dir("early_no_ste");
  fs::create_directories(dir);
  nlohmann::json table = nlohmann::json::parse(
    slurp(std::string(HERTZGEAR_SOURCE_DIR) + "/data/stiffness/paper_uncrowned.json"));
  table.erase("unloaded_ste_m");
  table["samples"].erase("unloaded_ste_m");
  const fs::path no_ste = dir / "no_ste.json";
  std::ofstream(no_ste) << table.dump(1);
  expect_refused_by_check_and_run(table_scene + " --set Stiffness/table_file=" + quoted(no_ste) +
                                    " --set Effects/ste_excitation=table",
                                  "Effects/ste_excitation = table", "unloaded STE");
  expect_refused_by_check_and_run(analytic_scene + " --set Effects/ste_excitation=table"
                                                   " --set Stiffness/table_file=" +
                                    quoted(no_ste),
                                  "Effects/ste_excitation = table", "does not compute");
  // The shipped table holds the unloaded STE: the same scene on it is valid.
  const auto r = run_hertzgear("check " + table_scene + " --set Effects/ste_excitation=table");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(EarlyChecks, MisalignmentInThe2dFeModelIsRefused)
{
  // Requirement: a mesh misalignment (or another value that varies along the face width) with
  // the plane-strain FE model, which would ignore it, is refused by `check` and `run` with exit
  // code 2 naming the key and saying that it needs the 3D model, before any folder or FE work.
  const std::string fe2d = scene_path("paper_uncrowned.prm") + " --set Stiffness/fe_dimension=2";
  expect_refused_by_check_and_run(fe2d + " --set Operating/mesh_misalignment_um=10",
                                  "Operating/mesh_misalignment_um = 10 um", "need the 3D model");
  expect_refused_by_check_and_run(fe2d + " --set Operating/axis_deviation_um=5",
                                  "Operating/axis_deviation_um", "need the 3D model");
  expect_refused_by_check_and_run(fe2d + " --set 'Gear pair/Gear/lead_end_relief_um=4'"
                                         " --set 'Gear pair/Gear/lead_end_relief_length_mm=2'",
                                  "Gear pair/Gear/lead_end_relief_um", "need the 3D model");
  // The 3D model takes it.
  const auto r = run_hertzgear("check " + scene_path("paper_uncrowned.prm") +
                               " --set Stiffness/fe_dimension=3 --set Operating/mesh_misalignment_um=10");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// 4. The reserved cache name.
TEST(EarlyChecks, AFileNamedLikeTheCacheIsReplacedWithAProgressLine)
{
  // Requirement: a regular file (or a link) named .hertzgear-cache in the run folder does not
  // stop `run`: it is removed (a link: the link, never its target) with a progress line saying
  // that the name is reserved for the cache, and the run ends with exit code 0 and its manifests.
  const fs::path out = fresh_temp_dir("early_cache_file");
  fs::create_directories(out);
  std::ofstream(out / ".hertzgear-cache") << "not a cache\n";
  const auto r = run_hertzgear("run " + fourier_scene + " --out " + quoted(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr(".hertzgear-cache was a regular file, not the cache folder: removed"));
  EXPECT_TRUE(fs::is_regular_file(out / ".hertzgear-cache" / "dynamics.json"));
  // The next run reuses the stage.
  const auto again = run_hertzgear("run " + fourier_scene + " --out " + quoted(out));
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_THAT(again.err, HasSubstr("dynamics: reused"));

  const fs::path linked = fresh_temp_dir("early_cache_link");
  const fs::path target = fresh_temp_dir("early_cache_link_target");
  fs::create_directories(linked);
  fs::create_directories(target);
  std::ofstream(target / "keep.txt") << "kept\n";
  fs::create_directory_symlink(target, linked / ".hertzgear-cache");
  const auto l = run_hertzgear("run " + fourier_scene + " --out " + quoted(linked));
  ASSERT_EQ(l.exit_code, 0) << l.err;
  EXPECT_THAT(l.err, HasSubstr("was a symbolic link, not the cache folder: removed"));
  EXPECT_FALSE(fs::is_symlink(linked / ".hertzgear-cache"));
  EXPECT_TRUE(fs::is_regular_file(linked / ".hertzgear-cache" / "dynamics.json"));
  EXPECT_EQ(slurp(target / "keep.txt"), "kept\n");
  EXPECT_FALSE(fs::exists(target / "dynamics.json")) << "a manifest was written through the link";
}

// 5. Micro-geometry in the pair record.
TEST(EarlyChecks, ATableMadeWithTipReliefRefusesASceneWithoutIt)
{
  // Requirement: the pair record of a stiffness table carries the micro-geometry and
  // misalignment it was computed with; a scene that differs is refused (exit 2) naming the key;
  // a table that does not record them (written before) is read with a warning naming what is not
  // recorded when the scene has such values, and silently when it has none.
  const fs::path dir = fresh_temp_dir("early_tip_relief");
  const std::string relief = " --set 'Gear pair/Pinion/tip_relief_um=20'"
                             " --set 'Gear pair/Pinion/tip_relief_length_mm=1.5'";
  const auto made = run_hertzgear("stiffness " + scene_path("paper_uncrowned.prm") +
                                  " --set Stiffness/source=iso6336" + relief + " --out " + quoted(dir));
  ASSERT_EQ(made.exit_code, 0) << made.err;
  const auto record = nlohmann::json::parse(slurp(dir / "stiffness.json")).at("pair");
  EXPECT_EQ(record.at("pinion").at("tip_relief_um").get<double>(), 20.0);
  EXPECT_EQ(record.at("pinion").at("tip_relief_length_mm").get<double>(), 1.5);
  EXPECT_EQ(record.at("pinion").at("tip_relief_shape").get<std::string>(), "linear");
  EXPECT_EQ(record.at("gear").at("tip_relief_um").get<double>(), 0.0);
  EXPECT_EQ(record.at("mesh_misalignment_um").get<double>(), 0.0);

  const std::string on_table = table_scene + " --set Stiffness/table_file=" + quoted(dir / "stiffness.json");
  expect_refused_by_check_and_run(on_table, "Gear pair/Pinion/tip_relief_um 20 (table) / 0 (scene)",
                                  "was computed for another pair");
  // The scene with the same relief takes the table.
  const auto same = run_hertzgear("check " + on_table + relief);
  EXPECT_EQ(same.exit_code, 0) << same.err;

  // A table whose record holds no micro-geometry (as tables written before the record held it):
  // a scene with a tip relief is warned about, the paper scene is not.
  auto old_table = nlohmann::json::parse(
    slurp(fs::path(HERTZGEAR_SOURCE_DIR) / "data" / "stiffness" / "paper_uncrowned.json"));
  nlohmann::json old_pair = {{"module_mm", old_table.at("pair").at("module_mm")},
                             {"pressure_angle_deg", old_table.at("pair").at("pressure_angle_deg")}};
  for (const char *gear : {"pinion", "gear"})
    for (const char *key : {"teeth", "face_width_mm", "profile_shift_coefficient", "crowning_um"})
      old_pair[gear][key] = old_table.at("pair").at(gear).at(key);
  old_table["pair"] = old_pair;
  const fs::path old_dir = fresh_temp_dir("early_old_record");
  fs::create_directories(old_dir);
  std::ofstream(old_dir / "stiffness.json") << old_table.dump(2);
  const std::string on_old = table_scene + " --set Stiffness/table_file=" + quoted(old_dir / "stiffness.json");
  const auto warned = run_hertzgear("check " + on_old + relief);
  EXPECT_EQ(warned.exit_code, 0) << warned.err;
  EXPECT_THAT(warned.err, HasSubstr("does not record pinion/tip_relief_length_mm, "
                                    "pinion/tip_relief_shape, pinion/tip_relief_um of its pair"));
  const auto plain = run_hertzgear("check " + on_old);
  EXPECT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_THAT(plain.err, Not(HasSubstr("does not record")));
  // The shipped tables record their whole pair: a scene with a tip relief is refused.
  expect_refused_by_check_and_run(table_scene + relief,
                                  "Gear pair/Pinion/tip_relief_um 0 (table) / 20 (scene)",
                                  "was computed for another pair");
}

// 6. Plausibility.
TEST(EarlyChecks, AnAbsurdLoadWarnsAndThePaperScenesDoNot)
{
  // Requirement: a load whose ISO 6336-2 nominal contact stress sigma_H0 exceeds 3000 MPa gets a
  // warning line on stderr from `check` and `run`, naming Operating/torque_Nm and the measure,
  // with the exit code unchanged (0); the bundled paper scenes get none.
  const auto c = run_hertzgear("check " + fourier_scene + " --set Operating/torque_Nm=1e7");
  EXPECT_EQ(c.exit_code, 0) << c.err;
  EXPECT_THAT(c.err, HasSubstr("warning: Operating/torque_Nm = 10000000 gives a nominal contact "
                               "stress sigma_H0 ="));
  const fs::path out = fresh_temp_dir("early_absurd_load");
  const auto     r   = run_hertzgear("run " + fourier_scene + " --set Operating/torque_Nm=1e7 --out " +
                               quoted(out));
  EXPECT_THAT(r.err, HasSubstr("warning: Operating/torque_Nm = 10000000"));
  const auto plain = run_hertzgear("run " + fourier_scene + " --out " + quoted(out));
  EXPECT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(r.exit_code, plain.exit_code) << r.err;
  for (const std::string scene : {"paper_uncrowned.prm", "paper_crowned.prm", "paper_uncrowned_table.prm",
                                  "paper_crowned_table.prm", "paper_uncrowned_fourier.prm",
                                  "paper_crowned_fourier.prm", "backside_impacts_fourier.prm"})
    {
      const auto p = run_hertzgear("check " + scene_path(scene));
      EXPECT_EQ(p.exit_code, 0) << scene << "\n" << p.err;
      EXPECT_THAT(p.err, Not(HasSubstr("sigma_H0"))) << scene;
    }
}
