#pragma once
// The processes of one hertzgear run. Under mpirun (a build with the FE stage) every rank runs the
// command: the FE stiffness is collective and sweep points are shared out; rank 0 alone writes
// files and progress. A build without the FE stage, or a run without mpirun, is one process.
//
// Failures between processes (docs/architecture.md, "Under mpirun"): a failure that every rank
// knows — decided on one rank and shared, or the first of several ranks' outcomes of one step —
// is *shared*: every rank ends with its exit code and rank 0 alone prints it. A failure on one
// rank alone after the command's start ends the whole job (abort_all), so that no rank waits for
// a collective call that another rank has left.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace hertzgear::processes
{
  int  rank();
  int  count();
  bool is_root();
  // Every process's text, in rank order (collective).
  std::vector<std::string> all_gather(const std::string &mine);
  // Rank 0's text on every rank (collective).
  std::string broadcast(const std::string &from_root);

  // Runs `step` on every rank (on rank 0 alone with `root_only`) and shares its outcome
  // (collective): when a rank's step throws, every rank throws the failure of the lowest such
  // rank — that rank its own exception, the others the exception of its exit code with its text
  // (common/errors.h) — and the failure is marked shared.
  void agree(const std::function<void()> &step, bool root_only = false);

  // Marks the failure being thrown as known to every rank (main then prints it on rank 0 only and
  // every rank returns its exit code). For code that shares failures by its own collective calls.
  void mark_failure_shared();
  bool failure_is_shared();

  // Ends every rank of the job with `exit_code` (MPI_Abort); returns only in a single process.
  void abort_all(int exit_code);

  // Under mpirun with more than one rank: a rank ended by a fatal signal it can catch (SIGTERM
  // from a batch system or from mpirun ending the job, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT,
  // SIGXCPU, SIGHUP) says so on stderr, naming its rank and the signal, and exits with 3 (a
  // numerical failure: the run has no result), so that mpirun ends the other ranks and the job
  // exits with 3. Nothing is written: files become visible only by a rename at their end
  // (common/atomic_file.h). SIGKILL cannot be caught (mpirun then reports the killed rank with
  // its own status, 137). Call once, after MPI is initialised; a no-op in a single process.
  void end_with_exit_code_on_fatal_signals();

  // Independent units of work shared out over `count` processes by their expected work (any
  // measure that grows with it): largest first, each to the process with the least of it so far
  // (the longest-processing-time rule: the busiest process ends at most 4/3 of the best possible,
  // and at most the largest unit above the mean). A tie goes to the process with the least
  // `earlier_work` (the work each did before, in any unit; none: all equal), then to the lowest
  // rank. Returns the process of each unit. The same inputs give the same shares on every rank,
  // so every rank knows who solves what without a message.
  std::vector<std::size_t> share_by_work(const std::vector<double> &work, std::size_t count,
                                         const std::vector<double> &earlier_work = {});
} // namespace hertzgear::processes
