// Requirements on the command line: documented exit codes (0 ok, 2 bad input, 3 numerical, 1
// other), messages that name the offending file/key, and no artifact left behind on bad input.
#include "tests/support/run_command.h"

#include <nlohmann/json.hpp>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

using namespace hertzgear::testing;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

TEST(Cli, VersionNamesVersionAndGitRevision)
{
  const auto r = run_hertzgear("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_THAT(r.out, HasSubstr("hertzgear 0."));
  EXPECT_THAT(r.out, HasSubstr("git "));
}

TEST(Cli, HelpListsTheCommands)
{
  const auto r = run_hertzgear("--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_THAT(r.out, HasSubstr("check"));
  EXPECT_THAT(r.out, HasSubstr("defaults"));
}

TEST(Cli, CheckAcceptsThePaperScenes)
{
  for (const char *name : {"paper_crowned.prm", "paper_uncrowned.prm"})
    {
      const auto r = run_hertzgear("check " + scene_path(name));
      EXPECT_EQ(r.exit_code, 0) << r.err;
      EXPECT_THAT(r.out, HasSubstr("is valid"));
      EXPECT_THAT(r.out, HasSubstr("set teeth"));
    }
}

TEST(Cli, OutOfRangeOverrideExitsTwoNamingKeyAndRange)
{
  const fs::path out = fresh_temp_dir("cli_range");
  const auto     r   = run_hertzgear("check " + scene_path("paper_crowned.prm") +
                               " --set 'Gear pair/Pinion/teeth=-3' --out " + out.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("Gear pair/Pinion/teeth"));
  EXPECT_THAT(r.err, HasSubstr("6...1000"));
  EXPECT_FALSE(fs::exists(out)) << "bad input must leave no artifact behind";
}

TEST(Cli, BadInputExitsTwoAndLeavesNoArtifact)
{
  const fs::path dir = fresh_temp_dir("cli_bad");
  fs::create_directories(dir);
  std::ofstream(dir / "unknown.prm") << "subsection Material\n  subsection Pinion\n"
                                        "    set youngs_modulus_GPa = 206\n  end\nend\n";
  std::ofstream(dir / "malformed.prm") << "subsection Operating\n  set torque_Nm = 2l0\nend\n";
  std::ofstream(dir / "section.prm") << "subsection Gear Pair\nend\n";

  struct Case
  {
    std::string args, expected;
  };
  const std::vector<Case> cases = {
    {"check " + (dir / "missing.prm").string(), "missing.prm does not exist"},
    {"check " + (dir / "unknown.prm").string(), "youngs_modulus_GPa"},
    {"check " + (dir / "malformed.prm").string(), "torque_Nm"},
    {"check " + (dir / "section.prm").string(), "Gear Pair"},
    {"frobnicate " + scene_path("paper_crowned.prm"), "frobnicate"},
    {"check", "scene"},
    {"check " + scene_path("paper_crowned.prm") + " --set 'Operating/torque=1'", "torque"},
  };
  for (const auto &c : cases)
    {
      const fs::path out = dir / "out";
      const auto     r   = run_hertzgear(c.args + " --out " + out.string());
      EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
      EXPECT_THAT(r.err, HasSubstr(c.expected)) << c.args;
      EXPECT_FALSE(fs::exists(out)) << c.args << ": bad input must leave no artifact behind";
    }
}

TEST(Cli, CheckWithOutWritesProvenance)
{
  const fs::path out = fresh_temp_dir("cli_out");
  const auto     r   = run_hertzgear("check " + scene_path("paper_uncrowned.prm") + " --out " +
                               out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(fs::exists(out / "used_parameters.prm"));
  const auto run = nlohmann::json::parse(slurp(out / "run.json"));
  EXPECT_EQ(run.at("scene_hash").get<std::string>().size(), 16u);
  EXPECT_THAT(run.at("command").get<std::string>(), HasSubstr("check"));
  EXPECT_TRUE(run.at("stage_timings").is_array());
  EXPECT_TRUE(run.contains("git_revision"));
  // The used parameters are a valid scene with the same hash.
  const auto again = run_hertzgear("check " + (out / "used_parameters.prm").string());
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_THAT(again.out, HasSubstr(run.at("scene_hash").get<std::string>()));
}

TEST(Cli, DefaultsRoundTripThroughCheck)
{
  const fs::path dir = fresh_temp_dir("cli_defaults");
  fs::create_directories(dir);
  const auto d = run_hertzgear("defaults");
  ASSERT_EQ(d.exit_code, 0);
  EXPECT_THAT(d.out, HasSubstr("module_mm"));
  std::ofstream(dir / "defaults.prm") << d.out;
  const auto c = run_hertzgear("check " + (dir / "defaults.prm").string());
  EXPECT_EQ(c.exit_code, 0) << c.err;
}
