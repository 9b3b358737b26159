#pragma once
// Checks shared by the stiffness CLI tests and the long shipped-table tests: the rows of the
// stiffness CSVs, and the static consistency of the FE force law with the FE it comes from.
#include "dynamics/mesh_force_law.h"
#include "table/stiffness_table.h"
#include "tests/support/run_command.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace hertzgear::testing
{
  namespace fs = std::filesystem;

  // The rows of a stiffness CSV as text (header dropped), optionally of one map case, without
  // the map's leading case columns.
  inline std::vector<std::string> csv_rows(const fs::path &file, const int map_case = -1)
  {
    std::istringstream       in(slurp(file));
    std::vector<std::string> rows;
    std::string              line;
    std::getline(in, line);
    while (std::getline(in, line))
      {
        if (map_case < 0)
          {
            rows.push_back(line);
            continue;
          }
        std::size_t at = 0;
        for (int k = 0; k < 9; ++k) // case, torque, percent, load, two crownings, misalignment, two f_Hb
          at = line.find(',', at) + 1;
        if (std::stoi(line.substr(0, line.find(','))) == map_case)
          rows.push_back(line.substr(at));
      }
    return rows;
  }

  inline double column(const std::string &row, const int index)
  {
    std::stringstream ss(row);
    std::string       cell;
    for (int k = 0; k <= index; ++k)
      std::getline(ss, cell, ',');
    return std::stod(cell);
  }

  // Two stiffness tables (stiffness.json) agree within `tolerance` relative: every Fourier
  // series (its mean, and each harmonic as the complex number a e^(i phi) against the series'
  // mean, so that the phase of a negligible harmonic does not count), every sampled series and
  // every rung of the FE force law's load ladder (each value against itself).
  inline void expect_tables_close(const nlohmann::json &fresh, const nlohmann::json &reference,
                                  const double tolerance)
  {
    for (const std::string s : {"k_total_N_per_m", "k_hertz_N_per_m_pow_n", "k_rest_N_per_m", "ste_m"})
      {
        const auto  &a = fresh.at(s), &b = reference.at(s);
        const double scale = std::abs(b.at("mean").get<double>());
        EXPECT_NEAR(a.at("mean").get<double>(), b.at("mean").get<double>(), tolerance * scale) << s;
        const auto aa = a.at("amplitudes").get<std::vector<double>>();
        const auto ba = b.at("amplitudes").get<std::vector<double>>();
        const auto ap = a.at("phases_rad").get<std::vector<double>>();
        const auto bp = b.at("phases_rad").get<std::vector<double>>();
        ASSERT_EQ(aa.size(), ba.size()) << s;
        for (std::size_t j = 0; j < aa.size(); ++j)
          {
            EXPECT_NEAR(aa[j] * std::cos(ap[j]), ba[j] * std::cos(bp[j]), tolerance * scale) << s << " harmonic " << j + 1;
            EXPECT_NEAR(aa[j] * std::sin(ap[j]), ba[j] * std::sin(bp[j]), tolerance * scale) << s << " harmonic " << j + 1;
          }
        const auto as = fresh.at("samples").at(s).get<std::vector<double>>();
        const auto bs = reference.at("samples").at(s).get<std::vector<double>>();
        ASSERT_EQ(as.size(), bs.size()) << s;
        for (std::size_t i = 0; i < as.size(); ++i)
          EXPECT_NEAR(as[i], bs[i], tolerance * std::abs(bs[i])) << s << " sample " << i;
      }
    const auto &fl = fresh.at("load_ladder"), &rl = reference.at("load_ladder");
    EXPECT_EQ(fl.at("load_N"), rl.at("load_N"));
    for (const std::string s : {"approach_m", "hertz_approach_m"})
      {
        const auto a = fl.at(s).get<std::vector<std::vector<double>>>();
        const auto b = rl.at(s).get<std::vector<std::vector<double>>>();
        ASSERT_EQ(a.size(), b.size()) << s;
        for (std::size_t j = 0; j < a.size(); ++j)
          {
            ASSERT_EQ(a[j].size(), b[j].size()) << s << " rung " << j;
            for (std::size_t i = 0; i < a[j].size(); ++i)
              EXPECT_NEAR(a[j][i], b[j][i], tolerance * std::abs(b[j][i])) << s << " rung " << j << " position " << i;
          }
      }
  }

  // The compression a >= 0 of one member of `law` that carries the force F at `phase`, and the
  // member's tangent dF/da there: Newton on the law's own force and slope, safeguarded by
  // bisection (the force grows strictly with the compression), to 1e-14 relative.
  struct MemberAt
  {
    double compression = 0.0, tangent = 0.0;
  };
  inline MemberAt member_compression(const hertzgear::dynamics::MeshForceLaw &law,
                              const hertzgear::dynamics::MeshPhase &phase, const bool hertzian,
                              const double F)
  {
    hertzgear::dynamics::MeshLawForces out;
    const auto at = [&](const double a) {
      law.evaluate(phase, hertzian ? 0.0 : a, hertzian ? a : 0.0, out);
      return hertzian ? std::make_pair(out.hertz, out.hertz_ddelta) :
                        std::make_pair(out.structural, out.structural_du);
    };
    double lo = 0.0, hi = 1e-6;
    while (at(hi).first < F)
      hi *= 2.0;
    double a = 0.5 * (lo + hi);
    for (int it = 0; it < 200 && hi - lo > 1e-14 * hi; ++it)
      {
        const auto [f, df] = at(a);
        (f < F ? lo : hi)  = a;
        double next        = a - (f - F) / df;
        a                  = next > lo && next < hi ? next : 0.5 * (lo + hi);
      }
    return {a, at(a).second};
  }

  // The requirements below, on one paper pair at the FE level `settings` chooses (scene values);
  // without `between_rungs` (2) and (3) are measured and printed, not required.
  inline void expect_static_consistency(const std::string &scene_name, const std::string &settings,
                                        const bool between_rungs = true,
                                        fs::path *rungs_dir = nullptr)
  {
    // Requirements (static consistency of the FE force law with the FE): the law's static
    // equilibrium -- structural and Hertzian members each carrying the applied load F -- at every
    // position (1) at each rung of the default ladder reproduces the FE's approach (loaded minus
    // unloaded STE) of that rung to round-off (1e-10 relative: the spline passes through its data,
    // the rest is the solve above at 1e-14); (2) midway between rungs (their geometric mean, where
    // a spline in log F is least constrained) agrees with the FE's own cycle at that load -- a
    // second ladder made of the midpoints, the same contact problem as a rung -- within 0.5 % of
    // the approach, the interpolation error allowed at the default ladder; and (3) its series
    // tangent 1 / (1 / K_r' + 1 / K_h') is within 1 % of the FE's k_total_tangent at that load (a
    // torque map case of the same run). The largest errors are printed for docs/validation-force-law.md.
    const std::string fe_law = " --set Effects/mesh_force_law=fe-map";
    const fs::path    rungs  = fresh_temp_dir("ladder_rungs_" + scene_name);
    const auto        a      = run_hertzgear("stiffness " + scene_path(scene_name) + settings +
                                 fe_law + " --set Output/write_fields=false --out " + rungs.string());
    ASSERT_EQ(a.exit_code, 0) << a.err;
    if (rungs_dir)
      *rungs_dir = rungs; // the default ladder's run, for the caller's own checks
    const auto table = hertzgear::table::read_stiffness_table(rungs / "stiffness.json");
    const auto &l    = table.ladder;
    ASSERT_GE(l.n_rungs(), 10u); // the default ladder
    const std::size_t S = l.n_positions();

    // The midpoints, as percentages of the nominal load, and the ladder that holds them.
    std::vector<double> mid_percent;
    std::string         ladder, map;
    for (std::size_t j = 0; j + 1 < l.n_rungs(); ++j)
      mid_percent.push_back(100.0 * std::sqrt(l.load_N[j] * l.load_N[j + 1]) / l.nominal_load_N);
    std::vector<double> mid_ladder = mid_percent;
    mid_ladder.push_back(100.0);
    std::sort(mid_ladder.begin(), mid_ladder.end());
    const auto join = [](const std::vector<double> &v) {
      std::ostringstream os;
      os.precision(17);
      for (std::size_t i = 0; i < v.size(); ++i)
        os << (i ? "," : "") << v[i];
      return os.str();
    };
    const fs::path mids = fresh_temp_dir("ladder_midpoints_" + scene_name);
    const auto     b    = run_hertzgear("stiffness " + scene_path(scene_name) + settings + fe_law +
                                 " --set Output/write_fields=false --set Stiffness/load_ladder_percent=" +
                                 join(mid_ladder) + " --set Stiffness/Map/torque_percent=" +
                                 join(mid_percent) + " --out " + mids.string());
    ASSERT_EQ(b.exit_code, 0) << b.err;
    const auto direct = hertzgear::table::read_stiffness_table(mids / "stiffness.json");
    ASSERT_EQ(direct.ladder.n_rungs(), mid_ladder.size());

    const auto law = hertzgear::dynamics::fe_map_law(table, true, true);
    const auto at_phase = [&](const std::size_t s) {
      auto taylor = std::make_shared<std::vector<double>>(3 * law->n_phase_coefficients());
      const double theta = 2.0 * M_PI * double(s) / double(S);
      law->phase_coefficients(theta, std::cos(theta), std::sin(theta), taylor->data());
      return taylor;
    };
    // (1) At the rungs.
    double rung_error = 0.0;
    for (std::size_t s = 0; s < S; ++s)
      {
        const auto taylor = at_phase(s);
        const hertzgear::dynamics::MeshPhase phase{taylor->data(), 0.0, 1.0};
        for (std::size_t j = 0; j < l.n_rungs(); ++j)
          {
            const double u = member_compression(*law, phase, false, l.load_N[j]).compression;
            const double d = member_compression(*law, phase, true, l.load_N[j]).compression;
            rung_error = std::max(rung_error, std::abs(u + d - l.approach_m[j][s]) / l.approach_m[j][s]);
          }
      }
    EXPECT_LT(rung_error, 1e-10);

    // (2), (3) Between them: the midpoint ladder's rungs and the map's tangents (case c: the
    // midpoint c; map rows: case, ..., then the cycle's columns, k_total_tangent the 13th).
    double approach_error = 0.0, hertz_error = 0.0, tangent_error = 0.0;
    std::string approach_at, hertz_at, tangent_at; // where each largest error lies
    std::vector<double> position_approach(S, 0.0), position_tangent(S, 0.0);
    for (std::size_t c = 0; c < mid_percent.size(); ++c)
      {
        const double F = l.nominal_load_N * mid_percent[c] / 100.0;
        const auto   j = static_cast<std::size_t>(
          std::find(mid_ladder.begin(), mid_ladder.end(), mid_percent[c]) - mid_ladder.begin());
        ASSERT_NEAR(direct.ladder.load_N[j], F, 1e-9 * F);
        const auto rows = csv_rows(mids / "stiffness_map.csv", int(c));
        ASSERT_EQ(rows.size(), S);
        for (std::size_t s = 0; s < S; ++s)
          {
            const auto taylor = at_phase(s);
            const hertzgear::dynamics::MeshPhase phase{taylor->data(), 0.0, 1.0};
            const auto   u = member_compression(*law, phase, false, F);
            const auto   d = member_compression(*law, phase, true, F);
            const double fe_a = direct.ladder.approach_m[j][s], fe_h = direct.ladder.hertz_approach_m[j][s];
            const double e_a  = std::abs(u.compression + d.compression - fe_a) / fe_a;
            const double e_h  = std::abs(d.compression - fe_h) / fe_a;
            const double k    = 1.0 / (1.0 / u.tangent + 1.0 / d.tangent);
            const double fe_k = column(rows[s], 13);
            const double e_k  = std::abs(k - fe_k) / fe_k;
            if (between_rungs)
              {
                EXPECT_LT(e_a, 5e-3) << "load " << F << " N, position " << s;
                EXPECT_LT(e_k, 1e-2) << "load " << F << " N, position " << s << ": law " << k
                                     << ", FE " << fe_k;
              }
            position_approach[s] = std::max(position_approach[s], e_a);
            position_tangent[s]  = std::max(position_tangent[s], e_k);
            std::ostringstream at;
            at << " (" << F << " N, position " << s << ")";
            if (e_a > approach_error)
              approach_error = e_a, approach_at = at.str();
            if (e_h > hertz_error)
              hertz_error = e_h, hertz_at = at.str();
            if (e_k > tangent_error)
              tangent_error = e_k, tangent_at = at.str();
          }
      }
    std::cout << scene_name << ": FE law against the FE: at the rungs " << rung_error << ", between them: approach "
              << approach_error << approach_at << ", its Hertzian part " << hertz_error << hertz_at
              << " (of the approach), tangent " << tangent_error << tangent_at
              << " (largest relative errors)" << std::endl;
    for (std::size_t s = 0; s < S; ++s)
      std::cout << "  position " << s << ": approach " << position_approach[s] << ", tangent "
                << position_tangent[s] << std::endl;
  }
} // namespace hertzgear::testing
