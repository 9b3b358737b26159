// Requirements on `hertzgear run SCENE --out DIR` (docs/architecture.md, "The pipeline and its
// cache"):
//  - the stages follow from the scene: a closed-form stiffness source runs stiffness + dynamics,
//    a table source runs only dynamics, an enabled sweep adds the sweep;
//  - a second run with nothing changed executes no stage;
//  - changing a dynamics-only value (damping ratio, speed, integrator tolerance) reruns only the
//    dynamics; changing crowning reruns the stiffness and the dynamics;
//  - a truncated or corrupt artifact is detected and its stage rebuilt; a run interrupted by
//    SIGINT leaves no manifest that a later run would trust, and the next run completes;
//  - bad input exits with 2 and leaves no directory behind.
//
// The scene is the paper's crowned pair with Stiffness/source = hertz-analytic (closed forms, no
// FE) and 60 mesh periods, so a whole run takes about a second. Which stages ran is read from
// run.json ("pipeline"), which the run writes at its end.
#include "tests/support/run_command.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <map>

using namespace hertzgear::testing;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

namespace
{
  std::string quoted(const fs::path &p) { return "'" + p.string() + "'"; }

  // A small scene: closed-form stiffness, short integration, no report (the report has its own
  // test in test_report.cc).
  const std::string small_scene =
    scene_path("paper_crowned.prm") +
    " --set Stiffness/source=hertz-analytic --set Stiffness/positions_per_cycle=16"
    " --set Dynamics/periods=60 --set Dynamics/transient_periods=30 --set Output/report=false";

  // stage -> ran, from DIR/run.json.
  std::map<std::string, bool> stages_that_ran(const fs::path &dir)
  {
    std::map<std::string, bool> ran;
    const auto                  run = nlohmann::json::parse(slurp(dir / "run.json"));
    for (const auto &s : run.at("pipeline"))
      ran[s.at("stage").get<std::string>()] = s.at("ran").get<bool>();
    return ran;
  }

  CommandResult run_small(const fs::path &dir, const std::string &extra = "")
  {
    const auto r = run_hertzgear("run " + small_scene + " --out " + quoted(dir) + " " + extra);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return r;
  }

  const std::map<std::string, bool> all_ran  = {{"stiffness", true}, {"dynamics", true}};
  const std::map<std::string, bool> none_ran = {{"stiffness", false}, {"dynamics", false}};
  const std::map<std::string, bool> only_dynamics = {{"stiffness", false}, {"dynamics", true}};
} // namespace

TEST(Run, SecondRunExecutesNoStage)
{
  const fs::path dir = fresh_temp_dir("run_second");
  run_small(dir);
  EXPECT_EQ(stages_that_ran(dir), all_ran);
  const std::string summary = slurp(dir / "summary.json");
  const auto        r       = run_small(dir);
  EXPECT_EQ(stages_that_ran(dir), none_ran);
  EXPECT_THAT(r.err, HasSubstr("stiffness: reused"));
  EXPECT_THAT(r.err, HasSubstr("dynamics: reused"));
  EXPECT_THAT(r.out, HasSubstr("0 of 2 stages ran"));
  EXPECT_EQ(slurp(dir / "summary.json"), summary) << "a reused stage must not rewrite its artifacts";
}

TEST(Run, SecondRunWithReportExecutesNoStage)
{
  // The report is a stage too: its key holds the hashes of the artifacts of the stages before it,
  // also when those were reused.
  const fs::path dir = fresh_temp_dir("run_second_report");
  const auto     first = run_hertzgear("run " + small_scene + " --set Output/report=true --out " + quoted(dir));
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_TRUE(stages_that_ran(dir).at("report"));
  const auto second = run_hertzgear("run " + small_scene + " --set Output/report=true --out " + quoted(dir));
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_EQ(stages_that_ran(dir),
            (std::map<std::string, bool>{{"stiffness", false}, {"dynamics", false}, {"report", false}}));
}

