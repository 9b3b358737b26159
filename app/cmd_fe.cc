// The commands that need the FE stage, registered together (FE build).
#include "app/cmd_validate_hertz.h"
#include "app/command.h"

namespace hertzgear
{
  void add_mesh_command(CommandRegistry &registry);
  void add_accuracy_stiffness_command(CommandRegistry &registry, CLI::App *top);

  void add_fe_commands(CommandRegistry &registry, CLI::App &top)
  {
    add_mesh_command(registry);
    add_validation_commands(registry, top);
    add_accuracy_stiffness_command(registry, &top);
  }
} // namespace hertzgear
