#include "fem/elastic_body.h"
#include "fem/petsc_ksp.h"

#include "common/errors.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/mpi_remote_point_evaluation.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/vector_tools.h>
#include <deal.II/numerics/vector_tools_evaluate.h>

#include <petscksp.h>

#include <algorithm>
#include <cmath>
#include <fstream>

namespace hertzgear
{
  namespace fem
  {
    using namespace dealii;

    namespace
    {
      // Bytes of one dense block of right-hand sides (and as much again for the solutions) in a
      // block substitution: 256 MB, e.g. 160 columns of a 200 000-DOF 2D body, 16 of a 2-million-DOF
      // 3D one.
      constexpr double block_solve_bytes = 256.0 * 1024 * 1024;
    } // namespace

    template <int dim>
    void read_gmsh_mesh(const std::string &filename, Triangulation<dim> &triangulation)
    {
      std::ifstream in(filename);
      HG_REQUIRE_INPUT(in.good(), "cannot open the mesh file ", filename);
      GridIn<dim> grid_in;
      grid_in.attach_triangulation(triangulation);
      try
        {
          grid_in.read_msh(in);
        }
      catch (const std::exception &e)
        {
          throw InputError(msg("cannot read the gmsh mesh ", filename, ": ", e.what()));
        }
    }

    // The KSP reused for every right-hand side: PREONLY + LU (MUMPS) holding the factors, or CG
    // + GAMG holding the AMG hierarchy (and the near-null space it was built from).
    template <int dim>
    struct ElasticBody<dim>::Factorisation
    {
      KSP          ksp            = nullptr;
      MatNullSpace near_nullspace = nullptr;
      ~Factorisation()
      {
        if (ksp != nullptr)
          KSPDestroy(&ksp);
        if (near_nullspace != nullptr)
          MatNullSpaceDestroy(&near_nullspace);
      }
    };

    template <int dim>
    typename ElasticBody<dim>::LinearSolver ElasticBody<dim>::parse_linear_solver(const std::string &name)
    {
      if (name == "direct")
        return LinearSolver::direct;
      if (name == "amg-cg")
        return LinearSolver::amg_cg;
      throw InputError(msg("unknown linear solver '", name, "' (direct or amg-cg)"));
    }

    template <int dim>
    std::string ElasticBody<dim>::linear_solver_name(const LinearSolver solver)
    {
      return solver == LinearSolver::direct ? "direct" : "amg-cg";
    }

    template <int dim>
    ElasticBody<dim>::ElasticBody(const Triangulation<dim> &triangulation,
                                  const Parameters &        parameters)
      : triangulation(triangulation)
      , parameters(parameters)
      , mpi_communicator(triangulation.get_communicator())
      , fe(FE_Q<dim>(parameters.fe_degree), dim)
      , mapping(parameters.mapping_degree)
      , dof_handler(triangulation)
    {
      HG_REQUIRE_INPUT(parameters.youngs_modulus > 0, "Young's modulus must be positive, got ",
                       parameters.youngs_modulus);
      HG_REQUIRE_INPUT(parameters.poisson_ratio > -1.0 && parameters.poisson_ratio < 0.5,
                       "Poisson ratio must lie in (-1, 0.5), got ", parameters.poisson_ratio);
      HG_REQUIRE_INPUT(parameters.fe_degree >= 1 && parameters.mapping_degree >= 1,
                       "FE and mapping degrees must be at least 1");
      HG_REQUIRE_INPUT(parameters.linear_solver == LinearSolver::direct ||
                         (parameters.linear_solver_tolerance > 0 &&
                          parameters.linear_solver_tolerance < 1 &&
                          parameters.linear_solver_max_iterations >= 1),
                       "the amg-cg solver needs a tolerance in (0, 1) and at least one iteration, "
                       "got tolerance ", parameters.linear_solver_tolerance, " and ",
                       parameters.linear_solver_max_iterations, " iterations");
    }

    template <int dim>
    ElasticBody<dim>::~ElasticBody() = default;

