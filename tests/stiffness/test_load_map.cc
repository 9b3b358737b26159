// Requirements on the cases of the load and design map (stiffness/load_map.h): their order and
// values, and the refusal of a map the contact analysis cannot run, before any work.
#include "common/errors.h"
#include "stiffness/load_map.h"
#include "tests/stiffness/stiffness_fixtures.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

using namespace hertzgear;
using namespace hertzgear::stiffness;
using ::testing::HasSubstr;

TEST(LoadMap, TorquesRunWithEveryCrowningThenMisalignmentsAtTheScenesTorque)
{
  // Requirement: every torque with every crowning variant (crowning outer, so that a crowning's
  // STE-against-torque curve is contiguous), then every misalignment at 100 % with every
  // crowning; a crowning variant crowns both gears, and without one each keeps its own.
  auto in                = test_pairs::paper_pair(0.080);
  in.fe.dimension        = 3;
  in.torque_map_percent  = {50, 200};
  in.crowning_map_mm     = {0.0, 0.020};
  in.misalignment_map_mm = {-0.010};
  const auto cases       = map_cases(in);
  ASSERT_EQ(cases.size(), 6u);
  const double expected[6][3] = {{105, 0, 0}, {420, 0, 0}, {105, 0.020, 0}, {420, 0.020, 0},
                                 {210, 0, -0.010}, {210, 0.020, -0.010}};
  for (std::size_t c = 0; c < cases.size(); ++c)
    {
      EXPECT_DOUBLE_EQ(cases[c].torque_Nm, expected[c][0]) << c;
      EXPECT_DOUBLE_EQ(cases[c].pinion_crowning_mm, expected[c][1]) << c;
      EXPECT_DOUBLE_EQ(cases[c].gear_crowning_mm, expected[c][1]) << c;
      EXPECT_DOUBLE_EQ(cases[c].mesh_misalignment_mm, expected[c][2]) << c;
      const auto pair = map_case_pair(in, cases[c]);
      EXPECT_DOUBLE_EQ(pair.gear.crowning_mm, expected[c][1]) << c;
      EXPECT_DOUBLE_EQ(pair.mesh_misalignment_mm, expected[c][2]) << c;
    }
  in.crowning_map_mm.clear();
  in.misalignment_map_mm.clear();
  for (const auto &c : map_cases(in))
    EXPECT_DOUBLE_EQ(c.pinion_crowning_mm, 0.080);
  EXPECT_TRUE(map_cases(test_pairs::paper_pair()).empty());
}

TEST(LoadMap, HelixSlopeVariantsAreThePinionsAtTheScenesTorque)
{
  // Requirement: each helix slope variant f_Hb replaces the pinion's own at the scene's torque
  // and misalignment, with every crowning, after the torques; the gear keeps its own f_Hb.
  auto in                               = test_pairs::paper_pair(0.080);
  in.fe.dimension                       = 3;
  in.pair.gear.helix_slope_deviation_mm = 0.003;
  in.pair.mesh_misalignment_mm          = 0.004;
  in.torque_map_percent                 = {50};
  in.helix_slope_map_mm                 = {-0.010, 0.010};
  const auto cases                      = map_cases(in);
  ASSERT_EQ(cases.size(), 3u);
  EXPECT_DOUBLE_EQ(cases[0].pinion_helix_slope_deviation_mm, 0.0);
  for (std::size_t c = 1; c < 3; ++c)
    {
      EXPECT_DOUBLE_EQ(cases[c].torque_percent, 100.0) << c;
      EXPECT_DOUBLE_EQ(cases[c].pinion_crowning_mm, 0.080) << c;
      EXPECT_DOUBLE_EQ(cases[c].mesh_misalignment_mm, 0.004) << c;
      EXPECT_DOUBLE_EQ(cases[c].pinion_helix_slope_deviation_mm, c == 1 ? -0.010 : 0.010) << c;
      const auto pair = map_case_pair(in, cases[c]);
      EXPECT_DOUBLE_EQ(pair.pinion.helix_slope_deviation_mm, c == 1 ? -0.010 : 0.010) << c;
      EXPECT_DOUBLE_EQ(pair.gear.helix_slope_deviation_mm, 0.003) << c;
    }
}

