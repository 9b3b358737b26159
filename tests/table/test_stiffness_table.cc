// Requirements on the stiffness table, the contract between the stiffness stage and the dynamics.
#include "table/stiffness_table.h"

#include "common/errors.h"

#include <gtest/gtest.h>

#include <string>

using namespace hertzgear::table;

// Requirement: the stiffness table survives a JSON round trip, and a table given only as samples
// is fitted on reading. Exact equality for the round trip: JSON writes doubles with 17 digits.
TEST(StiffnessTable, JsonRoundTripAndSampledTables)
{
  StiffnessTable t;
  t.hertz_exponent        = 1.5;
  t.k_rest_N_per_m        = {2.79e8, {}, {}};
  t.k_hertz_N_per_m_pow_n = {5.095e10, {2.045e10}, {0.5}};
  t.unloaded_ste_m        = {0.0, {1e-6}, {0.0}};
  t.has_unloaded_ste      = true;
  const StiffnessTable back = stiffness_table_from_json_text(stiffness_table_to_json_text(t));
  EXPECT_EQ(back.hertz_exponent, t.hertz_exponent);
  EXPECT_EQ(back.k_hertz_N_per_m_pow_n.amplitudes, t.k_hertz_N_per_m_pow_n.amplitudes);
  EXPECT_EQ(back.k_hertz_N_per_m_pow_n.phases_rad, t.k_hertz_N_per_m_pow_n.phases_rad);
  EXPECT_TRUE(back.has_unloaded_ste);

  const std::string sampled = R"({"hertz_exponent": 1.0, "k_rest_N_per_m": {"mean": 4.17e8},
    "samples": {"mesh_phase": [0, 0.2, 0.4, 0.6, 0.8],
                "k_hertz_N_per_m_pow_n": [2e9, 1e9, 1e9, 1e9, 1e9]}})";
  const StiffnessTable s = stiffness_table_from_json_text(sampled);
  EXPECT_NEAR(s.k_hertz_N_per_m_pow_n.mean, 1.2e9, 1e-3);
  EXPECT_EQ(s.k_hertz_N_per_m_pow_n.n_harmonics(), 2u);

  // Bad tables fail with InputError naming the problem.
  EXPECT_THROW(stiffness_table_from_json_text(R"({"hertz_exponent": 3})"), hertzgear::InputError);
  EXPECT_THROW(stiffness_table_from_json_text("{not json"), hertzgear::InputError);
}

// Requirement: a table's load ladder survives the JSON round trip exactly (17 digits), and a
// ladder whose approach does not grow with the load is refused on reading, naming the position,
// its mesh phase and both loads.
TEST(StiffnessTable, LoadLadderRoundTripAndRefusal)
{
  StiffnessTable t;
  t.hertz_exponent          = 1.5;
  t.k_rest_N_per_m          = {2.79e8, {}, {}};
  t.k_hertz_N_per_m_pow_n   = {5.095e10, {}, {}};
  t.ladder.nominal_load_N   = 1000.0;
  t.ladder.load_N           = {100.0, 1000.0, 4000.0};
  t.ladder.approach_m       = {{1e-6, 1.1e-6}, {6e-6, 6.5e-6}, {2e-5, 2.2e-5}};
  t.ladder.hertz_approach_m = {{0.5e-6, 0.6e-6}, {2e-6, 2.5e-6}, {5e-6, 5.5e-6}};
  const std::string    text = stiffness_table_to_json_text(t);
  const StiffnessTable back = stiffness_table_from_json_text(text);
  EXPECT_EQ(back.ladder.nominal_load_N, t.ladder.nominal_load_N);
  EXPECT_EQ(back.ladder.load_N, t.ladder.load_N);
  EXPECT_EQ(back.ladder.approach_m, t.ladder.approach_m);
  EXPECT_EQ(back.ladder.hertz_approach_m, t.ladder.hertz_approach_m);

  StiffnessTable bad    = t;
  bad.ladder.approach_m[2][1] = 6.4e-6;
  try
    {
      stiffness_table_from_json_text(stiffness_table_to_json_text(bad), "M/stiffness.json");
      ADD_FAILURE() << "a ladder whose approach shrinks was accepted";
    }
  catch (const hertzgear::InputError &e)
    {
      const std::string m = e.what();
      EXPECT_NE(m.find("M/stiffness.json"), std::string::npos) << m;
      EXPECT_NE(m.find("position 1 (mesh phase 0.5) at 4000 N"), std::string::npos) << m;
      EXPECT_NE(m.find("at 1000 N"), std::string::npos) << m;
    }
}
