#include "fem/sector_group.h"

#include "common/errors.h"
#include "common/progress.h"
#include "fem/harmonic_sharing.h"
#include "fem/petsc_ksp.h"

#include <dmumps_c.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <limits>
#include <string>
#include <thread>

namespace hertzgear::fem
{
  namespace
  {
    constexpr int command_tag = 5300;
    constexpr int done_tag    = 5301; // a member's harmonic is done: its work so far
    enum Command : long
    {
      factorise_command        = 1,
      solve_command            = 2,
      harmonics_command        = 3,
      blocks_command           = 4,
      round_command            = 5,
      dismiss_command          = 6,
      functionals_command      = 7,
      functional_solve_command = 8
    };

    int rank_of(MPI_Comm comm)
    {
      int r = 0;
      MPI_Comm_rank(comm, &r);
      return r;
    }

    // The owner's next command to this member, tested for every millisecond.
    std::vector<long> next_command(MPI_Comm group)
    {
      MPI_Status status;
      for (int flag = 0;;)
        {
          MPI_Iprobe(0, command_tag, group, &flag, &status);
          if (flag != 0)
            break;
          std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
      int length = 0;
      MPI_Get_count(&status, MPI_LONG, &length);
      std::vector<long> message(static_cast<std::size_t>(length));
      MPI_Recv(message.data(), length, MPI_LONG, 0, command_tag, group, MPI_STATUS_IGNORE);
      return message;
    }

    int size_of(MPI_Comm comm)
    {
      int s = 1;
      MPI_Comm_size(comm, &s);
      return s;
    }

    // From rank 0 of `comm` (which only reads `a`) to the others (which receive it into `a`).
    void broadcast_matrix(Eigen::MatrixXd &a, MPI_Comm comm)
    {
      long dims[2] = {static_cast<long>(a.rows()), static_cast<long>(a.cols())};
      MPI_Bcast(dims, 2, MPI_LONG, 0, comm);
      if (rank_of(comm) != 0)
        a.resize(dims[0], dims[1]);
      MPI_Bcast(a.data(), static_cast<int>(a.size()), MPI_DOUBLE, 0, comm);
    }
  } // namespace

  struct SectorFactorisation::Mumps
  {
    DMUMPS_STRUC_C        id{};
    bool                  initialised = false;
    std::vector<MUMPS_INT> irn, jcn, schur_list;
    std::vector<double>    a;
    MPI_Comm               comm = MPI_COMM_SELF;
    int                    rank = 0, processes = 1;
    std::array<long, 2>    estimate_MB = {0, 0}; // the analysis' INFOG(16), INFOG(17)
    Eigen::MatrixXd        schur;                   // on rank 0: MUMPS's lower triangle by rows
    std::vector<double>    rhs_block;               // on rank 0: the right-hand sides, then solutions
    // The functionals' solves: F, its columns at this process's solution entries (once these are
    // known, after the first solve), MUMPS's sparse right-hand sides (rank 0) and the distributed
    // solutions.
    Eigen::SparseMatrix<double> F, F_local;
    bool                        F_local_ready = false;
    std::vector<MUMPS_INT>      rhs_ptr, rhs_rows, solution_rows;
    std::vector<double>         rhs_values, solution;

    void call(const int job, const char *what)
    {
      id.job = job;
      dmumps_c(&id);
      if (id.infog[0] >= 0)
        return;
      const std::string text = msg("the MUMPS ", what, " failed: INFOG(1) = ", id.infog[0], ", INFOG(2) = ",
                                   id.infog[1], ": ",
                                   mumps_failure_reason(id.infog[0], id.infog[15], id.infog[16], id.icntl[22]));
      if (id.infog[0] == -19)
        throw FactorisationTooLarge(text, id.infog[15], id.icntl[22], processes);
      throw NumericalError(text);
    }
    ~Mumps()
    {
      if (initialised)
        {
          id.job = -2;
          dmumps_c(&id);
        }
    }
  };

