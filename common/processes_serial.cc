// One process: the build without the FE stage has no MPI.
#include "common/processes.h"

namespace hertzgear::processes
{
  namespace
  {
    bool shared_failure = false;
  }

  int  rank() { return 0; }
  int  count() { return 1; }
  bool is_root() { return true; }

  std::vector<std::string> all_gather(const std::string &mine) { return {mine}; }
  std::string              broadcast(const std::string &from_root) { return from_root; }

  void agree(const std::function<void()> &step, bool) { step(); }

  void mark_failure_shared() { shared_failure = true; }
  bool failure_is_shared() { return shared_failure; }
  void abort_all(int) {}
  void end_with_exit_code_on_fatal_signals() {}
} // namespace hertzgear::processes
