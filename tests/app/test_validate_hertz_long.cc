// The full Hertz validation study (label long, minutes): the acceptance bounds (2 % against the
// Hertz closed forms, 5 % for the TCA's local penetration) on the finest level of every case.
// Measured numbers and their discussion: docs/validation-hertz.md.
#include "../support/run_command.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

using namespace hertzgear::testing;
namespace fs = std::filesystem;

namespace
{
  // (case, quantity) -> relative error on the finest level of that case.
  std::map<std::pair<std::string, std::string>, double> finest_errors(const fs::path &csv)
  {
    std::map<std::pair<std::string, std::string>, std::pair<int, double>> best;
    std::ifstream in(csv);
    std::string   line;
    std::getline(in, line);
    while (std::getline(in, line))
      {
        std::vector<std::string> c;
        std::stringstream        ss(line);
        for (std::string s; std::getline(ss, s, ',');)
          c.push_back(s);
        const int level = std::stoi(c[5]);
        auto     &b     = best[{c[0], c[1]}];
        if (level >= b.first)
          b = {level, std::stod(c[4])};
      }
    std::map<std::pair<std::string, std::string>, double> out;
    for (const auto &[k, v] : best)
      out[k] = v.second;
    return out;
  }
} // namespace

// Requirement: on the finest level the resolved FE contact agrees with the Hertz closed
// form within 2 % for both semi-axes and the peak pressure of the sphere, the 1:5 and 1:20
// ellipsoids and the crowned flank, and for the half-width of the 2D cylinder; the TCA's hybrid
// local penetration agrees with the resolved FE within 5 % for the crowned flank at the pitch
// point. The bounds are the acceptance bounds themselves, not fitted to the measurements.
TEST(ValidateHertzLong, FullStudyMeetsTheAcceptance)
{
  const fs::path dir = fresh_temp_dir("validate_hertz_full");
  const auto     r   = run_hertzgear("validate hertz --out '" + dir.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto e = finest_errors(dir / "hertz_validation.csv");
  for (const std::string c : {"sphere", "ellipsoid_1to5", "ellipsoid_1to20", "crowned_flank"})
    for (const std::string q : {"semi_axis_x", "semi_axis_y", "peak_pressure"})
      {
        ASSERT_TRUE(e.count({c, q})) << c << " " << q;
        EXPECT_LT(std::abs(e.at({c, q})), 0.02) << c << " " << q;
      }
  EXPECT_LT(std::abs(e.at({"cylinder_2d", "half_width"})), 0.02);
  EXPECT_LT(std::abs(e.at({"cylinder_2d", "peak_pressure"})), 0.02);
  EXPECT_LT(std::abs(e.at({"crowned_flank", "penetration_vs_tca_hybrid"})), 0.05);
}
