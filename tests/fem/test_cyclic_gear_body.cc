// Requirement: the cyclic full-gear model (CyclicGearBody: one tooth sector, its Schur complement
// on the cut faces, a block-circulant interface split into harmonics) is exact: its compliance
// table equals that of a direct solve on the full gear mesh assembled from the N rotated copies
// of the same sector mesh (same DoFs, same equations), to round-off. Tolerance 1e-8 relative: the
// two computations differ only in the order of floating-point operations (MUMPS on the whole
// gear against MUMPS on one sector, a dense Schur complement and LAPACK's Cholesky per harmonic);
// the measured difference is ~1e-12 (2D) and ~1e-11 (3D).
// Also: a load pattern that is one pure cyclic harmonic excites that harmonic's problem alone,
// and a sector mesh whose cut faces do not match is refused.
#include "fem/cyclic_gear_body.h"
#include "fem/elastic_body.h"
#include "fem/flank_compliance.h"
#include "fem/harmonic_sharing.h"
#include "fem/sector_group.h"
#include "meshing/gear_body_mesher.h"
#include "meshing/pair_kinematics.h"
#include "tests/support/spur_pair.h"

#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <gtest/gtest.h>

#include <numeric>

#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>

#include <unistd.h>

using namespace hertzgear;

namespace
{
  constexpr double E_MPa = 206000.0, nu = 0.3;

  // 18/30 teeth, 12/20 mm bores: a small pair, quick to mesh whole; helical with a right-hand
  // pinion when beta_deg > 0.
  meshing::PairParameters small_pair(const double face_width_mm, const double beta_deg = 0)
  {
    auto p = hertzgear::testing::spur_pair({18, 30, face_width_mm, 0.0, 12.0, 20.0, 0.1});
    p.pinion.helix_angle_rad = p.gear.helix_angle_rad = beta_deg * M_PI / 180.0;
    p.pinion.hand = meshing::HelixHand::right;
    p.gear.hand   = meshing::HelixHand::left;
    return p;
  }

  // A one-tooth sector of the pinion (coarse), written by the mesher.
  std::filesystem::path sector_mesh(const meshing::PairKinematics &kin, const int dim,
                                    const std::string &tag)
  {
    meshing::MeshSettings m;
    m.dimension           = dim;
    m.teeth_per_sector    = 1;
    m.refinement_level    = 0;
    m.face_width_layers   = 3;
    m.band_size_modules   = 0.25;
    m.fillet_size_modules = 0.3;
    m.far_size_modules    = 0.8;
    const auto msh = std::filesystem::temp_directory_path() /
                     ("hertzgear_cyclic_" + tag + "_" + std::to_string(::getpid()) + ".msh");
    meshing::GearBodyMesher mesher;
    mesher.mesh(kin.pinion(), m, kin.point('A').radius_pinion_mm, msh);
    return msh;
  }

  template <int dim>
  typename fem::ElasticBody<dim>::Parameters body_parameters()
  {
    typename fem::ElasticBody<dim>::Parameters p;
    p.youngs_modulus      = E_MPa;
    p.poisson_ratio       = nu;
    p.fe_degree           = 1;
    p.mapping_degree      = 1;
    p.clamped_boundary_id = meshing::physical_tag::bore;
    return p;
  }

  // The full gear of n_teeth teeth from `sector`, loadable on its tooth's drive flank; not yet run.
  template <int dim>
  std::unique_ptr<fem::CyclicGearBody<dim>> cyclic_body(const dealii::Triangulation<dim> &sector,
                                                        const int n_teeth,
                                                        const MPI_Comm harmonics = MPI_COMM_SELF,
                                                        const double twist_rad_per_mm = 0)
  {
    typename fem::CyclicGearBody<dim>::Parameters cp;
    cp.body                  = body_parameters<dim>();
    cp.n_teeth               = static_cast<unsigned int>(n_teeth);
    cp.harmonic_communicator = harmonics;
    cp.twist_rad_per_mm      = twist_rad_per_mm;
    auto body = std::make_unique<fem::CyclicGearBody<dim>>(sector, cp);
    body->set_load_boundary_ids({meshing::physical_tag::drive_flank});
    return body;
  }

  template <int dim>
  void rotate(const double angle, dealii::Triangulation<dim> &tria)
  {
    if constexpr (dim == 2)
      dealii::GridTools::rotate(angle, tria);
    else
      dealii::GridTools::rotate(dealii::Tensor<1, 3>({0.0, 0.0, 1.0}), angle, tria);
  }

