// `hertzgear stiffness SCENE --out DIR`: loaded TCA over the mesh cycle with the FE bodies.
#include "app/command.h"
#include "app/run_directory.h"
#include "app/stiffness_stage.h"

#include <iostream>

namespace hertzgear
{
  namespace
  {
    int run_stiffness(const CommandContext &ctx)
    {
      PhaseTimer  timer;
      const Scene scene = load_scene(ctx.scene_file, ctx.overrides);
      const std::filesystem::path out = ctx.out_dir.empty() ? "results/stiffness" : ctx.out_dir;
      const auto   result = run_stiffness_stage(scene, out / "mesh", timer);
      RunDirectory dir(out, scene, ctx.command_line);
      dir.write_text("stiffness.csv", stiffness_csv(result, scene.stiffness.hertz_exponent));
      const auto json = stiffness_json(result, scene);
      dir.write_json("stiffness.json", json);
      std::cout << "mean k_total " << json["mean_k_total_N_per_m"].get<double>() << " N/m, "
                << "k_mh " << json["mean_k_hertz_N_per_m_pow_n"].get<double>() << " N/m^n (n = "
                << scene.stiffness.hertz_exponent << "), "
                << "mean k_rest " << json["mean_k_rest_N_per_m"].get<double>() << " N/m, "
                << "STE peak-to-peak " << json["ste_peak_to_peak_um"].get<double>() << " um\n"
                << "written to " << out.string() << std::endl;
      dir.finish(timer, {{"stage", "stiffness"}});
      return 0;
    }
  } // namespace

  void add_stiffness_commands(CommandRegistry &registry)
  {
    registry.add_command({"stiffness",
                          "Loaded tooth contact analysis over a mesh cycle (FE + half-space): "
                          "stiffness.csv, stiffness.json",
                          true, true},
                         run_stiffness);
  }
} // namespace hertzgear
