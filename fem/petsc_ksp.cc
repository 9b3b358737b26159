#include "fem/petsc_ksp.h"

#include "common/errors.h"

namespace hertzgear
{
  namespace fem
  {
    void check_petsc(const PetscErrorCode ierr, const char *what)
    {
      HG_REQUIRE_NUMERIC(ierr == 0, "PETSc call ", what, " failed with error code ", ierr);
    }

    void create_mumps_lu(KSP &ksp, Mat A, MPI_Comm comm)
    {
      check_petsc(KSPCreate(comm, &ksp), "KSPCreate");
      check_petsc(KSPSetOperators(ksp, A, A), "KSPSetOperators");
      check_petsc(KSPSetType(ksp, KSPPREONLY), "KSPSetType");
      PC pc;
      check_petsc(KSPGetPC(ksp, &pc), "KSPGetPC");
      check_petsc(PCSetType(pc, PCLU), "PCSetType");
      check_petsc(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
      check_petsc(KSPSetFromOptions(ksp), "KSPSetFromOptions");
      check_petsc(KSPSetUp(ksp), "KSPSetUp (MUMPS factorisation)");
    }
  } // namespace fem
} // namespace hertzgear
