#include "app/command.h"

#include "app/scene.h"
#include "app/scene_keys.h"
#include "common/errors.h"
#include "common/folder_lock.h"
#include "common/processes.h"
#include "common/progress.h"

#ifdef HERTZGEAR_WITH_FEM
#  include <deal.II/base/exceptions.h>
#endif

#include <sstream>

namespace hertzgear
{
  Scene load_scene(const CommandContext &ctx, PhaseTimer &timer)
  {
    PhaseTimer::Scope scope(timer, "scene");
    return load_scene(ctx.scene_file, ctx.overrides);
  }

  std::string FailureReport::line() const
  {
    return std::string("hertzgear: ") +
           (exit_code == exit_bad_input ? "input error" :
            exit_code == exit_numerical ? "numerical failure" :
                                          "error") +
           ": " + text;
  }

  FailureReport describe_failure(const std::exception_ptr &failure)
  {
    try
      {
        std::rethrow_exception(failure);
      }
    catch (const ParameterError &e)
      {
        return {exit_bad_input, scene_message(e)};
      }
    catch (const InputError &e)
      {
        return {exit_bad_input, with_scene_keys(e.what())};
      }
    catch (const NumericalError &e)
      {
        return {exit_numerical, with_scene_keys(e.what())};
      }
#ifdef HERTZGEAR_WITH_FEM
    catch (const dealii::ExceptionBase &e)
      {
        std::ostringstream info;
        e.print_info(info);
        return {exit_other, info.str()};
      }
#endif
    catch (const std::exception &e)
      {
        return {exit_other, e.what()};
      }
    catch (...)
      {
        return {exit_other, "an unknown exception"};
      }
  }

  CommandStart::CommandStart()  = default;
  CommandStart::~CommandStart() = default;

  void CommandStart::begin(const std::vector<std::filesystem::path> &folders, const std::string &role)
  {
    std::vector<std::pair<std::filesystem::path, std::string>> with_roles;
    for (const auto &folder : folders)
      with_roles.emplace_back(folder, role);
    begin(with_roles);
  }

  void CommandStart::begin(const std::vector<std::pair<std::filesystem::path, std::string>> &folders)
  {
    if (done)
      throw std::logic_error("CommandStart::begin: the command has started already");
    done = true; // settled from here on, whatever follows: the ranks take the same calls below
    // Every rank's checks passed (a rank that failed before this point shares its failure from
    // fail_before_start in the same collective call) ...
    processes::agree([] {});
    // ... then rank 0 locks the folders for all.
    processes::agree(
      [&] {
        for (const auto &[folder, role] : folders)
          if (!FolderLock::held_here(folder))
            locks.push_back(std::make_unique<FolderLock>(folder, role));
      },
      true);
  }

  void CommandStart::pass_at_end()
  {
    if (done)
      return;
    done = true;
    processes::agree([] {});
  }

  void CommandStart::fail_before_start(const std::exception_ptr &failure)
  {
    done = true;
    if (processes::count() == 1)
      std::rethrow_exception(failure);
    // The text main would print, shared: every rank throws it, rank 0 prints it.
    const FailureReport report = describe_failure(failure);
    processes::agree([&] { throw_for_exit_code(report.exit_code, report.text); });
    throw std::logic_error("CommandStart::fail_before_start: the failure was not shared");
  }

  void begin_on_out(const CommandContext &ctx)
  {
    if (ctx.out_dir.empty())
      ctx.start->begin();
    else
      ctx.start->begin({ctx.out_dir});
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
              // Every command passes its start (CommandStart) exactly once on every rank.
              CommandContext context = *e.context;
              context.command_line   = line;
              context.start          = std::make_shared<CommandStart>();
              int code               = 0;
              try
                {
                  code = e.action(context);
                }
              catch (...)
                {
                  if (!context.start->passed())
                    context.start->fail_before_start(std::current_exception());
                  throw;
                }
              context.start->pass_at_end();
              return code;
            };
        }
    return {};
  }
} // namespace hertzgear