    template <int dim>
    void ElasticBody<dim>::assemble()
    {
      {
        PhaseTimer::Scope t(timer, "set-up");
        setup_system();
      }
      PhaseTimer::Scope t(timer, "assembly");
      assemble_system();
    }

    template <int dim>
    void ElasticBody<dim>::run()
    {
      assemble();
      PhaseTimer::Scope t(timer, parameters.linear_solver == LinearSolver::direct ? "factorisation" :
                                                                                   "AMG hierarchy");
      setup_solver();
    }

    template <int dim>
    std::vector<std::pair<types::global_dof_index, double>>
    ElasticBody<dim>::reading_functional(const PointReading &reading) const
    {
      HG_REQUIRE_INPUT(Utilities::MPI::n_mpi_processes(mpi_communicator) == 1,
                       "reading_functional needs a body on one process");
      // A table has hundreds of readings: the vertex-to-cell maps of the search are built once.
      if (!point_search)
        point_search = std::make_unique<GridTools::Cache<dim>>(triangulation, mapping);
      const auto found = GridTools::find_active_cell_around_point(*point_search, reading.point);
      HG_REQUIRE_INPUT(found.first.state() == IteratorState::valid, "the reading point (",
                       reading.point, ") lies outside the body");
      const typename DoFHandler<dim>::active_cell_iterator cell(&triangulation, found.first->level(),
                                                                found.first->index(), &dof_handler);
      const Quadrature<dim> at_point(GeometryInfo<dim>::project_to_unit_cell(found.second));
      FEValues<dim>         fe_values(mapping, fe, at_point, update_values);
      fe_values.reinit(cell);
      std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
      cell->get_dof_indices(dofs);
      std::vector<std::pair<types::global_dof_index, double>> weights;
      for (unsigned int i = 0; i < dofs.size(); ++i)
        {
          const unsigned int c = fe.system_to_component_index(i).first;
          const double       w = fe_values.shape_value_component(i, 0, c) * reading.direction[c];
          if (w != 0.0 && !constraints.is_constrained(dofs[i]))
            weights.emplace_back(dofs[i], w);
        }
      return weights;
    }

    template <int dim>
    void ElasticBody<dim>::set_load_boundary_ids(const std::set<types::boundary_id> &ids)
    {
      load_boundary_ids = ids;
    }

    template <int dim>
    bool ElasticBody<dim>::is_load_face(const types::boundary_id id) const
    {
      if (load_boundary_ids.empty())
        return id != parameters.clamped_boundary_id;
      return load_boundary_ids.count(id) > 0;
    }

    template <int dim>
    types::global_dof_index ElasticBody<dim>::n_dofs() const
    {
      return dof_handler.n_dofs();
    }

    template <int dim>
    void ElasticBody<dim>::setup_system()
    {
      dof_handler.distribute_dofs(fe);
      locally_owned_dofs = dof_handler.locally_owned_dofs();
      DoFTools::extract_locally_relevant_dofs(dof_handler, locally_relevant_dofs);

      constraints.clear();
      constraints.reinit(locally_relevant_dofs);
      DoFTools::make_hanging_node_constraints(dof_handler, constraints);
      VectorTools::interpolate_boundary_values(mapping, dof_handler,
                                               parameters.clamped_boundary_id,
                                               Functions::ZeroFunction<dim>(dim), constraints);
      constraints.close();
      // A body that is not clamped anywhere is singular: say so instead of letting the solver fail.
      const unsigned int n_constrained =
        Utilities::MPI::sum(static_cast<unsigned int>(constraints.n_constraints()), mpi_communicator);
      HG_REQUIRE_INPUT(n_constrained > 0, "no face carries the clamped boundary id ",
                       static_cast<unsigned int>(parameters.clamped_boundary_id));

      DynamicSparsityPattern dsp(locally_relevant_dofs);
      DoFTools::make_sparsity_pattern(dof_handler, dsp, constraints, false);
      SparsityTools::distribute_sparsity_pattern(dsp, locally_owned_dofs, mpi_communicator,
                                                 locally_relevant_dofs);
      system_matrix.reinit(locally_owned_dofs, locally_owned_dofs, dsp, mpi_communicator);
    }

