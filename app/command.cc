#include "app/command.h"

#include "app/scene.h"
#include "common/progress.h"

namespace hertzgear
{
  Scene load_scene(const CommandContext &ctx, PhaseTimer &timer)
  {
    PhaseTimer::Scope scope(timer, "scene");
    return load_scene(ctx.scene_file, ctx.overrides);
  }

  CLI::App *CommandRegistry::add_command(const CommandSpec &spec, CommandAction action,
                                         CLI::App *parent)
  {
    CLI::App *owner   = parent ? parent : &app;
    auto      context = std::make_shared<CommandContext>();
    CLI::App *sub     = owner->add_subcommand(spec.name, spec.description);
    if (spec.scene_allowed)
      {
        auto *opt = sub->add_option("scene", context->scene_file,
                                    "Scene file (.prm or .json)");
        if (spec.scene_required)
          opt->required();
      }
    sub->add_option("--set", context->overrides,
                    "Override a scene value: \"Section/Subsection/key=value\" (repeatable)")
      ->allow_extra_args(false);
    sub->add_option("--out", context->out_dir, "Output directory for the artifacts");
    entries.push_back({sub, std::move(action), context});
    return sub;
  }

  CLI::App *command_group(CLI::App &top, const std::string &name, const std::string &description)
  {
    for (CLI::App *sub : top.get_subcommands([&](CLI::App *a) { return a->get_name() == name; }))
      return sub;
    CLI::App *group = top.add_subcommand(name, description);
    group->require_subcommand(1);
    return group;
  }

  std::function<int()> CommandRegistry::chosen() const
  {
    for (const auto &e : entries)
      if (e.sub->parsed())
        {
          // Nested commands: the deepest parsed one wins (its parent has no action of its own).
          bool child_parsed = false;
          for (const auto &other : entries)
            if (other.sub != e.sub && other.sub->get_parent() == e.sub && other.sub->parsed())
              child_parsed = true;
          if (!child_parsed)
            return [e, line = command_line]() {
              CommandContext context = *e.context;
              context.command_line   = line;
              return e.action(context);
            };
        }
    return {};
  }
} // namespace hertzgear
