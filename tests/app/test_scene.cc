// Requirements on scene files: the paper's scenes carry Tables 1 and 2; overrides apply in order;
// the printed defaults parse back to the same values; bad input names file, line and key.
#include "app/dynamics_setup.h"
#include "app/meshing_setup.h"
#include "app/scene.h"
#include "common/errors.h"
#include "meshing/pair_kinematics.h"
#include "stiffness/iso6336.h"

#include "tests/support/run_command.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

using namespace hertzgear;
using hertzgear::testing::fresh_temp_dir;
using hertzgear::testing::scene_path;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

namespace
{
  fs::path write_scene(const std::string &name, const std::string &text)
  {
    const fs::path dir = fs::temp_directory_path() / "hertzgear_test_scenes";
    fs::create_directories(dir);
    std::ofstream(dir / name) << text;
    return dir / name;
  }

  std::string input_error_of(const fs::path &file, const std::vector<std::string> &overrides = {})
  {
    try
      {
        load_scene(file, overrides);
      }
    catch (const InputError &e)
      {
        return e.what();
      }
    return "(no error)";
  }
} // namespace

TEST(Scene, PaperCrownedCarriesTables1And2)
{
  const Scene s = load_scene(scene_path("paper_crowned.prm"));
  EXPECT_EQ(s.pinion.teeth, 23);
  EXPECT_EQ(s.gear.teeth, 34);
  for (const GearScene *g : {&s.pinion, &s.gear})
    {
      EXPECT_DOUBLE_EQ(g->module_mm, 3.0);
      EXPECT_DOUBLE_EQ(g->pressure_angle_deg, 20.0);
      EXPECT_DOUBLE_EQ(g->face_width_mm, 20.0);
      EXPECT_DOUBLE_EQ(g->crowning_um, 80.0);
    }
  for (const Material *m : {&s.pinion_material, &s.gear_material})
    {
      EXPECT_DOUBLE_EQ(m->youngs_modulus_MPa, 206000.0);
      EXPECT_DOUBLE_EQ(m->poisson_ratio, 0.3);
      EXPECT_DOUBLE_EQ(m->density_kg_per_m3, 7850.0);
    }
  EXPECT_DOUBLE_EQ(s.operating.backlash_mm, 0.1172);
  EXPECT_DOUBLE_EQ(s.operating.torque_Nm, 210.0);
  EXPECT_DOUBLE_EQ(s.operating.speed_rpm, 150.0);
  EXPECT_DOUBLE_EQ(s.dynamics.damping_ratio, 0.015);
  EXPECT_DOUBLE_EQ(s.dynamics.alpha_s_per_m, 0.26);
  EXPECT_EQ(s.dynamics.periods, 800);
  EXPECT_EQ(s.stiffness.positions_per_cycle, 9);
  EXPECT_DOUBLE_EQ(s.stiffness.hertz_exponent, 1.5);
  EXPECT_EQ(s.hash.size(), 16u);
}

TEST(Scene, PaperUncrownedDiffersOnlyWhereTable2Does)
{
  const Scene u = load_scene(scene_path("paper_uncrowned.prm"));
  const Scene c = load_scene(scene_path("paper_crowned.prm"));
  EXPECT_DOUBLE_EQ(u.pinion.crowning_um, 0.0);
  EXPECT_DOUBLE_EQ(u.gear.crowning_um, 0.0);
  EXPECT_DOUBLE_EQ(u.stiffness.hertz_exponent, 1.0);
  EXPECT_NE(u.hash, c.hash);
  // Dynamics-relevant values other than Table 2 are the same.
  EXPECT_EQ(scene_values_for(u, {"Operating", "Material", "Dynamics"}),
            scene_values_for(c, {"Operating", "Material", "Dynamics"}));
}

