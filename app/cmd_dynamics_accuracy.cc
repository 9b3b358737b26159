// `hertzgear accuracy dynamics SCENE --out DIR [--integrators a,b] [--tightest-rtol 1e-12]`: what
// accuracy costs in time, per integrator. Every integrator (radau-iia with 3, 5, 7 and 9 stages)
// runs the scene at rtol 1e-4 ... 1e-12 (fixed steps for rk4); errors are measured against a
// converged reference (dynamics/work_precision.h). Writes accuracy_dynamics.csv and, when python3
// with matplotlib is available, accuracy_dynamics.png.
#include "app/cmd_dynamics.h"
#include "app/run_directory.h"
#include "app/scripts.h"
#include "common/errors.h"
#include "common/progress.h"
#include "dynamics/work_precision.h"

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
    std::string csv_text(const std::string &s)
    {
      std::string t = "\"";
      for (const char ch : s)
        t += (ch == '"') ? std::string("\"\"") : std::string(1, ch);
      return t + "\"";
    }

    std::string case_text(const WorkPrecisionCase &c)
    {
      return (c.stages > 0 ? msg("s=", c.stages, " ") : std::string()) +
             (c.rtol > 0 ? msg("rtol ", c.rtol) : msg(c.steps_per_period, " steps/period"));
    }
  } // namespace

  int run_accuracy_dynamics(const CommandContext &ctx, const AccuracyDynamicsOptions &options)
  {
    PhaseTimer          timer;
    const Scene         scene = load_scene(ctx, timer);
    const DynamicsSetup setup = make_dynamics_setup(scene);
    WorkPrecisionStudy  study;
    {
      PhaseTimer::Scope scope(timer, "reference and ladder");
      const auto cases = work_precision_cases(setup.parameters.damping_N_s_per_m == 0.0,
                                              options.tightest_rtol, options.integrators);
      const std::size_t n = cases.size();
      study = work_precision(setup.parameters, setup.run, initial_state(scene), cases,
                             [&](const std::size_t i, const WorkPrecisionPoint &p) {
                               progress_line("accuracy",
                                             msg(i + 1, "/", n, "  ", integrator_name(p.case_.kind),
                                                 " ", case_text(p.case_), "  ", p.stats.wall_time_s,
                                                 " s  rms error ", p.rms_relative_error,
                                                 "  poincare error ", 1e6 * p.poincare_max_error_m,
                                                 " um  ", p.ok ? "" : p.status));
                             });
    }
    progress_line("accuracy", msg("reference (", study.reference_name, "): rms DTE ",
                                  1e6 * study.reference_summary.rms_dte_m, " um, max force ",
                                  study.reference_summary.max_force_N, " N, ",
                                  study.reference_stats.wall_time_s, " s; against its check (s=9): "
                                  "rms DTE ", study.check_rms_relative_difference, " relative, "
                                  "Poincare ", 1e6 * study.check_poincare_max_difference_m,
                                  " um, max force ", study.check_max_force_relative_difference,
                                  " relative"));
    std::ostringstream csv;
    csv << "integrator,stages,relative_tolerance,steps_per_period,wall_time_s,rhs_evals,steps,"
           "rms_dte_um,rms_dte_relative_error,poincare_max_error_um,poincare_relative_error,"
           "max_force_relative_error,status\n";
    csv.precision(6);
    for (const auto &p : study.points)
      csv << integrator_name(p.case_.kind) << ',' << (p.case_.stages > 0 ? msg(p.case_.stages) : "")
          << ',' << (p.case_.rtol > 0 ? msg(p.case_.rtol) : "")
          << ',' << (p.case_.steps_per_period > 0 ? msg(p.case_.steps_per_period) : "") << ','
          << p.stats.wall_time_s << ',' << p.stats.rhs_evals << ',' << p.stats.steps << ','
          << 1e6 * p.rms_dte_m << ',' << p.rms_relative_error << ',' << 1e6 * p.poincare_max_error_m
          << ',' << p.poincare_relative_error << ',' << p.max_force_relative_error << ','
          << csv_text(p.status) << '\n';
    if (ctx.out_dir.empty())
      std::cout << csv.str();
    else
      {
        PhaseTimer::Scope scope(timer, "write");
        RunDirectory      dir(ctx.out_dir, scene, ctx.command_line);
        dir.write_text("accuracy_dynamics.csv", csv.str());
        dir.finish(timer, {{"stage", "accuracy dynamics"},
                           {"reference_name", study.reference_name},
                           {"reference", nlohmann::json(study.reference_stats)},
                           {"reference_rms_dte_um", 1e6 * study.reference_summary.rms_dte_m},
                           {"reference_max_force_N", study.reference_summary.max_force_N},
                           {"reference_check_rms_relative_difference",
                            study.check_rms_relative_difference},
                           {"reference_check_poincare_max_difference_um",
                            1e6 * study.check_poincare_max_difference_m},
                           {"reference_check_max_force_relative_difference",
                            study.check_max_force_relative_difference}});
        draw_figure("plot_accuracy_dynamics.py", {(dir.path() / "accuracy_dynamics.csv").string(),
                                                  (dir.path() / "accuracy_dynamics.png").string()});
      }
    if (ctx.out_dir.empty())
      timer.print_summary(progress_stream());
    return 0;
  }
} // namespace hertzgear