    template <int dim>
    void ElasticBody<dim>::assemble_system()
    {
      const double E      = parameters.youngs_modulus;
      const double nu     = parameters.poisson_ratio;
      // In 2D this is plane strain: the 3D Lame constants with eps_zz = 0.
      const double lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
      const double mu     = E / (2.0 * (1.0 + nu));

      const QGauss<dim> quadrature(fe.degree + 1);
      FEValues<dim>     fe_values(mapping, fe, quadrature,
                              update_gradients | update_JxW_values);
      const FEValuesExtractors::Vector displacement(0);

      const unsigned int dofs_per_cell = fe.n_dofs_per_cell();
      FullMatrix<double> cell_matrix(dofs_per_cell, dofs_per_cell);
      std::vector<types::global_dof_index> local_dof_indices(dofs_per_cell);
      std::vector<SymmetricTensor<2, dim>> eps(dofs_per_cell);
      std::vector<double>                  div(dofs_per_cell);

      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            cell_matrix = 0;
            fe_values.reinit(cell);
            for (const unsigned int q : fe_values.quadrature_point_indices())
              {
                for (unsigned int k = 0; k < dofs_per_cell; ++k)
                  {
                    eps[k] = fe_values[displacement].symmetric_gradient(k, q);
                    div[k] = trace(eps[k]);
                  }
                const double JxW = fe_values.JxW(q);
                for (unsigned int i = 0; i < dofs_per_cell; ++i)
                  for (unsigned int j = 0; j <= i; ++j)
                    cell_matrix(i, j) += (lambda * div[i] * div[j] + 2.0 * mu * (eps[i] * eps[j])) * JxW;
              }
            for (unsigned int i = 0; i < dofs_per_cell; ++i)
              for (unsigned int j = i + 1; j < dofs_per_cell; ++j)
                cell_matrix(i, j) = cell_matrix(j, i);

            cell->get_dof_indices(local_dof_indices);
            constraints.distribute_local_to_global(cell_matrix, local_dof_indices, system_matrix);
          }
      system_matrix.compress(VectorOperation::add);
    }

    template <int dim>
    void ElasticBody<dim>::setup_solver()
    {
      factorisation = std::make_unique<Factorisation>();
      if (parameters.linear_solver == LinearSolver::direct)
        setup_direct();
      else
        setup_amg_cg();
    }

    template <int dim>
    void ElasticBody<dim>::setup_direct()
    {
      // The clamped elasticity matrix is symmetric positive definite (the constraints keep the
      // symmetry): Cholesky needs half the memory and flops of LU.
      create_mumps_cholesky(factorisation->ksp, system_matrix, mpi_communicator,
                            parameters.factorisation_memory_limit_MB);
    }

    // CG on the SPD stiffness matrix, preconditioned by PETSc's smoothed-aggregation AMG. The
    // aggregation needs the near-null space of the unclamped operator, the rigid-body modes
    // (dim translations, dim (dim - 1) / 2 rotations), to build coarse spaces that represent them;
    // without it GAMG would only preserve constants per scalar unknown and CG would converge slowly.
    template <int dim>
    void ElasticBody<dim>::setup_amg_cg()
    {
      const Mat A = system_matrix;

      // Support point and component of every locally owned DoF (every DoF of a vector FE_Q system
      // has a support point; owned DoFs all lie on locally owned cells).
      const std::size_t             n_owned = locally_owned_dofs.n_elements();
      const types::global_dof_index first   = n_owned > 0 ? locally_owned_dofs.nth_index_in_set(0) : 0;
      HG_REQUIRE_NUMERIC(n_owned == 0 || locally_owned_dofs.is_contiguous(),
                         "amg-cg: the locally owned DoFs are not a contiguous range");
      std::vector<Point<dim>>   support(n_owned);
      std::vector<unsigned char> component(n_owned, 0xff);
      {
        const Quadrature<dim> at_support(fe.get_unit_support_points());
        FEValues<dim>         fe_values(mapping, fe, at_support, update_quadrature_points);
        std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              fe_values.reinit(cell);
              cell->get_dof_indices(dofs);
              for (unsigned int i = 0; i < dofs.size(); ++i)
                if (locally_owned_dofs.is_element(dofs[i]))
                  {
                    const std::size_t k = dofs[i] - first;
                    support[k]          = fe_values.quadrature_point(i);
                    component[k]        = fe.system_to_component_index(i).first;
                  }
            }
      }
      for (std::size_t k = 0; k < n_owned; ++k)
        HG_REQUIRE_NUMERIC(component[k] < dim, "amg-cg: locally owned DoF ", first + k,
                           " lies on no locally owned cell");