TEST(Scene, OverridesApplyInOrderAndChangeTheHash)
{
  const Scene base = load_scene(scene_path("paper_crowned.prm"));
  const Scene s    = load_scene(scene_path("paper_crowned.prm"),
                             {"Operating/speed_rpm=1000", "Gear pair/Pinion/crowning_um = 40",
                              "Operating/speed_rpm=2000"});
  EXPECT_DOUBLE_EQ(s.operating.speed_rpm, 2000.0);
  EXPECT_DOUBLE_EQ(s.pinion.crowning_um, 40.0);
  EXPECT_DOUBLE_EQ(s.gear.crowning_um, 80.0);
  EXPECT_NE(s.hash, base.hash);
  EXPECT_THAT(s.used_parameters_prm, HasSubstr("2000"));
}

// Requirement: the helix keys are per gear (ISO 21771) and converted to the meshing stage's
// radians and hands; a spur gear's helix keys (helix angle 0) and the tolerance study's map keys at
// their defaults stay out of the scene hash, so a spur scene keeps the hash it had before those
// keys existed (run.json and the stiffness tables record
// it): ee57e12182fca8d8 for paper_uncrowned.prm with the contact grid's face extent of that time
// (face-width; with the default, load, every scene hashes differently, as a changed default
// must), whatever hand or spelling of 0 it gives; a helical scene has its own hash.
TEST(Scene, HelixKeysConvertAndLeaveTheSpurHashAsItWas)
{
  const Scene helical = load_scene(scene_path("paper_helical.prm"));
  EXPECT_DOUBLE_EQ(helical.pinion.helix_angle_deg, 15.0);
  EXPECT_EQ(helical.pinion.hand, "right");
  EXPECT_EQ(helical.gear.hand, "left");
  const auto pair = pair_parameters(helical);
  EXPECT_EQ(pair.pinion.helix_angle_rad, 15.0 * M_PI / 180);
  EXPECT_EQ(pair.gear.helix_angle_rad, 15.0 * M_PI / 180);
  EXPECT_EQ(pair.pinion.hand, meshing::HelixHand::right);
  EXPECT_EQ(pair.gear.hand, meshing::HelixHand::left);

  const std::string then = "Stiffness/contact_grid_face_extent=face-width";
  EXPECT_EQ(load_scene(scene_path("paper_uncrowned.prm"), {then}).hash, "ee57e12182fca8d8")
    << "the hash of paper_uncrowned.prm before the helix keys";
  EXPECT_EQ(load_scene(scene_path("paper_uncrowned.prm"), {then, "Gear pair/Pinion/hand=left"}).hash,
            "ee57e12182fca8d8");
  const Scene spur = load_scene(scene_path("paper_uncrowned.prm"));
  EXPECT_EQ(pair_parameters(spur).pinion.helix_angle_rad, 0.0);
  const Scene spelled = load_scene(scene_path("paper_uncrowned.prm"),
                                   {"Gear pair/Pinion/hand=left", "Gear pair/Gear/helix_angle_deg=0.0"});
  EXPECT_EQ(spelled.hash, spur.hash);
  EXPECT_NE(helical.hash, spur.hash);
  // The tolerance study's keys at their defaults stay out of the hash too; set, they count.
  EXPECT_EQ(load_scene(scene_path("paper_uncrowned.prm"), {"Stiffness/Map/combination=separate"}).hash,
            spur.hash);
  EXPECT_NE(load_scene(scene_path("paper_uncrowned.prm"), {"Stiffness/Map/combination=product"}).hash,
            spur.hash);
  EXPECT_NE(load_scene(scene_path("paper_uncrowned.prm"),
                       {"Stiffness/Map/helix_slope_deviation_um=5"}).hash,
            spur.hash);
  // The resolved parameters list the keys all the same (what a run used).
  EXPECT_THAT(spur.used_parameters_prm, HasSubstr("set helix_angle_deg"));
}

