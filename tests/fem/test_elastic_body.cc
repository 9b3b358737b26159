// ElasticBody<dim> (fem/elastic_body.h): linear elasticity against Lame's thick cylinder,
// Maxwell-Betti reciprocity of the compliance, equality of distributed and serial runs, and the
// AMG-preconditioned CG solver against the direct one.
#include "fem/elastic_body.h"
#include "fem/petsc_ksp.h"

#include "common/errors.h"

#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_generator.h>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <set>
#include <string>

using namespace dealii;
using hertzgear::fem::ElasticBody;

namespace
{
  constexpr double E = 206.0e3, nu = 0.3; // MPa, with lengths in mm
  constexpr double r_bore = 10.0, r_outer = 20.0, pressure = 100.0;

  // Plane-strain thick cylinder clamped at the bore (u = 0 at r = r_bore) under external pressure
  // (sigma_rr = -p at r = r_outer): u_r = C1 (r - r_bore^2 / r), from sigma_rr = 2 (lambda + mu) C1
  // - 2 mu C2 / r^2 with C2 = -C1 r_bore^2 (Lame; Timoshenko & Goodier section 28).
  class ClampedCylinder : public Function<2>
  {
  public:
    ClampedCylinder()
      : Function<2>(2)
    {
      const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
      c1 = -pressure / (2 * (lambda + mu) + 2 * mu * r_bore * r_bore / (r_outer * r_outer));
    }
    double radial(const double r) const { return c1 * (r - r_bore * r_bore / r); }
    double value(const Point<2> &x, const unsigned int component) const override
    {
      const double r = x.norm();
      return radial(r) * x[component] / r;
    }

  private:
    double c1;
  };

  template <int dim>
  void make_shell(parallel::distributed::Triangulation<dim> &tria, const unsigned int n_refinements)
  {
    // Boundary ids (colorize): 0 on the bore, 1 outside; the shell manifold is on every cell.
    GridGenerator::hyper_shell(tria, Point<dim>(), r_bore, r_outer, dim == 2 ? 8 : 6, true);
    tria.refine_global(n_refinements);
  }

  typename ElasticBody<2>::Parameters parameters_2d(const unsigned int degree)
  {
    typename ElasticBody<2>::Parameters p;
    p.youngs_modulus      = E;
    p.poisson_ratio       = nu;
    p.fe_degree           = degree;
    p.mapping_degree      = degree;
    p.clamped_boundary_id = 0;
    return p;
  }

  // L2 error of the Lame problem on a shell refined n times, with the body on `comm`.
  double lame_error(const MPI_Comm comm, const unsigned int degree, const unsigned int n_refinements,
                    types::global_dof_index *n_dofs = nullptr, double *solution_norm = nullptr)
  {
    parallel::distributed::Triangulation<2> tria(comm);
    make_shell(tria, n_refinements);
    ElasticBody<2> body(tria, parameters_2d(degree));
    body.run();
    const auto u = body.solve_traction(1, [](const Point<2> &, const Tensor<1, 2> &n) {
      return -pressure * n; // external pressure pushes inwards
    });
    if (n_dofs != nullptr)
      *n_dofs = body.n_dofs();
    if (solution_norm != nullptr)
      *solution_norm = body.l2_error(u, Functions::ZeroFunction<2>(2));
    return body.l2_error(u, ClampedCylinder());
  }

