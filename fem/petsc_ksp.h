#pragma once
// Small PETSc helpers shared by the FE solvers of fem/ (elastic bodies, resolved contact).
#include <petscksp.h>

#include <vector>

namespace hertzgear
{
  namespace fem
  {
    // Throws a NumericalError naming the PETSc call when ierr is non-zero.
    void check_petsc(PetscErrorCode ierr, const char *what);

    // Creates `ksp` on `comm` as a MUMPS LU of A (KSPPREONLY + PCLU) and factorises it now, once:
    // every KSPSolve afterwards is one forward/backward substitution. MUMPS controls (ordering,
    // memory) stay tunable through PETSC_OPTIONS, e.g. "-mat_mumps_icntl_7 5" for METIS ordering.
    void create_mumps_lu(KSP &ksp, Mat A, MPI_Comm comm);

    // The same with a MUMPS Cholesky (LDL^T) factorisation of a symmetric positive definite A
    // (KSPPREONLY + PCCHOLESKY, A flagged MAT_SPD): half the factor memory and flops of the LU.
    void create_mumps_cholesky(KSP &ksp, Mat A, MPI_Comm comm);

    // Solves A X = B for several right-hand sides at once with the factors held by `ksp` (made
    // by create_mumps_lu or create_mumps_cholesky): the columns go to MUMPS as one dense block, so
    // the factors are read once per block instead of once per right-hand side (BLAS 3 instead of
    // BLAS 2). rhs[j] and solution[j] share A's row layout; solution[j] must be created.
    void mumps_block_solve(KSP ksp, const std::vector<Vec> &rhs, const std::vector<Vec> &solution);
  } // namespace fem
} // namespace hertzgear
