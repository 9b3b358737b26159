#pragma once
// Work that one MPI rank does for all (gmsh, the file system), with its errors shared: an
// exception on rank 0 is re-thrown on every rank with its kind (its exit code) and text, so that
// no rank waits forever in the next collective call.
#include <mpi.h>

#include <functional>

namespace hertzgear::fem
{
  // Runs `work` on rank 0 of `comm` only; collective.
  void on_root(MPI_Comm comm, const std::function<void()> &work);
} // namespace hertzgear::fem
