#pragma once
// One tooth sector of a full gear factorised and solved by a group of processes.
//
// Under mpirun with more ranks than a pair has bodies, each full gear (fem/cyclic_gear_body.h) is
// built by a group of ranks. Its owner, rank 0 of the group, reads the sector mesh, assembles K,
// pairs the cut faces, builds every load and reading, exactly as alone. Three parts of the work
// run over the whole group:
//   - the sparse factorisation of K with the Schur complement on the cut faces: MUMPS spreads its
//     fronts and factors over the group's processes (the owner's matrix is handed over as one
//     distributed matrix whose rows all lie on the owner; the ordering is the sequential one of
//     one process), and returns the dense Schur complement to the owner (ICNTL(19) = 1);
//   - the interior solves: the compliance table's sparse loads and readings go in from the owner,
//     the substitution runs on every process of the group, each process applies the functionals
//     the table reads (cut reactions, readings) to its own part of the solutions, and the sums of
//     these products reach the owner (solve_functionals); for the fields, blocks of dense
//     right-hand sides go in from the owner and their solutions come back to it (solve);
//   - the cyclic harmonics H_k u^_k = q^_k: they go out one at a time to each process of the
//     group that is free, shared by the work each process has done (the owner has the group's
//     serial work besides: it takes fewer, see harmonics), and their sum is reduced onto the
//     owner (the members hold D and E, 2 n^2 doubles, sent once, and the condensed loads q of the
//     call); meanwhile the owner may give harmonics to ranks outside the group whose own work is
//     done (fem/harmonic_sharing.h).
// The other ranks of the group hold no mesh: they run serve_sector_group, which follows the
// owner's commands until the owner dismisses them. Commands go from the owner to each member
// point to point; a member waits for the next without spinning (a test every millisecond); the
// data of a command then goes in calls collective over the group.
//
// Memory: the factors are spread over the group (MUMPS's INFO(16) per process), so a sector too
// large for one rank's memory fits on a group of several; the owner holds in addition the whole
// matrix K and the dense Schur complement.
//
// The sums of a parallel factorisation and of the harmonics run in another order than on one
// process: a body built by a group equals the one of a single process to round-off, not bit for
// bit (docs/accuracy-stiffness.md, "MPI: what runs where", gives the measured differences).
#include "common/errors.h"

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <petscmat.h>

#include <mpi.h>