  // The full gear as N rotated copies of the sector, merged at the cuts, with the sector's
  // boundary ids (matched by face centre turned back into the sector).
  template <int dim>
  void full_gear(const dealii::Triangulation<dim> &sector, const fem::CyclicGearBody<dim> &cyclic,
                 dealii::Triangulation<dim> &full)
  {
    const unsigned int N = cyclic.n_teeth();
    std::vector<dealii::Triangulation<dim>> copies(N);
    std::vector<const dealii::Triangulation<dim> *> pointers;
    for (unsigned int s = 0; s < N; ++s)
      {
        copies[s].copy_triangulation(sector);
        rotate(2.0 * M_PI * s / N, copies[s]);
        pointers.push_back(&copies[s]);
      }
    dealii::GridGenerator::merge_triangulations(pointers, full, 1e-8);
    std::vector<std::pair<dealii::Point<dim>, dealii::types::boundary_id>> sector_faces;
    for (const auto &face : sector.active_face_iterators())
      if (face->at_boundary())
        sector_faces.emplace_back(face->center(), face->boundary_id());
    for (const auto &face : full.active_face_iterators())
      if (face->at_boundary())
        {
          const int  t     = cyclic.tooth_of(face->center());
          const auto local = cyclic.to_sector(face->center(), t);
          double     best  = 1e300;
          dealii::types::boundary_id id = 0;
          for (const auto &[c, b] : sector_faces)
            if (c.distance(local) < best)
              best = c.distance(local), id = b;
          ASSERT_LT(best, 1e-8) << "boundary face at " << face->center() << " has no sector face";
          face->set_boundary_id(id);
        }
  }

  fem::FlankTableSettings table_settings(const meshing::GearGeometry &g, const int dim)
  {
    fem::FlankTableSettings s;
    s.teeth              = {-1, 0, 1};
    s.n_roll             = 4;
    s.n_face             = dim == 3 ? 2 : 1;
    const double r_pitch = std::sqrt(std::pow(g.reference_radius_mm(), 2) - std::pow(g.base_radius_mm(), 2));
    s.roll_min_mm        = r_pitch - 2.0;
    s.roll_max_mm        = r_pitch + 2.0;
    s.reference_depth_mm = 2.0;
    s.patch_radius_mm    = 1.2;
    return s;
  }

