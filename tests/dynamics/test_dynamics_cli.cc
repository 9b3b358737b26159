// The command-line contract of `hertzgear dynamics`, `sweep` and `accuracy dynamics`.
#include "tests/support/run_command.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace fs = std::filesystem;
using hertzgear::testing::run_hertzgear;
using hertzgear::testing::slurp;

namespace
{
  const std::string scene = std::string(HERTZGEAR_SOURCE_DIR) + "/data/scenes/paper_crowned_fourier.prm";
  const std::string short_run = " --set Dynamics/periods=12 --set Dynamics/transient_periods=6";

  fs::path fresh_dir(const std::string &name)
  {
    const fs::path d = fs::temp_directory_path() / ("hg_dyn_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    return d;
  }
} // namespace

// Requirement: `hertzgear dynamics SCENE --out DIR` writes the listed artifacts, and summary.json
// has every listed key and says that its extremes come from the dense output; the mean mesh force of the (period-1) paper scene equals F_0 within 0.1 %.
TEST(DynamicsCli, WritesTheArtifacts)
{
  const fs::path out = fresh_dir("artifacts");
  const auto     r   = run_hertzgear("dynamics '" + scene + "'" + short_run + " --out '" + out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char *f : {"timeseries.csv", "poincare.csv", "spectrum.csv", "force_penetration.csv",
                        "summary.json", "used_parameters.prm", "run.json"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  EXPECT_EQ(slurp(out / "timeseries.csv").substr(0, 66),
            "time_s,dte_um,dte_rate_m_per_s,penetration_um,mesh_force_N,contact");
  const auto s = nlohmann::json::parse(slurp(out / "summary.json"));
  for (const char *key :
       {"rms_dte_um", "mean_mesh_force_N", "static_force_N", "max_mesh_force_N", "dynamic_factor",
        "contact_loss_fraction", "contact_losses_per_period", "backside_impacts",
        "period_multiplicity", "max_penetration_um", "extremes_from", "state_dimension", "effects",
        "equivalent_mass_kg", "integrator", "wall_time_s"})
    EXPECT_TRUE(s.contains(key)) << key;
  for (const char *key : {"name", "steps", "rejected_steps", "rhs_evals", "events"})
    EXPECT_TRUE(s["integrator"].contains(key)) << key;
  EXPECT_EQ(s["state_dimension"].get<int>(), 3);
  EXPECT_EQ(s["extremes_from"].get<std::string>(), "dense output");
  EXPECT_NEAR(s["mean_mesh_force_N"].get<double>(), s["static_force_N"].get<double>(),
              1e-3 * s["static_force_N"].get<double>());
  EXPECT_NE(r.err.find("[dynamics] period"), std::string::npos) << "progress lines on stderr";
  fs::remove_all(out);
}

// Requirement: stiffness sources produced by another stage are a clear input error (exit 2) that
// says how to proceed, and bad input leaves no run directory behind.
TEST(DynamicsCli, StiffnessFromAnotherStageIsAnInputError)
{
  const fs::path out = fresh_dir("fem");
  const auto     r   = run_hertzgear("dynamics '" + std::string(HERTZGEAR_SOURCE_DIR) +
                                 "/data/scenes/paper_crowned.prm' --out '" + out.string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("source = table"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

// Requirement: c = 0 with an ODE integrator (the scene's radau-iia, the default, and cvode-bdf)
// is an input error naming the key and the remedy (ida, or c > 0); a blow-up of the fixed-step RK4
// is a numerical failure (exit 3) that names the time, state and remedy (the default radau-iia).
TEST(DynamicsCli, ClearErrorsForDaeAndBlowUp)
{
  const std::string zero_damping = " --set Dynamics/damping_from=coefficient"
                                   " --set Dynamics/damping_coefficient_N_s_per_m=0";
  for (const std::string integrator : {"", " --set Dynamics/integrator=radau-iia",
                                       " --set Dynamics/integrator=cvode-bdf"})
    {
      const auto r =
        run_hertzgear("dynamics '" + scene + "'" + short_run + zero_damping + integrator);
      EXPECT_EQ(r.exit_code, 2) << integrator << "\n" << r.err;
      EXPECT_NE(r.err.find("Dynamics/integrator = ida"), std::string::npos)
        << integrator << "\n" << r.err;
      EXPECT_NE(r.err.find("c > 0"), std::string::npos) << integrator << "\n" << r.err;
    }

  const auto r =
    run_hertzgear("dynamics '" + scene + "'" + short_run + " --set Dynamics/integrator=rk4");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("t = "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("radau-iia"), std::string::npos) << r.err;
}

// Requirement: `hertzgear sweep` writes sweep.csv and bifurcation.csv with the listed columns,
// one row per speed and direction.
TEST(DynamicsCli, SweepWritesItsTables)
{
  const fs::path out = fresh_dir("sweep");
  const auto     r   = run_hertzgear(
    "sweep '" + scene + "' --threads 2 --set Sweep/points=3 --set Sweep/speed_min_rpm=100"
    " --set Sweep/speed_max_rpm=300 --set Sweep/periods_per_point=12"
    " --set Sweep/transient_periods_per_point=6 --out '" + out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string sweep = slurp(out / "sweep.csv");
  EXPECT_EQ(sweep.substr(0, sweep.find('\n')),
            "speed_rpm,direction,rms_dte_um,min_dte_um,max_dte_um,dynamic_factor,"
            "contact_loss_fraction,period_multiplicity,extremes_from,extrapolated_fraction");
  EXPECT_EQ(std::count(sweep.begin(), sweep.end(), '\n'), 1 + 3 * 3); // up, down, independent
  EXPECT_EQ(slurp(out / "bifurcation.csv").substr(0, 26), "speed_rpm,poincare_dte_um\n");
  fs::remove_all(out);
}

// Requirement: a sweep spread over MPI ranks (`mpirun -np 2`) gives the same tables as the serial
// sweep. Every point runs the same deterministic code on one rank whichever rank that is, so the
// tables must agree byte for byte (tolerance 0); only rank 0 writes.
TEST(DynamicsCli, SweepOverTwoMpiRanksEqualsSerial)
{
  const std::string args = "sweep '" + scene + "' --threads 1 --set Sweep/points=3"
                           " --set Sweep/speed_min_rpm=100 --set Sweep/speed_max_rpm=300"
                           " --set Sweep/periods_per_point=12 --set Sweep/transient_periods_per_point=6";
  const fs::path serial = fresh_dir("sweep_serial"), parallel = fresh_dir("sweep_mpi");
  const auto     r = run_hertzgear(args + " --out '" + serial.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;

  ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  const fs::path    log = parallel.string() + ".log";
  const std::string cmd = std::string("mpirun -np 2 --oversubscribe '") + HERTZGEAR_EXE + "' " +
                          args + " --out '" + parallel.string() + "' >'" + log.string() + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(log);
  const std::string mpi_log = slurp(log);
  EXPECT_NE(mpi_log.find("rank 1: "), std::string::npos) << "rank 1 computed no point:\n" << mpi_log;
  for (const char *table : {"sweep.csv", "bifurcation.csv"})
    EXPECT_EQ(slurp(parallel / table), slurp(serial / table)) << table;
  fs::remove_all(serial);
  fs::remove_all(parallel);
  fs::remove(log);
}

// Requirement: `hertzgear response SCENE --out DIR` writes response.csv (one row per orbit with
// its stability, multipliers and bifurcation) and response.json (branches with their end
// reasons, bifurcations); on the crowned Fourier pair from 12000 to 14000 rpm the branch passes
// the two folds of its bent resonance (measured 12885 and 12136 rpm) and the unstable orbits
// between them are marked unstable. The folds are located to 1e-6 of a step, so 1 rpm is wide.
TEST(DynamicsCli, ResponseFollowsTheOrbitsThroughTheirFolds)
{
  const fs::path out = fresh_dir("response");
  const auto     r   = run_hertzgear("response '" + scene +
                                     "' --set Sweep/speed_min_rpm=12000 --set Sweep/speed_max_rpm=14000 --out '" +
                                     out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(slurp(out / "response.csv").substr(0, 58),
            "speed_rpm,branch,period_multiple,stable,bifurcation,rms_dt");
  const auto j = nlohmann::json::parse(slurp(out / "response.json"));
  ASSERT_EQ(j["branches"].size(), 1u);
  EXPECT_FALSE(j["branches"][0]["ended_in_failure"].get<bool>());
  std::vector<double> folds;
  for (const auto &b : j["bifurcations"])
    if (b["type"] == "fold")
      folds.push_back(b["speed_rpm"].get<double>());
  ASSERT_EQ(folds.size(), 2u) << j.dump(1);
  EXPECT_NEAR(std::max(folds[0], folds[1]), 12885.2, 1.0);
  EXPECT_NEAR(std::min(folds[0], folds[1]), 12135.7, 1.0);
  EXPECT_LT(j["branches"][0]["stable_points"].get<int>(), j["branches"][0]["points"].get<int>());
  EXPECT_NE(r.err.find("[response] branch 0 (period 1) point"), std::string::npos) << r.err;
  fs::remove_all(out);
}

// Requirement: continuation from either end of the range finds the same folds, to 1e-8
// relative, on both force laws (the crowned pair's FE table with its load ladder, 10000-18000 rpm:
// the serial law's folds at 14963.49 and 15996.41 rpm, the FE law's at 13488.39 and 15846.41),
// and each is a fold: a Floquet multiplier within 1e-4 of 1 at it (the continuation's own test). The folds are located to 1e-6
// of a step, their orbits corrected to a tenth of the Newton tolerance, and the period map is
// integrated at Response/relative_tolerance 1e-10; measured from the two ends: 4.9e-11 and
// 5.3e-14 (serial), 2.2e-10 and 7.9e-13 (FE law: the low folds, on the contact-losing branch where
// two switchings come close together, are the least sharp).
TEST(DynamicsCli, ResponseFindsTheSameFoldsFromEitherEnd)
{
  const std::string table = std::string(HERTZGEAR_SOURCE_DIR) + "/data/scenes/paper_crowned_table.prm";
  for (const std::string law : {"serial-hertz", "fe-map"})
    {
      std::vector<std::vector<double>> folds;
      for (const std::string start : {"low", "high"})
        {
          const fs::path out = fresh_dir("response_" + law + "_" + start);
          const auto     r   = run_hertzgear("response '" + table + "' --set Effects/mesh_force_law=" + law +
                                       " --set Response/start=" + start +
                                       " --set Sweep/speed_min_rpm=10000 --set Sweep/speed_max_rpm=18000"
                                       " --out '" + out.string() + "'");
          ASSERT_EQ(r.exit_code, 0) << r.err;
          const auto j = nlohmann::json::parse(slurp(out / "response.json"));
          ASSERT_EQ(j["branches"].size(), 1u);
          EXPECT_FALSE(j["branches"][0]["ended_in_failure"].get<bool>())
            << j["branches"][0]["end_reason"];
          std::vector<double> f;
          for (const auto &b : j["bifurcations"])
            {
              ASSERT_EQ(b["type"], "fold") << b.dump();
              f.push_back(b["speed_rpm"].get<double>());
              // The multiplier nearest 1 (the first of the list, as re+imi).
              const std::string mu = b["multipliers"].get<std::string>();
              EXPECT_NEAR(std::stod(mu.substr(0, mu.find_first_of("+-", 1))), 1.0, 1e-4) << b.dump();
            }
          std::sort(f.begin(), f.end());
          ASSERT_EQ(f.size(), 2u) << law << " from " << start << ": " << j["bifurcations"].dump();
          folds.push_back(f);
          fs::remove_all(out);
        }
      for (std::size_t i = 0; i < 2; ++i)
        {
          std::printf("%s fold %zu: %.10f (from low), %.10f (from high), relative %.2e\n",
                      law.c_str(), i, folds[0][i], folds[1][i],
                      std::abs(folds[0][i] - folds[1][i]) / folds[0][i]);
          EXPECT_NEAR(folds[0][i], folds[1][i], 1e-8 * folds[0][i]) << law;
        }
    }
}

namespace
{
  // The folds of a response.json in increasing speed, each checked to have a Floquet multiplier
  // within 1e-4 of 1 (the location tolerance's effect on it is far smaller).
  std::vector<double> folds_with_a_multiplier_at_one(const nlohmann::json &j)
  {
    std::vector<double> folds;
    for (const auto &b : j["bifurcations"])
      if (b["type"] == "fold")
        {
          folds.push_back(b["speed_rpm"].get<double>());
          const std::string mu = b["multipliers"].get<std::string>();
          EXPECT_NEAR(std::stod(mu.substr(0, mu.find_first_of("+-", 1))), 1.0, 1e-4) << b.dump();
        }
    std::sort(folds.begin(), folds.end());
    return folds;
  }

  // The crowned pair's response on the FE law of the table data/stiffness/TABLE, 1000-20000 rpm,
  // with the period map integrated coarsely (Response/relative_tolerance = 1e-6,
  // newton_tolerance = 1e-4), into `out`.
  hertzgear::testing::CommandResult coarse_fe_law_response(const std::string &table, const fs::path &out)
  {
    return run_hertzgear("response '" + std::string(HERTZGEAR_SOURCE_DIR) +
                         "/data/scenes/paper_crowned_table.prm' --set Effects/mesh_force_law=fe-map"
                         " --set Stiffness/table_file='" + std::string(HERTZGEAR_SOURCE_DIR) +
                         "/data/stiffness/" + table + "'"
                         " --set Sweep/speed_min_rpm=1000 --set Sweep/speed_max_rpm=20000"
                         " --set Response/relative_tolerance=1e-6 --set Response/newton_tolerance=1e-4"
                         " --out '" + out.string() + "'");
  }
} // namespace

// Requirement (a hard case of the continuation): a branch passes corners where its turning point
// cannot be located and goes on. The crowned pair's FE table at FE level 0 with a 6-rung ladder
// (data/stiffness/paper_crowned_level0_six_rungs.json, test data: its command in
// data/stiffness/README.md) with the FE law, 1000-20000 rpm, with the period map integrated
// coarsely (Response/relative_tolerance = 1e-6, newton_tolerance = 1e-4): the coarse period map
// has corners where every step shorter than the corner steps fails. A step that passed such a
// corner and was retaken shorter (its turning point could not be located) would fail down to the
// corner steps and pass the same corner again, without end. The command ends (measured 9.4 s,
// 175 corners passed, 75 turning points noted as not located), and the two folds are found with
// a multiplier at 1 (15 865.82 and 13 288.46 rpm, as at the default tolerance).
TEST(DynamicsCli, ResponsePassesACornerWhoseTurningPointCannotBeLocated)
{
  const fs::path out = fresh_dir("response_corner");
  const auto     r   = coarse_fe_law_response("paper_crowned_level0_six_rungs.json", out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(out / "response.json"));
  ASSERT_EQ(j["branches"].size(), 1u);
  const auto &branch = j["branches"][0];
  EXPECT_GE(branch["corners_passed"].get<int>(), 1);
  EXPECT_FALSE(branch["ended_in_failure"].get<bool>()) << branch["end_reason"];
  bool noted = false;
  for (const auto &n : branch["notes"])
    noted = noted || n["text"].get<std::string>().find("could not be located") != std::string::npos;
  EXPECT_TRUE(noted) << branch["notes"].dump(1);
  const std::vector<double> folds = folds_with_a_multiplier_at_one(j);
  ASSERT_EQ(folds.size(), 2u) << j["bifurcations"].dump(1);
  // Where they lie (to 0.1 rpm: the coarse integration moves them by ~1e-6 of the speed).
  EXPECT_NEAR(folds[0], 13288.46, 0.1);
  EXPECT_NEAR(folds[1], 15865.82, 0.1);
  fs::remove_all(out);
}

// Requirement (a hard case of the continuation): a branch that comes back onto its own path
// stops there instead of repeating it. On the crowned pair's table on the whole-face contact grid
// (data/stiffness/paper_crowned_whole_face.json, test data) with the FE law, 1000-20000 rpm,
// integrated coarsely (Response/relative_tolerance = 1e-6, newton_tolerance = 1e-4), the unstable
// branch from the upper fold meets corners near 13 443 rpm where a turning point cannot be
// located, and its corrected points then follow the unstable branch back up: unchecked, it
// reaches the upper fold a second time (15 802.0100 and 15 802.0106 rpm) and goes on down the
// stable branch to 1000 rpm, a frequency response with one fold reported twice and the lower one
// missing. The branch ends at the repeated fold with a warning that names it and the tolerance to
// tighten, the fold reported once (at the default tolerance the branch finds both folds,
// 13 320.89 and 15 802.01 rpm, docs/dynamics.md).
TEST(DynamicsCli, ResponseThatComesBackOntoItsOwnPathStopsThere)
{
  const fs::path out = fresh_dir("response_retrace");
  const auto     r   = coarse_fe_law_response("paper_crowned_whole_face.json", out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("came back onto its own path"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Response/relative_tolerance"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(slurp(out / "response.json"));
  ASSERT_EQ(j["branches"].size(), 1u);
  const auto &branch = j["branches"][0];
  EXPECT_TRUE(branch["ended_in_failure"].get<bool>());
  EXPECT_NE(branch["end_reason"].get<std::string>().find("came back onto its own path"), std::string::npos)
    << branch["end_reason"];
  const std::vector<double> folds = folds_with_a_multiplier_at_one(j);
  ASSERT_EQ(folds.size(), 1u) << j["bifurcations"].dump(1);
  EXPECT_NEAR(folds[0], 15802.01, 0.1);
  fs::remove_all(out);
}

// Requirement: the FE force law is smooth enough in the load (C4 across its rungs) that the
// continuation does not see them. On the crowned pair's FE table at FE level 0 with a 6-rung ladder
// (data/stiffness/paper_crowned_level0_six_rungs.json: `hertzgear stiffness
// data/scenes/paper_crowned.prm --set Stiffness/fe_level=0 --set Effects/mesh_force_law=fe-map
// --set Stiffness/load_ladder_percent=5,20,50,100,200,400 --set Output/write_fields=false
// --set Stiffness/contact_grid_face_extent=face-width`, the whole-face contact grid), FE
// law, 1000-20000 rpm: with a C2 interpolant over the load (a cubic spline) the unstable branch
// from its upper fold turned back at a corner near 13 301 rpm whose turning point could not be
// located, a corner of the law, not of the motion. On the quintic spline the branch has no corner,
// reaches the end of the range and finds both folds with a multiplier at 1 (measured 13 288.46
// and 15 865.82 rpm, 1 s).
TEST(DynamicsCli, ResponseOnACoarseLadderSeesNoCornerAtItsRungs)
{
  const std::string scene = std::string(HERTZGEAR_SOURCE_DIR) + "/data/scenes/paper_crowned_table.prm";
  const std::string table = std::string(HERTZGEAR_SOURCE_DIR) + "/data/stiffness/paper_crowned_level0_six_rungs.json";
  const fs::path    out   = fresh_dir("response_rungs");
  const auto        r     = run_hertzgear("response '" + scene + "' --set Stiffness/table_file='" + table +
                                   "' --set Effects/mesh_force_law=fe-map --set Sweep/speed_min_rpm=1000"
                                   " --set Sweep/speed_max_rpm=20000 --out '" + out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(out / "response.json"));
  ASSERT_EQ(j["branches"].size(), 1u);
  const auto &branch = j["branches"][0];
  EXPECT_FALSE(branch["ended_in_failure"].get<bool>()) << branch["end_reason"];
  EXPECT_NE(branch["end_reason"].get<std::string>().find("reached speed_rpm = 20000"), std::string::npos)
    << branch["end_reason"];
  EXPECT_EQ(branch["corners_passed"].get<int>(), 0);
  EXPECT_TRUE(branch["notes"].empty()) << branch["notes"].dump(1);
  const std::vector<double> folds = folds_with_a_multiplier_at_one(j);
  ASSERT_EQ(folds.size(), 2u) << j["bifurcations"].dump(1);
  // Where they lie (to 0.1 rpm: the table is data, the location is 1e-8 of the speed).
  EXPECT_NEAR(folds[0], 13288.46, 0.1);
  EXPECT_NEAR(folds[1], 15865.82, 0.1);
  fs::remove_all(out);
}

// Requirement: the shooting method's bad input and failures: rk4 (no event location) and a
// Newton tolerance below the integration's accuracy are input errors naming the key (exit 2);
// Newton that does not converge at the start is a numerical error (exit 3). No folder is left.
TEST(DynamicsCli, ResponseRefusesWhatShootingCannotServe)
{
  const fs::path out = fresh_dir("response_bad");
  auto r = run_hertzgear("response '" + scene + "' --set Dynamics/integrator=rk4 --out '" + out.string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("Dynamics/integrator = rk4"), std::string::npos) << r.err;
  r = run_hertzgear("response '" + scene + "' --set Response/newton_tolerance=1e-10 --out '" + out.string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("Response/newton_tolerance"), std::string::npos) << r.err;
  r = run_hertzgear("response '" + scene + "' --set Response/relative_tolerance=1e-4 " +
                    "--set Response/newton_tolerance=1e-3 --set Dynamics/initial_state=given " +
                    "--set Dynamics/initial_dte_um=5000 --set Dynamics/periods=2 --set Dynamics/transient_periods=1 " +
                    "--set Sweep/speed_min_rpm=15000 --set Sweep/speed_max_rpm=16000 --out '" + out.string() + "'");
  // A start 5 mm off on a coarse integration: Newton's steps do not reduce the residual.
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("no periodic orbit found at speed_rpm = 15000"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(out);
}