  // Observed orders between successive refinements, printed as a convergence table.
  std::vector<double> observed_orders(const unsigned int degree, const unsigned int first, const unsigned int last)
  {
    std::vector<double> errors, orders;
    std::cout << "    Q" << degree << ":   level     dofs     L2 error   order\n";
    for (unsigned int level = first; level <= last; ++level)
      {
        types::global_dof_index n_dofs;
        errors.push_back(lame_error(MPI_COMM_SELF, degree, level, &n_dofs));
        std::cout << "            " << level << std::setw(10) << n_dofs << std::setw(13) << std::scientific
                  << std::setprecision(3) << errors.back();
        if (errors.size() > 1)
          {
            orders.push_back(std::log2(errors[errors.size() - 2] / errors.back()));
            std::cout << std::fixed << std::setprecision(2) << std::setw(8) << orders.back();
          }
        std::cout << std::defaultfloat << "\n";
      }
    return orders;
  }
  // Patch loads on the outer surface of the shell, along the inward normal and oblique to it
  // (2D), or along the inward normal at points spread over the sphere (3D).
  template <int dim>
  std::vector<typename ElasticBody<dim>::PatchLoad> shell_loads(const std::vector<double> &angles)
  {
    std::vector<typename ElasticBody<dim>::PatchLoad> loads;
    for (const double angle : angles)
      {
        Point<dim> x;
        x[0] = r_outer * std::cos(angle);
        x[1] = r_outer * std::sin(angle) * (dim == 3 ? std::cos(2 * angle) : 1.0);
        if (dim == 3)
          x[2] = r_outer * std::sin(angle) * std::sin(2 * angle);
        const Tensor<1, dim> inward = -x / x.norm();
        loads.push_back({x, inward, dim == 2 ? 1.0 : 6.0});
        if (dim == 2)
          {
            Tensor<1, dim> tangent;
            tangent[0] = -inward[1];
            tangent[1] = inward[0];
            loads.push_back({x, 0.6 * inward + 0.8 * tangent, 1.0});
          }
      }
    return loads;
  }

  // A posteriori bound of the amg-cg error of the patch compliance. The CG solution u~_j of
  // K u = f_j stops at ||f_j - K u~_j|| <= tol ||f_j|| (unpreconditioned residual, zero start), so
  // with the exact u_i = K^-1 f_i (the direct solution, itself exact to round-off):
  //   |C~_ij - C_ij| = |f_i . (u~_j - u_j)| = |u_i . (K u~_j - f_j)| <= tol ||u_i|| ||f_j||.
  // A factor 2 covers the drift of CG's recursive residual from the true one; the direct
  // solution's own round-off (about cond(K) eps ~ 1e-12 of max |C|, see PatchComplianceIsReciprocal)
  // is added as 1e-10 max |C|. Returns the largest |C~_ij - C_ij| / bound_ij (must be <= 1).
  template <int dim>
  double amg_error_over_bound(const ElasticBody<dim> &direct, const FullMatrix<double> &C_direct,
                              const FullMatrix<double> &C_amg, const double tolerance,
                              const std::vector<typename ElasticBody<dim>::PatchLoad> &loads,
                              double *max_relative_difference = nullptr)
  {
    std::vector<double> u_norm, f_norm;
    double              max_c = 0;
    for (const auto &load : loads)
      {
        u_norm.push_back(direct.solve_patch_load(load).l2_norm());
        f_norm.push_back(direct.patch_load_vector(load).l2_norm());
      }
    for (unsigned int i = 0; i < C_direct.m(); ++i)
      for (unsigned int j = 0; j < C_direct.n(); ++j)
        max_c = std::max(max_c, std::abs(C_direct(i, j)));
    double worst = 0, max_rel = 0;
    for (unsigned int i = 0; i < C_direct.m(); ++i)
      for (unsigned int j = 0; j < C_direct.n(); ++j)
        {
          const double difference = std::abs(C_amg(i, j) - C_direct(i, j));
          const double bound      = 2.0 * tolerance * u_norm[i] * f_norm[j] + 1e-10 * max_c;
          worst                   = std::max(worst, difference / bound);
          max_rel                 = std::max(max_rel, difference / max_c);
        }
    if (max_relative_difference != nullptr)
      *max_relative_difference = max_rel;
    return worst;
  }

