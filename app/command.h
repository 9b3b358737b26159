#pragma once
// The command registry of the `hertzgear` program. Each command file adds its sub-command with
// `add_command`; main() parses, runs the chosen action and maps exceptions to exit codes.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace hertzgear
{
  class FolderLock;
  class PhaseTimer;
  struct Scene;

  // The start of every command, the one place where the processes of a run agree before any of
  // them writes or computes (docs/architecture.md, "Under mpirun"). Under mpirun every rank runs
  // the command. A command calls begin() once, after its checks and before its first write or
  // long computation: every rank's outcome so far is shared (a refusal on any rank ends every
  // rank with its exit code, and rank 0 alone prints it), then rank 0 takes the lock of each
  // output folder (FolderLock, held until the command ends) and shares that outcome too, so a
  // busy folder ends all ranks with exit 2 at once. The registry runs every command through it:
  // a command that fails before begin(), or that writes nothing and never calls it, passes the
  // start when it ends, so that no rank waits for another. A failure after the start on one
  // rank alone ends the whole job (main: processes::abort_all).
  class CommandStart
  {
  public:
    CommandStart();
    ~CommandStart();
    // Shares the checks' outcome and locks `folders` (after `role`, the option that named them).
    void begin(const std::vector<std::filesystem::path> &folders = {},
               const std::string                        &role    = "--out");
    // The same with a role per folder (a folder this process holds already is skipped).
    void begin(const std::vector<std::pair<std::filesystem::path, std::string>> &folders);
    bool passed() const { return done; }

    // For the registry: the command ended (successfully) without begin(), or failed before it
    // with the exception in flight; the latter shares the failure and throws it on every rank.
    void pass_at_end();
    [[noreturn]] void fail_before_start(const std::exception_ptr &failure);

  private:
    bool                                     done = false;
    std::vector<std::unique_ptr<FolderLock>> locks;
  };

  // What every command accepts.
  struct CommandContext;
  // The command's start with its --out folder, when it has one.
  void begin_on_out(const CommandContext &ctx);

  // What every command accepts.
  struct CommandContext
  {
    std::string              scene_file; // may be empty where the command allows it
    std::vector<std::string> overrides;  // --set "Section/key=value", in order
    std::string              out_dir;    // --out DIR (may be empty)
    std::string              command_line;
    // The command's start (see CommandStart); set by the registry for every command.
    std::shared_ptr<CommandStart> start;
  };

  // How a failure ends the program: its exit code and its text, with scene keys in place of
  // library field names; line() is what main prints ("hertzgear: input error: <text>").
  struct FailureReport
  {
    int         exit_code = 1;
    std::string text;
    std::string line() const;
  };
  FailureReport describe_failure(const std::exception_ptr &failure);

  using CommandAction = std::function<int(const CommandContext &)>;

  // The scene of a command (SCENE with its --set overrides), loaded in the phase "scene" of
  // `timer`.
  Scene load_scene(const CommandContext &ctx, PhaseTimer &timer);

  struct CommandSpec
  {
    std::string name;
    std::string description;
    bool        scene_required = true; // positional SCENE
    bool        scene_allowed  = true;
  };

  class CommandRegistry
  {
  public:
    explicit CommandRegistry(CLI::App &app) : app(app) {}

    // Adds `name` under `parent` (the top-level app unless given) with SCENE, --set and --out.
    // Returns the CLI11 sub-command so the caller can add its own flags.
    CLI::App *add_command(const CommandSpec &spec, CommandAction action, CLI::App *parent = nullptr);

    // The action of the parsed command, or an empty function if none was chosen.
    std::function<int()> chosen() const;

    // The whole command line, recorded in run.json.
    std::string command_line;

  private:
    struct Entry
    {
      CLI::App                       *sub;
      CommandAction                   action;
      std::shared_ptr<CommandContext> context;
    };
    CLI::App          &app;
    std::vector<Entry> entries;
  };

  // The group command NAME under `top` (e.g. `accuracy`, `validate`), created with DESCRIPTION by
  // the first stage that registers a command in it; it requires one of its sub-commands.
  CLI::App *command_group(CLI::App &top, const std::string &name, const std::string &description);

  // Registration functions, one per command file.
  void add_scene_commands(CommandRegistry &registry); // check, defaults
  void add_dynamics_commands(CommandRegistry &registry); // dynamics, sweep, accuracy dynamics
  void add_response_command(CommandRegistry &registry);  // response
  void add_geometry_commands(CommandRegistry &registry); // geometry
  void add_report_command(CommandRegistry &registry); // report
  void add_stiffness_commands(CommandRegistry &registry); // stiffness
  void add_run_command(CommandRegistry &registry); // run (app/cmd_run.cc, app/pipeline.h)
  // The commands that need the FE stage: mesh, validate hertz, accuracy stiffness. A build without
  // it (cmake -DHERTZGEAR_WITH_FEM=OFF) declares the same names, which say so and exit 2
  // (app/cmd_without_fe.cc).
  void add_fe_commands(CommandRegistry &registry, CLI::App &top);

  // Figures and DIR/report/index.html (or report_dir) from the artifacts in run_dir; returns the
  // exit code (2 when run_dir holds no artifact). Used by `report` and at the end of `run`.
  // `compared`: other runs' folders whose periodic orbits the response figure draws beside.
  int write_report(const std::filesystem::path &run_dir,
                   const std::filesystem::path &report_dir = {},
                   const std::vector<std::filesystem::path> &compared = {});
} // namespace hertzgear
