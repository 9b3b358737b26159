// `hertzgear accuracy dynamics SCENE --out DIR [--integrators a,b] [--tightest-rtol 1e-12]`: what
// accuracy costs in time, per integrator. Every integrator (radau-iia with 3, 5, 7 and 9 stages)
// runs the scene at rtol 1e-4 ... 1e-12 (fixed steps for rk4); errors are measured against a
// converged reference (dynamics/work_precision.h). Writes accuracy_dynamics.csv and, when python3
// with matplotlib is available, accuracy_dynamics.png.
#include "app/cmd_dynamics.h"
#include "app/run_directory.h"
#include "app/scripts.h"
#include "common/errors.h"
#include "common/processes.h"
#include "common/progress.h"
#include "dynamics/result_writer.h"
#include "dynamics/work_precision.h"

#include <filesystem>
#include <iostream>

namespace hertzgear
{
  using namespace dynamics;

  namespace
  {
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
    const auto          cases = work_precision_cases(setup.parameters.damping_N_s_per_m == 0.0,
                                                     options.tightest_rtol, options.integrators);
    begin_on_out(ctx);
    if (!processes::is_root())
      return 0; // one process's study: rank 0's
    WorkPrecisionStudy study;
    {
      PhaseTimer::Scope scope(timer, "reference and ladder");
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
    const std::string csv = work_precision_csv(study);
    if (ctx.out_dir.empty())
      std::cout << csv;
    else
      {
        PhaseTimer::Scope scope(timer, "write");
        RunDirectory      dir(ctx.out_dir, scene, ctx.command_line);
        dir.write_text("accuracy_dynamics.csv", csv);
        nlohmann::json record = work_precision_reference_json(study);
        record["stage"]       = "accuracy dynamics";
        dir.finish(timer, record);
        draw_figure("plot_accuracy_dynamics.py", {(dir.path() / "accuracy_dynamics.csv").string(),
                                                  (dir.path() / "accuracy_dynamics.png").string()});
      }
    if (ctx.out_dir.empty())
      timer.print_summary(progress_stream());
    return 0;
  }
} // namespace hertzgear