  // Patch compliance of the shell with the direct solver and with amg-cg at `tolerance`; prints
  // and returns the error of amg-cg relative to its bound (amg_error_over_bound).
  template <int dim>
  double amg_against_direct(const unsigned int degree, const unsigned int n_refinements,
                            const double tolerance, const std::vector<double> &angles)
  {
    parallel::distributed::Triangulation<dim> tria(MPI_COMM_SELF);
    make_shell(tria, n_refinements);
    typename ElasticBody<dim>::Parameters p;
    p.youngs_modulus = E;
    p.poisson_ratio  = nu;
    p.fe_degree      = degree;
    p.mapping_degree = std::min(degree, 2u);
    ElasticBody<dim> direct(tria, p);
    direct.run();
    p.linear_solver           = ElasticBody<dim>::LinearSolver::amg_cg;
    p.linear_solver_tolerance = tolerance;
    ElasticBody<dim> amg(tria, p);
    amg.run();
    const auto loads = shell_loads<dim>(angles);
    const auto C_direct = direct.patch_compliance(loads);
    const auto C_amg    = amg.patch_compliance(loads);
    double     max_rel  = 0;
    const double ratio  = amg_error_over_bound(direct, C_direct, C_amg, tolerance, loads, &max_rel);
    std::cout << "    " << dim << "D Q" << degree << ", " << direct.n_dofs() << " DOFs, tol "
              << tolerance << ": max |C_amg - C_direct| / max |C| = " << max_rel
              << ", largest error / bound = " << ratio << "\n";
    return ratio;
  }
  // A compliance table shall be symmetric (Maxwell-Betti reciprocity): MUMPS LU on ~10^4
  // unknowns has a backward error ~1e-15 times a condition number ~1e5, hence 1e-10 max |C|.
  void expect_reciprocal(const FullMatrix<double> &C, const std::string &label)
  {
    double max_c = 0, max_asym = 0;
    for (unsigned int i = 0; i < C.m(); ++i)
      for (unsigned int j = 0; j < C.n(); ++j)
        {
          max_c    = std::max(max_c, std::abs(C(i, j)));
          max_asym = std::max(max_asym, std::abs(C(i, j) - C(j, i)));
        }
    std::cout << "    " << label << ": max |C_ij - C_ji| / max |C| = " << max_asym / max_c << "\n";
    EXPECT_LT(max_asym, 1e-10 * max_c);
  }

  // `run` shall throw a NumericalError (else: ADD_FAILURE with `returned`) whose message, printed,
  // holds every one of `parts`.
  template <typename Run>
  void expect_numerical_error(const Run &run, const std::string &returned,
                              const std::vector<std::string> &parts)
  {
    try
      {
        run();
        ADD_FAILURE() << returned;
      }
    catch (const hertzgear::NumericalError &e)
      {
        const std::string what = e.what();
        std::cout << "    " << what << "\n";
        for (const auto &part : parts)
          EXPECT_NE(what.find(part), std::string::npos) << part;
      }
  }
} // namespace

// The elastic body shall converge to Lame's thick-cylinder solution at the optimal L2 rate
// h^(p+1) for Q1 (2) and Q2 (3) with a mapping of the same degree. Band: +-0.2 around the
// theoretical rate on the last refinement, where the asymptotic regime is reached (the smooth
// solution and curved boundary represented to O(h^(p+1)) give no reason for a lower rate).
TEST(ElasticBody, ConvergesToLameCylinderAtOptimalRate)
{
  const auto q1 = observed_orders(1, 2, 5);
  EXPECT_NEAR(q1.back(), 2.0, 0.2);
  const auto q2 = observed_orders(2, 1, 4);
  EXPECT_NEAR(q2.back(), 3.0, 0.2);
}

// The compliance between patches shall be symmetric (Maxwell-Betti): C_ij = C_ji to the round-off
// of the direct solver, in 2D and 3D, for loads along the normal and oblique to it.
TEST(ElasticBody, PatchComplianceIsReciprocal)
{
  {
    parallel::distributed::Triangulation<2> tria(MPI_COMM_SELF);
    make_shell(tria, 3);
    ElasticBody<2> body(tria, parameters_2d(2));
    body.run();
    std::vector<ElasticBody<2>::PatchLoad> loads;
    for (const double angle : {0.1, 0.5, 1.3, 2.9})
      {
        const Point<2>     x(r_outer * std::cos(angle), r_outer * std::sin(angle));
        const Tensor<1, 2> inward = -x / x.norm();
        Tensor<1, 2>       tangent;
        tangent[0] = -inward[1];
        tangent[1] = inward[0];
        loads.push_back({x, inward, 1.0});
        loads.push_back({x, 0.6 * inward + 0.8 * tangent, 1.0});
      }
    const FullMatrix<double> C = body.patch_compliance(loads);
    expect_reciprocal(C, "2D");
    for (unsigned int i = 0; i < C.m(); ++i)
      EXPECT_GT(C(i, i), 0.0); // work of a load on its own displacement is positive
  }
  {
    parallel::distributed::Triangulation<3> tria(MPI_COMM_SELF);
    make_shell(tria, 1);
    typename ElasticBody<3>::Parameters p;
    p.youngs_modulus = E;
    p.poisson_ratio  = nu;
    p.fe_degree      = 1;
    p.mapping_degree = 1;
    ElasticBody<3> body(tria, p);
    body.run();
    std::vector<ElasticBody<3>::PatchLoad> loads;
    for (const Point<3> &x : {Point<3>(r_outer, 0, 0), Point<3>(0, r_outer, 0), Point<3>(0, 0, -r_outer),
                              Point<3>(r_outer / std::sqrt(2.0), 0, r_outer / std::sqrt(2.0))})
      loads.push_back({x, -x / x.norm(), 6.0});
    expect_reciprocal(body.patch_compliance(loads), "3D");
  }
}

