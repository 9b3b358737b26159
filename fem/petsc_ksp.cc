#include "fem/petsc_ksp.h"

#include "common/errors.h"

#include <petscmat.h>

#include <algorithm>
#include <thread>

#include <dlfcn.h>
#include <fstream>
#include <limits>
#include <sstream>
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
      // A number from the first line of a file (cgroup files: "max" or bytes); -1 if none.
      long long read_bytes(const char *path)
      {
        std::ifstream in(path);
        std::string   word;
        if (!(in >> word) || word == "max")
          return -1;
        try
          {
            return std::stoll(word);
          }
        catch (...)
          {
            return -1;
          }
      }
    } // namespace

    long available_memory_MB_per_rank(MPI_Comm comm)
    {
      long long available = std::numeric_limits<long long>::max();
      {
        std::ifstream in("/proc/meminfo");
        std::string   key;
        long long     kB = 0;
        std::string   unit;
        while (in >> key >> kB >> unit)
          if (key == "MemAvailable:")
            {
              available = kB * 1024;
              break;
            }
      }
      const long long v2_max = read_bytes("/sys/fs/cgroup/memory.max");
      const long long v2_cur = read_bytes("/sys/fs/cgroup/memory.current");
      if (v2_max > 0 && v2_cur >= 0)
        available = std::min(available, v2_max - v2_cur);
      const long long v1_max = read_bytes("/sys/fs/cgroup/memory/memory.limit_in_bytes");
      const long long v1_cur = read_bytes("/sys/fs/cgroup/memory/memory.usage_in_bytes");
      if (v1_max > 0 && v1_max < (1LL << 60) && v1_cur >= 0)
        available = std::min(available, v1_max - v1_cur);
      const int ranks = ranks_on_node(comm);
      // Unknown (no /proc/meminfo): no limit. The smallest share over the ranks, so that every
      // rank applies the same limit (every rank takes part in the reduction).
      const long share =
        available == std::numeric_limits<long long>::max() ?
          std::numeric_limits<int>::max() :
          static_cast<long>(std::max<long long>(1, available / ranks / (1024 * 1024)));
      long smallest = share;
      MPI_Allreduce(&share, &smallest, 1, MPI_LONG, MPI_MIN, comm);
      return smallest;
    }

    int ranks_on_node(MPI_Comm comm)
    {
      MPI_Comm node;
      int      ranks = 1;
      if (MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node) == MPI_SUCCESS)
        {
          MPI_Comm_size(node, &ranks);
          MPI_Comm_free(&node);
        }
      return ranks;
    }

    bool set_blas_threads(const int threads)
    {
      using SetThreads = void (*)(int);
      const auto set   = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
      if (set == nullptr)
        return false;
      set(std::max(1, threads));
      return true;
    }

    int cores_of_node()
    {
      return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    }

    int share_blas_threads_between_ranks(MPI_Comm comm)
    {
      const int ranks = ranks_on_node(comm);
      if (ranks <= 1)
        return 0;
      const int threads = std::max(1, cores_of_node() / ranks);
      return set_blas_threads(threads) ? threads : 0;
    }

    std::string mumps_failure_reason(const long infog1, const long estimate_max_MB, const long estimate_sum_MB,
                                     const long limit_MB)
    {
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
            return "a MUMPS work array was too small for the fill-in; raise MUMPS's estimate through "
                   "PETSC_OPTIONS=\"-mat_mumps_icntl_14 100\" (per cent extra workspace)";
          case -13:
          case -19:
            {
              std::ostringstream os;
              os << "MUMPS " << (infog1 == -19 ? "stopped before the factorisation: it " : "ran out of memory; it ")
                 << "estimates " << estimate_max_MB << " MB per process (" << estimate_sum_MB
                 << " MB in all) against " << limit_MB
                 << " MB per process (ICNTL(23): the memory available when the "
                    "factorisation started, or PETSC_OPTIONS -mat_mumps_icntl_23); use a coarser {level}, "
                    "{degree} or {face_width_layers}, more MPI ranks on "
                    "more memory, or {linear_solver} = amg-cg";
              return os.str();
            }
          case -10:
            return "the matrix is numerically singular: is the body clamped?";
          default:
            return "see the MUMPS users' guide for INFOG(1)";
        }
    }

    namespace
    {
      void create_mumps(KSP &ksp, Mat A, MPI_Comm comm, const PCType factorisation,
                        const long memory_limit_MB)
      {
        check_petsc(KSPCreate(comm, &ksp), "KSPCreate");
        check_petsc(KSPSetOperators(ksp, A, A), "KSPSetOperators");
        check_petsc(KSPSetType(ksp, KSPPREONLY), "KSPSetType");
        PC pc;
        check_petsc(KSPGetPC(ksp, &pc), "KSPGetPC");
        check_petsc(PCSetType(pc, factorisation), "PCSetType");
        check_petsc(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
        check_petsc(KSPSetFromOptions(ksp), "KSPSetFromOptions");
        // The memory guard (ICNTL(23)) unless PETSC_OPTIONS sets it.
        check_petsc(PCFactorSetUpMatSolverType(pc), "PCFactorSetUpMatSolverType");
        Mat F;
        check_petsc(PCFactorGetMatrix(pc, &F), "PCFactorGetMatrix");
        PetscBool user_limit = PETSC_FALSE;
        check_petsc(PetscOptionsHasName(nullptr, nullptr, "-mat_mumps_icntl_23", &user_limit),
                    "PetscOptionsHasName");
        long limit_MB = memory_limit_MB > 0 ? memory_limit_MB : available_memory_MB_per_rank(comm);
        limit_MB      = std::min<long>(limit_MB, std::numeric_limits<int>::max());
        if (!user_limit)
          check_petsc(MatMumpsSetIcntl(F, 23, static_cast<PetscInt>(limit_MB)),
                      "MatMumpsSetIcntl(23)");
        // Right-hand sides per pass of a block substitution (mumps_rhs_per_pass) unless
        // PETSC_OPTIONS sets it.
        PetscBool user_block = PETSC_FALSE;
        check_petsc(PetscOptionsHasName(nullptr, nullptr, "-mat_mumps_icntl_27", &user_block),
                    "PetscOptionsHasName");
        if (!user_block)
          check_petsc(MatMumpsSetIcntl(F, 27, mumps_rhs_per_pass), "MatMumpsSetIcntl(27)");
        check_petsc(KSPSetUp(ksp), "KSPSetUp (MUMPS factorisation)");
        // PETSc does not stop on a failed MUMPS factorisation; a later substitution would fail
        // with a misleading INFOG(1) = -3. Say what MUMPS reported, now.
        MatFactorError error = MAT_FACTOR_NOERROR;
        check_petsc(MatFactorGetError(F, &error), "MatFactorGetError");
        if (error != MAT_FACTOR_NOERROR)
          {
            PetscInt infog1 = 0, infog2 = 0;
            MatMumpsGetInfog(F, 1, &infog1);
            MatMumpsGetInfog(F, 2, &infog2);
            // INFOG(16): the analysis' estimate of the largest per-process memory of the
            // factorisation [MB]; INFOG(17): its sum over the processes.
            PetscInt est_max = 0, est_sum = 0, limit = 0;
            MatMumpsGetInfog(F, 16, &est_max);
            MatMumpsGetInfog(F, 17, &est_sum);
            MatMumpsGetIcntl(F, 23, &limit);
            const std::string why = mumps_failure_reason(infog1, est_max, est_sum, limit);
            throw NumericalError(msg("the MUMPS factorisation failed: INFOG(1) = ", infog1,
                                     ", INFOG(2) = ", infog2, " (PETSc factor error ",
                                     static_cast<int>(error), "): ", why));
          }
      }
    } // namespace

    void create_mumps_lu(KSP &ksp, Mat A, MPI_Comm comm, const long memory_limit_MB)
    {
      create_mumps(ksp, A, comm, PCLU, memory_limit_MB);
    }

    void create_mumps_cholesky(KSP &ksp, Mat A, MPI_Comm comm, const long memory_limit_MB)
    {
      check_petsc(MatSetOption(A, MAT_SPD, PETSC_TRUE), "MatSetOption(MAT_SPD)");
      create_mumps(ksp, A, comm, PCCHOLESKY, memory_limit_MB);
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
