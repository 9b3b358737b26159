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
