// Requirement: `hertzgear geometry SCENE --json` prints one JSON object with the keys of the
// command-line contract (lengths in mm), and the bundled paper scenes reproduce the paper's
// contact ratio 1.559 (Table 1) with its backlash 0.1172 mm. The helical keys are there for a spur
// pair too, with helix angles 0, overlap ratio 0 and total contact ratio = eps_alpha exactly.
#include "tests/support/run_command.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

using namespace hertzgear::testing;

TEST(GeometryCommand, JsonHasTheContractKeys)
{
  const auto r = run_hertzgear("geometry --json " + scene_path("paper_crowned.prm"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char *key : {"contact_ratio", "center_distance_mm", "operating_pressure_angle_deg",
                          "base_pitch_mm", "path_of_contact_mm", "backlash_loa_mm"})
    EXPECT_TRUE(j.at(key).is_number()) << key;
  for (const char *body : {"pinion", "gear"})
    {
      for (const char *key : {"base_radius_mm", "tip_radius_mm", "root_radius_mm"})
        EXPECT_TRUE(j.at(body).at(key).is_number()) << body << "/" << key;
      // Crowned: b^2 / (8 beta) = 400 / 0.64 = 625 mm.
      EXPECT_NEAR(j.at(body).at("crowning_radius_mm").get<double>(), 625.0, 1e-9);
    }
  for (const char *p : {"A", "B", "C", "D", "E"})
    for (const char *key : {"roll_distance_mm", "rho_pinion_mm", "rho_gear_mm"})
      EXPECT_TRUE(j.at("points").at(p).at(key).is_number()) << p << "/" << key;
  for (const char *key : {"c_prime_th_N_per_mm_um", "c_prime_N_per_mm_um", "c_gamma_alpha_N_per_mm_um"})
    EXPECT_TRUE(j.at("iso6336").at(key).is_number()) << key;
  // The paper: 1.559 (three decimals printed) and 0.1172 mm.
  EXPECT_NEAR(j.at("contact_ratio").get<double>(), 1.559, 5e-4);
  EXPECT_NEAR(j.at("backlash_loa_mm").get<double>(), 0.1172, 1e-12);
  EXPECT_EQ(j.at("helix_angle_deg").get<double>(), 0.0);
  EXPECT_EQ(j.at("base_helix_angle_deg").get<double>(), 0.0);
  EXPECT_EQ(j.at("face_contact_ratio").get<double>(), 0.0);
  EXPECT_EQ(j.at("total_contact_ratio").get<double>(), j.at("contact_ratio").get<double>());
}

TEST(GeometryCommand, UncrownedHasNullCrowningRadius)
{
  const auto r = run_hertzgear("geometry --json " + scene_path("paper_uncrowned.prm"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j.at("pinion").at("crowning_radius_mm").is_null());
  EXPECT_TRUE(j.at("gear").at("crowning_radius_mm").is_null());
  EXPECT_NEAR(j.at("contact_ratio").get<double>(), 1.559, 5e-4);
}
