#pragma once
// The Python scripts of hertzgear (figures drawn with matplotlib): where they are found and how
// they are run (by common/child_process.h). Used by `report`, `run` and the accuracy and
// validation studies.
#include <filesystem>
#include <string>
#include <vector>

namespace hertzgear
{
  // Where a bundled file or folder may be, in order: $ENV_OVERRIDE when that variable is given
  // and set, then `installed` under the install prefix of this executable (<prefix>/bin/hertzgear
  // -> <prefix>/share/hertzgear/installed), then `in_source` in the source tree the program was
  // built from.
  std::vector<std::filesystem::path> bundled_locations(const char                  *env_override,
                                                       const std::filesystem::path &installed,
                                                       const std::filesystem::path &in_source);

  // scripts/NAME at the first of its bundled locations. Throws with the list of places searched.
  std::filesystem::path find_script(const std::string &name, const char *env_override = nullptr);

  // Debian's python3 carries python3-matplotlib; a python3 found first on PATH (a virtual
  // environment, pyenv) often does not. $HERTZGEAR_PYTHON overrides both.
  std::string find_python();

  // Draws a figure of a study with scripts/SCRIPT (arguments: input files, output PNG). A figure
  // is a convenience of a table that is already written: when Python, matplotlib or the script is
  // missing, or the script fails, a warning goes to the progress stream and false is returned.
  bool draw_figure(const std::string &script, const std::vector<std::string> &args);
} // namespace hertzgear
