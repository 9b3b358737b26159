// hertzgear — finite-element contact stiffness and gear-pair dynamics from one scene file.
//
//   hertzgear check data/scenes/paper_crowned.prm
//   hertzgear check data/scenes/paper_crowned.prm --set "Gear pair/Pinion/crowning_um=40"
//   hertzgear defaults > my_scene.prm
//
// Exit codes: 0 success, 2 bad input (scene, arguments, geometry), 3 numerical failure,
// 1 anything else.
#include "app/command.h"
#include "app/scene_keys.h"
#include "common/errors.h"
#include "common/processes.h"

#include <hertzgear/version.h>

#ifdef HERTZGEAR_WITH_FEM
#  include <deal.II/base/mpi.h>

#  include "fem/petsc_ksp.h"
#endif

#include <iostream>

int main(int argc, char **argv)
{
  using namespace hertzgear;
  // MPI and PETSc for the FE stage (and sweeps over ranks); one deal.II thread per rank: deal.II's
  // worker threads (WorkStream in DataOut, KellyErrorEstimator) read PETSc vectors concurrently,
  // which is not thread-safe and aborted a resolved-contact run when they were allowed.
#ifdef HERTZGEAR_WITH_FEM
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  // Ranks on one node share its cores: BLAS threads per rank = cores / ranks.
  fem::share_blas_threads_between_ranks(MPI_COMM_WORLD);
  // A rank ended by a signal ends the job with exit 3 (a rank killed by SIGKILL cannot).
  processes::end_with_exit_code_on_fatal_signals();
#endif
  CLI::App app{"hertzgear: finite-element contact stiffness and gear-pair dynamics", "hertzgear"};
  app.set_version_flag("--version",
                       std::string("hertzgear ") + version + " (git " + git_revision + ")");
  app.require_subcommand(1);

  CommandRegistry registry(app);
  for (int i = 0; i < argc; ++i)
    registry.command_line += (i ? " " : "") + std::string(argv[i]);
  add_scene_commands(registry);
  add_dynamics_commands(registry);
  add_response_command(registry);
  add_geometry_commands(registry);
  add_report_command(registry);
  add_stiffness_commands(registry);
  add_fe_commands(registry, app);
  add_run_command(registry);

  // CLI11 would call an unknown command "extra positional arguments"; name it instead.
  if (argc > 1 && argv[1][0] != '-')
    {
      bool known = false;
      for (const CLI::App *sub : app.get_subcommands({}))
        known = known || sub->check_name(argv[1]);
      if (!known)
        {
          if (processes::is_root())
            std::cerr << "hertzgear: error: unknown command \"" << argv[1]
                    << "\" (see hertzgear --help)" << std::endl;
          return exit_bad_input;
        }
    }

  try
    {
      app.parse(argc, argv);
    }
  catch (const CLI::CallForHelp &e)
    {
      return app.exit(e);
    }
  catch (const CLI::CallForAllHelp &e)
    {
      return app.exit(e);
    }
  catch (const CLI::CallForVersion &e)
    {
      return app.exit(e);
    }
  catch (const CLI::ParseError &e)
    {
      if (processes::is_root())
        std::cerr << "hertzgear: error: " << e.what() << "\n(see hertzgear --help)" << std::endl;
      return exit_bad_input;
    }

  try
    {
      const auto action = registry.chosen();
      if (!action)
        {
          if (processes::is_root())
            std::cerr << "hertzgear: error: no command given (see hertzgear --help)" << std::endl;
          return exit_bad_input;
        }
      return action();
    }
  catch (...)
    {
      const FailureReport failure = describe_failure(std::current_exception());
      // Under mpirun a failure every rank knows (a refusal at the command's start, a failure the
      // ranks shared) ends every rank with its exit code and rank 0 prints it; a failure on one
      // rank alone ends the whole job, so that no rank waits for it in a collective call.
      if (processes::count() > 1 && !processes::failure_is_shared())
        {
          std::cerr << failure.line() << " (rank " << processes::rank() << " of "
                    << processes::count() << "; ending every rank)" << std::endl;
          processes::abort_all(failure.exit_code);
        }
      if (processes::is_root())
        std::cerr << failure.line() << std::endl;
      return failure.exit_code;
    }
}
