#include "fem/cyclic_gear_body.h"

#include "common/errors.h"
#include "fem/harmonic_sharing.h"
#include "fem/petsc_ksp.h"
#include "fem/sector_group.h"

#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_tools.h>

#include <Eigen/Sparse>

#include <petscksp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <deque>

namespace hertzgear::fem
{
  using namespace dealii;

  namespace
  {
    // Bytes of one block of sector right-hand sides, solved in place (one MUMPS substitution).
    constexpr double block_solve_bytes = 256.0 * 1024 * 1024;

    // Columns of one block of solutions of n DoFs: MUMPS reads its factors once per block.
    std::size_t columns_per_block(const std::size_t n)
    {
      return static_cast<std::size_t>(
        std::max(1.0, std::floor(block_solve_bytes / (8.0 * std::max<double>(1, static_cast<double>(n))))));
    }

    // The rotation (c, s) in the x-y plane applied in place to every node of x (node-blocked, dim
    // entries a node): to its rows, x <- R x, or to its columns, x <- (R x^T)^T = x R^T.
    // Column by column: the matrices are stored by columns.
    template <int dim>
    void turn_rows(Eigen::MatrixXd &x, const double c, const double s)
    {
      for (Eigen::Index j = 0; j < x.cols(); ++j)
        for (Eigen::Index i = 0; i < x.rows(); i += dim)
          {
            const double a = x(i, j), b = x(i + 1, j);
            x(i, j)     = c * a - s * b;
            x(i + 1, j) = s * a + c * b;
          }
    }

    template <int dim>
    void turn_columns(Eigen::MatrixXd &x, const double c, const double s)
    {
      for (Eigen::Index j = 0; j < x.cols(); j += dim)
        for (Eigen::Index i = 0; i < x.rows(); ++i)
          {
            const double a = x(i, j), b = x(i, j + 1);
            x(i, j)     = c * a - s * b;
            x(i, j + 1) = s * a + c * b;
          }
    }

    // f(values) on the array of a one-process PETSc vector.
    template <class F>
    auto with_values(const Vec v, F &&f)
    {
      const PetscScalar *values = nullptr;
      check_petsc(VecGetArrayRead(v, &values), "VecGetArrayRead");
      auto result = f(values);
      check_petsc(VecRestoreArrayRead(v, &values), "VecRestoreArrayRead");
      return result;
    }

    template <int dim>
    Tensor<1, dim> turned(const Tensor<1, dim> &v, const double angle)
    {
      Tensor<1, dim> r = v;
      const double   c = std::cos(angle), s = std::sin(angle);
      r[0] = c * v[0] - s * v[1];
      r[1] = s * v[0] + c * v[1];
      return r;
    }
  } // namespace

  template <int dim>
  long CyclicGearBody<dim>::factorisation_memory_MB() const
  {
    HG_REQUIRE_INPUT(factors != nullptr, "CyclicGearBody::run() must be called first");
    return factors->estimated_memory_MB_per_process();
  }

  template <int dim>
  bool CyclicGearBody<dim>::in_group() const
  {
    return parameters.sector_group != nullptr && parameters.sector_group->shared();
  }

  template <int dim>
  CyclicGearBody<dim>::CyclicGearBody(const Triangulation<dim> &sector, const Parameters &parameters)
    : parameters(parameters), body(sector, parameters.body)
  {
    HG_REQUIRE_INPUT(parameters.n_teeth >= 3, "the cyclic gear model needs at least 3 teeth, got ",
                     parameters.n_teeth);
    HG_REQUIRE_INPUT(Utilities::MPI::n_mpi_processes(sector.get_communicator()) == 1,
                     "the cyclic gear model factorises its sector on one process: give it a serial "
                     "triangulation");
    HG_REQUIRE_INPUT(parameters.body.linear_solver == ElasticBody<dim>::LinearSolver::direct,
                     "the cyclic gear model needs the direct solver (its Schur complement comes "
                     "from the MUMPS factorisation)");
    theta = 2.0 * M_PI / parameters.n_teeth;
  }

  template <int dim>
  CyclicGearBody<dim>::~CyclicGearBody() = default;

  template <int dim>
  void CyclicGearBody<dim>::set_load_boundary_ids(const std::set<types::boundary_id> &ids)
  {
    body.set_load_boundary_ids(ids);
  }

