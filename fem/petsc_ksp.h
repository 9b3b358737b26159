#pragma once
// Small PETSc helpers shared by the FE solvers of fem/ (elastic bodies, resolved contact).
#include <petscksp.h>

#include <string>
#include <vector>

namespace hertzgear
{
  namespace fem
  {
    // Throws a NumericalError naming the PETSc call when ierr is non-zero.
    void check_petsc(PetscErrorCode ierr, const char *what);

    // Creates `ksp` on `comm` as a MUMPS LU of A (KSPPREONLY + PCLU) and factorises it now, once:
    // every KSPSolve afterwards is one forward/backward substitution; block substitutions carry
    // mumps_rhs_per_pass right-hand sides per pass. MUMPS controls (ordering, memory, blocking)
    // stay tunable through PETSC_OPTIONS, e.g. "-mat_mumps_icntl_7 5" for METIS ordering.
    //
    // Memory guard: MUMPS may allocate at most `memory_limit_MB` per process for the
    // factorisation (its ICNTL(23)); 0 = the memory available to this process now
    // (available_memory_MB_per_rank). A factorisation whose analysis estimates more stops before
    // it allocates, as a NumericalError that names the estimate and the limit, instead of an
    // allocation failure after minutes or the kernel's OOM killer. PETSC_OPTIONS
    // "-mat_mumps_icntl_23 N" overrides the limit.
    void create_mumps_lu(KSP &ksp, Mat A, MPI_Comm comm, long memory_limit_MB = 0);

    // The same with a MUMPS Cholesky (LDL^T) factorisation of a symmetric positive definite A
    // (KSPPREONLY + PCCHOLESKY, A flagged MAT_SPD): half the factor memory and flops of the LU.
    void create_mumps_cholesky(KSP &ksp, Mat A, MPI_Comm comm, long memory_limit_MB = 0);
    // What a failed MUMPS factorisation means for the user, from its INFOG(1), the analysis'
    // memory estimates (INFOG(16), the largest per process, and INFOG(17), their sum, in MB) and
    // the limit per process (ICNTL(23), MB).
    std::string mumps_failure_reason(long infog1, long estimate_max_MB, long estimate_sum_MB, long limit_MB);

    // Memory [MB] this process may still use: MemAvailable of /proc/meminfo, capped by the
    // cgroup (v2 memory.max - memory.current, or v1 limit - usage) when one is set, shared
    // equally by the ranks of `comm` on this node. At least 1.
    long available_memory_MB_per_rank(MPI_Comm comm);

    // The cores of a node shared between the ranks on it: when several ranks of `comm` share a
    // node, each lets OpenBLAS (MUMPS's and LAPACK's BLAS) use cores / ranks threads, so that
    // `mpirun -np 2` on 2 cores runs 2 threads in all, not 4. One rank keeps OpenBLAS's default
    // (every core). Nothing happens with another BLAS. Returns the threads per rank set, 0 if none.
    int share_blas_threads_between_ranks(MPI_Comm comm);
    // The ranks of `comm` on this process's node, and the cores of the node.
    int ranks_on_node(MPI_Comm comm);
    int cores_of_node();
    // Lets OpenBLAS use `threads` threads from its next call on; false with another BLAS.
    bool set_blas_threads(int threads);

    // Solves A X = B for several right-hand sides at once with the factors held by `ksp` (made
    // by create_mumps_lu or create_mumps_cholesky): the columns go to MUMPS as one dense block, so
    // the factors are read once per block instead of once per right-hand side (BLAS 3 instead of
    // BLAS 2). rhs[j] and solution[j] share A's row layout; solution[j] must be created.
    void mumps_block_solve(KSP ksp, const std::vector<Vec> &rhs, const std::vector<Vec> &solution);

    // Right-hand sides MUMPS carries through one pass over its factors in a block substitution
    // (its ICNTL(27); MUMPS's own default is 32). A pass reads the whole factor, so wider passes
    // read it fewer times: on the 3D full-gear sectors (118 899 and 105 039 DoFs, 494 right-hand
    // sides) 128 takes 20 % off the solves and no memory the factorisation's peak does not already
    // hold; 512 gains no more and adds 0.3 GB (docs/accuracy-stiffness.md, "Cost of a full
    // cycle"). PETSC_OPTIONS "-mat_mumps_icntl_27 N" overrides it.
    constexpr int mumps_rhs_per_pass = 128;
  } // namespace fem
} // namespace hertzgear
