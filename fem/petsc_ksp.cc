#include "fem/petsc_ksp.h"

#include "common/errors.h"

#include <petscmat.h>

#include <string>

namespace hertzgear
{
  namespace fem
  {
    void check_petsc(const PetscErrorCode ierr, const char *what)
    {
      HG_REQUIRE_NUMERIC(ierr == 0, "PETSc call ", what, " failed with error code ", ierr);
    }

    namespace
    {
      void create_mumps(KSP &ksp, Mat A, MPI_Comm comm, const PCType factorisation)
      {
        check_petsc(KSPCreate(comm, &ksp), "KSPCreate");
        check_petsc(KSPSetOperators(ksp, A, A), "KSPSetOperators");
        check_petsc(KSPSetType(ksp, KSPPREONLY), "KSPSetType");
        PC pc;
        check_petsc(KSPGetPC(ksp, &pc), "KSPGetPC");
        check_petsc(PCSetType(pc, factorisation), "PCSetType");
        check_petsc(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
        check_petsc(KSPSetFromOptions(ksp), "KSPSetFromOptions");
        check_petsc(KSPSetUp(ksp), "KSPSetUp (MUMPS factorisation)");
        // PETSc does not stop on a failed MUMPS factorisation; a later substitution would fail
        // with a misleading INFOG(1) = -3. Say what MUMPS reported, now.
        Mat F;
        check_petsc(PCFactorGetMatrix(pc, &F), "PCFactorGetMatrix");
        MatFactorError error = MAT_FACTOR_NOERROR;
        check_petsc(MatFactorGetError(F, &error), "MatFactorGetError");
        if (error != MAT_FACTOR_NOERROR)
          {
            PetscInt infog1 = 0, infog2 = 0;
            MatMumpsGetInfog(F, 1, &infog1);
            MatMumpsGetInfog(F, 2, &infog2);
            std::string why;
            switch (infog1)
              {
                case -8:
                case -9:
                case -11:
                case -12:
                case -14:
                case -15:
                case -17:
                case -20:
                  why = "a MUMPS work array was too small for the fill-in; raise MUMPS's "
                        "estimate through PETSC_OPTIONS=\"-mat_mumps_icntl_14 100\" (per cent "
                        "extra workspace)";
                  break;
                case -13:
                case -19:
                  why = "MUMPS ran out of memory: use a coarser Stiffness/fe_level or "
                        "Stiffness/fe_degree, more MPI ranks on more memory, or "
                        "Stiffness/linear_solver = amg-cg";
                  break;
                case -10:
                  why = "the matrix is numerically singular: is the body clamped?";
                  break;
                default:
                  why = "see the MUMPS users' guide for INFOG(1)";
              }
            throw NumericalError(msg("the MUMPS factorisation failed: INFOG(1) = ", infog1,
                                     ", INFOG(2) = ", infog2, " (PETSc factor error ",
                                     static_cast<int>(error), "): ", why));
          }
      }
    } // namespace

    void create_mumps_lu(KSP &ksp, Mat A, MPI_Comm comm)
    {
      create_mumps(ksp, A, comm, PCLU);
    }

    void create_mumps_cholesky(KSP &ksp, Mat A, MPI_Comm comm)
    {
      check_petsc(MatSetOption(A, MAT_SPD, PETSC_TRUE), "MatSetOption(MAT_SPD)");
      create_mumps(ksp, A, comm, PCCHOLESKY);
    }

    void mumps_block_solve(KSP ksp, const std::vector<Vec> &rhs, const std::vector<Vec> &solution)
    {
      HG_REQUIRE_INPUT(rhs.size() == solution.size(), "mumps_block_solve: ", rhs.size(),
                       " right-hand sides but ", solution.size(), " solutions");
      if (rhs.empty())
        return;
      PC  pc;
      Mat F;
      check_petsc(KSPGetPC(ksp, &pc), "KSPGetPC");
      check_petsc(PCFactorGetMatrix(pc, &F), "PCFactorGetMatrix");
      MPI_Comm comm;
      check_petsc(PetscObjectGetComm(reinterpret_cast<PetscObject>(rhs[0]), &comm), "PetscObjectGetComm");
      PetscInt n_local = 0, n_global = 0;
      check_petsc(VecGetLocalSize(rhs[0], &n_local), "VecGetLocalSize");
      check_petsc(VecGetSize(rhs[0], &n_global), "VecGetSize");
      const PetscInt n_columns = static_cast<PetscInt>(rhs.size());
      // Destroys both dense blocks also when a PETSc call throws.
      struct DenseBlocks
      {
        Mat B = nullptr, X = nullptr;
        ~DenseBlocks()
        {
          MatDestroy(&B);
          MatDestroy(&X);
        }
      } blocks;
      Mat &B = blocks.B, &X = blocks.X;
      check_petsc(MatCreateDense(comm, n_local, PETSC_DECIDE, n_global, n_columns, nullptr, &B),
                  "MatCreateDense");
      check_petsc(MatCreateDense(comm, n_local, PETSC_DECIDE, n_global, n_columns, nullptr, &X),
                  "MatCreateDense");
      for (PetscInt j = 0; j < n_columns; ++j)
        {
          Vec column;
          check_petsc(MatDenseGetColumnVecWrite(B, j, &column), "MatDenseGetColumnVecWrite");
          check_petsc(VecCopy(rhs[j], column), "VecCopy");
          check_petsc(MatDenseRestoreColumnVecWrite(B, j, &column), "MatDenseRestoreColumnVecWrite");
        }
      check_petsc(MatAssemblyBegin(B, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
      check_petsc(MatAssemblyEnd(B, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
      check_petsc(MatMatSolve(F, B, X), "MatMatSolve (MUMPS block substitution)");
      for (PetscInt j = 0; j < n_columns; ++j)
        {
          Vec column;
          check_petsc(MatDenseGetColumnVecRead(X, j, &column), "MatDenseGetColumnVecRead");
          check_petsc(VecCopy(column, solution[j]), "VecCopy");
          check_petsc(MatDenseRestoreColumnVecRead(X, j, &column), "MatDenseRestoreColumnVecRead");
        }
    }
  } // namespace fem
} // namespace hertzgear