TEST(Run, DynamicsOnlyValueRerunsOnlyDynamics)
{
  const fs::path dir = fresh_temp_dir("run_dynamics_only");
  run_small(dir);
  // One value of each dynamics-only kind: the damping ratio, the speed, the integrator tolerance.
  for (const std::string set : {"Dynamics/damping_ratio=0.02", "Operating/speed_rpm=300",
                                "Dynamics/relative_tolerance=1e-7"})
    {
      const auto r = run_small(dir, "--set " + set);
      EXPECT_EQ(stages_that_ran(dir), only_dynamics) << set;
      // The reason names the changed value.
      EXPECT_THAT(r.err, HasSubstr(set.substr(0, set.find('=')))) << set;
    }
}

TEST(Run, CrowningRerunsStiffnessAndDynamics)
{
  const fs::path dir = fresh_temp_dir("run_crowning");
  run_small(dir);
  const std::string table = slurp(dir / "stiffness.json");
  const auto r = run_small(dir, "--set \"Gear pair/Pinion/crowning_um=40\"");
  EXPECT_EQ(stages_that_ran(dir), all_ran);
  EXPECT_THAT(r.err, HasSubstr("Gear pair/Pinion/crowning_um: 80 -> 40"));
  EXPECT_NE(slurp(dir / "stiffness.json"), table) << "less crowning must change the stiffness";
}

TEST(Run, TableSourceRunsOnlyDynamicsAndSweepAddsTheSweep)
{
  // The stiffness table of a first run drives a second scene with source = table.
  const fs::path first = fresh_temp_dir("run_table_source");
  run_small(first);
  const fs::path dir = fresh_temp_dir("run_table_consumer");
  // Dynamics and a small sweep on the table that the first run wrote.
  const std::string consumer =
    "run " + scene_path("paper_crowned.prm") +
    " --set Stiffness/source=table --set " + quoted(fs::path("Stiffness/table_file=" + (first / "stiffness.json").string())) +
    " --set Dynamics/periods=60 --set Dynamics/transient_periods=30 --set Output/report=false"
    " --set Sweep/enabled=true --set Sweep/points=3 --set Sweep/speed_min_rpm=100"
    " --set Sweep/speed_max_rpm=200 --set Sweep/periods_per_point=40"
    " --set Sweep/transient_periods_per_point=20 --set Sweep/mode=independent --out " + quoted(dir);
  const auto r = run_hertzgear(consumer);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(stages_that_ran(dir), (std::map<std::string, bool>{{"dynamics", true}, {"sweep", true}}));
  EXPECT_EQ(slurp(dir / "stiffness.json"), slurp(first / "stiffness.json"))
    << "the run directory keeps a copy of the table that drove the dynamics";
  EXPECT_TRUE(fs::exists(dir / "sweep.csv"));
  EXPECT_THAT(r.err, HasSubstr("no meshing, no FE"));

  // The table is an input of the dynamics and the sweep: a new table (of the same pair, at a higher
  // torque) reruns both, and the reason names the table; the other load is said.
  run_small(first, "--set Operating/torque_Nm=300");
  const auto again = run_hertzgear(consumer);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_THAT(again.err, HasSubstr("warning: the stiffness table"));
  EXPECT_EQ(stages_that_ran(dir), (std::map<std::string, bool>{{"dynamics", true}, {"sweep", true}}));
  EXPECT_THAT(again.err, HasSubstr("dynamics: runs (input changed: " + (first / "stiffness.json").string()));
}

