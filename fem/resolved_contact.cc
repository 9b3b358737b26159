// Resolved FE contact against a rigid plane: primal-dual active set with load control, adaptive
// refinement. See fem/resolved_contact.h for the model and docs/validation-hertz.md for the
// method and the measured accuracy.
#include "fem/resolved_contact.h"
#include "fem/petsc_ksp.h"

#include "common/errors.h"

#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/mpi_remote_point_evaluation.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/grid_refinement.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/error_estimator.h>
#include <deal.II/numerics/vector_tools.h>
#include <deal.II/numerics/vector_tools_evaluate.h>

#include <petscksp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <set>

namespace hertzgear
{
  namespace fem
  {
    using namespace dealii;

    namespace
    {
      using VectorType = PETScWrappers::MPI::Vector;
      using MatrixType = PETScWrappers::MPI::SparseMatrix;

      // MUMPS LU of one matrix through a PETSc KSP (PREONLY + PCLU): factorised once in KSPSetUp,
      // then one substitution per right-hand side.
      class MumpsFactorisation
      {
      public:
        MumpsFactorisation(const MatrixType &matrix, const MPI_Comm comm)
        {
          create_mumps_lu(ksp, matrix, comm);
        }
        ~MumpsFactorisation() { KSPDestroy(&ksp); }
        MumpsFactorisation(const MumpsFactorisation &) = delete;
        MumpsFactorisation &operator=(const MumpsFactorisation &) = delete;

        void solve(const VectorType &rhs, VectorType &solution) const
        {
          check_petsc(KSPSolve(ksp, rhs, solution), "KSPSolve");
          KSPConvergedReason reason;
          check_petsc(KSPGetConvergedReason(ksp, &reason), "KSPGetConvergedReason");
          HG_REQUIRE_NUMERIC(reason >= 0, "the MUMPS substitution failed (KSP reason ",
                             static_cast<int>(reason), ")");
        }

      private:
        KSP ksp = nullptr;
      };

      // Order-independent fingerprint of an index set (summed over ranks): detects a repeated
      // active set without gathering it.
      std::uint64_t mix(std::uint64_t x)
      {
        x += 0x9e3779b97f4a7c15ULL;
        x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
        x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
        return x ^ (x >> 31);
      }

      // Boundary ids of GridGenerator::subdivided_hyper_rectangle(..., colorize = true).
      template <int dim>
      struct Ids
      {
        static constexpr types::boundary_id symmetry_x = 0;                 // x = 0
        static constexpr types::boundary_id symmetry_y = 2;                 // y = 0 (3D)
        static constexpr types::boundary_id bottom     = 2 * (dim - 1);     // z = -H
        static constexpr types::boundary_id contact    = 2 * (dim - 1) + 1; // z = 0
      };

      struct NodeSample
      {
        double x, y, pressure, force, active;
        template <class Archive>
        void serialize(Archive &ar, const unsigned int)
        {
          ar &x &y &pressure &force &active;
        }
      };
    } // namespace

    template <int dim>
    class ResolvedContactProblem
    {
    public:
      explicit ResolvedContactProblem(const ResolvedContactSettings &settings);
      std::vector<ResolvedContactLevel>
      run(const std::function<void(const ResolvedContactLevel &)> &report);

    private:
      void   make_grid();
      double smallest_contact_cell() const;
      void   zoom_to_design_size();
      void   setup_system();
      void   build_constraints(AffineConstraints<double> &constraints, const double bottom_value,
                               const bool with_gap) const;
      void   assemble(const bool complete);
      void   solve_active_set(ResolvedContactLevel &result);
      void   collect_results(ResolvedContactLevel &result);
      void   refine();

      double gap(const Point<dim> &p) const;
      double horizontal_y(const Point<dim> &p) const { return dim == 3 ? p[1] : 0.0; }

      const ResolvedContactSettings s;
      MPI_Comm                      comm;
      static constexpr unsigned int vertical = dim - 1;
      const double                  symmetry_factor = dim == 3 ? 4.0 : 2.0;