      // Node-blocked numbering (the dim DoFs of a support point consecutive, in component order,
      // as deal.II numbers FE_Q^dim systems of degree <= 2)? Then the matrix gets block size dim
      // (GAMG aggregates nodes, not scalar unknowns) and PETSc builds the rigid-body modes from
      // the interleaved coordinates. Otherwise (e.g. degree >= 3, whose line DoFs are numbered
      // component by component) the modes are built here DoF by DoF.
      bool node_blocked = (first % dim == 0) && (n_owned % dim == 0);
      for (std::size_t k = 0; node_blocked && k < n_owned; ++k)
        node_blocked = component[k] == k % dim &&
                       support[k].distance(support[k - k % dim]) <=
                         1e-12 * (1.0 + support[k].norm());
      node_blocked = Utilities::MPI::min(node_blocked ? 1 : 0, mpi_communicator) == 1;

      MatNullSpace &nullspace = factorisation->near_nullspace;
      if (node_blocked)
        {
          check_petsc(MatSetBlockSize(A, dim), "MatSetBlockSize");
          Vec coordinates;
          check_petsc(VecCreateMPI(mpi_communicator, n_owned, PETSC_DETERMINE, &coordinates),
                      "VecCreateMPI");
          check_petsc(VecSetBlockSize(coordinates, dim), "VecSetBlockSize");
          PetscScalar *x;
          check_petsc(VecGetArray(coordinates, &x), "VecGetArray");
          for (std::size_t k = 0; k < n_owned; ++k)
            x[k] = support[k][component[k]];
          check_petsc(VecRestoreArray(coordinates, &x), "VecRestoreArray");
          check_petsc(MatNullSpaceCreateRigidBody(coordinates, &nullspace),
                      "MatNullSpaceCreateRigidBody");
          check_petsc(VecDestroy(&coordinates), "VecDestroy");
        }
      else
        {
          // Rigid-body modes at each DoF: translation e_c, rotation about axis a (3D) or z (2D)
          // of value (omega x x)_c. Orthonormalised (modified Gram-Schmidt) as
          // MatNullSpaceCreate requires.
          const unsigned int n_modes = dim == 2 ? 3 : 6;
          std::vector<Vec>   modes(n_modes);
          for (unsigned int m = 0; m < n_modes; ++m)
            {
              check_petsc(VecCreateMPI(mpi_communicator, n_owned, PETSC_DETERMINE, &modes[m]),
                          "VecCreateMPI");
              PetscScalar *v;
              check_petsc(VecGetArray(modes[m], &v), "VecGetArray");
              for (std::size_t k = 0; k < n_owned; ++k)
                {
                  const unsigned int c = component[k];
                  const Point<dim> & x = support[k];
                  double             value;
                  if (m < dim)
                    value = (c == m) ? 1.0 : 0.0;
                  else
                    {
                      Tensor<1, 3> omega, position, rotation;
                      omega[dim == 2 ? 2 : m - dim] = 1.0;
                      for (unsigned int d = 0; d < dim; ++d)
                        position[d] = x[d];
                      rotation = cross_product_3d(omega, position);
                      value    = rotation[c];
                    }
                  v[k] = value;
                }
              check_petsc(VecRestoreArray(modes[m], &v), "VecRestoreArray");
              for (unsigned int n = 0; n < m; ++n)
                {
                  PetscScalar dot;
                  check_petsc(VecDot(modes[m], modes[n], &dot), "VecDot");
                  check_petsc(VecAXPY(modes[m], -dot, modes[n]), "VecAXPY");
                }
              PetscReal norm;
              check_petsc(VecNormalize(modes[m], &norm), "VecNormalize");
              HG_REQUIRE_NUMERIC(norm > 0, "amg-cg: rigid-body mode ", m, " is degenerate");
            }
          check_petsc(MatNullSpaceCreate(mpi_communicator, PETSC_FALSE, n_modes, modes.data(),
                                         &nullspace),
                      "MatNullSpaceCreate");
          for (auto &v : modes)
            check_petsc(VecDestroy(&v), "VecDestroy");
        }
      // A near-null space only guides the AMG; the operator itself is regular (clamped).
      check_petsc(MatSetNearNullSpace(A, nullspace), "MatSetNearNullSpace");

