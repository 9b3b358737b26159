// The command-line contract of `hertzgear dynamics`, `sweep` and `accuracy dynamics`.
#include "tests/support/run_command.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

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
            "contact_loss_fraction,period_multiplicity,extremes_from");
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