TEST(LoadMap, AProductMapRunsEveryCombinationWithTorqueInnermost)
{
  // Requirement of a tolerance study (map_product): every crowning x f_Hb x misalignment x
  // torque, nested in that order so that each design's torque curve is contiguous; an empty axis
  // is the pair's own value, and no torque list is the scene's torque.
  auto in                 = test_pairs::paper_pair(0.080);
  in.fe.dimension         = 3;
  in.map_product          = true;
  in.torque_map_percent   = {50, 100, 200};
  in.crowning_map_mm      = {0.040, 0.080};
  in.misalignment_map_mm  = {-0.010, 0.0, 0.010};
  in.helix_slope_map_mm   = {-0.008, 0.008};
  const auto cases        = map_cases(in);
  ASSERT_EQ(cases.size(), 2u * 2u * 3u * 3u);
  std::size_t c = 0;
  for (const double crowning : in.crowning_map_mm)
    for (const double slope : in.helix_slope_map_mm)
      for (const double misalignment : in.misalignment_map_mm)
        for (const double percent : in.torque_map_percent)
          {
            EXPECT_DOUBLE_EQ(cases[c].gear_crowning_mm, crowning) << c;
            EXPECT_DOUBLE_EQ(cases[c].pinion_helix_slope_deviation_mm, slope) << c;
            EXPECT_DOUBLE_EQ(cases[c].mesh_misalignment_mm, misalignment) << c;
            EXPECT_DOUBLE_EQ(cases[c].torque_Nm, 210.0 * percent / 100.0) << c;
            ++c;
          }
  in.torque_map_percent.clear();
  in.crowning_map_mm.clear();
  in.helix_slope_map_mm.clear();
  const auto by_misalignment = map_cases(in);
  ASSERT_EQ(by_misalignment.size(), 3u);
  for (const auto &m : by_misalignment)
    {
      EXPECT_DOUBLE_EQ(m.torque_percent, 100.0);
      EXPECT_DOUBLE_EQ(m.pinion_crowning_mm, 0.080);
      EXPECT_DOUBLE_EQ(m.pinion_helix_slope_deviation_mm, 0.0);
    }
}

TEST(LoadMap, AMapItCannotRunIsRefusedNamingItsField)
{
  // Requirement: a non-positive torque, a variant along the face in 2D, and a variant the pair
  // cannot take are ParameterErrors naming the map's field.
  const auto refused = [](const StiffnessInput &in) -> std::string {
    try
      {
        check_map(in);
      }
    catch (const ParameterError &e)
      {
        return e.parameter() + ": " + e.text();
      }
    return "";
  };
  auto in               = test_pairs::paper_pair();
  in.fe.dimension       = 3;
  in.torque_map_percent = {100, 0};
  EXPECT_THAT(refused(in), HasSubstr("torque_map_percent: 0: every torque of the map must be positive"));
  in.torque_map_percent  = {100};
  in.misalignment_map_mm = {0.2}; // above the 117 um backlash
  EXPECT_THAT(refused(in), HasSubstr("misalignment_map_mm: 200 um: shaft misalignment"));
  in.misalignment_map_mm = {};
  in.crowning_map_mm     = {0.9}; // leaves no top land
  EXPECT_THAT(refused(in), HasSubstr("crowning_map_mm: 900 um"));
  in.crowning_map_mm    = {};
  in.helix_slope_map_mm = {0.010, 1.8}; // 900 um removed at a face end: no top land either
  EXPECT_THAT(refused(in), HasSubstr("helix_slope_map_mm: 1800 um"));
  in.map_product     = true; // in a product too, the axis that breaks the pair alone is named
  in.crowning_map_mm = {0.0, 0.010}; // even where a crowning variant comes first
  EXPECT_THAT(refused(in), HasSubstr("helix_slope_map_mm: 1800 um"));
  // Values the pair takes alone but not together name the combination: 600 um of crowning and
  // 2 x 300 um of slope remove 900 um at a face end, as the 900 um crowning above.
  in.crowning_map_mm    = {0.0, 0.6};
  in.helix_slope_map_mm = {0.0, 0.6};
  EXPECT_THAT(refused(in), HasSubstr("map_combination: product: crowning 600 um with misalignment 0 "
                                     "um and helix slope deviation 600 um, each of which the pair "
                                     "takes alone, together:"));
  in.crowning_map_mm    = {};
  in.map_product        = false;
  in.helix_slope_map_mm = {};
  in.fe.dimension = 2;
  in.crowning_map_mm = {0.01};
  EXPECT_THAT(refused(in), HasSubstr("crowning_map_mm: 10 um: a lead crowning varies along the face"));
  in.crowning_map_mm    = {};
  in.helix_slope_map_mm = {0.01};
  EXPECT_THAT(refused(in), HasSubstr("helix_slope_map_mm: 10 um: a helix slope deviation varies along the face"));
  EXPECT_THAT(refused(in), HasSubstr("needs {dimension} = 3"));
  in.helix_slope_map_mm = {};
  EXPECT_EQ(refused(in), "");
}