// The direct solver substitutes many right-hand sides as dense blocks (fem/petsc_ksp.h,
// mumps_block_solve). Its compliance table and its fields of several load sets shall equal those
// of one substitution per load case, also when the loads span several blocks (3 columns per block
// for 8 loads here). Both are substitutions with the same Cholesky factors and differ only in the
// order of the floating-point operations: a backward-stable substitution errs by about
// cond(K) eps ~ 1e5 * 1e-16 relative, hence the bound 1e-10 max |C| (as for reciprocity above).
TEST(ElasticBody, BlockSubstitutionEqualsOneSolvePerLoad)
{
  parallel::distributed::Triangulation<2> tria(MPI_COMM_SELF);
  make_shell(tria, 3);
  auto p          = parameters_2d(2);
  p.block_columns = 3;
  ElasticBody<2> body(tria, p);
  body.run();
  std::vector<ElasticBody<2>::PatchLoad>    loads;
  std::vector<ElasticBody<2>::PointReading> readings;
  for (const double angle : {0.1, 0.5, 0.9, 1.3, 1.7, 2.1, 2.5, 2.9})
    {
      const Point<2>     x(r_outer * std::cos(angle), r_outer * std::sin(angle));
      const Tensor<1, 2> inward = -x / x.norm();
      loads.push_back({x, inward, 1.0});
      readings.push_back({x + 1.5 * inward, inward});
    }
  const FullMatrix<double> C = body.compliance(loads, readings);
  EXPECT_EQ(body.n_solves(), loads.size());

  std::vector<Point<2>> points;
  for (const auto &r : readings)
    points.push_back(r.point);
  double max_c = 0, max_diff = 0;
  for (unsigned int l = 0; l < loads.size(); ++l)
    {
      const auto values = body.point_values(body.solve_patch_load(loads[l]), points);
      for (unsigned int r = 0; r < readings.size(); ++r)
        {
          const double c = values[r] * readings[r].direction;
          max_c          = std::max(max_c, std::abs(c));
          max_diff       = std::max(max_diff, std::abs(C(r, l) - c));
        }
    }
  std::cout << "    compliance: max |C_block - C_single| / max |C| = " << max_diff / max_c << "\n";
  EXPECT_GT(max_c, 0.0);
  EXPECT_LT(max_diff, 1e-10 * max_c);

  // Fields of four load sets at once against one set at a time.
  std::vector<std::vector<ElasticBody<2>::PatchLoad>> sets;
  std::vector<std::vector<double>>                    forces;
  for (unsigned int s = 0; s < 4; ++s)
    {
      sets.push_back({loads[2 * s], loads[2 * s + 1]});
      forces.push_back({1.0 + s, 0.5 * s});
    }
  const auto fields = body.solve_patch_load_sets(sets, forces);
  ASSERT_EQ(fields.size(), sets.size());
  for (unsigned int s = 0; s < sets.size(); ++s)
    {
      const auto single = body.solve_patch_loads(sets[s], forces[s]);
      // Ghosted vectors are read-only: compare non-ghosted copies.
      ElasticBody<2>::VectorType diff(body.get_dof_handler().locally_owned_dofs(), MPI_COMM_SELF);
      ElasticBody<2>::VectorType block(body.get_dof_handler().locally_owned_dofs(), MPI_COMM_SELF);
      diff  = single;
      block = fields[s];
      diff -= block;
      EXPECT_GT(single.linfty_norm(), 0.0);
      EXPECT_LT(diff.linfty_norm(), 1e-10 * single.linfty_norm()) << "load set " << s;
    }
}

