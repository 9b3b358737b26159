#include "fem/cyclic_gear_body.h"

#include "common/errors.h"
#include "fem/petsc_ksp.h"

#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/lac/lapack_templates.h>

#include <petscksp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>

namespace hertzgear::fem
{
  using namespace dealii;

  namespace
  {
    // Bytes of one block of sector right-hand sides (and as much for the solutions).
    constexpr double block_solve_bytes = 256.0 * 1024 * 1024;

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
  struct CyclicGearBody<dim>::Factorisation
  {
    KSP ksp = nullptr;
    ~Factorisation()
    {
      if (ksp != nullptr)
        KSPDestroy(&ksp);
    }
  };

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
    return static_cast<int>(std::lround(std::atan2(x[1], x[0]) / theta));
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
    HG_REQUIRE_INPUT(nodes[0].size() == nodes[1].size(), "the cut faces of the sector mesh do not match: ",
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
                         "the cut faces of the sector mesh do not match: the start-cut node at (",
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
    const double    c = std::cos(theta), s = transpose ? -std::sin(theta) : std::sin(theta);
    Eigen::MatrixXd y = x;
    for (Eigen::Index i = 0; i < x.rows(); i += dim)
      {
        y.row(i)     = c * x.row(i) - s * x.row(i + 1);
        y.row(i + 1) = s * x.row(i) + c * x.row(i + 1);
      }
    return y;
  }

  template <int dim>
  void CyclicGearBody<dim>::factorise()
  {
    factorisation = std::make_unique<Factorisation>();
    const std::size_t     n_a = cut_a.size();
    std::vector<PetscInt> schur_rows;
    for (const auto d : cut_a)
      schur_rows.push_back(static_cast<PetscInt>(d));
    for (const auto d : cut_b)
      schur_rows.push_back(static_cast<PetscInt>(d));
    IS is;
    check_petsc(ISCreateGeneral(PETSC_COMM_SELF, static_cast<PetscInt>(schur_rows.size()),
                                schur_rows.data(), PETSC_COPY_VALUES, &is),
                "ISCreateGeneral");
    try
      {
        create_mumps_cholesky_with_schur(factorisation->ksp, body.get_system_matrix(), is,
                                         parameters.body.factorisation_memory_limit_MB);
      }
    catch (...)
      {
        ISDestroy(&is);
        throw;
      }
    ISDestroy(&is);
    PetscInt n = 0;
    const auto dense = schur_complement(factorisation->ksp, n);
    HG_REQUIRE_NUMERIC(static_cast<std::size_t>(n) == 2 * n_a, "the Schur complement has ", n,
                       " rows, not ", 2 * n_a);
    S = Eigen::Map<const Eigen::MatrixXd>(dense.data(), n, n);
    S = 0.5 * (S + S.transpose()).eval();
    const Eigen::Index m    = static_cast<Eigen::Index>(n_a);
    const Eigen::MatrixXd S_BB_T = turn(S.bottomRightCorner(m, m), true).transpose(); // S_BB T
    D = S.topLeftCorner(m, m) + turn(S_BB_T, true);
    E = turn(S.bottomLeftCorner(m, m), true).transpose(); // S_AB T = (T^T S_BA)^T
  }

  template <int dim>
  std::vector<double> CyclicGearBody<dim>::harmonic_norms(const std::map<int, Eigen::MatrixXd> &q) const
  {
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
    PhaseTimer::Scope t(timer, "harmonics");
    const int          N = static_cast<int>(parameters.n_teeth);
    const Eigen::Index n = D.rows();
    const Eigen::Index m = q.begin()->second.cols();
    std::map<int, Eigen::MatrixXd> u;
    for (int s = s_min; s <= s_max; ++s)
      u[s] = Eigen::MatrixXd::Zero(n, m);
    const MPI_Comm comm  = parameters.harmonic_communicator;
    const int      rank  = static_cast<int>(Utilities::MPI::this_mpi_process(comm));
    const int      ranks = static_cast<int>(Utilities::MPI::n_mpi_processes(comm));
    Eigen::MatrixXcd H(n, n), x(n, m);
    for (int k = rank; k <= N / 2; k += ranks)
      {
        if (only_harmonic >= 0 && k != only_harmonic)
          continue;
        const std::complex<double> w = std::polar(1.0, 2.0 * M_PI * k / N);
        H = D.cast<std::complex<double>>() + w * E.cast<std::complex<double>>() +
            std::conj(w) * E.transpose().cast<std::complex<double>>();
        x.setZero();
        for (const auto &[s, qs] : q)
          x += std::polar(1.0 / N, -2.0 * M_PI * k * s / N) * qs.template cast<std::complex<double>>();
        const types::blas_int nn = static_cast<types::blas_int>(n), mm = static_cast<types::blas_int>(m);
        types::blas_int       info = 0;
        potrf("L", &nn, H.data(), &nn, &info);
        HG_REQUIRE_NUMERIC(info == 0, "cyclic harmonic ", k, " of ", N,
                           ": the cut-face matrix is not positive definite (zpotrf info ", info, ")");
        potrs("L", &nn, &mm, H.data(), &nn, x.data(), &nn, &info);
        HG_REQUIRE_NUMERIC(info == 0, "cyclic harmonic ", k, ": zpotrs info ", info);
        // u_s = sum over all N harmonics; k and N - k are complex conjugates.
        const double weight = (k == 0 || 2 * k == N) ? 1.0 : 2.0;
        for (int s = s_min; s <= s_max; ++s)
          u[s] += weight * (x * std::polar(1.0, 2.0 * M_PI * k * s / N)).real();
      }
    if (ranks > 1)
      for (auto &[s, us] : u)
        Utilities::MPI::sum(ArrayView<const double>(us.data(), us.size()), comm,
                            ArrayView<double>(us.data(), us.size()));
    return u;
  }