  template <int dim>
  int CyclicGearBody<dim>::tooth_of(const Point<dim> &x) const
  {
    double angle = std::atan2(x[1], x[0]);
    if constexpr (dim == 3)
      angle -= parameters.twist_rad_per_mm * x[2];
    return static_cast<int>(std::lround(angle / theta));
  }

  template <int dim>
  Point<dim> CyclicGearBody<dim>::to_sector(const Point<dim> &x, const int tooth) const
  {
    Tensor<1, dim> v = x;
    return Point<dim>(turned(v, -tooth * theta));
  }

  template <int dim>
  Tensor<1, dim> CyclicGearBody<dim>::to_sector(const Tensor<1, dim> &v, const int tooth) const
  {
    return turned(v, -tooth * theta);
  }

  template <int dim>
  void CyclicGearBody<dim>::run()
  {
    body.assemble();
    for (const auto &[phase, seconds] : body.get_timer().phases())
      timer.add(phase, seconds);
    {
      PhaseTimer::Scope t(timer, "cut faces");
      pair_cut_faces();
    }
    PhaseTimer::Scope t(timer, "factorisation");
    factorise();
  }

  // Every unconstrained node of the start cut A and its partner on the end cut B (A turned by
  // theta), node-blocked: cut_a[dim i + c] and cut_b[dim i + c] are component c of pair i.
  template <int dim>
  void CyclicGearBody<dim>::pair_cut_faces()
  {
    const auto &dof_handler = body.get_dof_handler();
    const auto &fe          = dof_handler.get_fe();
    std::vector<Point<dim>> support(dof_handler.n_dofs());
    DoFTools::map_dofs_to_support_points(body.get_mapping(), dof_handler, support);

    using Node = std::array<types::global_dof_index, dim>;
    std::map<std::array<double, dim>, Node> nodes[2]; // A, B
    std::vector<types::global_dof_index>    face_dofs(fe.n_dofs_per_face());
    double                                  radius = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() &&
            (face->boundary_id() == parameters.cut_start_id || face->boundary_id() == parameters.cut_end_id))
          {
            const unsigned int side = face->boundary_id() == parameters.cut_start_id ? 0 : 1;
            face->get_dof_indices(face_dofs);
            for (unsigned int i = 0; i < face_dofs.size(); ++i)
              {
                const types::global_dof_index dof = face_dofs[i];
                std::array<double, dim>       key;
                for (unsigned int d = 0; d < dim; ++d)
                  key[d] = support[dof][d];
                radius = std::max(radius, support[dof].norm());
                auto it = nodes[side].emplace(key, Node{}).first;
                it->second[fe.face_system_to_component_index(i).first] = dof;
              }
          }
    const auto &constraints = body.get_constraints();
    for (auto &side : nodes)
      for (auto it = side.begin(); it != side.end();)
        it = constraints.is_constrained(it->second[0]) ? side.erase(it) : std::next(it);
    HG_REQUIRE_INPUT(!nodes[0].empty(), "the sector mesh has no free nodes on its start cut "
                                        "(boundary id ", static_cast<int>(parameters.cut_start_id), ")");
    HG_REQUIRE_INPUT(nodes[0].size() == nodes[1].size(), parameters.name,
                     ": the cut faces of the sector mesh do not match: ",
                     nodes[0].size(), " free nodes on the start cut, ", nodes[1].size(),
                     " on the end cut");