// Point readings shall see the displacement of a patch load: reading a load's own displacement
// at its centre agrees with the patch-averaged compliance to the variation over the patch, and
// a reading outside the body or a patch off the surface is refused with an InputError.
TEST(ElasticBody, PointReadingsAndBadInput)
{
  parallel::distributed::Triangulation<2> tria(MPI_COMM_SELF);
  make_shell(tria, 3);
  ElasticBody<2> body(tria, parameters_2d(2));
  body.run();
  const Point<2>                  x(0, r_outer);
  const ElasticBody<2>::PatchLoad load{x, Tensor<1, 2>({0.0, -1.0}), 0.5};
  // Depth reading 2 mm below the patch and the patch average: the same sign and order.
  const auto C_point = body.compliance({load}, {{Point<2>(0, r_outer - 2.0), Tensor<1, 2>({0.0, -1.0})}});
  const auto C_patch = body.patch_compliance({load});
  EXPECT_GT(C_point(0, 0), 0.0);
  EXPECT_LT(C_point(0, 0), C_patch(0, 0)); // the surface under the load moves most
  EXPECT_THROW(body.compliance({load}, {{Point<2>(0, 30.0), Tensor<1, 2>({0.0, -1.0})}}), hertzgear::InputError);
  EXPECT_THROW(body.solve_patch_load({Point<2>(0, 15.0), Tensor<1, 2>({0.0, -1.0}), 0.5}), hertzgear::InputError);
}

// A body distributed over all ranks shall give the serial body's results (L2 error against Lame,
// point values, compliance) to solver round-off. Run with mpirun -np 2 (ctest fem.elastic_body_mpi2).
TEST(ElasticBodyMpi, DistributedEqualsSerial)
{
  if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    std::cout << "    ranks: " << Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) << "\n";

  // | ||e_world|| - ||e_self|| | <= ||u_world - u_self||, which is the direct solver's round-off,
  // about cond(K) eps ||u|| ~ 1e-12 ||u||; 1e-10 ||u|| bounds it with margin. (The errors
  // themselves are 2e-5 ||u||, so a relative comparison of them would amplify round-off.)
  double       norm_self   = 0;
  const double error_world = lame_error(MPI_COMM_WORLD, 2, 3);
  const double error_self  = lame_error(MPI_COMM_SELF, 2, 3, nullptr, &norm_self);
  EXPECT_NEAR(error_world, error_self, 1e-10 * norm_self);

  std::vector<ElasticBody<2>::PatchLoad>    loads;
  std::vector<ElasticBody<2>::PointReading> readings;
  for (const double angle : {0.2, 1.7, 3.3, 4.9}) // spread over both halves of the partition
    {
      const Point<2>     x(r_outer * std::cos(angle), r_outer * std::sin(angle));
      const Tensor<1, 2> inward = -x / x.norm();
      loads.push_back({x, inward, 1.0});
      readings.push_back({x + 1.5 * inward, inward});
    }
  const auto compliance_on = [&](const MPI_Comm comm) {
    parallel::distributed::Triangulation<2> tria(comm);
    make_shell(tria, 3);
    ElasticBody<2> body(tria, parameters_2d(2));
    body.run();
    return std::pair{body.compliance(loads, readings), body.patch_compliance(loads)};
  };
  const auto [C_world, P_world] = compliance_on(MPI_COMM_WORLD);
  const auto [C_self, P_self]   = compliance_on(MPI_COMM_SELF);
  for (unsigned int i = 0; i < loads.size(); ++i)
    for (unsigned int j = 0; j < loads.size(); ++j)
      {
        // Different partitions change only the order of floating-point operations: round-off
        // times cond(K) ~ 1e-12 of the largest entry; 1e-10 leaves margin.
        EXPECT_NEAR(C_world(i, j), C_self(i, j), 1e-10 * std::abs(P_self(i, i)));
        EXPECT_NEAR(P_world(i, j), P_self(i, j), 1e-10 * std::abs(P_self(i, i)));
      }
}