// Requirement: a scene whose stiffness comes from the FE uses the FE force law by default
// (Effects/mesh_force_law = auto): the stiffness stage then makes the load ladder, and the dynamics
// on a table that holds one take fe-map; without the Hertzian layer (the law's second member),
// on Fourier coefficients, or where the paper's scenes ask for the paper's law, serial-hertz.
TEST(Scene, ForceLawAutoIsTheFeLawWhereTheStiffnessComesFromTheFe)
{
  using dynamics::MeshForceLawKind;
  EXPECT_EQ(load_scene("").effects.mesh_force_law, "auto");
  EXPECT_TRUE(makes_load_ladder(load_scene("")));
  EXPECT_FALSE(makes_load_ladder(load_scene(scene_path("paper_crowned.prm"))));
  const std::string as_auto = "Effects/mesh_force_law=auto";
  EXPECT_TRUE(makes_load_ladder(load_scene(scene_path("paper_crowned.prm"), {as_auto})));
  EXPECT_FALSE(makes_load_ladder(
    load_scene(scene_path("paper_crowned.prm"), {as_auto, "Effects/hertzian_layer=off"})));
  EXPECT_TRUE(makes_load_ladder(
    load_scene(scene_path("paper_crowned.prm"), {"Effects/mesh_force_law=fe-map"})));

  const auto law_of = [](const std::string &scene, std::vector<std::string> overrides) {
    return make_dynamics_setup(load_scene(scene_path(scene), overrides)).parameters.effects
      .mesh_force_law;
  };
  // The shipped tables hold their load ladder.
  EXPECT_EQ(law_of("paper_crowned_table.prm", {}), MeshForceLawKind::serial_hertz);
  EXPECT_EQ(law_of("paper_crowned_table.prm", {as_auto}), MeshForceLawKind::fe_map);
  EXPECT_EQ(law_of("paper_crowned_table.prm", {as_auto, "Effects/hertzian_layer=quasi-static"}),
            MeshForceLawKind::fe_map);
  EXPECT_EQ(law_of("paper_crowned_table.prm", {as_auto, "Effects/hertzian_layer=off"}),
            MeshForceLawKind::serial_hertz);
  EXPECT_EQ(law_of("paper_crowned_fourier.prm", {as_auto}), MeshForceLawKind::serial_hertz);
}

TEST(Scene, PrintedDefaultsParseBackToTheSameValues)
{
  const fs::path file     = write_scene("defaults.prm", default_scene_prm());
  const Scene    parsed   = load_scene(file);
  const Scene    defaults = load_scene("");
  EXPECT_EQ(parsed.hash, defaults.hash);
  EXPECT_EQ(parsed.used_parameters_prm, defaults.used_parameters_prm);
  // And the used parameters of a non-default scene parse back to the same scene.
  const Scene    paper = load_scene(scene_path("paper_crowned.prm"), {"Sweep/points=7"});
  const fs::path again = write_scene("used.prm", paper.used_parameters_prm);
  EXPECT_EQ(load_scene(again).hash, paper.hash);
}

TEST(Scene, JsonScenesAreAccepted)
{
  const fs::path file = write_scene("small.json", R"({
    "Gear pair": { "Pinion": { "teeth": "25" } },
    "Operating": { "speed_rpm": "1200" }
  })");
  const Scene s = load_scene(file);
  EXPECT_EQ(s.pinion.teeth, 25);
  EXPECT_DOUBLE_EQ(s.operating.speed_rpm, 1200.0);
  EXPECT_EQ(s.gear.teeth, 34);
}

TEST(SceneBadInput, MissingFileIsNamed)
{
  EXPECT_THAT(input_error_of("/nonexistent/scene.prm"),
              HasSubstr("/nonexistent/scene.prm does not exist"));
}

// A bad scene file: its message shall hold every one of `parts` (file, line, key, range, value).
struct BadSceneFile
{
  std::string              test;
  std::string              file;
  std::string              text;
  std::vector<std::string> parts;
};

class SceneBadFile : public ::testing::TestWithParam<BadSceneFile>
{};

TEST_P(SceneBadFile, MessageNamesWhatIsWrong)
{
  const auto       &c = GetParam();
  const std::string e = input_error_of(write_scene(c.file, c.text));
  for (const auto &part : c.parts)
    EXPECT_THAT(e, HasSubstr(part));
}