    // Brute force over the (a few thousand) cut nodes: each A node turned by theta must land on
    // a B node, one to one.
    const double tolerance = 1e-8 * radius;
    std::vector<std::pair<Point<dim>, Node>> b_nodes;
    for (const auto &[key, node] : nodes[1])
      {
        Point<dim> p;
        for (unsigned int d = 0; d < dim; ++d)
          p[d] = key[d];
        b_nodes.emplace_back(p, node);
      }
    std::vector<bool> used(b_nodes.size(), false);
    cut_a.clear();
    cut_b.clear();
    for (const auto &[key, node] : nodes[0])
      {
        Point<dim> p;
        for (unsigned int d = 0; d < dim; ++d)
          p[d] = key[d];
        const Point<dim> target(turned(Tensor<1, dim>(p), theta));
        std::size_t      best = 0;
        double           best_distance = std::numeric_limits<double>::max();
        for (std::size_t j = 0; j < b_nodes.size(); ++j)
          {
            const double d = b_nodes[j].first.distance(target);
            if (d < best_distance)
              best_distance = d, best = j;
          }
        HG_REQUIRE_INPUT(best_distance <= tolerance && !used[best],
                         parameters.name, ": the cut faces of the sector mesh do not match: the start-cut node at (",
                         p, ") turned by 2 pi / ", parameters.n_teeth, " lies ", best_distance,
                         " from the nearest end-cut node (tolerance ", tolerance,
                         "); the sector must span exactly one tooth pitch with a periodic cut mesh");
        used[best] = true;
        for (unsigned int c = 0; c < dim; ++c)
          {
            cut_a.push_back(node[c]);
            cut_b.push_back(b_nodes[best].second[c]);
          }
      }
  }

  template <int dim>
  Eigen::MatrixXd CyclicGearBody<dim>::turn(const Eigen::MatrixXd &x, const bool transpose) const
  {
    Eigen::MatrixXd y = x;
    turn_rows<dim>(y, std::cos(theta), transpose ? -std::sin(theta) : std::sin(theta));
    return y;
  }

  template <int dim>
  void CyclicGearBody<dim>::factorise()
  {
    const std::size_t     n_a = cut_a.size();
    std::vector<PetscInt> schur_rows;
    for (const auto d : cut_a)
      schur_rows.push_back(static_cast<PetscInt>(d));
    for (const auto d : cut_b)
      schur_rows.push_back(static_cast<PetscInt>(d));
    const auto n_dofs = static_cast<PetscInt>(body.n_dofs());
    on_cut.assign(body.n_dofs(), 0);
    for (const auto d : schur_rows)
      on_cut[static_cast<std::size_t>(d)] = 1;
    if (in_group())
      {
        parameters.sector_group->factorise(body.get_system_matrix(), n_dofs, schur_rows,
                                           parameters.body.factorisation_memory_limit_MB);
        factors = &parameters.sector_group->factorisation();
      }
    else
      {
        own_factors = std::make_unique<SectorFactorisation>(MPI_COMM_SELF, body.get_system_matrix(), n_dofs,
                                                            schur_rows, parameters.body.factorisation_memory_limit_MB);
        factors = own_factors.get();
      }
    const Eigen::MatrixXd S = factors->take_schur(); // symmetric to the last bit: one triangle mirrored
    HG_REQUIRE_NUMERIC(static_cast<std::size_t>(S.rows()) == 2 * n_a, "the Schur complement has ", S.rows(),
                       " rows, not ", 2 * n_a);
    {
      // The cut rows of K, for the cut reactions (K x)_c of interior solutions.
      const Mat K = body.get_system_matrix();
      std::vector<Eigen::Triplet<double>> entries;
      for (std::size_t r = 0; r < schur_rows.size(); ++r)
        {
          PetscInt           n_cols = 0;
          const PetscInt    *cols   = nullptr;
          const PetscScalar *vals   = nullptr;
          check_petsc(MatGetRow(K, schur_rows[r], &n_cols, &cols, &vals), "MatGetRow");
          for (PetscInt k = 0; k < n_cols; ++k)
            entries.emplace_back(static_cast<int>(r), static_cast<int>(cols[k]), vals[k]);
          check_petsc(MatRestoreRow(K, schur_rows[r], &n_cols, &cols, &vals), "MatRestoreRow");
        }
      K_cut.resize(static_cast<Eigen::Index>(schur_rows.size()), static_cast<Eigen::Index>(body.n_dofs()));
      K_cut.setFromTriplets(entries.begin(), entries.end());
    }
    const Eigen::Index m    = static_cast<Eigen::Index>(n_a);
    // D = S_AA + T^T S_BB T and E = S_AB T, turned in place (two matrices of m^2 are made, not six).
    const double c = std::cos(theta), s = -std::sin(theta); // T^T
    Eigen::MatrixXd W = S.bottomRightCorner(m, m);
    turn_rows<dim>(W, c, s);    // T^T S_BB
    turn_columns<dim>(W, c, s); // T^T S_BB T, transposed (S_BB is symmetric)
    D = S.topLeftCorner(m, m);
    D += W.transpose();
    E = S.topRightCorner(m, m); // S_AB = S_BA^T
    turn_columns<dim>(E, c, s);
    if (in_group())
      parameters.sector_group->send_interface_blocks(D, E);
  }

  template <int dim>
  std::vector<double> CyclicGearBody<dim>::harmonic_norms(const std::map<int, Eigen::MatrixXd> &q) const
  {
    HG_REQUIRE_INPUT(!q.empty(), "harmonic_norms: no condensed load");
    const int           N = static_cast<int>(parameters.n_teeth);
    std::vector<double> norms;
    for (int k = 0; k <= N / 2; ++k)
      {
        Eigen::MatrixXcd qk = Eigen::MatrixXcd::Zero(D.rows(), q.begin()->second.cols());
        for (const auto &[s, qs] : q)
          qk += std::polar(1.0 / N, -2.0 * M_PI * k * s / N) * qs.template cast<std::complex<double>>();
        norms.push_back(qk.norm());
      }
    return norms;
  }

  template <int dim>
  std::map<int, Eigen::MatrixXd>
  CyclicGearBody<dim>::solve_interface(const std::map<int, Eigen::MatrixXd> &q, const int s_min,
                                       const int s_max, const int only_harmonic) const
  {
    HG_REQUIRE_INPUT(!q.empty(), "solve_interface: no condensed load");
    PhaseTimer::Scope t(timer, "harmonics");
    const int          N = static_cast<int>(parameters.n_teeth);
    const Eigen::Index n = D.rows();
    const Eigen::Index m = q.begin()->second.cols();
    if (in_group() && only_harmonic < 0)
      {
        // Over the group, round by round; between rounds free ranks outside it take a share.
        HarmonicSharing *sharing = parameters.harmonic_sharing ? parameters.harmonic_sharing() : nullptr;
        std::deque<int>  todo;
        for (int k = 0; k <= N / 2; ++k)
          todo.push_back(k);
        try
          {
            auto u = parameters.sector_group->harmonics(
              N, D, E, q, s_min, s_max, todo, [&](std::deque<int> &t, const SectorGroup::WorkLevels &group) {
                if (sharing)
                  sharing->lend(parameters.sharing_body, t, N, D, E, q, s_min, s_max, group.seconds_per_harmonic,
                                group.levels);
              });
            if (sharing)
              sharing->collect(parameters.sharing_body, u);
            return u;
          }
        catch (...)
          {
            if (sharing)
              try
                {
                  std::map<int, Eigen::MatrixXd> ignored;
                  for (int s = s_min; s <= s_max; ++s)
                    ignored[s] = Eigen::MatrixXd::Zero(n, m);
                  sharing->collect(parameters.sharing_body, ignored); // the helpers' results, then this failure
                }
              catch (...)
                {}
            throw;
          }
      }
    std::map<int, Eigen::MatrixXd> u;
    for (int s = s_min; s <= s_max; ++s)
      u[s] = Eigen::MatrixXd::Zero(n, m);
    const MPI_Comm comm  = parameters.harmonic_communicator;
    const int      rank  = static_cast<int>(Utilities::MPI::this_mpi_process(comm));
    const int      ranks = static_cast<int>(Utilities::MPI::n_mpi_processes(comm));
    std::deque<int> todo;
    for (int k = rank; k <= N / 2; k += ranks)
      if (only_harmonic < 0 || k == only_harmonic)
        todo.push_back(k);
    // Harmonics not started yet may go to helper processes (fem/harmonic_sharing.h).
    HarmonicSharing *sharing =
      only_harmonic < 0 && ranks == 1 && parameters.harmonic_sharing ? parameters.harmonic_sharing() : nullptr;
    HarmonicWorkspace work;
    try
      {
        while (!todo.empty())
          {
            if (parameters.between_work_units)
              parameters.between_work_units();
            if (sharing)
              sharing->lend(parameters.sharing_body, todo, N, D, E, q, s_min, s_max, work.seconds_per_harmonic());
            const int k = todo.front();
            todo.pop_front();
            add_cyclic_harmonic(k, N, D, E, q, s_min, s_max, u, work);
          }
      }
    catch (...)
      {
        if (sharing)
          try
            {
              sharing->collect(parameters.sharing_body, u); // the helpers' results, then this failure
            }
          catch (...)
            {}
        throw;
      }
    if (sharing)
      sharing->collect(parameters.sharing_body, u);
    if (ranks > 1)
      for (auto &[s, us] : u)
        Utilities::MPI::sum(ArrayView<const double>(us.data(), us.size()), comm,
                            ArrayView<double>(us.data(), us.size()));
    return u;
  }

  template <int dim>
  Eigen::VectorXd CyclicGearBody<dim>::cut_values(const VectorType &u) const
  {
    return with_values(u, [&](const double *values) { return cut_values(values); });
  }

  template <int dim>
  Eigen::VectorXd CyclicGearBody<dim>::cut_values(const double *u) const
  {
    const std::size_t n_a = cut_a.size();
    Eigen::VectorXd   v(2 * n_a);
    for (std::size_t i = 0; i < n_a; ++i)
      {
        v[i]       = u[cut_a[i]];
        v[n_a + i] = u[cut_b[i]];
      }
    return v;
  }

  template <int dim>
  Eigen::VectorXd CyclicGearBody<dim>::cut_reaction(const double *x) const
  {
    // (K x) on the cut rows alone: the rows of K at [A; B], extracted once.
    Eigen::VectorXd y = Eigen::VectorXd::Zero(K_cut.rows());
    for (Eigen::Index r = 0; r < K_cut.outerSize(); ++r)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(K_cut, r); it; ++it)
        y[r] += it.value() * x[it.col()];
    return y;
  }

  template <int dim>
  Eigen::VectorXd CyclicGearBody<dim>::cut_reaction(const VectorType &x) const
  {
    return with_values(x, [&](const double *values) { return cut_reaction(values); });
  }

  template <int dim>
  void CyclicGearBody<dim>::zero_cut_entries(double *values) const
  {
    for (std::size_t i = 0; i < cut_a.size(); ++i)
      values[cut_a[i]] = values[cut_b[i]] = 0.0;
  }

  template <int dim>
  void CyclicGearBody<dim>::solve_interior_columns(const std::size_t n_rhs,
                                                   const std::function<void(std::size_t, double *)> &fill,
                                                   const std::function<void(std::size_t, const double *)> &use) const
  {
    // One block of right-hand sides (their solutions in place) is held at a time.
    const std::size_t n     = body.n_dofs();
    const std::size_t block = columns_per_block(n);
    for (std::size_t start = 0; start < n_rhs; start += block)
      {
        if (parameters.between_work_units)
          parameters.between_work_units();
        const std::size_t end       = std::min(n_rhs, start + block);
        const auto        n_columns = static_cast<PetscInt>(end - start);
        double           *columns   = factors->right_hand_sides(n_columns);
        for (std::size_t j = start; j < end; ++j)
          {
            double *b = columns + (j - start) * n;
            fill(j, b);
            zero_cut_entries(b);
          }
        {
          PhaseTimer::Scope t(timer, "solves");
          if (in_group())
            parameters.sector_group->solve(n_columns);
          else
            factors->solve(n_columns);
        }
        for (std::size_t j = start; j < end; ++j)
          {
            double *x = columns + (j - start) * n;
            zero_cut_entries(x);
            use(j, x);
          }
      }
  }

  template <int dim>
  Eigen::MatrixXd
  CyclicGearBody<dim>::solve_interior_functionals(const Eigen::SparseMatrix<double> &F, const std::size_t n_rhs,
                                                  const std::function<void(std::size_t, SparseColumns &)> &fill) const
  {
    // As many columns per block as the dense blocks of solve_interior_columns hold.
    const std::size_t block = columns_per_block(body.n_dofs());
    if (in_group())
      parameters.sector_group->set_functionals(F);
    else
      factors->set_functionals(&F);
    Eigen::MatrixXd FX(F.rows(), static_cast<Eigen::Index>(n_rhs));
    for (std::size_t start = 0; start < n_rhs; start += block)
      {
        if (parameters.between_work_units)
          parameters.between_work_units();
        const std::size_t end = std::min(n_rhs, start + block);
        SparseColumns     columns;
        for (std::size_t j = start; j < end; ++j)
          {
            fill(j, columns);
            columns.start.push_back(static_cast<long>(columns.rows.size()));
          }
        PhaseTimer::Scope t(timer, "solves");
        FX.middleCols(static_cast<Eigen::Index>(start), static_cast<Eigen::Index>(end - start)) =
          in_group() ? parameters.sector_group->solve_functionals(columns) :
                       factors->solve_functionals(static_cast<PetscInt>(end - start), &columns);
      }
    return FX;
  }

  template <int dim>
  void CyclicGearBody<dim>::solve_interior(std::vector<VectorType> &rhs,
                                           const std::function<void(std::size_t, const VectorType &)> &use) const
  {
    const std::size_t n = body.n_dofs();
    solve_interior_columns(
      rhs.size(),
      [&](const std::size_t j, double *b) {
        with_values(rhs[j], [&](const double *values) { return std::copy(values, values + n, b); });
        rhs[j] = VectorType(); // consumed
      },
      [&](const std::size_t j, const double *x) {
        VectorType   u(body.get_locally_owned_dofs(), MPI_COMM_SELF);
        PetscScalar *values = nullptr;
        check_petsc(VecGetArray(u, &values), "VecGetArray");
        std::copy(x, x + n, values);
        check_petsc(VecRestoreArray(u, &values), "VecRestoreArray");
        use(j, body.ghosted_solution(u));
      });
    rhs.clear();
  }

  template <int dim>
  FullMatrix<double> CyclicGearBody<dim>::compliance(const std::vector<PatchLoad<dim>>    &loads,
                                                     const std::vector<PointReading<dim>> &readings) const
  {
    HG_REQUIRE_INPUT(factors != nullptr, "CyclicGearBody::run() must be called first");
    // Loads and readings turned into the sector; equal ones solved once.
    const double scale = 1e-9; // relative: equal up to round-off of the rotation
    std::vector<PatchLoad<dim>>    unique_loads;
    std::vector<PointReading<dim>> unique_readings;
    std::vector<std::pair<int, std::size_t>> load_of(loads.size()), reading_of(readings.size());
    for (std::size_t l = 0; l < loads.size(); ++l)
      {
        const int      t = tooth_of(loads[l].centre);
        PatchLoad<dim> local{to_sector(loads[l].centre, t), to_sector(loads[l].direction, t), loads[l].radius};
        std::size_t    j = 0;
        while (j < unique_loads.size() &&
               !(unique_loads[j].centre.distance(local.centre) <= scale * (1 + local.centre.norm()) &&
                 (unique_loads[j].direction - local.direction).norm() <= 1e-12 &&
                 unique_loads[j].radius == local.radius))
          ++j;
        if (j == unique_loads.size())
          unique_loads.push_back(local);
        load_of[l] = {t, j};
      }
    for (std::size_t r = 0; r < readings.size(); ++r)
      {
        const int         t = tooth_of(readings[r].point);
        PointReading<dim> local{to_sector(readings[r].point, t), to_sector(readings[r].direction, t)};
        std::size_t       j = 0;
        while (j < unique_readings.size() &&
               !(unique_readings[j].point.distance(local.point) <= scale * (1 + local.point.norm()) &&
                 (unique_readings[j].direction - local.direction).norm() <= 1e-12))
          ++j;
        if (j == unique_readings.size())
          unique_readings.push_back(local);
        reading_of[r] = {t, j};
      }

    const std::size_t n_l = unique_loads.size(), n_r = unique_readings.size(), n_c = 2 * cut_a.size();
    std::map<types::global_dof_index, std::size_t> cut_index; // DoF -> row of [A; B]
    for (std::size_t i = 0; i < cut_a.size(); ++i)
      cut_index[cut_a[i]] = i, cut_index[cut_b[i]] = cut_a.size() + i;
    // Each reading split into its interior functional r_I (DoFs ascending, each once: a
    // right-hand side) and its cut-face part r_c.
    std::vector<std::vector<std::pair<long, double>>> reading_rhs(n_r);
    Eigen::MatrixXd Z = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n_r), static_cast<Eigen::Index>(n_c));
    Eigen::MatrixXd G(n_c, n_l); // condensed loads f_c - K_cI K_II^-1 f_I of the loaded sector
    {
      PhaseTimer::Scope t(timer, "load vectors");
      for (std::size_t r = 0; r < n_r; ++r)
        {
          std::map<long, double> interior;
          for (const auto &[dof, w] : body.reading_functional(unique_readings[r]))
            {
              const auto c = cut_index.find(dof);
              if (c != cut_index.end())
                Z(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c->second)) += w;
              else
                interior[static_cast<long>(dof)] += w;
            }
          reading_rhs[r].assign(interior.begin(), interior.end());
        }
    }
    // The functionals of the interior solutions read: the cut reactions K_cI (rows of K at the cut
    // faces, off them) and the readings' interior functionals r_I.
    Eigen::SparseMatrix<double> F(static_cast<Eigen::Index>(n_c + n_r), static_cast<Eigen::Index>(body.n_dofs()));
    {
      std::vector<Eigen::Triplet<double>> entries;
      for (Eigen::Index r = 0; r < K_cut.outerSize(); ++r)
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(K_cut, r); it; ++it)
          if (on_cut[static_cast<std::size_t>(it.col())] == 0)
            entries.emplace_back(static_cast<int>(r), static_cast<int>(it.col()), it.value());
      for (std::size_t r = 0; r < n_r; ++r)
        for (const auto &[dof, w] : reading_rhs[r])
          entries.emplace_back(static_cast<int>(n_c + r), static_cast<int>(dof), w);
      F.setFromTriplets(entries.begin(), entries.end());
      F.makeCompressed();
    }
    const auto fill = [&](const std::size_t j, SparseColumns &columns) {
      PhaseTimer::Scope t(timer, "load vectors");
      if (j < n_l)
        {
          const VectorType f = body.patch_load_vector(unique_loads[j]);
          with_values(f, [&](const double *values) {
            G.col(static_cast<Eigen::Index>(j)) = cut_values(values);
            for (std::size_t i = 0; i < body.n_dofs(); ++i)
              if (values[i] != 0.0 && on_cut[i] == 0)
                {
                  columns.rows.push_back(static_cast<long>(i));
                  columns.values.push_back(values[i]);
                }
            return 0;
          });
        }
      else
        for (const auto &[dof, w] : reading_rhs[j - n_l])
          {
            columns.rows.push_back(dof);
            columns.values.push_back(w);
          }
    };
    // Interior solves (cut faces held at zero): x = K_II^-1 f for the loads, w = K_II^-1 r_I
    // for the readings. A reading of a sector with cut displacement u_c and own load f is then
    // r_I . x - (K_cI w) . u_c + r_c . u_c. Only the functionals F of the solutions are read.
    const Eigen::MatrixXd FX = solve_interior_functionals(F, n_l + n_r, fill);
    const auto            cl = static_cast<Eigen::Index>(n_c), rl = static_cast<Eigen::Index>(n_r),
               ll = static_cast<Eigen::Index>(n_l);
    G -= FX.topLeftCorner(cl, ll);
    Z -= FX.topRightCorner(cl, rl).transpose();
    const Eigen::MatrixXd interior_readings = FX.bottomLeftCorner(rl, ll);

    const Eigen::Index m = static_cast<Eigen::Index>(cut_a.size());
    int d_min = 0, d_max = 0;
    for (const auto &[tr, r] : reading_of)
      for (const auto &[tl, l] : load_of)
        d_min = std::min(d_min, tr - tl), d_max = std::max(d_max, tr - tl);
    const auto u = solve_interface({{0, G.topRows(m)}, {1, turn(G.bottomRows(m), true)}}, d_min, d_max + 1);

    PhaseTimer::Scope t(timer, "readings");
    std::map<int, Eigen::MatrixXd> Y;
    for (int d = d_min; d <= d_max; ++d)
      {
        Eigen::MatrixXd cut(n_c, n_l);
        cut.topRows(m)    = u.at(d);
        cut.bottomRows(m) = turn(u.at(d + 1), false);
        Y[d]              = Z * cut;
        if (d == 0)
          Y[d] += interior_readings;
      }
    FullMatrix<double> C(readings.size(), loads.size());
    for (std::size_t r = 0; r < readings.size(); ++r)
      for (std::size_t l = 0; l < loads.size(); ++l)
        C(r, l) = Y.at(reading_of[r].first - load_of[l].first)(reading_of[r].second, load_of[l].second);
    return C;
  }

  template <int dim>
  typename CyclicGearBody<dim>::CondensedLoads
  CyclicGearBody<dim>::condense(const std::vector<SectorLoads> &cases) const
  {
    HG_REQUIRE_INPUT(factors != nullptr, "CyclicGearBody::run() must be called first");
    const Eigen::Index                  m = static_cast<Eigen::Index>(cut_a.size());
    const Eigen::Index                  n_cases = static_cast<Eigen::Index>(cases.size());
    std::vector<std::pair<Eigen::Index, int>> loaded; // (case, sector) of each right-hand side
    std::vector<VectorType>             rhs;
    {
      PhaseTimer::Scope t(timer, "load vectors");
      for (Eigen::Index c = 0; c < n_cases; ++c)
        for (const auto &[s, set] : cases[c].loads)
          {
            const auto f = cases[c].forces.find(s);
            HG_REQUIRE_INPUT(f != cases[c].forces.end() && f->second.size() == set.size(),
                             "sector ", s, ": ", set.size(), " loads but not as many forces");
            VectorType total(body.get_locally_owned_dofs(), MPI_COMM_SELF);
            for (std::size_t k = 0; k < set.size(); ++k)
              if (f->second[k] != 0.0)
                total.add(f->second[k], body.patch_load_vector(set[k]));
            loaded.emplace_back(c, s);
            rhs.push_back(std::move(total));
          }
    }
    CondensedLoads result;
    result.free_fields.resize(cases.size());
    std::vector<Eigen::VectorXd> f_cut;
    for (const auto &f : rhs)
      f_cut.push_back(cut_values(f));
    solve_interior(rhs, [&](const std::size_t j, const VectorType &u) {
      const auto [c, s]       = loaded[j];
      const Eigen::VectorXd g = f_cut[j] - cut_reaction(u);
      for (const auto &[sector, part] : {std::pair<int, Eigen::VectorXd>{s, g.head(m)},
                                         std::pair<int, Eigen::VectorXd>{s + 1, turn(g.tail(m), true)}})
        {
          auto it = result.q.find(sector);
          if (it == result.q.end())
            it = result.q.emplace(sector, Eigen::MatrixXd::Zero(m, n_cases)).first;
          it->second.col(c) += part;
        }
      result.free_fields[c][s] = u;
    });
    return result;
  }

  template <int dim>
  std::vector<std::map<int, typename ElasticBody<dim>::VectorType>>
  CyclicGearBody<dim>::sector_fields(const CondensedLoads &loads, const std::vector<int> &sectors,
                                     const int only_harmonic) const
  {
    HG_REQUIRE_INPUT(!sectors.empty(), "sector_fields: no sector asked for");
    const Eigen::Index m       = static_cast<Eigen::Index>(cut_a.size());
    const std::size_t  n_cases = loads.free_fields.size();
    const int          s_min   = *std::min_element(sectors.begin(), sectors.end());
    const int          s_max   = *std::max_element(sectors.begin(), sectors.end()) + 1;
    std::map<int, Eigen::MatrixXd> u;
    if (loads.q.empty())
      for (int s = s_min; s <= s_max; ++s)
        u[s] = Eigen::MatrixXd::Zero(m, static_cast<Eigen::Index>(n_cases));
    else
      u = solve_interface(loads.q, s_min, s_max, only_harmonic);

    // Sector s: cut displacement u_c, interior K_II^-1 (f_I - K_Ic u_c).
    std::vector<VectorType>                   rhs;
    std::vector<std::pair<std::size_t, int>> which;
    std::vector<Eigen::VectorXd>              cuts;
    for (std::size_t c = 0; c < n_cases; ++c)
      for (const int s : sectors)
        {
          Eigen::VectorXd cut(2 * m);
          cut.head(m) = u.at(s).col(static_cast<Eigen::Index>(c));
          cut.tail(m) = turn(u.at(s + 1).col(static_cast<Eigen::Index>(c)), false);
          VectorType on_cut(body.get_locally_owned_dofs(), MPI_COMM_SELF), f(body.get_locally_owned_dofs(), MPI_COMM_SELF);
          for (Eigen::Index i = 0; i < m; ++i)
            {
              on_cut[cut_a[i]] = cut[i];
              on_cut[cut_b[i]] = cut[m + i];
            }
          on_cut.compress(VectorOperation::insert);
          body.get_system_matrix().vmult(f, on_cut);
          f *= -1.0;
          rhs.push_back(std::move(f));
          which.emplace_back(c, s);
          cuts.push_back(cut);
        }
    std::vector<std::map<int, VectorType>> fields(n_cases);
    solve_interior(rhs, [&](const std::size_t j, const VectorType &v) {
      const auto [c, s] = which[j];
      VectorType field(body.get_locally_owned_dofs(), MPI_COMM_SELF);
      field           = v;
      const auto free = loads.free_fields[c].find(s);
      if (free != loads.free_fields[c].end())
        {
          VectorType owned(body.get_locally_owned_dofs(), MPI_COMM_SELF);
          owned = free->second;
          field += owned;
        }
      for (Eigen::Index i = 0; i < m; ++i)
        {
          field[cut_a[i]] = cuts[j][i];
          field[cut_b[i]] = cuts[j][m + i];
        }
      field.compress(VectorOperation::insert);
      fields[c][s] = body.ghosted_solution(field);
    });
    return fields;
  }

  template class CyclicGearBody<2>;
  template class CyclicGearBody<3>;
} // namespace hertzgear::fem
