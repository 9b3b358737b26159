// Requirement: `hertzgear geometry SCENE --json` prints one JSON object with the keys of the
// command-line contract (lengths in mm), and the bundled paper scenes reproduce the paper's
// contact ratio 1.559 (Table 1) with its backlash 0.1172 mm. The helical keys are there for a spur
// pair too, with helix angles 0, overlap ratio 0 and total contact ratio = eps_alpha exactly. The
// bundled helical scene (data/scenes/paper_helical.prm) runs `geometry`, whose JSON and summary give
// beta, beta_b, eps_alpha, eps_beta and eps_gamma of the ISO 21771 closed forms.
#include "tests/support/run_command.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <regex>

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

TEST(GeometryCommand, HelicalSceneGivesTheClosedFormsOfIso21771)
{
  // The scene's values: the paper's pair at beta = 15 deg, its addendum h_a = 0.945667 m_n, no
  // profile shift (so alpha_wt = alpha_t and a_w = r_1 + r_2; the backlash thins the teeth).
  const double pi = 3.14159265358979323846, beta = 15 * pi / 180, alpha_n = 20 * pi / 180;
  const double m_n = 3, b = 20, h_a = 0.945667 * m_n, z1 = 23, z2 = 34;
  const double alpha_t = std::atan(std::tan(alpha_n) / std::cos(beta)), m_t = m_n / std::cos(beta);
  const double r1 = m_t * z1 / 2, r2 = m_t * z2 / 2;
  const double rb1 = r1 * std::cos(alpha_t), rb2 = r2 * std::cos(alpha_t);
  const double g_alpha = std::sqrt(std::pow(r1 + h_a, 2) - rb1 * rb1) +
                         std::sqrt(std::pow(r2 + h_a, 2) - rb2 * rb2) - (r1 + r2) * std::sin(alpha_t);
  const double eps_alpha = g_alpha / (pi * m_t * std::cos(alpha_t));
  const double eps_beta  = b * std::sin(beta) / (pi * m_n);
  const double beta_b_deg = std::asin(std::sin(beta) * std::cos(alpha_n)) * 180 / pi;

  const auto r = run_hertzgear("geometry --json " + scene_path("paper_helical.prm"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  // 1e-12 relative: the code evaluates the same closed forms in another order (a few roundings of
  // 1e-16 each, amplified at most ~10 times by the cancellation in g_alpha, 13.6 of terms near 50).
  const auto expect_close = [](const double value, const double closed_form, const char *what) {
    EXPECT_NEAR(value, closed_form, 1e-12 * std::abs(closed_form)) << what;
  };
  expect_close(j.at("helix_angle_deg").get<double>(), 15.0, "beta");
  expect_close(j.at("base_helix_angle_deg").get<double>(), beta_b_deg, "beta_b");
  expect_close(j.at("contact_ratio").get<double>(), eps_alpha, "eps_alpha");
  expect_close(j.at("face_contact_ratio").get<double>(), eps_beta, "eps_beta");
  expect_close(j.at("total_contact_ratio").get<double>(), eps_alpha + eps_beta, "eps_gamma");

  // The summary prints the same numbers with 4 decimals: each within half a unit of its last digit.
  const auto summary = run_hertzgear("geometry " + scene_path("paper_helical.prm"));
  ASSERT_EQ(summary.exit_code, 0) << summary.err;
  EXPECT_NE(summary.out.find("helical pair geometry"), std::string::npos) << summary.out;
  const std::pair<const char *, double> lines[] = {{"helix angle beta", 15.0},
                                                   {"base helix angle beta_b", beta_b_deg},
                                                   {"contact ratio eps_alpha", eps_alpha},
                                                   {"overlap ratio eps_beta", eps_beta},
                                                   {"total ratio eps_gamma", eps_alpha + eps_beta}};
  for (const auto &[label, closed_form] : lines)
    {
      std::smatch m;
      ASSERT_TRUE(std::regex_search(summary.out, m, std::regex(std::string(label) + R"(\s+([0-9.]+))")))
        << label << " missing from\n" << summary.out;
      EXPECT_NEAR(std::stod(m[1]), closed_form, 0.5e-4 + 1e-12) << label;
    }
  // ISO 6336-1 for the helical pair beside them (the values themselves: Iso6336.HelicalPaperPairByHand).
  EXPECT_TRUE(j.at("iso6336").at("c_gamma_beta_N_per_mm_um").is_number());
  EXPECT_NE(summary.out.find("c_gamma_beta"), std::string::npos) << summary.out;
}