  SectorFactorisation::SectorFactorisation(MPI_Comm comm, Mat K, const PetscInt n,
                                           const std::vector<PetscInt> &schur_rows, const long memory_limit_MB)
    : mumps(std::make_unique<Mumps>())
  {
    auto &m     = *mumps;
    m.comm      = comm;
    m.rank      = rank_of(comm);
    m.processes = size_of(comm);
    auto &id    = m.id;
    id.sym      = 1; // symmetric positive definite
    id.par      = 1; // the host works too
    id.comm_fortran = static_cast<MUMPS_INT>(MPI_Comm_c2f(comm));
    m.call(-1, "initialisation");
    m.initialised = true;
    // Quiet, as PETSc keeps it; the sequential analysis (one ordering for every group size).
    id.icntl[0] = -1;
    id.icntl[1] = -1;
    id.icntl[2] = -1;
    id.icntl[3] = 0;
    id.icntl[27] = 1;
    // The memory guard: at most this per process (ICNTL(23), MB).
    const long limit = memory_limit_MB > 0 ? memory_limit_MB : available_memory_MB_per_rank(comm);
    id.icntl[22] = static_cast<MUMPS_INT>(std::min<long>(limit, std::numeric_limits<MUMPS_INT>::max()));
    // Right-hand sides per pass over the factors in a block substitution (fem/petsc_ksp.h).
    id.icntl[26] = mumps_rhs_per_pass;
    // PETSC_OPTIONS -mat_mumps_icntl_<i>, as for PETSc's own MUMPS factorisations.
    for (int i = 1; i <= 60; ++i)
      {
        PetscInt  value = 0;
        PetscBool set   = PETSC_FALSE;
        const std::string name = "-mat_mumps_icntl_" + std::to_string(i);
        check_petsc(PetscOptionsGetInt(nullptr, nullptr, name.c_str(), &value, &set), "PetscOptionsGetInt");
        if (set)
          id.icntl[i - 1] = static_cast<MUMPS_INT>(value);
      }
    id.n = static_cast<MUMPS_INT>(n);
    if (m.rank == 0)
      {
        // The upper triangle of K (1-based), assembled on the host (ICNTL(5) = 0, ICNTL(18) = 0).
        Mat       local  = K;
        PetscBool is_mpi = PETSC_FALSE;
        check_petsc(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(K), MATMPIAIJ, &is_mpi),
                    "PetscObjectTypeCompare");
        if (is_mpi)
          check_petsc(MatMPIAIJGetSeqAIJ(K, &local, nullptr, nullptr), "MatMPIAIJGetSeqAIJ");
        for (PetscInt r = 0; r < n; ++r)
          {
            PetscInt           n_cols = 0;
            const PetscInt    *cols   = nullptr;
            const PetscScalar *vals   = nullptr;
            check_petsc(MatGetRow(local, r, &n_cols, &cols, &vals), "MatGetRow");
            for (PetscInt k = 0; k < n_cols; ++k)
              if (cols[k] >= r)
                {
                  m.irn.push_back(static_cast<MUMPS_INT>(r + 1));
                  m.jcn.push_back(static_cast<MUMPS_INT>(cols[k] + 1));
                  m.a.push_back(vals[k]);
                }
            check_petsc(MatRestoreRow(local, r, &n_cols, &cols, &vals), "MatRestoreRow");
          }
        id.nnz = static_cast<MUMPS_INT8>(m.a.size());
        id.irn = m.irn.data();
        id.jcn = m.jcn.data();
        id.a   = m.a.data();
        for (const auto r : schur_rows)
          m.schur_list.push_back(static_cast<MUMPS_INT>(r + 1));
        id.size_schur    = static_cast<MUMPS_INT>(m.schur_list.size());
        id.listvar_schur = m.schur_list.data();
        // Not initialised: MUMPS writes the triangle, take_schur the other half.
        const auto ns = static_cast<Eigen::Index>(m.schur_list.size());
        m.schur.resize(ns, ns);
        id.schur = m.schur.data();
      }
    // The Schur complement centralized on the host (ICNTL(19) = 1).
    id.icntl[18] = 1;
    m.call(1, "analysis");
    m.estimate_MB = {id.infog[15], id.infog[16]};
    m.call(2, "factorisation");
    // The matrix itself is no longer needed.
    std::vector<MUMPS_INT>().swap(m.irn);
    std::vector<MUMPS_INT>().swap(m.jcn);
    std::vector<double>().swap(m.a);
    // Solves from now on are solves with the interior block alone: the Schur rows of the
    // right-hand side are ignored, those of the solution are 0 (ICNTL(26) = 0).
    id.icntl[25] = 0;
  }

