// `hertzgear stiffness SCENE --out DIR`: the scene's stiffness source over the mesh cycle
// (stiffness.csv, stiffness.json; an FE source also mesh/ and fields/).
#include "app/command.h"
#include "app/run_directory.h"
#include "app/stiffness_setup.h"
#include "common/processes.h"
#include "common/stage_cache.h"
#include "stiffness/table_writer.h"

#include <iostream>
#include <sstream>

namespace hertzgear
{
  namespace
  {
    int run_stiffness(const CommandContext &ctx)
    {
      // Under mpirun every rank runs an FE source (collective); rank 0 alone reports and writes.
      const QuietOtherRanks quiet;
      const bool            writer = processes::is_root();
      PhaseTimer  timer;
      const Scene scene  = load_scene(ctx.scene_file, ctx.overrides);
      const auto &source = stiffness_source(scene);
      check_stiffness_input(scene);
      const std::filesystem::path out = ctx.out_dir.empty() ? "results/stiffness" : ctx.out_dir;
      ctx.start->begin({out});
      if (!source.uses_fe() && !writer)
        return 0; // a closed form: rank 0's
      if (!source.uses_fe())
        progress_line("stiffness", "Stiffness/source = " + source.name() + ": " + source.summary() +
                                     ", no meshing or FE (set Stiffness/source = fem for the FE "
                                     "contact analysis)");
      const RunDirectory dir(out, scene, ctx.command_line);
      if (writer)
        remove_partial_files(out); // what an interrupted run left under temporary names
      // The previous run's record leaves with its table: a table is never beside the
      // used_parameters.prm and run.json of another run (they follow it at the end).
      const auto result = write_stiffness(scene, dir, scene.output.write_fields, timer,
                                          {"used_parameters.prm", "run.json"});
      if (writer)
        {
          const double n = scene.stiffness.hertz_exponent;
          std::cout << "mean k_total " << result.k_total_N_per_m.mean << " N/m, "
                    << "k_mh " << result.table.k_hertz_N_per_m_pow_n.mean << " N/m^n (n = " << n
                    << "), mean k_rest " << result.mean_k_rest_N_per_m << " N/m, "
                    << "STE peak-to-peak " << stiffness::ste_peak_to_peak_um(result) << " um\n"
                    << "written to " << out.string() << std::endl;
          dir.finish(timer, {{"stage", "stiffness"},
                             {"source", source.name()},
                             {"mpi_ranks", processes::count()}});
        }
      return 0;
    }
  } // namespace

  void add_stiffness_commands(CommandRegistry &registry)
  {
    registry.add_command({"stiffness",
                          "The scene's stiffness source over a mesh cycle: stiffness.csv, "
                          "stiffness.json; with Stiffness/source = fem the loaded tooth contact "
                          "analysis (FE + half-space), its meshes and fields/ (Output/write_fields)",
                          true, true},
                         run_stiffness);
  }
} // namespace hertzgear