      KSP &ksp = factorisation->ksp;
      check_petsc(KSPCreate(mpi_communicator, &ksp), "KSPCreate");
      check_petsc(KSPSetOperators(ksp, A, A), "KSPSetOperators");
      check_petsc(KSPSetType(ksp, KSPCG), "KSPSetType");
      // The tolerance is on the true residual ||b - K u|| / ||b||, not the preconditioned one, so
      // that it bounds the compliance error (see patch_load_vector).
      check_petsc(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
      check_petsc(KSPSetTolerances(ksp, parameters.linear_solver_tolerance, PETSC_DEFAULT,
                                   PETSC_DEFAULT, parameters.linear_solver_max_iterations),
                  "KSPSetTolerances");
      PC pc;
      check_petsc(KSPGetPC(ksp, &pc), "KSPGetPC");
      check_petsc(PCSetType(pc, PCGAMG), "PCSetType");
      // PETSC_OPTIONS tunes the solve, e.g. "-pc_gamg_threshold 0.02 -ksp_monitor".
      check_petsc(KSPSetFromOptions(ksp), "KSPSetFromOptions");
      // KSPSetUp builds the AMG hierarchy now, once; every solve reuses it.
      check_petsc(KSPSetUp(ksp), "KSPSetUp (GAMG hierarchy)");
    }

    template <int dim>
    typename ElasticBody<dim>::VectorType ElasticBody<dim>::solve(VectorType &rhs) const
    {
      HG_REQUIRE_INPUT(factorisation != nullptr, "ElasticBody::run() must be called before solving");
      VectorType solution(locally_owned_dofs, mpi_communicator);
      {
        PhaseTimer::Scope t(timer, "solves");
        check_petsc(KSPSolve(factorisation->ksp, rhs, solution), "KSPSolve");
        ++solves_done;
      }
      KSPConvergedReason reason;
      check_petsc(KSPGetConvergedReason(factorisation->ksp, &reason), "KSPGetConvergedReason");
      if (parameters.linear_solver == LinearSolver::direct)
        HG_REQUIRE_NUMERIC(reason >= 0, "the MUMPS substitution failed (KSP reason ",
                           static_cast<int>(reason), ")");
      else if (reason < 0)
        {
          PetscInt  iterations = 0;
          PetscReal residual   = 0;
          KSPGetIterationNumber(factorisation->ksp, &iterations);
          KSPGetResidualNorm(factorisation->ksp, &residual);
          const double rhs_norm = rhs.l2_norm();
          PetscReal    rtol = 0, abstol = 0, dtol = 0;
          PetscInt     max_iterations = 0;
          KSPGetTolerances(factorisation->ksp, &rtol, &abstol, &dtol, &max_iterations);
          throw NumericalError(msg(
            "the amg-cg solve of the elastic body (", n_dofs(), " DOFs) did not converge: KSP reason ",
            KSPConvergedReasons[reason], " (", static_cast<int>(reason), ") after ", iterations,
            " CG iterations (cap ", max_iterations, "), relative residual ",
            rhs_norm > 0 ? residual / rhs_norm : residual, " against the tolerance ", rtol,
            ". Loosen the tolerance ({linear_solver_tolerance}) if it is below what the "
            "round-off allows (about 1e-12), raise the iteration cap or tune the AMG through "
            "PETSC_OPTIONS (e.g. -ksp_max_it, -pc_gamg_threshold), or use the direct solver "
            "({linear_solver} = direct) if memory allows."));
        }
      return finish_solution(solution);
    }