// A gmsh mesh shall be read with its physical groups as boundary ids (faces) and material ids
// (cells), so that the body can be clamped on the bore group and loaded on a flank group; a
// missing file is an InputError.
TEST(ElasticBody, ReadsGmshPhysicalGroups)
{
  // A 2 x 1 plate of two quads: physical line 7 at y = 0, 9 at y = 1, physical surface 3.
  const std::string filename = ::testing::TempDir() + "hertzgear_plate.msh";
  {
    std::ofstream out(filename);
    out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n6\n"
           "1 0 0 0\n2 1 0 0\n3 2 0 0\n4 0 1 0\n5 1 1 0\n6 2 1 0\n$EndNodes\n"
           "$Elements\n6\n1 1 2 7 1 1 2\n2 1 2 7 1 2 3\n3 1 2 9 2 4 5\n4 1 2 9 2 5 6\n"
           "5 3 2 3 1 1 2 5 4\n6 3 2 3 1 2 3 6 5\n$EndElements\n";
  }
  parallel::distributed::Triangulation<2> tria(MPI_COMM_SELF);
  hertzgear::fem::read_gmsh_mesh(filename, tria);
  EXPECT_EQ(tria.n_active_cells(), 2u);
  std::set<types::boundary_id> ids;
  for (const auto &face : tria.active_face_iterators())
    if (face->at_boundary())
      ids.insert(face->boundary_id());
  EXPECT_EQ(ids.count(7), 1u);
  EXPECT_EQ(ids.count(9), 1u);
  for (const auto &cell : tria.active_cell_iterators())
    EXPECT_EQ(cell->material_id(), 3u);

  tria.refine_global(3);
  auto p                = parameters_2d(2);
  p.clamped_boundary_id = 7;
  ElasticBody<2> body(tria, p);
  body.set_load_boundary_ids({9});
  body.run();
  // A unit load pressing down on the top shall move the top down.
  const auto C = body.compliance({{Point<2>(1.0, 1.0), Tensor<1, 2>({0.0, -1.0}), 0.2}},
                                 {{Point<2>(1.0, 0.9), Tensor<1, 2>({0.0, -1.0})}});
  EXPECT_GT(C(0, 0), 0.0);

  parallel::distributed::Triangulation<2> other(MPI_COMM_SELF);
  EXPECT_THROW(hertzgear::fem::read_gmsh_mesh(::testing::TempDir() + "no_such_mesh.msh", other),
               hertzgear::InputError);
}

// The amg-cg solver (CG + GAMG with the rigid-body near-null space) shall give the direct
// solver's patch compliance to within what its tolerance allows: |C_amg - C_direct|_ij <=
// 2 tol ||u_i|| ||f_j|| + 1e-10 max |C| (derived at amg_error_over_bound), in 2D (Q2, whose DoFs
// are node-blocked, and Q3, whose line DoFs are not, so the near-null space is built DoF by DoF)
// and 3D (Q1 and Q2). tol = 1e-8 keeps the CG error well above the direct solver's round-off, so
// the comparison tests the bound and not round-off; the scene default 1e-10 is checked in 2D too.
TEST(ElasticBody, AmgCgMatchesDirectPatchComplianceWithinTolerance)
{
  const std::vector<double> angles_2d{0.1, 0.5, 1.3, 2.9};
  EXPECT_LE(amg_against_direct<2>(2, 3, 1e-8, angles_2d), 1.0);
  EXPECT_LE(amg_against_direct<2>(2, 3, 1e-10, angles_2d), 1.0);
  EXPECT_LE(amg_against_direct<2>(3, 2, 1e-8, angles_2d), 1.0);
  const std::vector<double> angles_3d{0.0, 0.7, 1.6, 2.4};
  EXPECT_LE(amg_against_direct<3>(1, 1, 1e-8, angles_3d), 1.0);
  EXPECT_LE(amg_against_direct<3>(2, 1, 1e-8, angles_3d), 1.0);
}

