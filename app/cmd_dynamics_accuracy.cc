// `hertzgear accuracy dynamics SCENE --out DIR`: what accuracy costs in time, per integrator.
// Every integrator runs the scene at a ladder of tolerances (fixed steps for rk4); errors are
// measured against a reference run of cvode-bdf at rtol 1e-12. Writes accuracy_dynamics.csv and,
// when python3 with matplotlib is available, accuracy_dynamics.png.
#include "app/cmd_dynamics.h"
#include "app/run_directory.h"
#include "app/scripts.h"
#include "common/errors.h"
#include "common/progress.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>

namespace hertzgear
{
  using namespace dynamics;

  namespace
  {
    struct Case
    {
      IntegratorKind kind;
      double         rtol             = 0; // adaptive
      int            steps_per_period = 0; // rk4
    };

    struct Outcome
    {
      bool             ok = false;
      std::string      status;
      SimulationResult result;
      SteadyStateSummary summary;
    };

    Outcome run_case(const DynamicsSetup &setup, const Scene &scene, const Case &c)
    {
      Outcome       o;
      GearPairModel model(setup.parameters);
      RunSettings   run              = setup.run;
      run.integrator.kind            = c.kind;
      if (c.kind == IntegratorKind::rk4)
        run.steps_per_period = c.steps_per_period;
      else
        {
          run.integrator.relative_tolerance = c.rtol;
          // Absolute tolerance tied to the relative one on the scale of the displacements, so
          // that one knob moves the accuracy.
          run.integrator.absolute_tolerance = c.rtol * 1e-2 * model.characteristic_displacement();
        }
      try
        {
          o.result  = simulate(model, run, initial_state(scene, model));
          o.summary = analyse(model, o.result);
          o.ok      = true;
          o.status  = "ok";
        }
      catch (const NumericalError &e)
        {
          o.status = std::string("failed: ") + e.what();
        }
      return o;
    }

    std::string csv_text(const std::string &s)
    {
      std::string t = "\"";
      for (const char ch : s)
        t += (ch == '"') ? std::string("\"\"") : std::string(1, ch);
      return t + "\"";
    }
  } // namespace

  int run_accuracy_dynamics(const CommandContext &ctx)
  {
    PhaseTimer timer;
    Scene      scene;
    {
      PhaseTimer::Scope scope(timer, "scene");
      scene = load_scene(ctx.scene_file, ctx.overrides);
    }
    const DynamicsSetup setup = make_dynamics_setup(scene);
    const bool          dae   = setup.parameters.damping_N_s_per_m == 0.0;

    Outcome reference;
    {
      PhaseTimer::Scope scope(timer, "reference");
      reference = run_case(setup, scene, {dae ? IntegratorKind::ida : IntegratorKind::cvode_bdf, 1e-12, 0});
      HG_REQUIRE_NUMERIC(reference.ok, "the reference run at rtol 1e-12 failed: ", reference.status);
      progress_line("accuracy", msg("reference (rtol 1e-12): rms DTE ",
                                    1e6 * reference.summary.rms_dte_m, " um, ",
                                    reference.result.stats.wall_time_s, " s"));
    }

    std::vector<Case> cases;
    for (const auto kind : {IntegratorKind::cvode_bdf, IntegratorKind::radau_iia, IntegratorKind::ida,
                            IntegratorKind::arkode_erk})
      {
        if (dae && kind != IntegratorKind::ida)
          continue;
        for (const double rtol : {1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10})
          cases.push_back({kind, rtol, 0});
      }
    if (!dae)
      for (const int n : {100, 300, 1000, 3000, 10000, 30000})
        cases.push_back({IntegratorKind::rk4, 0.0, n});

    std::ostringstream csv;
    csv << "integrator,relative_tolerance,steps_per_period,wall_time_s,rhs_evals,steps,rms_dte_um,"
           "rms_dte_relative_error,poincare_max_error_um,poincare_relative_error,status\n";
    const auto  &ref_p     = reference.result.poincare;
    const double ref_scale = std::max(reference.summary.max_dte_m - reference.summary.min_dte_m,
                                      std::abs(reference.summary.mean_dte_m));
    {
      PhaseTimer::Scope scope(timer, "ladder");
      for (std::size_t i = 0; i < cases.size(); ++i)
        {
          const Case   &c = cases[i];
          const Outcome o = run_case(setup, scene, c);
          double        rms_error = std::numeric_limits<double>::quiet_NaN(), p_error = rms_error;
          if (o.ok)
            {
              rms_error = std::abs(o.summary.rms_dte_m - reference.summary.rms_dte_m) /
                          reference.summary.rms_dte_m;
              p_error = 0.0;
              for (std::size_t j = 0; j < std::min(ref_p.size(), o.result.poincare.size()); ++j)
                p_error = std::max(p_error, std::abs(o.result.poincare[j].dte_m - ref_p[j].dte_m));
            }
          csv << integrator_name(c.kind) << ',' << (c.rtol > 0 ? msg(c.rtol) : "") << ','
              << (c.steps_per_period > 0 ? msg(c.steps_per_period) : "") << ','
              << o.result.stats.wall_time_s << ',' << o.result.stats.rhs_evals << ','
              << o.result.stats.steps << ',' << (o.ok ? 1e6 * o.summary.rms_dte_m : NAN) << ','
              << rms_error << ',' << 1e6 * p_error << ',' << p_error / ref_scale << ','
              << csv_text(o.status) << '\n';
          progress_line("accuracy",
                        msg(i + 1, "/", cases.size(), "  ", integrator_name(c.kind), " ",
                            c.rtol > 0 ? msg("rtol ", c.rtol) : msg(c.steps_per_period, " steps/period"),
                            "  ", o.result.stats.wall_time_s, " s  rms error ", rms_error,
                            "  poincare error ", 1e6 * p_error, " um  ", o.ok ? "" : o.status));
        }
    }
    if (ctx.out_dir.empty())
      std::cout << csv.str();
    else
      {
        PhaseTimer::Scope scope(timer, "write");
        RunDirectory      dir(ctx.out_dir, scene, ctx.command_line);
        dir.write_text("accuracy_dynamics.csv", csv.str());
        dir.finish(timer, {{"stage", "accuracy dynamics"},
                           {"reference", integrator_json(reference.result.stats)},
                           {"reference_rms_dte_um", 1e6 * reference.summary.rms_dte_m}});
        draw_figure("plot_accuracy_dynamics.py", {(dir.path() / "accuracy_dynamics.csv").string(),
                                                  (dir.path() / "accuracy_dynamics.png").string()});
      }
    if (ctx.out_dir.empty())
      timer.print_summary(progress_stream());
    return 0;
  }
} // namespace hertzgear