  template <int dim>
  Eigen::VectorXd CyclicGearBody<dim>::cut_values(const VectorType &u) const
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
  void CyclicGearBody<dim>::solve_sector(std::vector<VectorType> &rhs,
                                         const std::function<void(std::size_t, const VectorType &)> &use) const
  {
    const std::size_t block = static_cast<std::size_t>(
      std::max(1.0, std::floor(block_solve_bytes / (8.0 * std::max<double>(1, body.n_dofs())))));
    for (std::size_t start = 0; start < rhs.size(); start += block)
      {
        const std::size_t       end = std::min(rhs.size(), start + block);
        std::vector<Vec>        b, x;
        std::vector<VectorType> solutions(end - start);
        for (std::size_t j = start; j < end; ++j)
          {
            solutions[j - start].reinit(body.get_locally_owned_dofs(), MPI_COMM_SELF);
            b.push_back(rhs[j]);
            x.push_back(solutions[j - start]);
          }
        {
          PhaseTimer::Scope t(timer, "solves");
          mumps_block_solve(factorisation->ksp, b, x);
        }
        for (std::size_t j = start; j < end; ++j)
          use(j, body.ghosted_solution(solutions[j - start]));
      }
  }

  template <int dim>
  FullMatrix<double> CyclicGearBody<dim>::compliance(const std::vector<PatchLoad<dim>>    &loads,
                                                     const std::vector<PointReading<dim>> &readings) const
  {
    HG_REQUIRE_INPUT(factorisation != nullptr, "CyclicGearBody::run() must be called first");
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
    std::vector<std::vector<std::pair<types::global_dof_index, double>>> functionals;
    std::vector<VectorType> rhs;
    {
      PhaseTimer::Scope t(timer, "load vectors");
      for (const auto &load : unique_loads)
        rhs.push_back(body.patch_load_vector(load));
      for (const auto &reading : unique_readings)
        {
          functionals.push_back(body.reading_functional(reading));
          VectorType r(body.get_locally_owned_dofs(), MPI_COMM_SELF);
          for (const auto &[dof, w] : functionals.back())
            r[dof] += w;
          r.compress(VectorOperation::add);
          rhs.push_back(std::move(r));
        }
    }
    // U_c: cut displacements of the free sector under each load; W_c: those of each reading's
    // adjoint field (K^-1 r), so that r . K^-1 [0; h] = W_c^T h.
    Eigen::MatrixXd Uc(n_c, n_l), Wc(n_c, n_r), free_readings(n_r, n_l);
    solve_sector(rhs, [&](const std::size_t j, const VectorType &u) {
      if (j < n_l)
        {
          Uc.col(j) = cut_values(u);
          for (std::size_t r = 0; r < n_r; ++r)
            {
              double value = 0;
              for (const auto &[dof, w] : functionals[r])
                value += w * u[dof];
              free_readings(r, j) = value;
            }
        }
      else
        Wc.col(j - n_l) = cut_values(u);
    });
    rhs.clear();

    const Eigen::Index    m  = static_cast<Eigen::Index>(cut_a.size());
    const Eigen::MatrixXd g  = S * Uc;               // condensed loads of the loaded sector
    const Eigen::MatrixXd ZS = Wc.transpose() * S;   // reading of a cut displacement
    int d_min = 0, d_max = 0;
    for (const auto &[tr, r] : reading_of)
      for (const auto &[tl, l] : load_of)
        d_min = std::min(d_min, tr - tl), d_max = std::max(d_max, tr - tl);
    const auto u = solve_interface({{0, g.topRows(m)}, {1, turn(g.bottomRows(m), true)}}, d_min, d_max + 1);

    PhaseTimer::Scope t(timer, "readings");
    std::map<int, Eigen::MatrixXd> Y;
    for (int d = d_min; d <= d_max; ++d)
      {
        Eigen::MatrixXd cut(n_c, n_l);
        cut.topRows(m)    = u.at(d);
        cut.bottomRows(m) = turn(u.at(d + 1), false);
        Y[d]              = ZS * cut;
        if (d == 0)
          Y[d] += free_readings - ZS * Uc;
      }
    FullMatrix<double> C(readings.size(), loads.size());
    for (std::size_t r = 0; r < readings.size(); ++r)
      for (std::size_t l = 0; l < loads.size(); ++l)
        C(r, l) = Y.at(reading_of[r].first - load_of[l].first)(reading_of[r].second, load_of[l].second);
    return C;
  }