  SectorFactorisation::~SectorFactorisation() = default;

  long SectorFactorisation::estimated_memory_MB_per_process() const { return mumps->estimate_MB[0]; }
  long SectorFactorisation::estimated_memory_MB_in_all() const { return mumps->estimate_MB[1]; }

  Eigen::MatrixXd SectorFactorisation::take_schur() const
  {
    auto              &m  = *mumps;
    const Eigen::Index ns = static_cast<Eigen::Index>(m.schur_list.size());
    HG_REQUIRE_INPUT(m.rank == 0 && m.id.schur != nullptr && m.schur.rows() == ns,
                     "SectorFactorisation::take_schur: called twice, or on a rank other than 0");
    // MUMPS returns the lower triangle by rows (ICNTL(19) = 1, a symmetric matrix): read by
    // columns, that is the upper triangle. It is mirrored in place, tile by tile (a tile and its
    // transpose stay in cache), and the matrix handed over without a copy.
    Eigen::MatrixXd    S    = std::move(m.schur);
    constexpr Eigen::Index tile = 64;
    for (Eigen::Index j0 = 0; j0 < ns; j0 += tile)
      {
        const Eigen::Index nj = std::min(tile, ns - j0);
        for (Eigen::Index j = j0; j < j0 + nj; ++j) // the diagonal tile
          for (Eigen::Index i = j + 1; i < j0 + nj; ++i)
            S(i, j) = S(j, i);
        for (Eigen::Index i0 = j0 + nj; i0 < ns; i0 += tile) // below it: the transposed tile above
          {
            const Eigen::Index ni = std::min(tile, ns - i0);
            S.block(i0, j0, ni, nj) = S.block(j0, i0, nj, ni).transpose();
          }
      }
    m.schur    = Eigen::MatrixXd();
    m.id.schur = nullptr;
    return S;
  }

  double *SectorFactorisation::right_hand_sides(const PetscInt n_columns) const
  {
    auto &m = *mumps;
    HG_REQUIRE_INPUT(m.rank == 0, "SectorFactorisation::right_hand_sides: only rank 0 holds the block");
    const std::size_t size = static_cast<std::size_t>(m.id.n) * static_cast<std::size_t>(n_columns);
    if (m.rhs_block.size() < size)
      m.rhs_block.resize(size);
    std::fill(m.rhs_block.begin(), m.rhs_block.begin() + static_cast<std::ptrdiff_t>(size), 0.0);
    return m.rhs_block.data();
  }

  void SectorFactorisation::solve(const PetscInt n_columns) const
  {
    auto &m  = *mumps;
    auto &id = m.id;
    if (n_columns == 0)
      return;
    if (m.rank == 0)
      {
        HG_REQUIRE_INPUT(m.rhs_block.size() >= static_cast<std::size_t>(id.n) * static_cast<std::size_t>(n_columns),
                         "SectorFactorisation::solve: ", n_columns, " columns, but no block of them written");
        id.rhs  = m.rhs_block.data();
        id.lrhs = id.n;
      }
    id.nrhs      = static_cast<MUMPS_INT>(n_columns);
    id.icntl[19] = 0; // dense right-hand sides on the host
    id.icntl[20] = 0; // the solutions back on the host, in place
    m.call(3, "substitution");
    id.rhs = nullptr;
  }

  void SectorFactorisation::set_functionals(const Eigen::SparseMatrix<double> *F) const
  {
    auto    &m    = *mumps;
    MPI_Comm comm = m.comm;
    if (m.rank == 0)
      {
        HG_REQUIRE_INPUT(F != nullptr && F->cols() == m.id.n && F->isCompressed(),
                         "SectorFactorisation::set_functionals: rank 0 passes F (compressed, K's size columns)");
        m.F = *F;
      }
    long dims[3] = {static_cast<long>(m.F.rows()), static_cast<long>(m.F.cols()), static_cast<long>(m.F.nonZeros())};
    if (m.processes > 1)
      {
        MPI_Bcast(dims, 3, MPI_LONG, 0, comm);
        if (m.rank != 0)
          {
            m.F.resize(dims[0], dims[1]);
            m.F.resizeNonZeros(dims[2]);
          }
        static_assert(sizeof(Eigen::SparseMatrix<double>::StorageIndex) == sizeof(int), "F's indices are int");
        MPI_Bcast(m.F.outerIndexPtr(), static_cast<int>(dims[1] + 1), MPI_INT, 0, comm);
        MPI_Bcast(m.F.innerIndexPtr(), static_cast<int>(dims[2]), MPI_INT, 0, comm);
        MPI_Bcast(m.F.valuePtr(), static_cast<int>(dims[2]), MPI_DOUBLE, 0, comm);
      }
    m.F_local_ready = false;
  }