// A direct factorisation whose MUMPS analysis estimates more memory than the process may use shall
// stop before it allocates, as a NumericalError (exit 3) that names the estimate, the limit and
// the remedies, instead of an allocation failure after minutes or the kernel's OOM killer. A
// limit of 1 MB is below any MUMPS estimate; the automatic limit (the memory available now) lets
// the same body factorise.
TEST(ElasticBody, FactorisationBeyondTheMemoryLimitStopsWithTheEstimate)
{
  parallel::distributed::Triangulation<2> tria(MPI_COMM_SELF);
  make_shell(tria, 4);
  auto p                          = parameters_2d(2);
  p.factorisation_memory_limit_MB = 1;
  expect_numerical_error(
    [&] {
      ElasticBody<2> body(tria, p);
      body.run();
    },
    "a factorisation beyond its memory limit went ahead",
    {"INFOG(1) = -19", "against 1 MB", "estimates", "{level}"}); // the remedy names the level field
  p.factorisation_memory_limit_MB = 0;
  ElasticBody<2> body(tria, p);
  EXPECT_NO_THROW(body.run());
  EXPECT_GT(hertzgear::fem::available_memory_MB_per_rank(MPI_COMM_SELF), 1);
}

// An amg-cg solve that does not reach its tolerance within the iteration cap shall end with a
// NumericalError (exit 3) naming the KSP reason, the iterations and the remedies (tolerance, direct
// solver), never with a silently inaccurate compliance; bad solver settings are InputErrors.
TEST(ElasticBody, AmgCgThatDoesNotConvergeIsNumericalError)
{
  parallel::distributed::Triangulation<2> tria(MPI_COMM_SELF);
  make_shell(tria, 3);
  auto p                         = parameters_2d(2);
  p.linear_solver                = ElasticBody<2>::LinearSolver::amg_cg;
  p.linear_solver_tolerance      = 1e-12;
  p.linear_solver_max_iterations = 2; // CG needs ~20 here: 2 cannot reach 1e-12
  ElasticBody<2> body(tria, p);
  body.run();
  expect_numerical_error(
    [&] { body.solve_patch_load(shell_loads<2>({0.3})[0]); }, "a capped amg-cg solve returned",
    {"DIVERGED_ITS", "after 2 CG iterations", "linear_solver_tolerance", "direct"});

  EXPECT_EQ(ElasticBody<2>::parse_linear_solver("amg-cg"), ElasticBody<2>::LinearSolver::amg_cg);
  EXPECT_EQ(ElasticBody<2>::parse_linear_solver("direct"), ElasticBody<2>::LinearSolver::direct);
  EXPECT_THROW(ElasticBody<2>::parse_linear_solver("lu"), hertzgear::InputError);
  p.linear_solver_tolerance = 0;
  EXPECT_THROW(ElasticBody<2> bad(tria, p), hertzgear::InputError);
}

// amg-cg on a body distributed over all ranks (the AMG hierarchy then differs from the serial
// one) shall still give the serial direct compliance within the tolerance bound of
// amg_error_over_bound.
// Run with mpirun -np 2 (ctest fem.elastic_body_mpi2).
TEST(ElasticBodyMpi, AmgCgDistributedMatchesSerialDirect)
{
  const double tolerance = 1e-8;
  const auto   loads     = shell_loads<2>({0.2, 1.7, 3.3, 4.9}); // both halves of the partition

  parallel::distributed::Triangulation<2> tria_world(MPI_COMM_WORLD);
  make_shell(tria_world, 3);
  auto p                    = parameters_2d(2);
  p.linear_solver           = ElasticBody<2>::LinearSolver::amg_cg;
  p.linear_solver_tolerance = tolerance;
  ElasticBody<2> amg(tria_world, p);
  amg.run();
  const auto C_amg = amg.patch_compliance(loads);

  parallel::distributed::Triangulation<2> tria_self(MPI_COMM_SELF);
  make_shell(tria_self, 3);
  ElasticBody<2> direct(tria_self, parameters_2d(2));
  direct.run();
  const auto C_direct = direct.patch_compliance(loads);
  double     max_rel  = 0;
  const double ratio  = amg_error_over_bound(direct, C_direct, C_amg, tolerance, loads, &max_rel);
  if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    std::cout << "    " << Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD)
              << " ranks amg-cg vs serial direct: max rel. difference " << max_rel
              << ", largest error / bound = " << ratio << "\n";
  EXPECT_LE(ratio, 1.0);
}