  template <int dim>
  typename CyclicGearBody<dim>::CondensedLoads
  CyclicGearBody<dim>::condense(const std::map<int, std::vector<PatchLoad<dim>>> &loads,
                                const std::map<int, std::vector<double>>         &forces) const
  {
    HG_REQUIRE_INPUT(factorisation != nullptr, "CyclicGearBody::run() must be called first");
    const Eigen::Index      m = static_cast<Eigen::Index>(cut_a.size());
    std::vector<int>        loaded;
    std::vector<VectorType> rhs;
    {
      PhaseTimer::Scope t(timer, "load vectors");
      for (const auto &[s, set] : loads)
        {
          HG_REQUIRE_INPUT(forces.count(s) && forces.at(s).size() == set.size(), "sector ", s,
                           ": ", set.size(), " loads but not as many forces");
          VectorType total(body.get_locally_owned_dofs(), MPI_COMM_SELF);
          for (std::size_t k = 0; k < set.size(); ++k)
            if (forces.at(s)[k] != 0.0)
              total.add(forces.at(s)[k], body.patch_load_vector(set[k]));
          loaded.push_back(s);
          rhs.push_back(std::move(total));
        }
    }
    CondensedLoads c;
    solve_sector(rhs, [&](const std::size_t j, const VectorType &u) {
      const int             s = loaded[j];
      const Eigen::VectorXd g = S * cut_values(u);
      const auto add = [&](const int sector, const Eigen::MatrixXd &v) {
        const auto it = c.q.find(sector);
        if (it == c.q.end())
          c.q[sector] = v;
        else
          it->second += v;
      };
      add(s, g.head(m));
      add(s + 1, turn(g.tail(m), true));
      c.free_fields[s] = u;
    });
    return c;
  }

  template <int dim>
  std::map<int, typename ElasticBody<dim>::VectorType>
  CyclicGearBody<dim>::sector_fields(const CondensedLoads &loads, const std::vector<int> &sectors,
                                     const int only_harmonic) const
  {
    HG_REQUIRE_INPUT(!sectors.empty(), "sector_fields: no sector asked for");
    const Eigen::Index m     = static_cast<Eigen::Index>(cut_a.size());
    const int          s_min = *std::min_element(sectors.begin(), sectors.end());
    const int          s_max = *std::max_element(sectors.begin(), sectors.end()) + 1;
    std::map<int, Eigen::MatrixXd> u;
    if (loads.q.empty())
      for (int s = s_min; s <= s_max; ++s)
        u[s] = Eigen::MatrixXd::Zero(m, 1);
    else
      u = solve_interface(loads.q, s_min, s_max, only_harmonic);

    // Sector s = the free sector under its own load and the cut forces h = S (u_c - u_c,free).
    std::vector<VectorType> rhs;
    for (const int s : sectors)
      {
        Eigen::VectorXd cut(2 * m);
        cut.head(m) = u.at(s).col(0);
        cut.tail(m) = turn(u.at(s + 1), false).col(0);
        const auto free = loads.free_fields.find(s);
        if (free != loads.free_fields.end())
          cut -= cut_values(free->second);
        const Eigen::VectorXd h = S * cut;
        VectorType            f(body.get_locally_owned_dofs(), MPI_COMM_SELF);
        for (Eigen::Index i = 0; i < m; ++i)
          {
            f[cut_a[i]] += h[i];
            f[cut_b[i]] += h[m + i];
          }
        f.compress(VectorOperation::add);
        rhs.push_back(std::move(f));
      }
    std::map<int, VectorType> fields;
    solve_sector(rhs, [&](const std::size_t j, const VectorType &v) {
      const int  s = sectors[j];
      VectorType field(body.get_locally_owned_dofs(), MPI_COMM_SELF);
      field            = v;
      const auto free = loads.free_fields.find(s);
      if (free != loads.free_fields.end())
        {
          VectorType owned(body.get_locally_owned_dofs(), MPI_COMM_SELF);
          owned = free->second;
          field += owned;
        }
      fields[s] = body.ghosted_solution(field);
    });
    return fields;
  }

  template class CyclicGearBody<2>;
  template class CyclicGearBody<3>;
} // namespace hertzgear::fem
