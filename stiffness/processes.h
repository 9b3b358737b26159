#pragma once
// The processes of a stiffness computation. Under mpirun every rank computes an FE source
// (collective) and rank 0 alone writes files and prints progress; a build without the FE stage
// runs one process.
namespace hertzgear::stiffness
{
  bool is_writing_process();
  int  n_processes();
} // namespace hertzgear::stiffness