    template <int dim>
    typename ElasticBody<dim>::VectorType ElasticBody<dim>::finish_solution(VectorType &solution) const
    {
      constraints.distribute(solution);
      // Return a ghosted copy: point evaluation and error integration read neighbour values.
      VectorType ghosted(locally_owned_dofs, locally_relevant_dofs, mpi_communicator);
      ghosted = solution;
      return ghosted;
    }

    template <int dim>
    std::size_t ElasticBody<dim>::block_columns() const
    {
      if (parameters.block_columns > 0)
        return parameters.block_columns;
      return static_cast<std::size_t>(
        std::max(1.0, std::floor(block_solve_bytes / (8.0 * std::max<double>(1, n_dofs())))));
    }

    template <int dim>
    std::vector<typename ElasticBody<dim>::VectorType>
    ElasticBody<dim>::solve_many(std::vector<VectorType> &rhs) const
    {
      HG_REQUIRE_INPUT(factorisation != nullptr, "ElasticBody::run() must be called before solving");
      std::vector<VectorType> solutions;
      solutions.reserve(rhs.size());
      if (parameters.linear_solver != LinearSolver::direct || rhs.size() < 2)
        {
          for (auto &b : rhs)
            solutions.push_back(solve(b));
          return solutions;
        }
      const std::size_t block = block_columns();
      for (std::size_t start = 0; start < rhs.size(); start += block)
        {
          const std::size_t  end = std::min(rhs.size(), start + block);
          std::vector<Vec>   b, x;
          std::vector<VectorType> block_solutions(end - start);
          for (std::size_t j = start; j < end; ++j)
            {
              block_solutions[j - start].reinit(locally_owned_dofs, mpi_communicator);
              b.push_back(rhs[j]);
              x.push_back(block_solutions[j - start]);
            }
          {
            PhaseTimer::Scope t(timer, "solves");
            mumps_block_solve(factorisation->ksp, b, x);
            solves_done += end - start;
          }
          for (auto &u : block_solutions)
            solutions.push_back(finish_solution(u));
        }
      return solutions;
    }

