#pragma once
// The processes of one hertzgear run. Under mpirun (a build with the FE stage) every rank runs the
// command: the FE stiffness is collective and sweep points are shared out; rank 0 alone writes
// files and progress. A build without the FE stage, or a run without mpirun, is one process.
#include <string>
#include <vector>

namespace hertzgear::processes
{
  int  rank();
  int  count();
  bool is_root();
  // Every process's text, in rank order (collective).
  std::vector<std::string> all_gather(const std::string &mine);
} // namespace hertzgear::processes
