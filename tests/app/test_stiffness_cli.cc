// Requirements on `hertzgear stiffness`: the stiffness.csv / stiffness.json contract, a table the
// dynamics stage reads back, and clear errors (exit 2) for loads and settings it cannot analyse.
#include "dynamics/stiffness_table.h"

#include "tests/support/run_command.h"

#include <nlohmann/json.hpp>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>

using namespace hertzgear::testing;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

namespace
{
  // A coarse 2D cycle that runs in seconds: level 0, linear elements, a 5-tooth sector.
  const std::string coarse = " --set Stiffness/fe_level=0 --set Stiffness/fe_degree=1"
                             " --set Mesh/teeth_per_sector=5 --set Stiffness/positions_per_cycle=5"
                             " --set Stiffness/harmonics=2";
} // namespace

TEST(StiffnessCli, WritesTheContractColumnsAndATableTheDynamicsReads)
{
  const fs::path out = fresh_temp_dir("stiffness_cli");
  const auto     r = run_hertzgear("stiffness " + scene_path("paper_uncrowned.prm") + coarse +
                               " --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("position 5/5"));

  std::istringstream csv(slurp(out / "stiffness.csv"));
  std::string        header;
  std::getline(csv, header);
  EXPECT_EQ(header, "position,mesh_phase,ste_um,k_total_N_per_m,k_hertz,k_rest_N_per_m,"
                    "pairs_in_contact,load_share_1,load_share_2,hertz_penetration_um,"
                    "contact_a_mm,contact_b_mm,peak_pressure_MPa");
  int n_rows = 0;
  for (std::string line; std::getline(csv, line); ++n_rows)
    {
      std::vector<double> v;
      std::stringstream   ss(line);
      for (std::string cell; std::getline(ss, cell, ',');)
        v.push_back(std::stod(cell));
      ASSERT_EQ(v.size(), 13u) << line;
      // Load shares sum to 1: the contact solver balances the load to round-off; the CSV keeps
      // 10 significant digits.
      EXPECT_NEAR(v[7] + v[8], 1.0, 1e-9) << line;
      EXPECT_GT(v[3], 0.0);
      EXPECT_GT(v[9], 0.0);
    }
  EXPECT_EQ(n_rows, 5);

  const auto table = hertzgear::dynamics::read_stiffness_table(out / "stiffness.json");
  EXPECT_DOUBLE_EQ(table.hertz_exponent, 1.0);
  EXPECT_GT(table.k_hertz_N_per_m_pow_n.mean, 0.0);
  EXPECT_GT(table.k_rest_N_per_m.mean, 0.0);
  EXPECT_EQ(table.k_hertz_N_per_m_pow_n.n_harmonics(), 2u);
  const auto json = nlohmann::json::parse(slurp(out / "stiffness.json"));
  EXPECT_EQ(json.at("scene_hash").get<std::string>().size(), 16u);
  EXPECT_GT(json.at("fe").at("dofs").get<double>(), 0.0);
  EXPECT_TRUE(fs::exists(out / "run.json"));
  EXPECT_TRUE(fs::exists(out / "used_parameters.prm"));
}

TEST(StiffnessCli, LoadsAndSettingsItCannotAnalyseExitTwo)
{
  struct Case
  {
    std::string set, expected;
  };
  const std::vector<Case> cases = {
    {" --set Operating/torque_Nm=0", "torque_Nm = 0"},
    {" --set Stiffness/positions_per_cycle=4 --set Stiffness/harmonics=2", "too few"},
    {" --set 'Gear pair/Pinion/crowning_um=20'", "crowning"},
    {" --set Mesh/teeth_per_sector=2", "teeth_per_sector"},
  };
  for (const auto &c : cases)
    {
      const fs::path out = fresh_temp_dir("stiffness_bad");
      const auto     r   = run_hertzgear("stiffness " + scene_path("paper_uncrowned.prm") + coarse +
                                   c.set + " --out " + out.string());
      EXPECT_EQ(r.exit_code, 2) << c.set << "\n" << r.err;
      EXPECT_THAT(r.err, HasSubstr(c.expected)) << c.set;
      EXPECT_FALSE(fs::exists(out / "stiffness.csv")) << c.set;
    }
}

TEST(StiffnessCli, AContactSolveThatDoesNotConvergeExitsThree)
{
  // Requirement: a contact solve that reaches its iteration cap is a numerical failure (exit 3)
  // with a diagnostic, and leaves no stiffness table behind. One active-set iteration cannot
  // settle the contact of a tooth pair, whose initial guess (all cells active) is wrong.
  const fs::path out = fresh_temp_dir("stiffness_no_convergence");
  const auto     r   = run_hertzgear("stiffness " + scene_path("paper_uncrowned.prm") + coarse +
                               " --set Stiffness/contact_max_iterations=1 --out " + out.string());
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_THAT(r.err, HasSubstr("numerical failure"));
  EXPECT_FALSE(fs::exists(out / "stiffness.csv"));
  EXPECT_FALSE(fs::exists(out / "stiffness.json"));
}