    template <int dim>
    typename ElasticBody<dim>::VectorType
    ElasticBody<dim>::solve_traction(const types::boundary_id boundary_id,
                                     const TractionFunction & traction) const
    {
      VectorType rhs(locally_owned_dofs, mpi_communicator);

      const QGauss<dim - 1> face_quadrature(fe.degree + 1);
      FEFaceValues<dim>     fe_face_values(mapping, fe, face_quadrature,
                                       update_values | update_quadrature_points |
                                         update_normal_vectors | update_JxW_values);
      const FEValuesExtractors::Vector displacement(0);
      const unsigned int               dofs_per_cell = fe.n_dofs_per_cell();
      Vector<double>                   cell_rhs(dofs_per_cell);
      std::vector<types::global_dof_index> local_dof_indices(dofs_per_cell);

      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary() && face->boundary_id() == boundary_id)
              {
                fe_face_values.reinit(cell, face);
                cell_rhs = 0;
                for (const unsigned int q : fe_face_values.quadrature_point_indices())
                  {
                    const Tensor<1, dim> t = traction(fe_face_values.quadrature_point(q),
                                                      fe_face_values.normal_vector(q));
                    for (unsigned int i = 0; i < dofs_per_cell; ++i)
                      cell_rhs(i) += fe_face_values[displacement].value(i, q) * t * fe_face_values.JxW(q);
                  }
                cell->get_dof_indices(local_dof_indices);
                constraints.distribute_local_to_global(cell_rhs, local_dof_indices, rhs);
              }
      rhs.compress(VectorOperation::add);
      return solve(rhs);
    }

    template <int dim>
    std::pair<typename ElasticBody<dim>::VectorType, double>
    ElasticBody<dim>::assemble_patch_rhs(const PatchLoad &load) const
    {
      HG_REQUIRE_INPUT(load.radius > 0, "patch radius must be positive, got ", load.radius);
      PhaseTimer::Scope t(timer, "load vectors");
      VectorType        rhs(locally_owned_dofs, mpi_communicator);

      const QGauss<dim - 1> face_quadrature(fe.degree + 2);
      FEFaceValues<dim>     fe_face_values(mapping, fe, face_quadrature,
                                       update_values | update_quadrature_points | update_JxW_values);
      const FEValuesExtractors::Vector displacement(0);
      const unsigned int               dofs_per_cell = fe.n_dofs_per_cell();
      Vector<double>                   cell_rhs(dofs_per_cell);
      std::vector<types::global_dof_index> local_dof_indices(dofs_per_cell);

      double weighted_area = 0;
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned() && cell->at_boundary())
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary() && is_load_face(face->boundary_id()))
              {
                // Cheap rejection on the vertex-based face diameter before any mapping work.
                if (face->center().distance(load.centre) > load.radius + face->diameter())
                  continue;
                fe_face_values.reinit(cell, face);
                cell_rhs     = 0;
                bool touched = false;
                for (const unsigned int q : fe_face_values.quadrature_point_indices())
                  {
                    const double s = fe_face_values.quadrature_point(q).distance(load.centre) / load.radius;
                    if (s >= 1.0)
                      continue;
                    touched                = true;
                    const double w         = (1.0 - s * s) * (1.0 - s * s);
                    const double w_JxW     = w * fe_face_values.JxW(q);
                    weighted_area += w_JxW;
                    for (unsigned int i = 0; i < dofs_per_cell; ++i)
                      cell_rhs(i) += fe_face_values[displacement].value(i, q) * load.direction * w_JxW;
                  }
                if (!touched)
                  continue;
                cell->get_dof_indices(local_dof_indices);
                constraints.distribute_local_to_global(cell_rhs, local_dof_indices, rhs);
              }
      rhs.compress(VectorOperation::add);
      weighted_area = Utilities::MPI::sum(weighted_area, mpi_communicator);
      if (!(weighted_area > 0))
        throw PatchOffMeshError(msg("the load patch of radius ", load.radius, " around (",
                                    load.centre, ") touches no quadrature point of a loadable "
                                    "boundary face; the patch is off the surface or smaller than "
                                    "the surface mesh"));
      return {std::move(rhs), weighted_area};
    }

    template <int dim>
    typename ElasticBody<dim>::VectorType
    ElasticBody<dim>::solve_patch_loads(const std::vector<PatchLoad> &loads,
                                        const std::vector<double> &   forces) const
    {
      return std::move(solve_patch_load_sets({loads}, {forces}).front());
    }

    template <int dim>
    std::vector<typename ElasticBody<dim>::VectorType>
    ElasticBody<dim>::solve_patch_load_sets(const std::vector<std::vector<PatchLoad>> &loads,
                                            const std::vector<std::vector<double>> &   forces) const
    {
      HG_REQUIRE_INPUT(loads.size() == forces.size(), "solve_patch_load_sets: ", loads.size(),
                       " load sets but ", forces.size(), " force sets");
      std::vector<VectorType> rhs;
      for (std::size_t s = 0; s < loads.size(); ++s)
        {
          HG_REQUIRE_INPUT(loads[s].size() == forces[s].size(), "solve_patch_loads: ",
                           loads[s].size(), " loads but ", forces[s].size(), " forces");
          VectorType total(locally_owned_dofs, mpi_communicator);
          for (std::size_t k = 0; k < loads[s].size(); ++k)
            if (forces[s][k] != 0.0)
              {
                auto [f, area] = assemble_patch_rhs(loads[s][k]);
                total.add(forces[s][k] / area, f);
              }
          rhs.push_back(std::move(total));
        }
      return solve_many(rhs);
    }

    template <int dim>
    typename ElasticBody<dim>::VectorType ElasticBody<dim>::patch_load_vector(const PatchLoad &load) const
    {
      auto [rhs, area] = assemble_patch_rhs(load);
      rhs /= area;
      return std::move(rhs);
    }

    template <int dim>
    typename ElasticBody<dim>::VectorType ElasticBody<dim>::solve_patch_load(const PatchLoad &load) const
    {
      auto [rhs, area] = assemble_patch_rhs(load);
      rhs /= area;
      return solve(rhs);
    }

    template <int dim>
    std::vector<Tensor<1, dim>>
    ElasticBody<dim>::point_values(const VectorType &solution, const std::vector<Point<dim>> &points) const
    {
      Utilities::MPI::RemotePointEvaluation<dim> evaluation;
      evaluation.reinit(points, triangulation, mapping);
      HG_REQUIRE_INPUT(evaluation.all_points_found(), "some reading points lie outside the body");
      return VectorTools::point_values<dim>(evaluation, dof_handler, solution);
    }

    template <int dim>
    FullMatrix<double> ElasticBody<dim>::compliance(const std::vector<PatchLoad> &   loads,
                                                    const std::vector<PointReading> &readings) const
    {
      std::vector<Point<dim>> points;
      points.reserve(readings.size());
      for (const auto &r : readings)
        points.push_back(r.point);
      // One point search for all load cases.
      Utilities::MPI::RemotePointEvaluation<dim> evaluation;
      evaluation.reinit(points, triangulation, mapping);
      HG_REQUIRE_INPUT(evaluation.all_points_found(), "some reading points lie outside the body");

      FullMatrix<double> C(readings.size(), loads.size());
      // Load vectors and substitutions in blocks: a block's fields are held at once.
      const std::size_t block = block_columns();
      for (std::size_t start = 0; start < loads.size(); start += block)
        {
          const std::size_t       end = std::min(loads.size(), start + block);
          std::vector<VectorType> rhs;
          for (std::size_t l = start; l < end; ++l)
            {
              auto [f, area] = assemble_patch_rhs(loads[l]);
              f /= area;
              rhs.push_back(std::move(f));
            }
          const auto fields = solve_many(rhs);
          PhaseTimer::Scope t(timer, "readings");
          for (std::size_t l = start; l < end; ++l)
            {
              const auto values =
                VectorTools::point_values<dim>(evaluation, dof_handler, fields[l - start]);
              for (unsigned int r = 0; r < readings.size(); ++r)
                C(r, l) = values[r] * readings[r].direction;
            }
        }
      return C;
    }

    template <int dim>
    FullMatrix<double> ElasticBody<dim>::patch_compliance(const std::vector<PatchLoad> &loads) const
    {
      const unsigned int  n_loads = loads.size();
      std::vector<VectorType> rhs(n_loads);
      for (unsigned int l = 0; l < n_loads; ++l)
        {
          auto [f, area] = assemble_patch_rhs(loads[l]);
          f /= area;
          rhs[l] = std::move(f);
        }
      FullMatrix<double> C(n_loads, n_loads);
      for (unsigned int j = 0; j < n_loads; ++j)
        {
          VectorType f = rhs[j];
          const VectorType u_ghosted = solve(f);
          VectorType       u(locally_owned_dofs, mpi_communicator);
          u = u_ghosted;
          for (unsigned int i = 0; i < n_loads; ++i)
            C(i, j) = rhs[i] * u; // collective dot product
        }
      return C;
    }

    template <int dim>
    double ElasticBody<dim>::l2_error(const VectorType &solution, const Function<dim> &exact) const
    {
      Vector<float> cellwise(triangulation.n_active_cells());
      VectorTools::integrate_difference(mapping, dof_handler, solution, exact, cellwise,
                                        QGauss<dim>(fe.degree + 2), VectorTools::L2_norm);
      return VectorTools::compute_global_error(triangulation, cellwise, VectorTools::L2_norm);
    }

    template class ElasticBody<2>;
    template class ElasticBody<3>;
    template void read_gmsh_mesh<2>(const std::string &, Triangulation<2> &);
    template void read_gmsh_mesh<3>(const std::string &, Triangulation<3> &);
  } // namespace fem
} // namespace hertzgear