TEST(Run, TruncatedOrCorruptArtifactIsRebuilt)
{
  const fs::path dir = fresh_temp_dir("run_truncated");
  run_small(dir);
  const std::string table   = slurp(dir / "stiffness.json");
  const std::string summary = slurp(dir / "summary.json");

  // Truncated stiffness table: the stiffness stage reruns and writes the same table again (same
  // code, same scene: deterministic), so the dynamics, whose key holds the table's content hash,
  // stays valid.
  fs::resize_file(dir / "stiffness.json", table.size() / 2);
  auto r = run_small(dir);
  EXPECT_EQ(stages_that_ran(dir), (std::map<std::string, bool>{{"stiffness", true}, {"dynamics", false}}));
  EXPECT_THAT(r.err, HasSubstr("stiffness.json does not match its recorded hash"));
  EXPECT_EQ(slurp(dir / "stiffness.json"), table);

  // Same size, one byte changed: detected by the content hash, not only by the size.
  std::string corrupt = summary;
  corrupt[corrupt.size() / 2] = corrupt[corrupt.size() / 2] == '1' ? '2' : '1';
  std::ofstream(dir / "summary.json") << corrupt;
  run_small(dir);
  EXPECT_EQ(stages_that_ran(dir), only_dynamics);
  // Rebuilt, not patched: valid JSON with the same result (wall times differ between runs).
  EXPECT_EQ(nlohmann::json::parse(slurp(dir / "summary.json")).at("rms_dte_um"),
            nlohmann::json::parse(summary).at("rms_dte_um"));

  // A deleted artifact and a garbled manifest are also rebuilt.
  fs::remove(dir / "poincare.csv");
  run_small(dir);
  EXPECT_EQ(stages_that_ran(dir), only_dynamics);
  std::ofstream(dir / ".hertzgear-cache" / "stiffness.json") << "{ not json";
  run_small(dir);
  EXPECT_EQ(stages_that_ran(dir), (std::map<std::string, bool>{{"stiffness", true}, {"dynamics", false}}));
}

TEST(Run, InterruptedRunLeavesNothingTrusted)
{
  // SIGINT two seconds into a run whose dynamics takes far longer (20 000 mesh periods): the
  // dynamics is interrupted mid-stage. Whatever was finished may be reused, nothing else.
  const fs::path dir = fresh_temp_dir("run_sigint");
  const std::string long_run =
    scene_path("paper_crowned.prm") +
    " --set Stiffness/source=hertz-analytic --set Output/report=false"
    " --set Dynamics/periods=20000 --set Dynamics/transient_periods=100";
  const int status = std::system(("timeout -s INT 2 '" + std::string(HERTZGEAR_EXE) + "' run " +
                                  long_run + " --out " + quoted(dir) + " >/dev/null 2>&1")
                                   .c_str());
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_NE(WEXITSTATUS(status), 0) << "the run was expected to be interrupted";
  EXPECT_FALSE(fs::exists(dir / ".hertzgear-cache" / "dynamics.json"))
    << "an interrupted stage must leave no manifest";
  // The next run (now short) completes and reruns the interrupted dynamics.
  const auto r = run_hertzgear("run " + scene_path("paper_crowned.prm") +
                               " --set Stiffness/source=hertz-analytic --set Output/report=false"
                               " --set Dynamics/periods=60 --set Dynamics/transient_periods=30"
                               " --out " + quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(stages_that_ran(dir).at("dynamics"));
  for (const auto &e : fs::recursive_directory_iterator(dir))
    EXPECT_THAT(e.path().filename().string(), ::testing::Not(HasSubstr("hg-partial")))
      << "temporary files of the interrupted run must be gone";
}

TEST(Run, BadInputExitsWithTwoAndLeavesNothing)
{
  const fs::path dir = fresh_temp_dir("run_bad");
  const auto     r   = run_hertzgear("run " + scene_path("paper_crowned.prm") +
                               " --set Dynamics/damping_ratio=-1 --out " + quoted(dir));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("damping_ratio"));
  EXPECT_FALSE(fs::exists(dir));
}

TEST(Run, WithoutASceneRunsBothPaperScenesOnTheShippedTables)
{
  // The default job: both bundled paper scenes, stiffness from data/stiffness/ (no stiffness
  // stage), dynamics and a report each. Shortened here by --set, which applies to both scenes.
  const fs::path dir = fresh_temp_dir("run_default");
  const auto     r   = run_hertzgear("run --set Dynamics/periods=60 --set Dynamics/transient_periods=30"
                                 " --out " + quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const std::string name : {"paper_uncrowned", "paper_crowned"})
    {
      EXPECT_EQ(stages_that_ran(dir / name),
                (std::map<std::string, bool>{{"dynamics", true}, {"report", true}}))
        << name;
      EXPECT_TRUE(fs::exists(dir / name / "report" / "index.html")) << name;
      EXPECT_EQ(slurp(dir / name / "stiffness.json"),
                slurp(fs::path(HERTZGEAR_SOURCE_DIR) / "data" / "stiffness" / (name + ".json")))
        << "the run directory keeps the shipped table that drove the dynamics";
    }
}