      parallel::distributed::Triangulation<dim> triangulation;
      const FESystem<dim>                       fe;
      const MappingQ1<dim>                      mapping;
      DoFHandler<dim>                           dof_handler;

      IndexSet                  owned_dofs, relevant_dofs;
      AffineConstraints<double> hanging, constraints_gap, constraints_unit;
      MatrixType                system_matrix, complete_matrix;
      VectorType                rhs_gap, rhs_unit;

      // Vertical dofs of the contact face that are not hanging, with their point (relevant).
      std::map<types::global_dof_index, Point<dim>> contact_dofs;
      VectorType                                    lumped_area;     // ghosted
      std::set<types::global_dof_index>             active_set;      // relevant dofs
      VectorType                                    solution;        // ghosted
      VectorType                                    contact_force;   // owned: P_i >= 0 pushes -z
      double                                        approach = 0;
      double                                        contact_cell = 0;
      std::chrono::steady_clock::time_point         start;
    };

    template <int dim>
    ResolvedContactProblem<dim>::ResolvedContactProblem(const ResolvedContactSettings &settings)
      : s(settings)
      , comm(MPI_COMM_WORLD)
      , triangulation(comm, Triangulation<dim>::limit_level_difference_at_vertices)
      , fe(FE_Q<dim>(1), dim)
      , dof_handler(triangulation)
    {
      HG_REQUIRE_INPUT(s.youngs_modulus_MPa > 0, "youngs_modulus_MPa = ", s.youngs_modulus_MPa,
                       " must be positive");
      HG_REQUIRE_INPUT(s.poisson_ratio >= 0 && s.poisson_ratio < 0.5, "poisson_ratio = ",
                       s.poisson_ratio, " must lie in [0, 0.5)");
      HG_REQUIRE_INPUT(s.radius_x_mm > 0, "radius_x_mm = ", s.radius_x_mm, " must be positive");
      HG_REQUIRE_INPUT(s.radius_y_mm >= 0, "radius_y_mm = ", s.radius_y_mm,
                       " must be positive (or 0: no curvature along y)");
      HG_REQUIRE_INPUT(s.load > 0, "the load ", s.load, " must be positive");
      HG_REQUIRE_INPUT(s.half_width_x_mm > 0 && s.depth_mm > 0 &&
                         (dim == 2 || s.half_width_y_mm > 0),
                       "the block dimensions must be positive");
      HG_REQUIRE_INPUT(s.design_semi_axis_x_mm > 0 && (dim == 2 || s.design_semi_axis_y_mm > 0),
                       "the design semi-axes must be positive");
      HG_REQUIRE_INPUT(s.initial_cells_per_semi_axis >= 1 && s.n_levels >= 1,
                       "initial_cells_per_semi_axis and the number of levels must be >= 1");
      HG_REQUIRE_INPUT(s.kelly_fraction >= 0 && s.kelly_fraction < 1, "kelly_fraction = ",
                       s.kelly_fraction, " must lie in [0, 1)");
      for (const double d : s.reading_depths_mm)
        HG_REQUIRE_INPUT(d > 0 && d < s.depth_mm, "reading depth ", d,
                         " mm must lie inside the block (0 < d < ", s.depth_mm, " mm)");
    }

    template <int dim>
    double ResolvedContactProblem<dim>::gap(const Point<dim> &p) const
    {
      const double x = p[0], y = horizontal_y(p);
      if (s.rigid_end_y_mm > 0 && y > s.rigid_end_y_mm * (1 + 1e-12))
        return std::numeric_limits<double>::max(); // beyond the end of the rigid body
      return x * x / (2.0 * s.radius_x_mm) + (s.radius_y_mm > 0 ? y * y / (2.0 * s.radius_y_mm) : 0.0);
    }

