// `hertzgear validate hertz`: artifacts of the coarse study and the failure modes of the command.
// The accuracy of the resolved FE contact is tested in tests/fem/test_resolved_contact.cc (unit)
// and tests/app/test_validate_hertz_long.cc (the full study, label long).
#include "../support/run_command.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

using namespace hertzgear::testing;
namespace fs = std::filesystem;

namespace
{
  std::vector<std::vector<std::string>> read_csv(const fs::path &file)
  {
    std::vector<std::vector<std::string>> rows;
    std::ifstream                         in(file);
    for (std::string line; std::getline(in, line);)
      {
        std::vector<std::string> cells;
        std::stringstream        ss(line);
        for (std::string c; std::getline(ss, c, ',');)
          cells.push_back(c);
        rows.push_back(cells);
      }
    return rows;
  }

  std::string validation_scene(const std::string &name)
  {
    return std::string(HERTZGEAR_SOURCE_DIR) + "/data/scenes/validation/" + name;
  }

  // A copy of a validation scene with one line replaced (or appended to a section).
  fs::path edited_scene(const std::string &name, const std::string &from, const std::string &to,
                        const fs::path &dir)
  {
    std::string text = slurp(validation_scene(name));
    const auto  at   = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    fs::create_directories(dir);
    const fs::path file = dir / name;
    std::ofstream(file) << text;
    return file;
  }
} // namespace

// Requirement: `validate hertz --coarse --out DIR` shall write hertz_validation.csv with the
// columns case, quantity, closed_form, fe, relative_error, level, dofs, wall_time_s and rows for
// every canonical case, the pressure profiles and the rates, and every case shall carry exactly
// its load (the load control is exact).
TEST(ValidateHertzCli, CoarseStudyWritesTheTable)
{
  const fs::path dir = fresh_temp_dir("validate_hertz_coarse");
  const auto     r   = run_hertzgear("validate hertz --coarse --out '" + dir.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = read_csv(dir / "hertz_validation.csv");
  ASSERT_GT(rows.size(), 1u);
  EXPECT_EQ(rows[0], (std::vector<std::string>{"case", "quantity", "closed_form", "fe",
                                                "relative_error", "level", "dofs",
                                                "wall_time_s"}));
  std::set<std::string> cases;
  for (std::size_t i = 1; i < rows.size(); ++i)
    {
      ASSERT_EQ(rows[i].size(), 8u);
      cases.insert(rows[i][0]);
      if (rows[i][1] == "total_force")
        {
          EXPECT_LT(std::abs(std::stod(rows[i][4])), 1e-9) << rows[i][0];
        }
    }
  EXPECT_EQ(cases, (std::set<std::string>{"crowned_flank", "cylinder_2d", "ellipsoid_1to20",
                                          "ellipsoid_1to5", "finite_cylinder",
                                          "finite_cylinder_raceway", "sphere"}));
  EXPECT_TRUE(fs::exists(dir / "pressure_profiles.csv"));
  EXPECT_TRUE(fs::exists(dir / "hertz_rates.csv"));
  EXPECT_TRUE(fs::exists(dir / "used_parameters.prm"));
  // One progress line per level on stderr.
  EXPECT_NE(r.err.find("sphere level 0:"), std::string::npos) << r.err;
}

// Requirement: an unknown key in a validation scene shall end with exit code 2, a message that
// names the key, and no output directory.
TEST(ValidateHertzCli, UnknownKeyIsBadInput)
{
  const fs::path dir   = fresh_temp_dir("validate_hertz_unknown_key");
  const fs::path scene = edited_scene("sphere.prm", "  set load_N             = 1000",
                                      "  set load_kN            = 1", dir / "scenes");
  const auto r = run_hertzgear("validate hertz '" + scene.string() + "' --out '" +
                               (dir / "out").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("load_kN"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

// Requirement: a value out of range shall end with exit code 2 and a message naming the key and
// the value.
TEST(ValidateHertzCli, OutOfRangeValueIsBadInput)
{
  const auto r = run_hertzgear("validate hertz --case sphere --set 'Body/poisson_ratio=0.7'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("poisson_ratio"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("0.7"), std::string::npos) << r.err;
  const auto u = run_hertzgear("validate hertz --case no_such_case");
  EXPECT_EQ(u.exit_code, 2) << u.err;
  EXPECT_NE(u.err.find("no_such_case"), std::string::npos) << u.err;
}

// Requirement: a load so high that the contact leaves the modelled surface shall end with exit
// code 3, a clear message, and no half-written artifact.
TEST(ValidateHertzCli, ContactLeavingTheBlockIsANumericalFailure)
{
  const fs::path dir = fresh_temp_dir("validate_hertz_overload");
  // 1e6 N/mm: Hertz b = 10.6 mm on the 10 mm half-block.
  const auto r = run_hertzgear("validate hertz --case cylinder_2d --coarse "
                               "--set 'Body/load_per_length_N_per_mm=1e6' --out '" +
                               dir.string() + "'");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("edge of the modelled surface"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "hertz_validation.csv"));
}

// Requirement: an active set that does not settle within Refinement/max_active_set_iterations
// shall end with exit code 3 and the history of the active set.
TEST(ValidateHertzCli, UnsettledActiveSetIsANumericalFailure)
{
  const auto r = run_hertzgear("validate hertz --case cylinder_2d --coarse "
                               "--set 'Refinement/max_active_set_iterations=1'");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("did not settle"), std::string::npos) << r.err;
}