  Eigen::MatrixXd SectorFactorisation::solve_functionals(const PetscInt n_columns, const SparseColumns *rhs) const
  {
    auto    &m    = *mumps;
    auto    &id   = m.id;
    MPI_Comm comm = m.comm;
    if (n_columns == 0)
      return Eigen::MatrixXd(m.rank == 0 ? m.F.rows() : 0, 0);
    if (m.rank == 0)
      {
        HG_REQUIRE_INPUT(rhs != nullptr && static_cast<PetscInt>(rhs->n_columns()) == n_columns,
                         "SectorFactorisation::solve_functionals: rank 0 passes ", n_columns, " columns");
        // 1-based, as MUMPS reads them.
        m.rhs_ptr.resize(rhs->start.size());
        for (std::size_t j = 0; j < rhs->start.size(); ++j)
          m.rhs_ptr[j] = static_cast<MUMPS_INT>(rhs->start[j] + 1);
        m.rhs_rows.resize(rhs->rows.size());
        for (std::size_t k = 0; k < rhs->rows.size(); ++k)
          m.rhs_rows[k] = static_cast<MUMPS_INT>(rhs->rows[k] + 1);
        m.rhs_values = rhs->values;
        if (m.rhs_values.empty()) // MUMPS wants arrays even for empty columns
          {
            m.rhs_values.push_back(0.0);
            m.rhs_rows.push_back(1);
          }
        id.nz_rhs      = static_cast<MUMPS_INT>(rhs->values.size());
        id.irhs_ptr    = m.rhs_ptr.data();
        id.irhs_sparse = m.rhs_rows.data();
        id.rhs_sparse  = m.rhs_values.data();
      }
    // This process's share of the solutions: INFO(23) entries per column.
    const auto n_local = static_cast<std::size_t>(std::max<MUMPS_INT>(id.info[22], 0));
    m.solution_rows.resize(std::max<std::size_t>(n_local, 1));
    m.solution.resize(std::max<std::size_t>(n_local, 1) * static_cast<std::size_t>(n_columns));
    id.lsol_loc  = static_cast<MUMPS_INT>(std::max<std::size_t>(n_local, 1));
    id.sol_loc   = m.solution.data();
    id.isol_loc  = m.solution_rows.data();
    id.nrhs      = static_cast<MUMPS_INT>(n_columns);
    id.icntl[19] = 1; // sparse right-hand sides on the host, their sparsity used where it helps
    id.icntl[20] = 1; // the solutions stay distributed
    const auto reset = [&] {
      id.icntl[19] = 0;
      id.icntl[20] = 0;
      id.irhs_ptr    = nullptr;
      id.irhs_sparse = nullptr;
      id.rhs_sparse  = nullptr;
      id.sol_loc     = nullptr;
      id.isol_loc    = nullptr;
      id.nz_rhs      = 0;
    };
    try
      {
        m.call(3, "substitution");
      }
    catch (...)
      {
        reset();
        throw;
      }
    reset();
    if (!m.F_local_ready)
      {
        // F's columns at this process's solution entries (their rows do not change between solves).
        std::vector<Eigen::Triplet<double>> entries;
        for (std::size_t i = 0; i < n_local; ++i)
          {
            const Eigen::Index g = m.solution_rows[i] - 1;
            for (Eigen::SparseMatrix<double>::InnerIterator it(m.F, g); it; ++it)
              entries.emplace_back(static_cast<int>(it.row()), static_cast<int>(i), it.value());
          }
        m.F_local.resize(m.F.rows(), static_cast<Eigen::Index>(n_local));
        m.F_local.setFromTriplets(entries.begin(), entries.end());
        m.F_local_ready = true;
      }
    Eigen::MatrixXd FX = Eigen::MatrixXd::Zero(m.F.rows(), static_cast<Eigen::Index>(n_columns));
    if (n_local > 0)
      FX.noalias() = m.F_local * Eigen::Map<const Eigen::MatrixXd>(m.solution.data(), static_cast<Eigen::Index>(n_local),
                                                                    static_cast<Eigen::Index>(n_columns));
    if (m.processes > 1)
      {
        if (m.rank == 0)
          MPI_Reduce(MPI_IN_PLACE, FX.data(), static_cast<int>(FX.size()), MPI_DOUBLE, MPI_SUM, 0, comm);
        else
          {
            MPI_Reduce(FX.data(), nullptr, static_cast<int>(FX.size()), MPI_DOUBLE, MPI_SUM, 0, comm);
            FX.resize(0, 0);
          }
      }
    return FX;
  }

