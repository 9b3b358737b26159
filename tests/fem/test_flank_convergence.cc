// Requirement (issue 5): the FE global compliance of a gear body converges with refinement at
// the expected rate. The quantity is what the TCA tabulates: the displacement along the inward
// flank normal at a fixed depth below a fixed flank point, per unit normal force on a fixed patch
// there (TabulatedFlankCompliance), for the paper's pinion (2D plane strain, 5-tooth sector held
// at the bore and the cuts). The patch radius and the depth are those of level 0 at every level,
// so that only the discretisation changes: levels 0, 1, 2 (element size halved per level) of the
// gmsh mesh, Q1 and Q2.
#include "fem/elastic_body.h"
#include "fem/flank_compliance.h"
#include "meshing/gear_body_mesher.h"
#include "meshing/pair_kinematics.h"

#include <deal.II/grid/tria.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>

#include <unistd.h>

using namespace hertzgear;

namespace
{
  meshing::PairParameters paper_pair()
  {
    meshing::PairParameters p;
    for (auto *g : {&p.pinion, &p.gear})
      {
        g->module_mm          = 3.0;
        g->pressure_angle_rad = 20.0 * M_PI / 180.0;
        g->face_width_mm      = 20.0;
      }
    p.pinion.teeth          = 23;
    p.gear.teeth            = 34;
    p.pinion.bore_radius_mm = 15.0;
    p.gear.bore_radius_mm   = 20.0;
    p.pinion.name           = "pinion";
    p.gear.name             = "gear";
    p.backlash_loa_mm       = 0.1172;
    return p;
  }

  struct Sample
  {
    double      self = 0, cross = 0; // mm/N per mm of face (plane strain, unit thickness)
    std::size_t dofs = 0;
  };

  // The gmsh mesh of the pinion sector at a level, written once and read for both degrees.
  struct MeshedPinion
  {
    std::filesystem::path msh;
    int                   central = 0;
  };

  MeshedPinion mesh_pinion(const meshing::PairKinematics &kin, const unsigned int level)
  {
    meshing::MeshSettings m;
    m.dimension        = 2;
    m.teeth_per_sector = 5;
    m.refinement_level = static_cast<int>(level);
    MeshedPinion r;
    r.msh = std::filesystem::temp_directory_path() /
            ("hertzgear_flank_convergence_" + std::to_string(::getpid()) + "_L" +
             std::to_string(level) + ".msh");
    meshing::GearBodyMesher mesher;
    r.central = mesher.mesh(kin.pinion(), m, kin.point('A').radius_pinion_mm, r.msh).central_tooth;
    return r;
  }

  Sample flank_compliance(const meshing::PairKinematics &kin, const MeshedPinion &mesh,
                          const unsigned int degree)
  {
    const auto              &gear = kin.pinion();
    dealii::Triangulation<2> tria;
    fem::read_gmsh_mesh(mesh.msh.string(), tria);
    for (const auto &face : tria.active_face_iterators())
      if (face->at_boundary() && (face->boundary_id() == 11 || face->boundary_id() == 12))
        face->set_boundary_id(10); // sector cuts held like the bore, as the stiffness stage does
    fem::ElasticBody<2>::Parameters p;
    p.youngs_modulus      = 206000.0; // MPa, mm
    p.poisson_ratio       = 0.3;
    p.fe_degree           = degree;
    p.mapping_degree      = 1;
    p.clamped_boundary_id = 10;
    fem::ElasticBody<2> body(tria, p);
    body.set_load_boundary_ids({static_cast<dealii::types::boundary_id>(100 + mesh.central)});
    body.run();
    // Fixed load and reading: level-0 patch radius and depth, two flank nodes 1 mm apart around
    // the pitch point.
    const double h0 = meshing::MeshSettings{}.band_size_modules * gear.module_mm();
    fem::FlankTableSettings s;
    s.teeth  = {0};
    s.n_roll = 2;
    const double pitch_roll = std::sqrt(std::pow(gear.reference_radius_mm(), 2) -
                                        std::pow(gear.base_radius_mm(), 2));
    s.roll_min_mm        = pitch_roll - 0.5;
    s.roll_max_mm        = pitch_roll + 0.5;
    s.reference_depth_mm = 3.0 * h0;
    s.patch_radius_mm    = 1.5 * h0;
    const fem::TabulatedFlankCompliance<2> table(body, gear, mesh.central, s);
    return {table.matrix()(0, 0), table.matrix()(1, 0), body.n_dofs()};
  }
} // namespace

TEST(FlankCompliance, ConvergesWithRefinementAtTheExpectedRate)
{
  const meshing::PairKinematics kin(paper_pair());
  MeshedPinion                  meshes[3];
  for (unsigned int level = 0; level < 3; ++level)
    meshes[level] = mesh_pinion(kin, level);
  Sample c[2][3];
  for (const unsigned int degree : {1u, 2u})
    for (unsigned int level = 0; level < 3; ++level)
      c[degree - 1][level] = flank_compliance(kin, meshes[level], degree);
  for (const auto &m : meshes)
    std::filesystem::remove(m.msh);

  for (const auto member : {&Sample::self, &Sample::cross})
    {
      double order[2], extrapolated[2];
      for (unsigned int k = 0; k < 2; ++k)
        {
          const double d01 = c[k][1].*member - c[k][0].*member;
          const double d12 = c[k][2].*member - c[k][1].*member;
          // Monotone convergence: the differences keep their sign and shrink.
          EXPECT_GT(d01 * d12, 0.0) << "Q" << k + 1;
          EXPECT_LT(std::abs(d12), std::abs(d01)) << "Q" << k + 1;
          order[k]        = std::log2(d01 / d12);
          extrapolated[k] = c[k][2].*member + d12 / (std::pow(2.0, order[k]) - 1.0);
          std::cout << "    Q" << k + 1 << (member == &Sample::self ? " self " : " cross") << ": "
                    << c[k][0].*member << ", " << c[k][1].*member << ", " << c[k][2].*member
                    << " mm/N (DOFs " << c[k][0].dofs << ", " << c[k][1].dofs << ", "
                    << c[k][2].dofs << "), observed order " << order[k] << "\n";
        }
      // Q2: the expected order is 2, not 3. The cells are straight-sided (mapping degree 1, as in
      // the stiffness stage) on the curved flank, fillet and bore, an O(h^2) perturbation of the
      // domain that dominates Q2's O(h^3) pointwise error at a fixed interior point. The band
      // 1.6 .. 2.6 allows for the gmsh meshes not being nested (each level is a new mesh with
      // half the target sizes, so the error constant changes slightly from level to level).
      EXPECT_GT(order[1], 1.6);
      EXPECT_LT(order[1], 2.6);
      // Q1 at these levels is pre-asymptotic (the level-0 patch spans 1.5 elements; measured
      // orders 1.3 and 1.5 against the asymptotic 2): required is monotone convergence (above)
      // at an order of at least 1, and that Q1 and Q2 converge to the same compliance: their
      // extrapolated values agree to 0.5 %, while Q1 at level 0 is still 2 % off.
      EXPECT_GT(order[0], 1.0);
      EXPECT_NEAR(extrapolated[0] / extrapolated[1], 1.0, 5e-3);
    }
}
