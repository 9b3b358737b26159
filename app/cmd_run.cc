// `hertzgear run [SCENE] [--out DIR]`: the whole chain from one scene, cached.
//
//   hertzgear run                                   -> results/paper/{paper_uncrowned,paper_crowned}
//   hertzgear run data/scenes/paper_crowned.prm --out results/crowned
//   hertzgear run my_scene.prm --out r --set Dynamics/damping_ratio=0.02   (reruns only dynamics)
//
// The stages follow from the scene (app/pipeline.h); a second run reuses every stage whose key
// and artifacts verify. Without a scene it runs the bundled paper scenes, whose stiffness comes
// from the tables shipped in data/stiffness/ (data/scenes/paper_*_table.prm).
#include "app/command.h"
#include "app/pipeline.h"
#include "app/scripts.h"
#include "common/errors.h"
#include "common/processes.h"
#include "common/progress.h"

#include <chrono>
#include <iostream>

namespace hertzgear
{
  namespace fs = std::filesystem;

  namespace
  {
    // The bundled data: $HERTZGEAR_DATA_DIR, the install prefix of this executable
    // (<prefix>/bin/hertzgear -> <prefix>/share/hertzgear/), then the source tree.
    fs::path data_dir()
    {
      for (const auto &c : bundled_locations("HERTZGEAR_DATA_DIR", "", "data"))
        if (fs::is_regular_file(c / "scenes" / "paper_crowned_table.prm"))
          return c;
      throw std::runtime_error("cannot find the bundled scenes (data/scenes/paper_*_table.prm); "
                               "set HERTZGEAR_DATA_DIR to the data folder");
    }

    int run_run(const CommandContext &ctx, const PipelineOptions &options)
    {
      const QuietOtherRanks quiet; // rank 0 tells the progress
      const auto            start = std::chrono::steady_clock::now();
      // Scene file -> run directory. Every scene is parsed and checked before anything runs.
      std::vector<std::pair<Scene, fs::path>> jobs;
      if (!ctx.scene_file.empty())
        {
          Scene scene = load_scene(ctx.scene_file, ctx.overrides);
          const fs::path out =
            ctx.out_dir.empty() ? fs::path("results") / fs::path(ctx.scene_file).stem() :
                                  fs::path(ctx.out_dir);
          jobs.emplace_back(std::move(scene), out);
        }
      else
        {
          const fs::path data = data_dir();
          const fs::path out  = ctx.out_dir.empty() ? fs::path("results/paper") : fs::path(ctx.out_dir);
          for (const std::string name : {"paper_uncrowned", "paper_crowned"})
            jobs.emplace_back(load_scene(data / "scenes" / (name + "_table.prm"), ctx.overrides),
                              out / name);
          progress_line("run", "no scene given: the bundled paper scenes " +
                                 (data / "scenes" / "paper_{uncrowned,crowned}_table.prm").string() +
                                 " on the shipped stiffness tables");
        }
      // Every check before any folder is made, then every folder locked for the whole run.
      std::vector<fs::path> folders;
      for (const auto &[scene, out] : jobs)
        {
          check_run_inputs(scene);
          folders.push_back(out);
        }
      ctx.start->begin(folders);
      for (const auto &[scene, out] : jobs)
        {
          const auto outcomes = run_pipeline(scene, out, ctx.command_line, options);
          if (!processes::is_root())
            continue;
          int ran = 0;
          for (const auto &o : outcomes)
            ran += o.ran;
          std::cout << out.string() << ": " << ran << " of " << outcomes.size()
                    << " stages ran";
          if (scene.output.report)
            std::cout << ", report " << (out / "report" / "index.html").string();
          std::cout << std::endl;
        }
      progress_line("run", msg("done in ",
                               std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
                                 .count(),
                               " s"));
      return 0;
    }
  } // namespace

  void add_run_command(CommandRegistry &registry)
  {
    auto      options = std::make_shared<PipelineOptions>();
    CLI::App *run     = registry.add_command(
      {"run",
       "The whole chain from one scene (stiffness, dynamics, sweep, report), reusing cached "
       "stages; without a scene, the bundled paper scenes",
       false, true},
      [options](const CommandContext &ctx) { return run_run(ctx, *options); });
    run->add_flag("--force", options->force, "Rerun every stage, whatever the cache says");
    run->add_option("--threads", options->sweep_threads,
                    "Threads for the sweep jobs (0 = all hardware threads)");
  }
} // namespace hertzgear
