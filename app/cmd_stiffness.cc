// `hertzgear stiffness SCENE --out DIR`: loaded TCA over the mesh cycle with the FE bodies.
#include "app/analytic_stiffness.h"
#include "app/command.h"
#include "app/run_directory.h"
#include "app/stiffness_stage.h"

#include <deal.II/base/mpi.h>

#include <iostream>
#include <sstream>

namespace hertzgear
{
  namespace
  {
    int run_stiffness(const CommandContext &ctx)
    {
      // Under mpirun every rank runs the stage (collective); rank 0 alone reports and writes.
      std::ostringstream silent;
      if (!is_root_rank())
        set_progress_stream(&silent);
      PhaseTimer  timer;
      const Scene scene = load_scene(ctx.scene_file, ctx.overrides);
      const std::filesystem::path out = ctx.out_dir.empty() ? "results/stiffness" : ctx.out_dir;
      // A closed-form source is what the scene asks for: write its table, not an FE one.
      if (is_closed_form_source(scene.stiffness.source))
        {
          if (is_root_rank())
            {
              progress_line("stiffness", "Stiffness/source = " + scene.stiffness.source +
                                           ": the closed-form table, no meshing or FE "
                                           "(set Stiffness/source = fem for the FE contact analysis)");
              PhaseTimer::Scope scope(timer, "closed-form stiffness");
              const auto        a = analytic_stiffness(scene);
              RunDirectory      dir(out, scene, ctx.command_line);
              dir.write_text("stiffness.csv", a.csv);
              dir.write_json("stiffness.json", a.json);
              dir.finish(timer, {{"stage", "stiffness"}, {"source", scene.stiffness.source}});
              std::cout << "written to " << out.string() << std::endl;
            }
          set_progress_stream(nullptr);
          return 0;
        }
      StiffnessStageOptions options;
      if (scene.output.write_fields)
        options.fields_dir = out / "fields";
      const auto result = run_stiffness_stage(scene, out / "mesh", timer, options);
      const auto json   = stiffness_json(result, scene);
      if (is_root_rank())
        {
          RunDirectory dir(out, scene, ctx.command_line);
          dir.write_text("stiffness.csv", stiffness_csv(result, scene.stiffness.hertz_exponent));
          dir.write_json("stiffness.json", json);
        }
      // The fields folder appears complete, after the tables, or not at all.
      commit_stiffness_fields(result, out / "fields");
      if (is_root_rank())
        {
          RunDirectory dir(out, scene, ctx.command_line);
          std::cout << "mean k_total " << json["mean_k_total_N_per_m"].get<double>() << " N/m, "
                    << "k_mh " << json["mean_k_hertz_N_per_m_pow_n"].get<double>() << " N/m^n (n = "
                    << scene.stiffness.hertz_exponent << "), "
                    << "mean k_rest " << json["mean_k_rest_N_per_m"].get<double>() << " N/m, "
                    << "STE peak-to-peak " << json["ste_peak_to_peak_um"].get<double>() << " um\n"
                    << "written to " << out.string() << std::endl;
          dir.finish(timer, {{"stage", "stiffness"},
                             {"mpi_ranks", dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD)}});
        }
      set_progress_stream(nullptr);
      return 0;
    }
  } // namespace

  void add_accuracy_stiffness_command(CommandRegistry &registry, CLI::App *top);

  void add_stiffness_commands(CommandRegistry &registry)
  {
    CLI::App *sub = registry.add_command({"stiffness",
                          "Loaded tooth contact analysis over a mesh cycle (FE + half-space): "
                          "stiffness.csv, stiffness.json, fields/ (Output/write_fields); the "
                          "closed-form table when Stiffness/source is iso6336, hertz-analytic or potential-energy",
                          true, true},
                         run_stiffness);
    add_accuracy_stiffness_command(registry, sub->get_parent());
  }
} // namespace hertzgear
