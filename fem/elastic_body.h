#pragma once
// Linear elastic body (deal.II, PETSc, MPI): the global part of the gear compliance.
//
// The body is assembled once and its solver set up once; every further load case reuses it. Two
// solvers (Parameters::linear_solver):
//   direct  MUMPS Cholesky (LDL^T of the SPD stiffness matrix) through PETSc, factorised once;
//           load cases are forward/backward substitutions, many at once as one dense block
//           (exact to round-off; memory grows fast with the DOFs in 3D).
//   amg_cg  PETSc CG preconditioned by smoothed-aggregation AMG (PCGAMG) with the rigid-body
//           modes as near-null space; the AMG hierarchy is built once and reused, each load case
//           is one CG solve to the relative residual linear_solver_tolerance (memory ~ the matrix).
// That reuse is what makes the hybrid contact method affordable: the TCA needs the displacement
// field of a unit load at every contact-grid point.
//
//   ElasticBody<2> body(triangulation, parameters);   // plane strain in 2D
//   body.run();                                       // setup_system, assemble_system, setup_solver
//   const auto C = body.compliance(loads, readings);  // C(r, l) = u_l(point_r) . direction_r
//
// Inputs before outputs, SI or any consistent unit system (the class never converts units).
#include "common/errors.h"
#include "fem/body_compliance.h"
#include "common/progress.h"