    template <int dim>
    void ResolvedContactProblem<dim>::make_grid()
    {
      // Nearly cubic coarse cells, the smallest block dimension split in two.
      Point<dim> lower, upper;
      lower[0] = 0;
      upper[0] = s.half_width_x_mm;
      if (dim == 3)
        {
          lower[1] = 0;
          upper[1] = s.half_width_y_mm;
        }
      lower[vertical] = -s.depth_mm;
      upper[vertical] = 0;
      double h = std::min(s.half_width_x_mm, s.depth_mm);
      if (dim == 3)
        h = std::min(h, s.half_width_y_mm);
      h /= 2.0;
      std::vector<unsigned int> repetitions(dim);
      for (unsigned int d = 0; d < dim; ++d)
        repetitions[d] =
          std::max(1u, static_cast<unsigned int>(std::lround((upper[d] - lower[d]) / h)));
      GridGenerator::subdivided_hyper_rectangle(triangulation, repetitions, lower, upper, true);
    }

    template <int dim>
    double ResolvedContactProblem<dim>::smallest_contact_cell() const
    {
      double h = std::numeric_limits<double>::max();
      for (const auto &cell : triangulation.active_cell_iterators())
        if (cell->is_locally_owned() && cell->at_boundary())
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == Ids<dim>::contact)
              h = std::min(h, cell->extent_in_direction(0));
      return Utilities::MPI::min(h, comm);
    }

    template <int dim>
    void ResolvedContactProblem<dim>::zoom_to_design_size()
    {
      // Refine towards the expected contact zone until its cells are a fraction of the smaller
      // design semi-axis: the first solved level then already resolves the contact.
      const double ax = s.design_semi_axis_x_mm;
      const double ay = dim == 3 ? s.design_semi_axis_y_mm : ax;
      const double target = std::min(ax, ay) / s.initial_cells_per_semi_axis;
      for (unsigned int step = 0; step < 40 && smallest_contact_cell() > target * (1 + 1e-9); ++step)
        {
          for (const auto &cell : triangulation.active_cell_iterators())
            if (cell->is_locally_owned() && cell->at_boundary())
              for (const unsigned int f : cell->face_indices())
                if (cell->face(f)->at_boundary() &&
                    cell->face(f)->boundary_id() == Ids<dim>::contact)
                  {
                    const double     h  = cell->extent_in_direction(0);
                    const Point<dim> c  = cell->face(f)->center();
                    const double     rx = 1.5 * ax + h, ry = 1.5 * ay + h;
                    const double     ex = c[0] / rx, ey = horizontal_y(c) / ry;
                    if (ex * ex + ey * ey <= 1.0 && h > target * (1 + 1e-9))
                      cell->set_refine_flag();
                  }
          triangulation.execute_coarsening_and_refinement();
        }
    }

    template <int dim>
    void ResolvedContactProblem<dim>::setup_system()
    {
      dof_handler.distribute_dofs(fe);
      owned_dofs = dof_handler.locally_owned_dofs();
      DoFTools::extract_locally_relevant_dofs(dof_handler, relevant_dofs);

      hanging.clear();
      hanging.reinit(relevant_dofs);
      DoFTools::make_hanging_node_constraints(dof_handler, hanging);
      hanging.close();

      // Contact dofs and their lumped (row-sum) boundary mass: the nodal contact force divided
      // by it is the nodal pressure (step-41/42).
      contact_dofs.clear();
      VectorType area(owned_dofs, comm);
      const QGauss<dim - 1>  face_quadrature(2);
      FEFaceValues<dim>      fe_face(mapping, fe, face_quadrature, update_values | update_JxW_values);
      std::vector<types::global_dof_index> indices(fe.n_dofs_per_cell());
      Vector<double>                       local_area(fe.n_dofs_per_cell());
      contact_cell = std::numeric_limits<double>::max();
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (!cell->is_artificial() && cell->at_boundary())
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == Ids<dim>::contact)
              {
                for (unsigned int v = 0; v < cell->face(f)->n_vertices(); ++v)
                  {
                    const auto i = cell->face(f)->vertex_dof_index(v, vertical);
                    if (relevant_dofs.is_element(i) && !hanging.is_constrained(i))
                      contact_dofs[i] = cell->face(f)->vertex(v);
                  }
                if (!cell->is_locally_owned())
                  continue;
                contact_cell = std::min(contact_cell, cell->extent_in_direction(0));
                fe_face.reinit(cell, f);
                local_area = 0;
                for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
                  if (fe.system_to_component_index(i).first == vertical)
                    for (unsigned int q = 0; q < face_quadrature.size(); ++q)
                      local_area(i) += fe_face.shape_value_component(i, q, vertical) * fe_face.JxW(q);
                cell->get_dof_indices(indices);
                hanging.distribute_local_to_global(local_area, indices, area);
              }
      area.compress(VectorOperation::add);
      contact_cell = Utilities::MPI::min(contact_cell, comm);
      lumped_area.reinit(owned_dofs, relevant_dofs, comm);
      lumped_area = area;