  namespace
  {
    // The end of a call's harmonics on every process of the group: a failure anywhere fails
    // every process; the sums go to every process.
    void reduce_harmonics(MPI_Comm comm, std::map<int, Eigen::MatrixXd> &u, const std::string &failure)
    {
      int failed = failure.empty() ? 0 : 1, any = 0;
      MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, comm);
      if (any != 0)
        throw NumericalError(failure.empty() ? std::string("a cyclic harmonic solved by another process of the "
                                                           "group failed: its cut-face matrix is not positive "
                                                           "definite") :
                                               failure);
      for (auto &[s, us] : u)
        MPI_Allreduce(MPI_IN_PLACE, us.data(), static_cast<int>(us.size()), MPI_DOUBLE, MPI_SUM, comm);
    }

    // Adds harmonic k unless an earlier one failed (then the failure is kept for the reduction).
    void add_harmonic(const int k, const int N, const Eigen::MatrixXd &D, const Eigen::MatrixXd &E,
                      const std::map<int, Eigen::MatrixXd> &q, const int s_min, const int s_max,
                      std::map<int, Eigen::MatrixXd> &u, std::string &failure, HarmonicWorkspace &work)
    {
      if (!failure.empty())
        return;
      try
        {
          add_cyclic_harmonic(k, N, D, E, q, s_min, s_max, u, work);
        }
      catch (const std::exception &e)
        {
          failure = e.what();
        }
    }

