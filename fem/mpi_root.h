#pragma once
// Work that one MPI rank does for all (gmsh, the file system), or that each rank does on its own
// part, with its errors shared: an exception on one rank is re-thrown on every rank with its kind (its exit code) and text, so that
// no rank waits forever in the next collective call.
#include <mpi.h>

#include <functional>

namespace hertzgear::fem
{
  // Runs `work` on rank 0 of `comm` only; collective.
  void on_root(MPI_Comm comm, const std::function<void()> &work);
  // Runs `work` on every rank (each its own part of independent work); collective: if any rank
  // failed, every rank throws the failure of the lowest such rank.
  void on_every_rank(MPI_Comm comm, const std::function<void()> &work);
} // namespace hertzgear::fem
