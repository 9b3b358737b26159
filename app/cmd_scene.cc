// `hertzgear check SCENE` and `hertzgear defaults`.
#include "app/command.h"
#include "app/pipeline.h"
#include "app/run_directory.h"
#include "app/scene.h"
#include "common/processes.h"

#include <iostream>

namespace hertzgear
{
  namespace
  {
    int run_check(const CommandContext &ctx)
    {
      PhaseTimer  timer;
      const Scene scene = load_scene(ctx, timer);
      {
        // Exactly what `run` checks before it makes a folder: impossible geometry (undercut,
        // pointed tip, interference, eps_alpha < 1, jamming centre distance, ...), the stiffness
        // source's input and, for a table or Fourier source, the dynamics set-up.
        PhaseTimer::Scope scope(timer, "checks");
        check_run_inputs(scene);
      }
      begin_on_out(ctx);
      if (!processes::is_root())
        return 0;
      std::cout << "# scene " << scene.file.string() << " is valid (hash " << scene.hash << ")\n"
                << "# resolved parameters:\n"
                << scene.used_parameters_prm;
      if (!ctx.out_dir.empty())
        RunDirectory(ctx.out_dir, scene, ctx.command_line).finish(timer);
      return 0;
    }

    int run_defaults(const CommandContext &ctx, bool markdown)
    {
      std::string text;
      if (markdown)
        text = scene_reference_markdown();
      else if (ctx.overrides.empty())
        text = default_scene_prm();
      else
        text = load_scene("", ctx.overrides).used_parameters_prm;
      begin_on_out(ctx);
      if (!processes::is_root())
        return 0;
      if (!ctx.out_dir.empty())
        {
          const Scene scene = load_scene("", ctx.overrides);
          RunDirectory dir(ctx.out_dir, scene, ctx.command_line);
          dir.write_text(markdown ? "scenes.md" : "default_scene.prm", text);
        }
      else
        std::cout << text;
      return 0;
    }
  } // namespace

  void add_scene_commands(CommandRegistry &registry)
  {
    registry.add_command({"check", "Validate a scene and print the resolved parameters", true, true},
                         run_check);
    auto markdown = std::make_shared<bool>(false);
    CLI::App *defaults = registry.add_command(
      {"defaults", "Print a fully documented default scene", false, false},
      [markdown](const CommandContext &ctx) { return run_defaults(ctx, *markdown); });
    defaults->add_flag("--markdown", *markdown,
                       "Print the scene reference as Markdown (docs/scenes.md) instead");
  }
} // namespace hertzgear