INSTANTIATE_TEST_SUITE_P(
  SceneBadInput, SceneBadFile,
  ::testing::Values(
    BadSceneFile{"UnknownKeyNamesFileLineAndKey", "unknown_key.prm",
                 "subsection Operating\n"
                 "  set torque_Nm = 100\n"
                 "  set torque_Nmm = 100\n"
                 "end\n",
                 {"unknown_key.prm", "3" /* line */, "torque_Nmm"}},
    BadSceneFile{"UnknownSectionIsNamed", "unknown_section.prm",
                 "subsection Operatingg\n"
                 "  set torque_Nm = 100\n"
                 "end\n",
                 {"unknown_section.prm", "Operatingg"}},
    BadSceneFile{"OutOfRangeValueNamesKeyAndRange", "range.prm",
                 "subsection Gear pair\n"
                 "  subsection Pinion\n"
                 "    set teeth = -3\n"
                 "  end\n"
                 "end\n",
                 {"range.prm", "teeth", "6...1000"}},
    BadSceneFile{"MalformedNumberIsNamed", "malformed.prm",
                 "subsection Operating\n"
                 "  set speed_rpm = 1.5.3\n"
                 "end\n",
                 {"speed_rpm", "1.5.3"}}),
  [](const ::testing::TestParamInfo<BadSceneFile> &info) { return info.param.test; });

TEST(SceneBadInput, BadOverridesAreNamed)
{
  EXPECT_THAT(input_error_of("", {"Gear pair/Pinion/teeth=-3"}),
              HasSubstr("Gear pair/Pinion/teeth is not allowed; allowed: [Integer range 6...1000"));
  EXPECT_THAT(input_error_of("", {"Operating/speed=3"}), HasSubstr("unknown key \"speed\""));
  EXPECT_THAT(input_error_of("", {"Operating/speed_rpm"}), HasSubstr("expected"));
  EXPECT_THAT(input_error_of("", {"speed_rpm=3"}), HasSubstr("must name its section"));
}

TEST(SceneBadInput, ImpossibleGearPairIsRejected)
{
  // Requirement: spur gears in mesh share module and pressure angle.
  EXPECT_THAT(input_error_of("", {"Gear pair/Gear/module_mm=4"}),
              HasSubstr("impossible gear pair"));
  EXPECT_THAT(input_error_of("", {"Gear pair/Gear/pressure_angle_deg=25"}),
              HasSubstr("pressure angle"));
  EXPECT_THAT(input_error_of("", {"Gear pair/Pinion/bore_radius_mm=40"}),
              HasSubstr("bore_radius_mm = 40 is not inside the root circle"));
}

TEST(SceneBadInput, CrossFieldChecksNameBothValues)
{
  EXPECT_THAT(input_error_of("", {"Stiffness/positions_per_cycle=8", "Stiffness/harmonics=4"}),
              HasSubstr("positions_per_cycle = 8 is too few"));
  EXPECT_THAT(input_error_of("", {"Dynamics/transient_periods=900"}),
              HasSubstr("transient_periods = 900"));
  EXPECT_THAT(input_error_of("", {"Stiffness/source=table"}), HasSubstr("table_file"));
  EXPECT_THAT(input_error_of("", {"Stiffness/fe_dimension=2",
                                  "Gear pair/Pinion/crowning_um=10"}),
              HasSubstr("crowning"));
}