#include <deal.II/base/function.h>
#include <deal.II/base/index_set.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_tools_cache.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include <functional>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace hertzgear
{
  namespace fem
  {
    // Read a gmsh .msh file (physical groups of faces become boundary ids, of cells material ids)
    // into an empty triangulation, serial or parallel::distributed (each rank reads the coarse
    // mesh). Throws InputError if the file cannot be read.
    template <int dim>
    void read_gmsh_mesh(const std::string &filename, dealii::Triangulation<dim> &triangulation);

    // A patch load that touches no quadrature point of a loadable boundary face: the surface
    // mesh is coarser than the patch. An input error (exit 2); callers that know which scene
    // values set the mesh and the patch catch it and say so.
    class PatchOffMeshError : public InputError
    {
    public:
      using InputError::InputError;
    };

    template <int dim>
    class ElasticBody : public BodyCompliance<dim>
    {
    public:
      using VectorType = dealii::PETScWrappers::MPI::Vector;
      using MatrixType = dealii::PETScWrappers::MPI::SparseMatrix;

      enum class LinearSolver
      {
        direct, // MUMPS LU, factorised once
        amg_cg  // CG + PCGAMG (rigid-body near-null space), hierarchy built once
      };

      struct Parameters
      {
        double                      youngs_modulus = 206.0e9; // Pa (or MPa with mm)
        double                      poisson_ratio  = 0.3;
        unsigned int                fe_degree      = 2;       // FE_Q degree of each component
        unsigned int                mapping_degree = 2;       // MappingQ degree (curved boundaries)
        dealii::types::boundary_id  clamped_boundary_id = 0;  // the bore
        LinearSolver                linear_solver  = LinearSolver::direct;
        // amg_cg only: a solve stops when ||b - K u||_2 <= linear_solver_tolerance ||b||_2
        // (unpreconditioned residual, zero initial guess) and is a NumericalError if that takes
        // more than linear_solver_max_iterations CG iterations. PETSC_OPTIONS (-ksp_*, -pc_gamg_*)
        // can override both and tune the AMG.
        double                      linear_solver_tolerance      = 1.0e-10;
        unsigned int                linear_solver_max_iterations = 2000;
        // direct only: right-hand sides per block substitution; 0 = as many as fit in 256 MB.
        unsigned int                block_columns = 0;
        // direct only: most memory [MB] MUMPS may allocate per process for the factorisation;
        // 0 = what is available on the node now (fem/petsc_ksp.h, memory guard).
        long                        factorisation_memory_limit_MB = 0;
      };

      // "direct" / "amg-cg" (the scene's spelling) <-> LinearSolver; InputError for anything else.
      static LinearSolver       parse_linear_solver(const std::string &name);
      static std::string        linear_solver_name(const LinearSolver solver);

      using PatchLoad    = fem::PatchLoad<dim>;
      using PointReading = fem::PointReading<dim>;

      // Traction t(x, n) on a boundary part, n the outward unit normal.
      using TractionFunction = std::function<dealii::Tensor<1, dim>(const dealii::Point<dim> &,
                                                                    const dealii::Tensor<1, dim> &)>;

      // The triangulation (serial, parallel::distributed or fullydistributed) must outlive the
      // body; its communicator is the body's communicator. Manifolds must be attached to it.
      ElasticBody(const dealii::Triangulation<dim> &triangulation, const Parameters &parameters);
      ~ElasticBody();
      ElasticBody(const ElasticBody &) = delete;
      ElasticBody &operator=(const ElasticBody &) = delete;

      // setup_system, assemble_system, setup_solver: afterwards any number of load cases.
      void run();
      // setup_system and assemble_system only, for a caller that factorises the matrix itself
      // (CyclicGearBody condenses it onto the sector's cut faces).
      void assemble();

      // Patch loads may be restricted to boundary faces with these ids (empty: any boundary face
      // except the clamped one), e.g. the flank of one tooth.
      void set_load_boundary_ids(const std::set<dealii::types::boundary_id> &ids);

      // Displacement field of a traction on boundary part `boundary_id`.
      VectorType solve_traction(const dealii::types::boundary_id boundary_id,
                                const TractionFunction &         traction) const;
      // Load vector of one patch load scaled to a unit resultant (what solve_patch_load solves
      // for; not ghosted). Lets callers bound solver errors: |f_i . (u_j - u_j,exact)| <=
      // ||u_i|| ||b_j - K u_j|| <= linear_solver_tolerance ||u_i|| ||f_j|| for amg_cg.
      VectorType patch_load_vector(const PatchLoad &load) const;
      // Displacement field of one patch load.
      VectorType solve_patch_load(const PatchLoad &load) const;
      // Displacement field of several patch loads at once, patch k carrying the force
      // forces[k] * direction_k (one assembly pass, one solve): the loaded body of a mesh position.
      VectorType solve_patch_loads(const std::vector<PatchLoad> &loads,
                                   const std::vector<double> &   forces) const;
      // The same for several load sets (e.g. every mesh position) with one block substitution:
      // result[s] is the field of loads[s] carrying forces[s].
      std::vector<VectorType> solve_patch_load_sets(const std::vector<std::vector<PatchLoad>> &loads,
                                                    const std::vector<std::vector<double>> &forces) const;

      // Where the body's time went (wall seconds on this rank, accumulated over all calls), in
      // phases "set-up" (DoFs, constraints, sparsity), "assembly", "factorisation" (direct) or
      // "AMG hierarchy" (amg_cg), "load vectors", "solves" and "readings" (compliance table).
      const PhaseTimer &get_timer() const { return timer; }
      // Right-hand sides solved so far.
      unsigned int n_solves() const { return solves_done; }

      // Displacements (vectors) at points anywhere in the body; collective, every rank gets all.
      std::vector<dealii::Tensor<1, dim>> point_values(const VectorType &                     solution,
                                                       const std::vector<dealii::Point<dim>> &points) const;

      // C(r, l) = displacement of load case l read at reading r: n_readings x n_loads, replicated
      // on every rank. One substitution per load, one point search for all readings.
      dealii::FullMatrix<double> compliance(const std::vector<PatchLoad> &   loads,
                                            const std::vector<PointReading> &readings) const override;
      double youngs_modulus() const override { return parameters.youngs_modulus; }
      double poisson_ratio() const override { return parameters.poisson_ratio; }

      // The reading as a linear functional of the DoF values: (DoF, weight) pairs of the cell
      // that holds the point (serial bodies; constrained DoFs left out).
      std::vector<std::pair<dealii::types::global_dof_index, double>>
      reading_functional(const PointReading &reading) const;
      // The constraints applied to a solution of the assembled system, as a ghosted copy.
      VectorType ghosted_solution(VectorType &solution) const { return finish_solution(solution); }
      const MatrixType &                       get_system_matrix() const { return system_matrix; }
      const dealii::AffineConstraints<double> &get_constraints() const { return constraints; }
      const dealii::IndexSet &                 get_locally_owned_dofs() const { return locally_owned_dofs; }

      // C(i, j) = work of patch traction i on the displacement of patch load j: symmetric by
      // Maxwell-Betti (the discrete K^-1 is symmetric) up to the solver error: round-off for the
      // direct solver, but only to the solver tolerance for amg_cg (|C_ij - C_ji| <=
      // tol (||u_i|| ||f_j|| + ||u_j|| ||f_i||), see patch_load_vector).
      dealii::FullMatrix<double> patch_compliance(const std::vector<PatchLoad> &loads) const;

      // ||u_h - u||_L2 over the body (collective).
      double l2_error(const VectorType &solution, const dealii::Function<dim> &exact) const;

      dealii::types::global_dof_index n_dofs() const;
      const dealii::DoFHandler<dim> & get_dof_handler() const { return dof_handler; }
      const dealii::Mapping<dim> &    get_mapping() const { return mapping; }
      MPI_Comm                        get_communicator() const { return mpi_communicator; }
      const Parameters &              get_parameters() const { return parameters; }

    private:
      void setup_system();
      void assemble_system();
      // direct: MUMPS factorisation; amg_cg: KSPCG + PCGAMG with the rigid-body near-null space
      // and the AMG hierarchy built (KSPSetUp). Once per body.
      void setup_solver();
      void setup_direct();
      void setup_amg_cg();

      VectorType solve(VectorType &rhs) const;
      // Solves every right-hand side (consumed); direct: dense blocks of columns bounded in memory.
      std::vector<VectorType> solve_many(std::vector<VectorType> &rhs) const;
      std::size_t             block_columns() const;
      // The common tail of solve and solve_many: constraints, ghosted copy.
      VectorType finish_solution(VectorType &solution) const;
      // Load vector of a patch (not yet divided by the patch area) and the weighted patch area.
      std::pair<VectorType, double> assemble_patch_rhs(const PatchLoad &load) const;
      bool                          is_load_face(const dealii::types::boundary_id id) const;

      const dealii::Triangulation<dim> &triangulation;
      const Parameters                  parameters;
      MPI_Comm                          mpi_communicator;

      const dealii::FESystem<dim> fe;
      const dealii::MappingQ<dim> mapping;
      dealii::DoFHandler<dim>     dof_handler;

      dealii::IndexSet                  locally_owned_dofs;
      dealii::IndexSet                  locally_relevant_dofs;
      dealii::AffineConstraints<double> constraints;
      MatrixType                        system_matrix;

      std::set<dealii::types::boundary_id> load_boundary_ids;
      // The point search of reading_functional (vertex-to-cell maps, built on the first reading).
      mutable std::unique_ptr<dealii::GridTools::Cache<dim>> point_search;

      // The PETSc KSP that holds the MUMPS factors or the AMG hierarchy (opaque here to keep petsc
      // headers out).
      struct Factorisation;
      std::unique_ptr<Factorisation> factorisation;
      mutable PhaseTimer             timer;
      mutable unsigned int           solves_done = 0;
    };
  } // namespace fem
} // namespace hertzgear
