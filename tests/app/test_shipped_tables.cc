// Requirement: data/stiffness/ ships the stiffness tables of both paper scenes, and they
// are what the current code produces at the shipped level, load ladder included. The test
// regenerates each table with
// the command recorded in data/stiffness/README.md and compares it with the shipped file.
//
// Tolerance: 1e-6 relative to each series' mean. The same code at the same FE level with the
// direct solver (MUMPS) is deterministic up to the floating-point order of the threaded BLAS,
// which moves results by about 1e-12; any change of the model, the mesh or the contact grid moves
// them by 1e-4 or more. Fourier coefficients are compared as complex numbers
// (a cos(phi), a sin(phi)), so that the phase of a negligible harmonic does not count.
//
// Label `long`: the FE runs take minutes on 2 cores.
#include "tests/support/run_command.h"
#include "tests/support/stiffness_checks.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

using namespace hertzgear::testing;
namespace fs = std::filesystem;

namespace
{
  constexpr double tolerance = 1e-6;

  // The FE settings and sizes of a table, without the wall times that differ from run to run.
  nlohmann::json fe_settings(const nlohmann::json &table)
  {
    nlohmann::json fe = table.at("fe");
    if (fe.contains("load_ladder"))
      fe.at("load_ladder").erase("contact_time_s");
    if (fe.contains("bodies"))
      for (auto &[body, v] : fe.at("bodies").items())
        {
          v.erase("wall_time_s");
          v.erase("wall_time_breakdown_s");
        }
    return fe;
  }

  void regenerate_and_compare(const std::string &name, const std::string &settings)
  {
    const fs::path dir = fresh_temp_dir("shipped_" + name);
    const auto     r   = run_hertzgear("stiffness " + scene_path(name + ".prm") + " " + settings +
                                 " --set Output/write_fields=false --out '" + dir.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto fresh   = nlohmann::json::parse(slurp(dir / "stiffness.json"));
    const auto shipped = nlohmann::json::parse(
      slurp(fs::path(HERTZGEAR_SOURCE_DIR) / "data" / "stiffness" / (name + ".json")));

    EXPECT_EQ(fresh.at("hertz_exponent"), shipped.at("hertz_exponent"));
    EXPECT_EQ(fe_settings(fresh), fe_settings(shipped)) << "the FE settings of the shipped table";
    expect_tables_close(fresh, shipped, tolerance);
  }
} // namespace

TEST(ShippedTables, UncrownedMatchesTheCode)
{
  regenerate_and_compare("paper_uncrowned", "--set Effects/mesh_force_law=fe-map");
}

TEST(ShippedTables, CrownedMatchesTheCode)
{
  // The shipped crowned table is the scene's own level (Q1, level 1, 32 face layers, d = 1.08
  // mm): about 3.5 minutes and 14 GB.
  regenerate_and_compare("paper_crowned", "--set Effects/mesh_force_law=fe-map");
}

// Requirement: on the crowned pair at the shipped level, on the scene's contact grid whose face
// extent follows the load (Stiffness/contact_grid_face_extent = load, the default;
// docs/theory-tca.md, "Face extent of the grid"), the FE force law's static equilibrium is the
// FE's at every rung and position to round-off (expect_static_consistency (1)), and between the
// rungs within 0.5 % of the approach and 1 % of the tangent (expect_static_consistency (2), (3)).
// Measured 0.15 % (204.8 N, position 8) and 0.94 % (15 329 N, position 3); at position 5, whose
// leaving pair touches at the pinion tip at every load, 0.050 % and 0.54 % with the cells cut at
// the flank ends (1.20 % and 5.6 % with cells kept or dropped whole by their centres). Two FE runs
// at the shipped level, about 8 minutes.
TEST(ShippedTables, CrownedFeLawIsTheFeAtItsRungsAndBetweenThem)
{
  expect_static_consistency("paper_crowned.prm", "", true);
}

// Requirement: on the grid over the whole face width (contact_grid_face_extent = face-width) the
// FE law is the FE at its rungs to round-off as well. Between the rungs the errors are measured
// and printed for docs/validation-force-law.md, not required: the FE's Hertzian part of the
// approach is itself not smooth in the load on that grid, where the contact's edges cross the
// fixed face cells one by one (its log-log slope 0.85, 1.10, 0.43 between 458, 916, 1296 and
// 1714 N at the first position). Two FE runs at the shipped level, about 6 minutes; measured
// 6.0 % in the approach and 7.4 % in the tangent.
TEST(ShippedTables, CrownedFeLawOnTheWholeFaceGridIsTheFeAtItsRungs)
{
  expect_static_consistency("paper_crowned.prm", " --set Stiffness/contact_grid_face_extent=face-width", false);
}
