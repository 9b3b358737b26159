#pragma once
// Running another program (the Python scripts that draw figures and the report) and waiting for
// it, with its output going where hertzgear's goes.
#include <string>
#include <vector>

namespace hertzgear
{
  // Runs argv[0] (looked up on PATH) with the arguments, inheriting stdout/stderr; returns its
  // exit status, 127 when it could not be started, -1 when it died of a signal. Throws
  // std::runtime_error when no process can be made or waited for.
  int run_process(const std::vector<std::string> &args);
} // namespace hertzgear