  template <int dim>
  void expect_cyclic_equals_assembled_full_gear(const double beta_deg = 0)
  {
    const meshing::PairKinematics kin(small_pair(dim == 3 ? 6.0 : 20.0, beta_deg));
    const auto msh = sector_mesh(kin, dim, std::to_string(dim) + "d_beta" + std::to_string(int(beta_deg)));
    dealii::Triangulation<dim>    sector;
    fem::read_gmsh_mesh(msh.string(), sector);
    std::filesystem::remove(msh);

    const auto cyclic_ptr = cyclic_body(sector, kin.pinion().n_teeth(), MPI_COMM_SELF,
                                        kin.pinion().flank().section_angle_rad(1.0));
    auto      &cyclic     = *cyclic_ptr;
    cyclic.run();

    dealii::Triangulation<dim> full;
    full_gear(sector, cyclic, full);
    fem::ElasticBody<dim> direct(full, body_parameters<dim>());
    direct.set_load_boundary_ids({meshing::physical_tag::drive_flank});
    direct.run();

    const auto s = table_settings(kin.pinion(), dim);
    const fem::TabulatedFlankCompliance<dim> by_harmonics(cyclic, kin.pinion(), 0, s);
    const fem::TabulatedFlankCompliance<dim> by_full_mesh(direct, kin.pinion(), 0, s);
    const auto &a = by_harmonics.matrix();
    const auto &b = by_full_mesh.matrix();
    ASSERT_EQ(a.rows(), b.rows());
    ASSERT_EQ(a.cols(), b.cols());
    const double difference = (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
    std::cout << dim << "D: sector " << cyclic.n_dofs() << " DoFs, " << cyclic.n_cut_dofs()
              << " per cut face; full gear " << direct.n_dofs() << " DoFs; max |C_cyclic - C_full| / "
              << "max |C| = " << difference << std::endl;
    EXPECT_LT(difference, 1e-8);
    // The table reaches the neighbour teeth (-1 .. 1 read from -1 .. 1: offsets up to 2), whose
    // coupling a clamped-cut sector would miss: it is not small.
    EXPECT_GT(std::abs(b(0, b.cols() - 1)), 1e-3 * b.cwiseAbs().maxCoeff());
  }
} // namespace

TEST(CyclicGearBody, TwoDimensionalTableEqualsTheAssembledFullGear)
{
  expect_cyclic_equals_assembled_full_gear<2>();
}

TEST(CyclicGearBody, ThreeDimensionalTableEqualsTheAssembledFullGear)
{
  expect_cyclic_equals_assembled_full_gear<3>();
}

// The same for a helical gear (beta = 20 deg, right hand): its sector is twisted along the face,
// its cut faces are helicoids that one pitch's turn still maps onto each other node for node, and
// its flank table (loads and readings on the helical flanks of teeth -1 .. 1) equals the full
// gear's meshed whole from the same twisted sector, to the same 1e-8.
TEST(CyclicGearBody, HelicalTableEqualsTheAssembledFullGear)
{
  expect_cyclic_equals_assembled_full_gear<3>(20.0);
}

// A load on every tooth weighted cos(k0 s theta) is harmonic k0 alone: its condensed loads have
// no other harmonic (to round-off relative to the largest), and the gear's response computed from
// harmonic k0 alone equals the response from all harmonics on every tooth asked for. A sign or
// orientation error in the transform (w^k against w^-k, T against T^T) would put the response
// into harmonic N - k0 or mix the cosine and sine parts and fail the second check.
TEST(CyclicGearBody, APureHarmonicLoadExcitesOnlyThatHarmonic)
{
  const meshing::PairKinematics kin(small_pair(20.0));
  const auto                    msh = sector_mesh(kin, 2, "harmonic");
  dealii::Triangulation<2>      sector;
  fem::read_gmsh_mesh(msh.string(), sector);
  std::filesystem::remove(msh);
  const auto cyclic_ptr = cyclic_body(sector, kin.pinion().n_teeth());
  auto      &cyclic     = *cyclic_ptr;
  cyclic.run();

  const auto s = table_settings(kin.pinion(), 2);
  const fem::TabulatedFlankCompliance<2> table(cyclic, kin.pinion(), 0, s);
  const auto load = table.patch_load({0, 0.5 * (s.roll_min_mm + s.roll_max_mm), 0.0});
  const int  N    = kin.pinion().n_teeth();
  for (const int k0 : {0, 1, 4, N / 2})
    {
      fem::CyclicGearBody<2>::SectorLoads pattern;
      for (int t = 0; t < N; ++t)
        {
          pattern.loads[t]  = {load};
          pattern.forces[t] = {std::cos(2.0 * M_PI * k0 * t / N)};
        }
      const auto condensed = cyclic.condense({pattern});
      const auto norms     = cyclic.harmonic_norms(condensed.q);
      const double largest = *std::max_element(norms.begin(), norms.end());
      for (int k = 0; k <= N / 2; ++k)
        if (k != k0)
          {
            EXPECT_LT(norms[k], 1e-12 * largest) << "load harmonic " << k0 << " shows in harmonic " << k;
          }
      EXPECT_GT(norms[k0], 0.1 * largest);

      const std::vector<int> teeth{0, 1, 3, N - 2};
      const auto all  = cyclic.sector_fields(condensed, teeth).front();
      const auto only = cyclic.sector_fields(condensed, teeth, k0).front();
      for (const int t : teeth)
        {
          auto difference = all.at(t);
          difference -= only.at(t);
          EXPECT_LT(difference.linfty_norm(), 1e-9 * all.at(t).linfty_norm())
            << "harmonic " << k0 << ", tooth " << t;
        }
    }
}

// A sector whose end cut is not its start cut turned by one pitch (here: the mesh of a gear with
// more teeth than the model is told) cannot be tied: an input error that says so, naming the gear.
TEST(CyclicGearBody, RefusesCutFacesThatDoNotMatch)
{
  const meshing::PairKinematics kin(small_pair(20.0));
  const auto                    msh = sector_mesh(kin, 2, "mismatch");
  dealii::Triangulation<2>      sector;
  fem::read_gmsh_mesh(msh.string(), sector);
  std::filesystem::remove(msh);
  typename fem::CyclicGearBody<2>::Parameters cp;
  cp.body    = body_parameters<2>();
  cp.n_teeth = static_cast<unsigned int>(kin.pinion().n_teeth() + 1);
  cp.name    = "pinion";
  const auto cyclic = std::make_unique<fem::CyclicGearBody<2>>(sector, cp);
  try
    {
      cyclic->run();
      FAIL() << "a sector of the wrong angle was accepted";
    }
  catch (const InputError &e)
    {
      EXPECT_NE(std::string(e.what()).find("pinion: the cut faces of the sector mesh do not match"),
                std::string::npos)
        << e.what();
    }
}

// Requirement: the cyclic harmonics may be shared between processes (each factorises the
// harmonics k = rank, rank + P, ... and the cut displacements are summed): the table is the one
// process computes alone. Both contenders run the same LAPACK kernels on the same matrices; only
// the order of the final sum differs, so 1e-12 relative. Run by ctest under mpirun -np 2
// (fem.cyclic_gear_body_mpi2).
TEST(CyclicGearBodyMpi, HarmonicsSharedByTwoRanksGiveTheTableOfOne)
{
  const meshing::PairKinematics kin(small_pair(20.0));
  const unsigned int            rank = dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD);
  const auto msh = sector_mesh(kin, 2, "shared_r" + std::to_string(rank));
  dealii::Triangulation<2> sector; // serial, on every rank
  fem::read_gmsh_mesh(msh.string(), sector);
  std::filesystem::remove(msh);
  const auto s = table_settings(kin.pinion(), 2);
  Eigen::MatrixXd tables[2];
  for (const int shared : {0, 1})
    {
      const auto cyclic = cyclic_body(sector, kin.pinion().n_teeth(), shared ? MPI_COMM_WORLD : MPI_COMM_SELF);
      cyclic->run();
      tables[shared] = fem::TabulatedFlankCompliance<2>(*cyclic, kin.pinion(), 0, s).matrix();
    }
  const double difference = (tables[1] - tables[0]).cwiseAbs().maxCoeff() / tables[0].cwiseAbs().maxCoeff();
  EXPECT_LT(difference, 1e-12) << "rank " << rank;
}

