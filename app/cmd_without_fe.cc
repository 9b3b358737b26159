// A build without the FE stage (cmake -DHERTZGEAR_WITH_FEM=OFF): the commands that need it keep
// their names and say, with exit code 2, that this build cannot run them.
#include "app/command.h"
#include "common/errors.h"

namespace hertzgear
{
  namespace
  {
    CommandAction needs_fe(const std::string &command)
    {
      return [command](const CommandContext &) -> int {
        throw InputError("`hertzgear " + command + "` needs the finite-element stage, and this "
                         "hertzgear was built without it (cmake -DHERTZGEAR_WITH_FEM=OFF); rebuild "
                         "with -DHERTZGEAR_WITH_FEM=ON (deal.II, PETSc, gmsh)");
      };
    }
  } // namespace

  void add_fe_commands(CommandRegistry &registry, CLI::App &top)
  {
    const std::string not_here = " (not in this build: it needs -DHERTZGEAR_WITH_FEM=ON)";
    registry.add_command({"mesh", "gmsh meshes of both bodies" + not_here, false, true},
                         needs_fe("mesh"))
      ->allow_extras();
    CLI::App *validate = command_group(top, "validate", "Validation studies against closed forms");
    registry.add_command({"hertz", "Resolved FE contact against Hertz" + not_here, false, true},
                         needs_fe("validate hertz"), validate)
      ->allow_extras();
    CLI::App *accuracy = command_group(top, "accuracy", "Work-precision studies: error versus time");
    registry.add_command({"stiffness", "FE refinement and contact-grid ladders" + not_here, false, true},
                         needs_fe("accuracy stiffness"), accuracy)
      ->allow_extras();
  }
} // namespace hertzgear