      DynamicSparsityPattern dsp(relevant_dofs);
      // Constrained couplings kept: one pattern serves every active set.
      DoFTools::make_sparsity_pattern(dof_handler, dsp, hanging, true);
      SparsityTools::distribute_sparsity_pattern(dsp, owned_dofs, comm, relevant_dofs);
      system_matrix.reinit(owned_dofs, owned_dofs, dsp, comm);
      complete_matrix.reinit(owned_dofs, owned_dofs, dsp, comm);
      rhs_gap.reinit(owned_dofs, comm);
      rhs_unit.reinit(owned_dofs, comm);
      contact_force.reinit(owned_dofs, comm);
      solution.reinit(owned_dofs, relevant_dofs, comm);
    }

    template <int dim>
    void ResolvedContactProblem<dim>::build_constraints(AffineConstraints<double> &constraints,
                                                        const double bottom_value,
                                                        const bool   with_gap) const
    {
      constraints.clear();
      constraints.reinit(relevant_dofs);
      DoFTools::make_hanging_node_constraints(dof_handler, constraints);
      const FEValuesExtractors::Scalar ux(0), uy(1), uv(vertical);
      VectorTools::interpolate_boundary_values(mapping, dof_handler, Ids<dim>::symmetry_x,
                                               Functions::ZeroFunction<dim>(dim), constraints,
                                               fe.component_mask(ux));
      if (dim == 3)
        VectorTools::interpolate_boundary_values(mapping, dof_handler, Ids<dim>::symmetry_y,
                                                 Functions::ZeroFunction<dim>(dim), constraints,
                                                 fe.component_mask(uy));
      VectorTools::interpolate_boundary_values(mapping, dof_handler, Ids<dim>::bottom,
                                               Functions::ConstantFunction<dim>(bottom_value, dim),
                                               constraints, fe.component_mask(uv));
      for (const auto i : active_set)
        if (!constraints.is_constrained(i))
          {
            constraints.add_line(i);
            constraints.set_inhomogeneity(i, with_gap ? gap(contact_dofs.at(i)) : 0.0);
          }
      constraints.close();
    }

    template <int dim>
    void ResolvedContactProblem<dim>::assemble(const bool complete)
    {
      const double E = s.youngs_modulus_MPa, nu = s.poisson_ratio;
      // Plane strain in 2D: the 3D Lame constants with eps_zz = 0.
      const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
      const double mu     = E / (2 * (1 + nu));

      system_matrix = 0;
      rhs_gap       = 0;
      rhs_unit      = 0;
      if (complete)
        complete_matrix = 0;
      const QGauss<dim>  quadrature(2);
      FEValues<dim>      fe_values(mapping, fe, quadrature, update_gradients | update_JxW_values);
      const unsigned int n = fe.n_dofs_per_cell();
      FullMatrix<double> cell_matrix(n, n);
      Vector<double>     cell_rhs(n);
      std::vector<types::global_dof_index>   indices(n);
      const FEValuesExtractors::Vector       u(0);
      std::vector<SymmetricTensor<2, dim>>   eps(n);
      std::vector<double>                    div(n);
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            fe_values.reinit(cell);
            cell_matrix = 0;
            cell_rhs    = 0;
            for (unsigned int q = 0; q < quadrature.size(); ++q)
              {
                for (unsigned int i = 0; i < n; ++i)
                  {
                    eps[i] = fe_values[u].symmetric_gradient(i, q);
                    div[i] = trace(eps[i]);
                  }
                for (unsigned int i = 0; i < n; ++i)
                  for (unsigned int j = 0; j < n; ++j)
                    cell_matrix(i, j) +=
                      (lambda * div[i] * div[j] + 2 * mu * (eps[i] * eps[j])) * fe_values.JxW(q);
              }
            cell->get_dof_indices(indices);
            constraints_gap.distribute_local_to_global(cell_matrix, cell_rhs, indices,
                                                       system_matrix, rhs_gap);
            constraints_unit.distribute_local_to_global(cell_rhs, indices, rhs_unit, cell_matrix);
            if (complete)
              hanging.distribute_local_to_global(cell_matrix, indices, complete_matrix);
          }
      system_matrix.compress(VectorOperation::add);
      rhs_gap.compress(VectorOperation::add);
      rhs_unit.compress(VectorOperation::add);
      if (complete)
        complete_matrix.compress(VectorOperation::add);
    }

    template <int dim>
    void ResolvedContactProblem<dim>::solve_active_set(ResolvedContactLevel &result)
    {
      // Start from the node of smallest gap if nothing is active yet (first level).
      if (active_set.empty())
        for (const auto &[i, p] : contact_dofs)
          if (p.norm() < 1e-12 * s.half_width_x_mm)
            active_set.insert(i);

      // The complementarity weight c of step-41 (p + c (u - g) > 0): pressure per displacement,
      // of the order of the stiffness of one contact cell.
      const double c_weight = s.youngs_modulus_MPa / contact_cell;
      std::vector<std::uint64_t> fingerprints;
      std::vector<unsigned int>  sizes;
      VectorType u_gap(owned_dofs, comm), u_unit(owned_dofs, comm);
      VectorType f_gap(owned_dofs, comm), f_unit(owned_dofs, comm);
      VectorType u_total(owned_dofs, comm);
      bool       first = true;
      for (unsigned int iteration = 1;; ++iteration)
        {
          HG_REQUIRE_NUMERIC(iteration <= s.max_active_set_iterations,
                             "the contact active set did not settle in ",
                             s.max_active_set_iterations, " iterations (active nodes per iteration: ",
                             [&] {
                               std::string t;
                               for (const auto n : sizes)
                                 t += (t.empty() ? "" : ", ") + std::to_string(n);
                               return t;
                             }(),
                             "); raise the iteration cap or check the load");
          build_constraints(constraints_gap, 0.0, true);
          build_constraints(constraints_unit, 1.0, false);
          assemble(first);
          first = false;
          {
            const MumpsFactorisation lu(system_matrix, comm);
            lu.solve(rhs_gap, u_gap);
            lu.solve(rhs_unit, u_unit);
          }
          constraints_gap.distribute(u_gap);
          constraints_unit.distribute(u_unit);
          complete_matrix.vmult(f_gap, u_gap);
          complete_matrix.vmult(f_unit, u_unit);

          // Load control: F(delta) = F_gap + delta F_unit = F (per modelled part).
          double local_f[2] = {0, 0};
          for (const auto &[i, p] : contact_dofs)
            if (owned_dofs.is_element(i))
              {
                local_f[0] -= f_gap(i);
                local_f[1] -= f_unit(i);
              }
          const double f0 = Utilities::MPI::sum(local_f[0], comm);
          const double f1 = Utilities::MPI::sum(local_f[1], comm);
          HG_REQUIRE_NUMERIC(f1 > 0 && std::isfinite(f0),
                             "the contact carries no load (contact stiffness ", f1, ")");
          approach = (s.load / symmetry_factor - f0) / f1;

          u_total = u_gap;
          u_total.add(approach, u_unit);
          contact_force = f_gap;
          contact_force.add(approach, f_unit);
          contact_force *= -1.0;

          // New active set on the owned contact nodes, shared with the neighbours through a
          // ghosted indicator.
          VectorType indicator(owned_dofs, comm);
          std::uint64_t fingerprint = 0;
          unsigned int  n_active = 0, n_changed = 0;
          for (const auto &[i, p] : contact_dofs)
            if (owned_dofs.is_element(i))
              {
                const double pressure = contact_force(i) / lumped_area(i);
                const bool   active   = pressure + c_weight * (u_total(i) - gap(p)) > 0;
                if (active)
                  {
                    indicator(i) = 1.0;
                    fingerprint += mix(i);
                    ++n_active;
                  }
                if (active != (active_set.count(i) > 0))
                  ++n_changed;
              }
          indicator.compress(VectorOperation::insert);
          fingerprint = Utilities::MPI::sum(fingerprint, comm);
          n_active    = Utilities::MPI::sum(n_active, comm);
          n_changed   = Utilities::MPI::sum(n_changed, comm);
          solution    = u_total;

          if (n_changed == 0)
            {
              result.n_iterations = iteration;
              result.n_active     = n_active;
              break;
            }
          HG_REQUIRE_NUMERIC(std::find(fingerprints.begin(), fingerprints.end(), fingerprint) ==
                               fingerprints.end(),
                             "the contact active set cycles (it returned to an earlier set at ",
                             "iteration ", iteration, "; active nodes per iteration: ",
                             [&] {
                               std::string t;
                               for (const auto n : sizes)
                                 t += std::to_string(n) + ", ";
                               return t + std::to_string(n_active);
                             }(),
                             ")");
          fingerprints.push_back(fingerprint);
          sizes.push_back(n_active);
          HG_REQUIRE_NUMERIC(n_active > 0, "the contact active set became empty at iteration ",
                             iteration);

          VectorType ghosted(owned_dofs, relevant_dofs, comm);
          ghosted = indicator;
          active_set.clear();
          for (const auto &[i, p] : contact_dofs)
            if (ghosted(i) > 0.5)
              active_set.insert(i);
        }

      // The closed forms this solver is checked against idealise the block as a half-space, so a
      // contact that spreads over more than half of the modelled face (from the centre to the
      // edge) is not the modelled problem: the block's edges carry part of the load. It is
      // refused rather than reported as a Hertz comparison.
      constexpr double reach_limit = 0.5;
      double reach_x = 0, reach_y = 0;
      for (const auto i : active_set)
        if (owned_dofs.is_element(i))
          {
            reach_x = std::max(reach_x, contact_dofs.at(i)[0]);
            reach_y = std::max(reach_y, horizontal_y(contact_dofs.at(i)));
          }
      reach_x = Utilities::MPI::max(reach_x, comm);
      reach_y = Utilities::MPI::max(reach_y, comm);
      // A rigid roller that ends inside the face bounds the contact at its end by design.
      const double y_limit = std::max(reach_limit * s.half_width_y_mm,
                                      s.rigid_end_y_mm > 0 ? s.rigid_end_y_mm * (1 + 1e-9) : 0.0);
      HG_REQUIRE_NUMERIC(reach_x < reach_limit * s.half_width_x_mm &&
                           (dim == 2 || s.contact_may_reach_y_end || reach_y < y_limit),
                         "the contact zone reaches the edge of the modelled surface (more than half "
                         "of it: x up to ",
                         reach_x, " mm of ", s.half_width_x_mm, " mm",
                         dim == 3 ? msg(", y up to ", reach_y, " mm of ", s.half_width_y_mm, " mm") :
                                    std::string(),
                         "): the load ", s.load,
                         " is too high for this block; lower it or enlarge the block");
    }

    template <int dim>
    void ResolvedContactProblem<dim>::collect_results(ResolvedContactLevel &r)
    {
      r.approach_mm     = approach;
      r.n_dofs          = dof_handler.n_dofs();
      r.n_cells         = triangulation.n_global_active_cells();
      r.contact_cell_mm = contact_cell;

      std::vector<NodeSample> local;
      double                  sums[4] = {0, 0, 0, 0}; // sum P, sum P x^2, sum P y^2, -
      for (const auto &[i, p] : contact_dofs)
        if (owned_dofs.is_element(i))
          {
            const double P = contact_force(i);
            sums[0] += P;
            sums[1] += P * p[0] * p[0];
            sums[2] += P * horizontal_y(p) * horizontal_y(p);
            local.push_back({p[0], horizontal_y(p), P / lumped_area(i), P,
                             active_set.count(i) ? 1.0 : 0.0});
          }
      for (double &v : sums)
        v = Utilities::MPI::sum(v, comm);
      r.total_force = symmetry_factor * sums[0];
      const bool line_x = dim == 2 || s.radius_y_mm == 0;
      // Hertz: sum P x^2 / sum P = a^2/5 for the ellipse, b^2/4 for the line (per slice).
      r.semi_axis_x_mm = std::sqrt((line_x ? 4.0 : 5.0) * sums[1] / sums[0]);
      r.semi_axis_y_mm = (dim == 3 && !line_x) ? std::sqrt(5.0 * sums[2] / sums[0]) : 0.0;

      std::vector<NodeSample> all;
      for (const auto &part : Utilities::MPI::all_gather(comm, local))
        all.insert(all.end(), part.begin(), part.end());
      const double tol = 1e-9 * s.half_width_x_mm;
      r.profile_x.clear();
      r.profile_y.clear();
      std::vector<std::pair<double, double>> axis_x, axis_y; // coordinate, active
      for (const auto &n : all)
        {
          if (std::abs(n.y) < tol)
            {
              r.profile_x.push_back({n.x, n.pressure});
              axis_x.push_back({n.x, n.active});
            }
          if (dim == 3 && std::abs(n.x) < tol)
            {
              r.profile_y.push_back({n.y, n.pressure});
              axis_y.push_back({n.y, n.active});
            }
          if (std::abs(n.x) < tol && std::abs(n.y) < tol)
            r.peak_pressure_MPa = n.pressure;
        }
      const auto by_coordinate = [](const auto &a, const auto &b) {
        return a.coordinate_mm < b.coordinate_mm;
      };
      std::sort(r.profile_x.begin(), r.profile_x.end(), by_coordinate);
      std::sort(r.profile_y.begin(), r.profile_y.end(), by_coordinate);
      const auto active_edge = [](std::vector<std::pair<double, double>> axis) {
        std::sort(axis.begin(), axis.end());
        for (std::size_t k = 0; k + 1 < axis.size(); ++k)
          if (axis[k].second > 0.5 && axis[k + 1].second < 0.5)
            return 0.5 * (axis[k].first + axis[k + 1].first);
        return axis.empty() ? 0.0 : axis.back().first;
      };
      r.active_semi_axis_x_mm = active_edge(axis_x);
      r.active_semi_axis_y_mm = dim == 3 ? active_edge(axis_y) : 0.0;

      // Compression between the contact centre and points below it.
      if (!s.reading_depths_mm.empty())
        {
          std::vector<Point<dim>> points(1 + s.reading_depths_mm.size());
          for (std::size_t k = 0; k < s.reading_depths_mm.size(); ++k)
            points[k + 1][vertical] = -s.reading_depths_mm[k];
          Utilities::MPI::RemotePointEvaluation<dim> evaluation;
          evaluation.reinit(points, triangulation, mapping);
          HG_REQUIRE_INPUT(evaluation.all_points_found(), "a reading point lies outside the block");
          const auto values = VectorTools::point_values<dim>(evaluation, dof_handler, solution);
          r.depth_approach_mm.clear();
          for (std::size_t k = 0; k < s.reading_depths_mm.size(); ++k)
            r.depth_approach_mm.push_back(values[k + 1][vertical] - values[0][vertical]);
        }
    }

    template <int dim>
    void ResolvedContactProblem<dim>::refine()
    {
      // Kelly's estimator on the displacement, plus every contact-face cell in or next to the
      // active set (the pressure is the quantity of interest; Kelly alone would favour the
      // stress concentration under the surface).
      Vector<float> indicators(triangulation.n_active_cells());
      KellyErrorEstimator<dim>::estimate(mapping, dof_handler, QGauss<dim - 1>(2),
                                         std::map<types::boundary_id, const Function<dim> *>(),
                                         solution, indicators);
      parallel::distributed::GridRefinement::refine_and_coarsen_fixed_number(
        triangulation, indicators, s.kelly_fraction, 0.0);

      double ax = 0, ay = 0;
      for (const auto i : active_set)
        {
          ax = std::max(ax, contact_dofs.at(i)[0]);
          ay = std::max(ay, horizontal_y(contact_dofs.at(i)));
        }
      ax = Utilities::MPI::max(ax, comm);
      ay = Utilities::MPI::max(ay, comm);
      for (const auto &cell : triangulation.active_cell_iterators())
        if (cell->is_locally_owned() && cell->at_boundary())
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == Ids<dim>::contact)
              {
                const double     h  = cell->extent_in_direction(0);
                const Point<dim> c  = cell->face(f)->center();
                const double     rx = 1.25 * ax + h;
                const double     ry = dim == 3 ? 1.25 * ay + h : 1.0;
                const double     ex = c[0] / rx, ey = dim == 3 ? horizontal_y(c) / ry : 0.0;
                if (ex * ex + ey * ey <= 1.0)
                  cell->set_refine_flag();
              }
      triangulation.execute_coarsening_and_refinement();
    }

    template <int dim>
    std::vector<ResolvedContactLevel>
    ResolvedContactProblem<dim>::run(const std::function<void(const ResolvedContactLevel &)> &report)
    {
      start = std::chrono::steady_clock::now();
      make_grid();
      zoom_to_design_size();
      std::vector<ResolvedContactLevel> levels;
      for (unsigned int level = 0; level < s.n_levels; ++level)
        {
          if (level > 0)
            refine();
          // The active set carries over between levels by position (the mesh changed).
          std::vector<Point<dim>> previous;
          for (const auto i : active_set)
            if (owned_dofs.is_element(i))
              previous.push_back(contact_dofs.at(i));
          std::vector<Point<dim>> all_previous;
          for (const auto &part : Utilities::MPI::all_gather(comm, previous))
            all_previous.insert(all_previous.end(), part.begin(), part.end());
          setup_system();
          double extent_x = 0, extent_y = 0;
          for (const auto &p : all_previous)
            {
              extent_x = std::max(extent_x, p[0]);
              extent_y = std::max(extent_y, horizontal_y(p));
            }
          active_set.clear();
          if (!all_previous.empty())
            for (const auto &[i, p] : contact_dofs)
              {
                // Inside the previous contact ellipse (or line band).
                const double ex = p[0] / (extent_x + 1e-12);
                const double ey = (dim == 3 && extent_y > 0) ? horizontal_y(p) / extent_y : 0.0;
                if (ex * ex + ey * ey <= 1.0)
                  active_set.insert(i);
              }

          ResolvedContactLevel result;
          result.level = level;
          solve_active_set(result);
          collect_results(result);
          result.wall_time_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          levels.push_back(result);
          if (report)
            report(result);
        }
      return levels;
    }

    template <int dim>
    std::vector<ResolvedContactLevel>
    solve_resolved_contact(const ResolvedContactSettings &settings,
                           const std::function<void(const ResolvedContactLevel &)> &report)
    {
      ResolvedContactProblem<dim> problem(settings);
      return problem.run(report);
    }

    template std::vector<ResolvedContactLevel>
    solve_resolved_contact<2>(const ResolvedContactSettings &,
                              const std::function<void(const ResolvedContactLevel &)> &);
    template std::vector<ResolvedContactLevel>
    solve_resolved_contact<3>(const ResolvedContactSettings &,
                              const std::function<void(const ResolvedContactLevel &)> &);
  } // namespace fem
} // namespace hertzgear