#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace hertzgear::fem
{
  // A factorisation whose analysis estimates more memory per process than its limit (MUMPS
  // INFOG(1) = -19): thrown on every rank of the group before anything large is allocated, so that
  // the caller may try a larger group.
  class FactorisationTooLarge : public NumericalError
  {
  public:
    FactorisationTooLarge(const std::string &what, long estimate_MB, long limit_MB, int processes)
      : NumericalError(what), estimate_MB_per_process(estimate_MB), limit_MB_per_process(limit_MB),
        processes(processes)
    {}
    long estimate_MB_per_process, limit_MB_per_process;
    int  processes;
  };

  // Columns of a sparse matrix of K's size rows (0-based, compressed by columns): column j holds
  // rows[start[j] .. start[j+1]) with their values; a row at most once per column.
  struct SparseColumns
  {
    std::vector<long>   start = {0};
    std::vector<long>   rows;
    std::vector<double> values;
    std::size_t         n_columns() const { return start.size() - 1; }
  };

  // The MUMPS Cholesky (LDL^T) factorisation of a sector's symmetric positive definite K with its
  // Schur complement on the cut-face rows, on one process or over a group, through MUMPS's own C
  // interface: PETSc's MUMPS interface forms a Schur complement on one process only (its
  // MatMatSolve refuses one made over several). The controls are PETSc's: MUMPS's defaults but
  // for the right-hand sides per substitution pass (fem/petsc_ksp.h, mumps_rhs_per_pass), and
  // PETSC_OPTIONS "-mat_mumps_icntl_<i> <value>" sets ICNTL(i) here too. Memory guard as in
  // fem/petsc_ksp.h (ICNTL(23), the memory available per rank or `memory_limit_MB`).
  class SectorFactorisation
  {
  public:
    // Collective over `comm`. Rank 0 passes its K (sequential, or an MPI matrix of one process)
    // and the Schur rows; the other ranks pass nullptr, K's size n and no rows. MUMPS's
    // analysis is the sequential one (ICNTL(28) = 1) on every group size, so that the ordering
    // does not depend on it. Throws NumericalError (on every rank) if MUMPS fails.
    SectorFactorisation(MPI_Comm comm, Mat K, PetscInt n, const std::vector<PetscInt> &schur_rows,
                        long memory_limit_MB);
    ~SectorFactorisation(); // collective over `comm`
    SectorFactorisation(const SectorFactorisation &)            = delete;
    SectorFactorisation &operator=(const SectorFactorisation &) = delete;

    // On rank 0, once: the dense Schur complement, the triangle MUMPS wrote mirrored in place
    // (symmetric to the last bit) and handed over without a copy.
    Eigen::MatrixXd take_schur() const;
    // Interior solves (cut rows held at zero) of a block of right-hand sides, in place (MUMPS's
    // dense centralised right-hand sides). On rank 0, before the solve: the block to write,
    // column j (K's size n) at j n, zeroed; after the solve its columns hold the solutions. It
    // stays allocated for the next block, so that its pages are not taken and cleared again.
    double *right_hand_sides(PetscInt n_columns) const;
    // Collective; the others pass the same n_columns and hold no block.
    void solve(PetscInt n_columns) const;
    // Interior solves read through sparse functionals F (rows x n: the same for many solves, the
    // rows' weights on K's DoFs): for sparse right-hand sides b_j, F K_II^-1 b_j and nothing
    // else. The right-hand sides go in as they are (MUMPS's sparse right-hand sides, ICNTL(20) =
    // 1, whose forward substitution skips the branches of the elimination tree they do not
    // reach); each process keeps the part of the solutions it computed (distributed solutions,
    // ICNTL(21) = 1) and applies F to it, and the sums of these products reach rank 0: no dense
    // block of right-hand sides is formed and no solution is gathered or sent. Cut entries of b
    // are ignored; F must have no entries in the cut DoFs' columns (the solutions' cut entries
    // are 0).
    // set_functionals: collective; rank 0 passes F, the others nullptr.
    void set_functionals(const Eigen::SparseMatrix<double> *F) const;
    // solve_functionals: collective; rank 0 passes the right-hand sides and gets F X (rows of F
    // x n_columns); the others pass nullptr, the same n_columns, and get an empty matrix.
    Eigen::MatrixXd solve_functionals(PetscInt n_columns, const SparseColumns *rhs) const;

    // MUMPS's estimate of the largest memory per process of the factorisation, and its sum
    // over the processes [MB] (INFOG(16), INFOG(17) after the analysis).
    long estimated_memory_MB_per_process() const;
    long estimated_memory_MB_in_all() const;

  private:
    struct Mumps;
    std::unique_ptr<Mumps> mumps;
  };

  // The owner's side of a group.
  class SectorGroup
  {
  public:
    // `group`: the owner is its rank 0; with one process every call works alone.
    // `work_so_far()`: this process's work so far [s] (the FE stage's CPU time; by default the
    // process's CPU time), by which the harmonics are shared (see harmonics).
    explicit SectorGroup(MPI_Comm group, std::function<double()> work_so_far = {});
    // Dismisses the members if that was not done (also when the owner's work failed).
    ~SectorGroup();
    SectorGroup(const SectorGroup &)            = delete;
    SectorGroup &operator=(const SectorGroup &) = delete;

    int  size() const { return n_processes; }
    bool shared() const { return n_processes > 1; }

    // Factorises K over the group (see SectorFactorisation).
    void factorise(Mat K, PetscInt n, const std::vector<PetscInt> &schur_rows, long memory_limit_MB);
    // Sends the members the interface blocks D and E (after factorise, before harmonics).
    void send_interface_blocks(const Eigen::MatrixXd &D, const Eigen::MatrixXd &E) const;
    const SectorFactorisation &factorisation() const { return *factors; }
    // Interior solves over the group of the block written into factorisation().right_hand_sides
    // (see SectorFactorisation::solve).
    void solve(PetscInt n_columns) const;
    // The functionals' solves over the group (see SectorFactorisation::set_functionals,
    // solve_functionals).
    void set_functionals(const Eigen::SparseMatrix<double> &F) const;
    Eigen::MatrixXd solve_functionals(const SparseColumns &rhs) const;
    // The interface displacements u_s, s = s_min .. s_max, summed over the harmonics `todo`
    // (the owner's D and E, sent by send_interface_blocks). The members report their work so far
    // at the start and with each harmonic they finish; the harmonics go out one at a time to
    // each member that has none left to solve (the least busy first), so that those not yet
    // given stay free for helpers. The owner takes one itself when more are left than its free
    // members take and it is not ahead of the least busy member by more than half a harmonic
    // (the members' work counted with the harmonics they hold, at the owner's measured cost of
    // one; the owner does the group's serial work besides); otherwise it waits for a member
    // without spinning. Before each round `between_rounds(todo, levels)` may take harmonics
    // from the back of `todo` for helpers outside the group (fem/harmonic_sharing.h), told the
    // group's work in the same way (`levels.levels`: the owner's, then each member's) and the
    // owner's CPU time per harmonic (`levels.seconds_per_harmonic`, 0 before its first). Throws
    // NumericalError if a harmonic failed on any process of the group.
    struct WorkLevels
    {
      std::vector<double> levels;
      double              seconds_per_harmonic = 0;
    };
    std::map<int, Eigen::MatrixXd> harmonics(int n_teeth, const Eigen::MatrixXd &D, const Eigen::MatrixXd &E,
                                             const std::map<int, Eigen::MatrixXd> &q, int s_min, int s_max,
                                             std::deque<int> todo,
                                             const std::function<void(std::deque<int> &, const WorkLevels &)> &between_rounds) const;
    // Ends the members' service and frees the factorisation, collectively. Idempotent.
    void dismiss();

  private:
    MPI_Comm                             group;
    std::function<double()>              work_so_far;
    int                                  n_processes = 1;
    bool                                 dismissed   = false;
    std::unique_ptr<SectorFactorisation> factors;

    void command(int kind, const std::vector<long> &arguments) const;
  };

  // A member's side: follows the owner's commands until it is dismissed, and returns the wall
  // time it spent on them [s] (not the waits between them). Throws the NumericalError of a failed
  // factorisation or harmonic (the owner throws it too). `work_so_far` as for SectorGroup.
  double serve_sector_group(MPI_Comm group, std::function<double()> work_so_far = {});

} // namespace hertzgear::fem
