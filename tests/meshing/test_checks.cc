// Requirement: every geometry check stops an impossible pair with exit code 2 and a message
// that names the problem and the scene key to change, through `hertzgear check` and
// `hertzgear geometry`; valid scenes pass.
#include "tests/support/run_command.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

using namespace hertzgear::testing;
using ::testing::HasSubstr;

namespace
{
  struct Case
  {
    std::string name, overrides, message, key;
  };

  std::string set(const std::string &key, const std::string &value)
  {
    return " --set '" + key + "=" + value + "'";
  }
} // namespace

TEST(GeometryChecks, EachImpossiblePairExitsTwoWithItsMessage)
{
  const std::string P = "Gear pair/Pinion/", G = "Gear pair/Gear/";
  const std::vector<Case> cases = {
    // 14 teeth without profile shift: z < z_min = 17.1 for the ISO 53 rack.
    {"undercut", set(P + "teeth", "14"), "undercut", P + "teeth"},
    // A tip radius where both involutes of the tooth have crossed.
    {"pointed tip", set(P + "tip_radius_mm", "39.5"), "pointed tip", P + "tip_radius_mm"},
    // Gear tip radius r + 1.24 m: its tip reaches below the pinion's form circle (the rack's
    // straight flank generates the involute down to 1.0 m below the datum line only).
    {"interference", set(G + "tip_radius_mm", "54.72"), "involute interference", G + "tip_radius_mm"},
    // Addenda of 0.5 m leave a path of contact shorter than the base pitch.
    {"contact ratio", set(P + "tip_radius_mm", "36") + set(G + "tip_radius_mm", "52.5"), "below 1",
     G + "tip_radius_mm"},
    // 1 mm of crowning removes more than the top land (3D, so that the scene allows crowning).
    {"crowning", set(P + "crowning_um", "1000") + set("Stiffness/fe_dimension", "3"),
     "crowning 1000 um and tip relief 0 um are larger than the geometry allows", P + "crowning_um"},
    // A relief longer than the involute.
    {"tip relief", set(P + "tip_relief_um", "10") + set(P + "tip_relief_length_mm", "20"),
     "tip relief length 20 mm is larger than the geometry allows", P + "tip_relief_length_mm"},
    // A 0.5 mm face width for a 3 mm module.
    {"absurd", set(P + "face_width_mm", "0.5"), "absurd dimensions", P + "face_width_mm"},
    // Closer than the tight-mesh distance 85.5 mm.
    {"jamming", set("Operating/center_distance_mm", "85.2") + set("Operating/backlash_mm", "0"),
     "jams the pair", "Operating/center_distance_mm"},
  };
  // Every case through `check`; `geometry` runs the same checks (one case is enough to show it).
  for (const auto &c : cases)
    for (const std::string &command : c.name == "undercut" ? std::vector<std::string>{"check", "geometry"}
                                                           : std::vector<std::string>{"check"})
      {
        const auto r = run_hertzgear(command + " " + scene_path("paper_uncrowned.prm") + c.overrides);
        EXPECT_EQ(r.exit_code, 2) << c.name << " (" << command << ")\n" << r.err;
        EXPECT_THAT(r.err, HasSubstr(c.message)) << c.name << " (" << command << ")";
        EXPECT_THAT(r.err, HasSubstr(c.key)) << c.name << " (" << command << ")\n" << r.err;
      }
}

TEST(GeometryChecks, PaperScenesPass)
{
  for (const char *name : {"paper_uncrowned.prm", "paper_crowned.prm"})
    {
      const auto r = run_hertzgear("geometry " + scene_path(name));
      EXPECT_EQ(r.exit_code, 0) << r.err;
    }
}