// Requirement: the bundled scene of ISO/TR 6336-30 Example 1 (a published helical pair, its data in
// the scene's header) gives the example's published ISO 6336-1 values: F_t = 127 352.0 N,
// c'_th = 17.85584, c' = 12.37047, c_gamma_alpha = 17.46485 and c_gamma_beta = 14.84512
// N/(mm um) (as reproduced in the open ISO 6336 implementation gfsReboucas/Drivetrain,
// MATISO_6336.m, example_01, which checks against the report's Annex A). Tolerance: half a unit
// in the last printed digit, the published values' own rounding. This checks the scene's reading
// of the example (helix, shift, basic rack, tip diameters, centre distance) and hertzgear's
// ISO 6336-1 method B for a helical pair together: eps_alpha enters c_gamma_alpha, z_n and x1 c'_th.
// Also ISO 6336-2's nominal contact stress with its helical factors: Z_H = 2.39533, Z_eps = 0.803,
// sigma_H0 = 1206.58207 MPa, each to half a unit of its last printed digit.
TEST(Scene, TheIsoTrExampleGivesThePublishedIsoStiffness)
{
  const Scene                   scene = load_scene(scene_path("iso_tr_6336_30_example1.prm"));
  const meshing::PairKinematics pair(pair_parameters(scene));
  const auto                    iso = stiffness::iso6336_method_b(pair, scene.operating.torque_Nm);
  EXPECT_NEAR(iso.line_load_N_per_mm * 100.0, 127352.0, 0.5); // F_t over b = 100 mm, to the newton
  EXPECT_NEAR(iso.c_prime_th_N_per_mm_um, 17.85584, 5e-6);
  EXPECT_NEAR(iso.c_prime_N_per_mm_um, 12.37047, 5e-6);
  EXPECT_NEAR(iso.c_gamma_alpha_N_per_mm_um, 17.46485, 5e-6);
  EXPECT_NEAR(iso.c_gamma_beta_N_per_mm_um, 14.84512, 5e-6);
  EXPECT_TRUE(iso.within_validity);
  const auto sigma = stiffness::nominal_contact_stress(pair, scene.pinion_material, scene.gear_material,
                                                       scene.operating.torque_Nm);
  std::printf("Z_H %.6f Z_E %.4f Z_eps %.6f Z_beta %.6f sigma_H0 %.6f MPa\n", sigma.Z_H, sigma.Z_E,
              sigma.Z_eps, sigma.Z_beta, sigma.sigma_H0_MPa);
  EXPECT_NEAR(sigma.Z_H, 2.39533, 5e-6);
  EXPECT_NEAR(sigma.Z_eps, 0.803, 5e-4);
  EXPECT_NEAR(sigma.sigma_H0_MPa, 1206.58207, 5e-6);
}

// Requirement: a scene that gives the centre distance gives the dynamics the backlash that
// distance leaves (Operating/center_distance_mm's help): b_c is half the pair's backlash along the
// line of action, exactly as the geometry computes it; with center_distance_mm = 0 it is half of
// backlash_mm. The paper's pair 0.3 mm further apart than its tight mesh.
TEST(Scene, TheDynamicsTakeTheBacklashOfAGivenCentreDistance)
{
  const std::string fourier = scene_path("paper_uncrowned_fourier.prm");
  const Scene       tight   = load_scene(fourier);
  const double      a_tight = meshing::PairKinematics(pair_parameters(tight)).center_distance_mm();
  const Scene       apart   = load_scene(fourier, {"Operating/center_distance_mm=" + std::to_string(a_tight + 0.3),
                                                   "Operating/backlash_mm=0"});
  const double      j_bn    = meshing::PairKinematics(pair_parameters(apart)).backlash_loa_mm();
  EXPECT_GT(j_bn, 0.2);
  EXPECT_EQ(make_dynamics_setup(apart).parameters.half_backlash_m, 0.5e-3 * j_bn);
  EXPECT_EQ(make_dynamics_setup(tight).parameters.half_backlash_m, 0.5e-3 * tight.operating.backlash_mm);
}

// Requirement: every bundled scene passes `hertzgear check` (what `run` checks before it starts:
// geometry, stiffness input, dynamics, the load's plausibility), helical ones included.
TEST(Scene, EveryBundledSceneIsValid)
{
  int scenes = 0;
  for (const auto &entry : std::filesystem::directory_iterator(std::string(HERTZGEAR_SOURCE_DIR) + "/data/scenes"))
    if (entry.path().extension() == ".prm")
      {
        const auto r = hertzgear::testing::run_hertzgear("check '" + entry.path().string() + "'");
        EXPECT_EQ(r.exit_code, 0) << entry.path() << ": " << r.err;
        ++scenes;
      }
  EXPECT_GE(scenes, 9);
}
