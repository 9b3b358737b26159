#pragma once
// Cores lent between two ranks that each work on a body of their own.
//
// Under `mpirun -np 2` each gear of a pair is built and tabulated by its own rank, with half the
// node's cores for its dense kernels (OpenBLAS under MUMPS and LAPACK,
// share_blas_threads_between_ranks). The gears differ in size, so one rank finishes first and
// would then wait, its cores idle, for the other. Instead it tells the other rank that it is
// done and waits without spinning (a test of the message every millisecond); the other rank,
// at its next unit of work (a block of interior solves, a cyclic harmonic: `poll`), takes every
// core of the node for its OpenBLAS threads. Each rank goes back to its share when both are done.
//
// The exchange is one message each way between ranks 0 and 1 of `comm`; it is active only when
// `comm` has exactly two ranks on one node and OpenBLAS is the BLAS. Then every thread of the
// process may run on every core of the node (mpirun's default binding of each rank to one core
// would keep a lent core out of reach); the thread counts share the cores out. Otherwise every call is a
// no-op. `finish` must be called on both ranks (also after a failure of the rank's own work: it
// does not throw), before any collective call of `comm`.
#include <mpi.h>

namespace hertzgear::fem
{
  class CoreLending
  {
  public:
    explicit CoreLending(MPI_Comm comm);
    ~CoreLending();
    CoreLending(const CoreLending &) = delete;
    CoreLending &operator=(const CoreLending &) = delete;

    // Between units of this rank's own work: once the partner has finished, take its cores.
    void poll();
    // This rank's own work is done (or failed): tell the partner (announce, once), wait for it,
    // and go back to this rank's share of the cores (finish). A rank may announce first and do
    // other work before it finishes (help the partner's body, fem/harmonic_sharing.h).
    void announce();
    void finish();
    // Back to this rank's share of the cores for good (the partner works for this rank's body
    // itself, with its own cores).
    void give_back();

    // Whether this rank took the partner's cores before it finished (for the progress lines).
    bool borrowed() const { return took_cores; }

  private:
    MPI_Comm    comm;
    int         partner    = -1; // -1: inactive
    int         own_threads = 0, all_threads = 0;
    MPI_Request request    = MPI_REQUEST_NULL;
    int         message    = 0;
    bool        partner_done = false, announced = false, finished = false, took_cores = false,
                given_back = false;

    bool test_partner();
  };
} // namespace hertzgear::fem
