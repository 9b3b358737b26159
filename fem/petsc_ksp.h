#pragma once
// Small PETSc helpers shared by the FE solvers of fem/ (elastic bodies, resolved contact).
#include <petscksp.h>

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
  } // namespace fem
} // namespace hertzgear