namespace
{
  // On rank 0: the pinion's flank table of the small pair's full gear (level 2), built with the
  // parameters that `configure` sets, twice (variant 0 and 1); the largest difference of the
  // second from the first, relative to the first's largest entry.
  double pinion_table_difference(const std::string &name,
                                 const std::function<void(int, fem::CyclicGearBody<2>::Parameters &)> &configure)
  {
    const meshing::PairKinematics kin(small_pair(20.0));
    const auto                    s   = table_settings(kin.pinion(), 2);
    const auto                    msh = sector_mesh(kin, 2, name);
    dealii::Triangulation<2>      sector;
    fem::read_gmsh_mesh(msh.string(), sector);
    std::filesystem::remove(msh);
    Eigen::MatrixXd tables[2];
    for (const int variant : {0, 1})
      {
        typename fem::CyclicGearBody<2>::Parameters cp;
        cp.body    = body_parameters<2>();
        cp.n_teeth = static_cast<unsigned int>(kin.pinion().n_teeth());
        configure(variant, cp);
        fem::CyclicGearBody<2> cyclic(sector, cp);
        cyclic.set_load_boundary_ids({meshing::physical_tag::drive_flank});
        cyclic.run();
        tables[variant] = fem::TabulatedFlankCompliance<2>(cyclic, kin.pinion(), 0, s).matrix();
      }
    return (tables[1] - tables[0]).cwiseAbs().maxCoeff() / tables[0].cwiseAbs().maxCoeff();
  }
} // namespace