TEST(Run, Iso6336SourceGivesAConstantTable)
{
  // ISO 6336 gives one mesh stiffness: every sample equal, no harmonics.
  const fs::path dir = fresh_temp_dir("run_iso");
  const auto     r   = run_hertzgear("run " + scene_path("paper_uncrowned.prm") +
                               " --set Stiffness/source=iso6336 --set Dynamics/periods=60"
                               " --set Dynamics/transient_periods=30 --set Output/report=false"
                               " --out " + quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto t = nlohmann::json::parse(slurp(dir / "stiffness.json"));
  const auto k = t.at("samples").at("k_hertz_N_per_m_pow_n").get<std::vector<double>>();
  ASSERT_FALSE(k.empty());
  for (const double v : k)
    EXPECT_EQ(v, k.front());
  EXPECT_GT(t.at("mean_k_rest_N_per_m").get<double>(), 0);
}

// Requirement: `hertzgear run` on an FE scene writes the fields of the loaded bodies (fields/)
// when Output/write_fields is true, as `hertzgear stiffness` does, and records them as artifacts
// of the stiffness stage; with write_fields = false a rerun removes them, so that no table
// stands beside the fields of another. The 2D paper pair at level 0 and 3 positions keeps the
// FE run to seconds.
TEST(Run, AnFeSceneWritesItsFieldsWhenAsked)
{
  const fs::path    dir   = fresh_temp_dir("run_fe_fields");
  const std::string scene = scene_path("paper_uncrowned.prm") +
                            " --set Stiffness/fe_level=0 --set Stiffness/positions_per_cycle=3"
                            " --set Stiffness/harmonics=1 --set Dynamics/periods=60"
                            " --set Dynamics/transient_periods=30 --set Output/report=false";
  auto r = run_hertzgear("run " + scene + " --set Output/write_fields=true --out " + quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_regular_file(dir / "fields" / "pinion.pvd"));
  EXPECT_TRUE(fs::is_regular_file(dir / "fields" / "gear_contact.pvd"));
  const auto manifest = slurp(dir / ".hertzgear-cache" / "stiffness.json");
  EXPECT_THAT(manifest, HasSubstr("fields/pinion.pvd"));

  r = run_hertzgear("run " + scene + " --set Output/write_fields=false --out " + quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(stages_that_ran(dir).at("stiffness"), true);
  EXPECT_FALSE(fs::exists(dir / "fields"));
}

// Requirement: `run` checks everything it can before it makes a folder, and `check` accepts
// exactly what `run` accepts: a pointed tooth on a scene whose stiffness comes from Fourier
// coefficients (the dynamics still uses the geometry), and a damping ratio of 0 that makes the
// Hertzian layer a DAE for the scene's radau-iia, are refused by both with exit 2, naming the key,
// and `run` leaves no folder behind.
TEST(Run, BadInputIsRefusedBeforeAnyFolderAndCheckAgrees)
{
  const std::string scene = scene_path("paper_crowned_fourier.prm") +
                            " --set Dynamics/periods=60 --set Dynamics/transient_periods=30"
                            " --set Output/report=false";
  const std::pair<std::string, std::string> cases[] = {
    {"--set \"Gear pair/Pinion/tip_radius_mm=45\"", "pinion"},
    {"--set Dynamics/damping_ratio=0", "Dynamics/integrator"}};
  for (const auto &[bad, named] : cases)
    {
      const fs::path dir = fresh_temp_dir("run_refused");
      fs::remove_all(dir);
      const auto run = run_hertzgear("run " + scene + " " + bad + " --out " + quoted(dir));
      EXPECT_EQ(run.exit_code, 2) << bad << "\n" << run.err;
      EXPECT_THAT(run.err, HasSubstr(named)) << bad;
      EXPECT_FALSE(fs::exists(dir)) << bad << ": run left a folder";
      const auto check = run_hertzgear("check " + scene + " " + bad);
      EXPECT_EQ(check.exit_code, 2) << bad << "\n" << check.err;
    }
}