    std::map<int, Eigen::MatrixXd> zero_interface(const Eigen::Index n, const Eigen::Index m, const int s_min,
                                                  const int s_max)
    {
      std::map<int, Eigen::MatrixXd> u;
      for (int s = s_min; s <= s_max; ++s)
        u[s] = Eigen::MatrixXd::Zero(n, m);
      return u;
    }
  } // namespace

  SectorGroup::SectorGroup(MPI_Comm g, std::function<double()> work)
    : group(g), work_so_far(work ? std::move(work) : std::function<double()>(process_cpu_seconds)),
      n_processes(size_of(g))
  {}

  SectorGroup::~SectorGroup()
  {
    try
      {
        dismiss();
      }
    catch (...)
      {}
  }

  void SectorGroup::command(const int kind, const std::vector<long> &arguments) const
  {
    std::vector<long> message = {kind};
    message.insert(message.end(), arguments.begin(), arguments.end());
    for (int r = 1; r < n_processes; ++r)
      MPI_Send(message.data(), static_cast<int>(message.size()), MPI_LONG, r, command_tag, group);
  }

  void SectorGroup::factorise(Mat K, const PetscInt n, const std::vector<PetscInt> &schur_rows,
                              const long memory_limit_MB)
  {
    HG_REQUIRE_INPUT(!dismissed && !factors, "SectorGroup::factorise: called twice or after dismiss");
    command(factorise_command, {static_cast<long>(n), memory_limit_MB});
    factors = std::make_unique<SectorFactorisation>(group, K, n, schur_rows, memory_limit_MB);
  }

  void SectorGroup::send_interface_blocks(const Eigen::MatrixXd &D, const Eigen::MatrixXd &E) const
  {
    if (!shared())
      return;
    command(blocks_command, {});
    broadcast_matrix(const_cast<Eigen::MatrixXd &>(D), group); // rank 0 sends: read only
    broadcast_matrix(const_cast<Eigen::MatrixXd &>(E), group);
  }

  void SectorGroup::solve(const PetscInt n_columns) const
  {
    command(solve_command, {static_cast<long>(n_columns)});
    factors->solve(n_columns);
  }

  void SectorGroup::set_functionals(const Eigen::SparseMatrix<double> &F) const
  {
    command(functionals_command, {});
    factors->set_functionals(&F);
  }

  Eigen::MatrixXd SectorGroup::solve_functionals(const SparseColumns &rhs) const
  {
    const auto n_columns = static_cast<PetscInt>(rhs.n_columns());
    command(functional_solve_command, {static_cast<long>(n_columns)});
    return factors->solve_functionals(n_columns, &rhs);
  }

  std::map<int, Eigen::MatrixXd> SectorGroup::harmonics(const int n_teeth, const Eigen::MatrixXd &D,
                                                        const Eigen::MatrixXd &E,
                                                        const std::map<int, Eigen::MatrixXd> &q, const int s_min,
                                                        const int s_max, std::deque<int> todo,
                                                        const std::function<void(std::deque<int> &, const WorkLevels &)> &between_rounds) const
  {
    std::vector<long> header = {n_teeth, s_min, s_max};
    for (const auto &[s, qs] : q)
      header.push_back(s);
    command(harmonics_command, header);
    for (const auto &[s, qs] : q)
      broadcast_matrix(const_cast<Eigen::MatrixXd &>(qs), group); // rank 0 sends: read only
    // The members' work as each last reported it (at the start, then with each harmonic done)
    // and the harmonics given to each that it has not reported done.
    std::vector<double> reported(static_cast<std::size_t>(n_processes), 0.0);
    double              mine = work_so_far();
    MPI_Gather(&mine, 1, MPI_DOUBLE, reported.data(), 1, MPI_DOUBLE, 0, group);
    std::vector<int> outstanding(static_cast<std::size_t>(n_processes), 0);
    const auto       receive_done = [&](const int p) {
      double level = 0;
      MPI_Recv(&level, 1, MPI_DOUBLE, p, done_tag, group, MPI_STATUS_IGNORE);
      reported[static_cast<std::size_t>(p)] = level;
      --outstanding[static_cast<std::size_t>(p)];
    };
    auto              u = zero_interface(D.rows(), q.begin()->second.cols(), s_min, s_max);
    std::string       failure;
    HarmonicWorkspace work;
    WorkLevels        levels;
    while (!todo.empty())
      {
        for (int p = 1; p < n_processes; ++p)
          for (int flag = 1; flag != 0 && outstanding[static_cast<std::size_t>(p)] > 0;)
            {
              MPI_Iprobe(p, done_tag, group, &flag, MPI_STATUS_IGNORE);
              if (flag != 0)
                receive_done(p);
            }
        // The owner's work as it is, the members' as it will be when they have solved theirs.
        levels.seconds_per_harmonic = work.seconds_per_harmonic();
        levels.levels               = {work_so_far()};
        for (int p = 1; p < n_processes; ++p)
          levels.levels.push_back(reported[static_cast<std::size_t>(p)] +
                                  outstanding[static_cast<std::size_t>(p)] * levels.seconds_per_harmonic);
        if (between_rounds)
          between_rounds(todo, levels);
        if (todo.empty())
          break;
        // A round: one harmonic for each member that has none left to solve, the least busy
        // first (slot p for process p, -1 for none), and one for the owner if more are left than
        // the free members take and it is not ahead of the least busy member by more than half a
        // harmonic (the owner does the group's serial work besides). A member that is still busy
        // gets nothing now, so that harmonics not yet given can still go to helpers.
        std::vector<int> free_members;
        for (int p = 1; p < n_processes; ++p)
          if (outstanding[static_cast<std::size_t>(p)] == 0)
            free_members.push_back(p);
        std::stable_sort(free_members.begin(), free_members.end(), [&](const int a, const int b) {
          return levels.levels[static_cast<std::size_t>(a)] < levels.levels[static_cast<std::size_t>(b)];
        });
        const double least_member =
          n_processes > 1 ? *std::min_element(levels.levels.begin() + 1, levels.levels.end()) : levels.levels[0];
        const bool owner_takes = todo.size() > free_members.size() &&
                                 (levels.seconds_per_harmonic <= 0 ||
                                  levels.levels[0] <= least_member + 0.5 * levels.seconds_per_harmonic);
        std::vector<long> round(static_cast<std::size_t>(n_processes), -1);
        if (owner_takes)
          {
            round[0] = todo.front();
            todo.pop_front();
          }
        bool to_members = false;
        for (const int p : free_members)
          {
            if (todo.empty())
              break;
            round[static_cast<std::size_t>(p)] = todo.front();
            todo.pop_front();
            ++outstanding[static_cast<std::size_t>(p)];
            to_members = true;
          }
        if (to_members)
          command(round_command, round);
        if (round[0] >= 0)
          add_harmonic(static_cast<int>(round[0]), n_teeth, D, E, q, s_min, s_max, u, failure, work);
        else if (!to_members)
          std::this_thread::sleep_for(std::chrono::milliseconds(1)); // every member busy, the owner ahead
      }
    command(round_command, {}); // the end of the call
    for (int p = 1; p < n_processes; ++p)
      while (outstanding[static_cast<std::size_t>(p)] > 0)
        receive_done(p);
    reduce_harmonics(group, u, failure);
    return u;
  }

  void SectorGroup::dismiss()
  {
    if (dismissed)
      return;
    dismissed = true;
    command(dismiss_command, {});
    factors.reset(); // collective with the members' own
  }

  double serve_sector_group(MPI_Comm group, std::function<double()> work_so_far)
  {
    if (!work_so_far)
      work_so_far = process_cpu_seconds;
    std::unique_ptr<SectorFactorisation> factors;
    Eigen::MatrixXd                      D, E;
    double                               busy_s = 0;
    while (true)
      {
        const std::vector<long> message = next_command(group);
        const auto t0 = std::chrono::steady_clock::now();
        switch (message.at(0))
          {
            case factorise_command:
              try
                {
                  factors = std::make_unique<SectorFactorisation>(group, nullptr, static_cast<PetscInt>(message.at(1)),
                                                                  std::vector<PetscInt>{}, message.at(2));
                }
              catch (const FactorisationTooLarge &)
                {
                  // The owner decides: it dismisses the group, and may try a larger one.
                }
              break;
            case blocks_command:
              broadcast_matrix(D, group);
              broadcast_matrix(E, group);
              break;
            case solve_command:
              factors->solve(static_cast<PetscInt>(message.at(1)));
              break;
            case functionals_command:
              factors->set_functionals(nullptr);
              break;
            case functional_solve_command:
              factors->solve_functionals(static_cast<PetscInt>(message.at(1)), nullptr);
              break;
            case harmonics_command:
              {
                const int N = static_cast<int>(message.at(1)), s_min = static_cast<int>(message.at(2)),
                          s_max = static_cast<int>(message.at(3));
                std::map<int, Eigen::MatrixXd> q;
                for (std::size_t i = 4; i < message.size(); ++i)
                  broadcast_matrix(q[static_cast<int>(message[i])], group);
                const double mine = work_so_far(); // by which the owner shares the harmonics
                MPI_Gather(&mine, 1, MPI_DOUBLE, nullptr, 1, MPI_DOUBLE, 0, group);
                auto              u = zero_interface(D.rows(), q.begin()->second.cols(), s_min, s_max);
                std::string       failure;
                HarmonicWorkspace work;
                const int         me = rank_of(group);
                // Rounds until an empty one; slot me + 1 (after the command) is this process's,
                // and each harmonic done is reported with this process's work so far.
                for (auto round = next_command(group); round.size() > 1; round = next_command(group))
                  if (static_cast<std::size_t>(me) < round.size() - 1 && round[static_cast<std::size_t>(me) + 1] >= 0)
                    {
                      add_harmonic(static_cast<int>(round[static_cast<std::size_t>(me) + 1]), N, D, E, q, s_min,
                                   s_max, u, failure, work);
                      const double level = work_so_far();
                      MPI_Send(&level, 1, MPI_DOUBLE, 0, done_tag, group);
                    }
                reduce_harmonics(group, u, failure);
              }
              break;
            case dismiss_command:
              factors.reset(); // with the owner's
              return busy_s + std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            default:
              throw NumericalError(msg("sector group: unknown command ", message.at(0)));
          }
        busy_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      }
  }
} // namespace hertzgear::fem