TEST(HarmonicSharing, SharesLevelTheWorkOfTheGroupAndTheFreeHelpers)
{
  // Requirement (fem/harmonic_sharing.h, work_levelling_shares): the owner of a body gives free
  // helpers the shares of its remaining harmonics that make every process's work come out even.
  // The expected shares are the closed form of the level L = (remaining work + the levels below
  // it) / (their number), counted in harmonics of 1 s.
  // Equal work so far: an equal share each (12 harmonics over a group of two and one helper).
  EXPECT_EQ(fem::work_levelling_shares(12, 1.0, {10, 10}, {10}), std::vector<int>({4}));
  // A helper that has done less work takes more: levels 20 | 10, 12 and 10 harmonics give
  // L = (10 + 10 + 12) / 2 = 16, shares 6 and 4; the group keeps one, so the larger is cut to 5.
  EXPECT_EQ(fem::work_levelling_shares(10, 1.0, {20}, {10, 12}), std::vector<int>({5, 4}));
  // A helper already above the level takes none (levels 10, 10 | 13 and 4 harmonics: L = 12).
  EXPECT_EQ(fem::work_levelling_shares(4, 1.0, {10, 10}, {13}), std::vector<int>({0}));
  // Costs in any unit: 2.5 s per harmonic, levels 0 | 5 and 8 harmonics: L = (20 + 5) / 2 = 12.5,
  // the helper's share (12.5 - 5) / 2.5 = 3.
  EXPECT_EQ(fem::work_levelling_shares(8, 2.5, {0}, {5}), std::vector<int>({3}));
  // Without a measured cost, or with fewer than two harmonics left, nothing is lent.
  EXPECT_EQ(fem::work_levelling_shares(12, 0.0, {10}, {0, 0}), std::vector<int>({0, 0}));
  EXPECT_EQ(fem::work_levelling_shares(1, 1.0, {10}, {0}), std::vector<int>({0}));
  // Many idle helpers and few harmonics: never more than todo - 1 in all.
  const auto many = fem::work_levelling_shares(3, 1.0, {50}, {0, 0, 0, 0});
  EXPECT_EQ(std::accumulate(many.begin(), many.end(), 0), 2);
}

TEST(CyclicGearBodyMpi, HarmonicsSolvedByAHelperWithoutTheSectorGiveTheTableOfOne)
{
  // Requirement (fem/harmonic_sharing.h): a rank that holds no sector takes cyclic harmonics the
  // owner has not started. Rank 0 builds the body and tabulates it with rank 1 as its helper,
  // which says it is free at once, so it gets a share of the harmonics as soon as the owner
  // reaches them; the table equals rank 0's table built alone. Only the order of the harmonics'
  // sums differs: 1e-12 relative, as for the harmonics shared by a communicator. Rank 1 reports
  // the harmonics it solved. Both ranks report no work of their own (the process CPU time of
  // earlier tests, busy waits in MPI included, would decide the shares otherwise), so the owner
  // levels them by the harmonics alone and gives the helper half of those left after its first.
  // Run under mpirun -np 2 (fem.cyclic_gear_body_mpi2).
  const int size = static_cast<int>(dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD));
  if (size != 2)
    GTEST_SKIP() << "needs two ranks";
  const int rank = static_cast<int>(dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD));
  fem::HarmonicSharing sharing(MPI_COMM_WORLD, {0}, {{1}}, {}, [] { return 0.0; });
  if (rank == 0)
    {
      EXPECT_LT(pinion_table_difference("helped_r0",
                                      [&sharing](const int helped, fem::CyclicGearBody<2>::Parameters &cp) {
                                        if (helped)
                                          cp.harmonic_sharing = [&sharing] { return &sharing; };
                                      }),
                1e-12);
    }
  sharing.finish();
  if (rank == 1)
    {
      ASSERT_EQ(sharing.harmonics_helped().count(0), 1u);
      EXPECT_GT(sharing.harmonics_helped().at(0), 0);
    }
}

TEST(CyclicGearBodyMpi, ASectorFactorisedByAGroupGivesTheTableOfOne)
{
  // Requirement (fem/sector_group.h): a full gear built by a group of ranks, rank 0 holding the
  // sector and rank 1 nothing but its share of MUMPS's factors, D and E, gives the table of rank 0
  // built alone. The factorisation over two processes uses the ordering of one; its fronts'
  // contributions and the harmonics' sums run in another order, so the tables agree to round-off:
  // 1e-12 relative, as for the harmonics shared by a communicator. Run under mpirun -np 2
  // (fem.cyclic_gear_body_mpi2).
  const int size = static_cast<int>(dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD));
  if (size != 2)
    GTEST_SKIP() << "needs two ranks";
  const int rank = static_cast<int>(dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD));
  if (rank == 0)
    {
      std::unique_ptr<fem::SectorGroup> group;
      EXPECT_LT(pinion_table_difference("group_r0",
                                        [&group](const int grouped, fem::CyclicGearBody<2>::Parameters &cp) {
                                          group = std::make_unique<fem::SectorGroup>(grouped ? MPI_COMM_WORLD :
                                                                                               MPI_COMM_SELF);
                                          cp.sector_group = group.get();
                                        }),
                1e-12);
    }
  else
    EXPECT_GT(fem::serve_sector_group(MPI_COMM_WORLD), 0.0) << "rank 1 worked for the group";
}
