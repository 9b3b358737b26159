// Requirements on the contact stage for helical pairs (contact/mesh_cycle.h, docs/theory-tca.md
// "Helical pairs on the contact grid"): a spur pair's results unchanged, the band of every face
// column on its pair's inclined contact line (a straight line of the flank), the balance of the normal force on the flank's
// area, the loaded contact length following the kinematic contact lines over the cycle, the limit
// of a vanishing helix angle, and the mirror symmetry of the two hands. Rigid bodies only (the
// local half-space part, or the half-space as the body), so that each answer has an independent
// reference.
#include "contact/half_space_flank_compliance.h"
#include "contact/mesh_cycle.h"
#include "meshing/flank_surface.h"
#include "meshing/pair_kinematics.h"
#include "tests/support/spur_pair.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <utility>
#include <vector>

using namespace hertzgear;
using namespace hertzgear::contact;

namespace
{
  const Material steel{206000.0, 0.3};

  // The paper's pair (23/34 teeth, m_n = 3 mm, 20 deg, b = 20 mm) with helix angle beta, the
  // pinion of the given hand and the gear of the other.
  meshing::PairParameters helical_pair(const double beta_rad,
                                       const meshing::HelixHand pinion_hand = meshing::HelixHand::right,
                                       const double crowning_mm = 0)
  {
    meshing::PairParameters p = hertzgear::testing::spur_pair({23, 34, 20.0, crowning_mm});
    p.pinion.helix_angle_rad  = beta_rad;
    p.gear.helix_angle_rad    = beta_rad;
    p.pinion.hand             = pinion_hand;
    p.gear.hand = pinion_hand == meshing::HelixHand::right ? meshing::HelixHand::left : meshing::HelixHand::right;
    return p;
  }

  constexpr double deg = M_PI / 180.0;

  // The paper's nominal torque 210 N m as the load along the (transverse) line of action,
  // T_1 / r_b1, the measure MeshCycle takes.
  double nominal_load_N(const meshing::PairKinematics &kin)
  {
    return 210.0e3 / kin.pinion().base_radius_mm();
  }

  // The loaded cells of a position grouped by face column: (pair, z) -> indices of its cells.
  std::map<std::pair<int, double>, std::vector<std::size_t>> columns_of(const PositionResult &p)
  {
    std::map<std::pair<int, double>, std::vector<std::size_t>> columns;
    for (std::size_t k = 0; k < p.cell_pair.size(); ++k)
      columns[{p.cell_pair[k], p.cell_z_mm[k]}].push_back(k);
    return columns;
  }
} // namespace

// Requirement: a helical pair's terms (cos(beta_b) factors, inclined lines, developed offsets) leave
// a spur pair's results as they were: the golden values below were recorded with the spur-only
// contact stage (crowned pair with tip relief and misalignment, 3D, 12 x 8 cells, whole face), for
// STE, unloaded STE, tangent stiffness, Hertzian penetration, the first pair's load share and face
// semi-axis and the contact centre, and for the kinematics' gap, rigid approach and separation
// (the Hertzian penetration as read about the loaded cell of largest local displacement, the
// contact stage's reading; docs/theory-tca.md). The build that made them reproduces them bit for bit; 1e-12
// relative leaves room for another compiler's or optimisation level's rounding in the contact
// solve (Eigen's reductions), far below any physical effect (the helical terms are factors
// cos(beta_b) and slopes that are exactly 1 and 0 here).
TEST(HelicalContact, SpurPairKeepsItsGoldenResults)
{
  auto p                        = hertzgear::testing::spur_pair({23, 34, 20.0, 0.02});
  p.pinion.tip_relief_mm        = 0.015;
  p.pinion.tip_relief_length_mm = 4.0;
  p.mesh_misalignment_mm        = 0.01;
  const meshing::PairKinematics kin(p);
  EXPECT_EQ(kin.cos_base_helix(), 1.0);
  EXPECT_EQ(kin.contact_line_slope(), 0.0);
  const RigidFlankCompliance rigid(0.5);
  MeshCycleSettings          settings;
  settings.profile_cells = 12;
  settings.face_cells    = 8;
  settings.face_extent   = MeshCycleSettings::FaceExtent::face_width; // as recorded
  const MeshCycle cycle(kin, steel, steel, rigid, rigid, settings);
  const double    golden[3][7] = {
    {0x1.90fc016157c9dp-8, 0x1.145a79792d37ep-12, 0x1.afd8bcea978a5p+20, 0x1.9008b73333caap-8,
     0x1.5ce7de718b813p-2, 0x1.fae5c7fa08ec4p+1, -0x1.6687e5c95e1cfp-1},
    {0x1.d26eb89af52a1p-8, 0x1.73ef6f8d55106p-12, 0x1.dc8abe9920a18p+20, 0x1.a12546e2c1d32p-8,
     0x1.85f5ce48a3129p-1, 0x1.faf8045a4f6c5p+1, -0x1.5ff6bd49de976p-1},
    {0x1.036dc2ab01023p-7, 0x1.27ff732650ccep-12, 0x1.99e2599716fc6p+20, 0x1.087991269ebd1p-7,
     0x1p+0, 0x1.0a95c1a2942f7p+2, -0x1.894d5d4204647p-1}};
  const double taus[3] = {0.0, 0.3, 0.7};
  for (int i = 0; i < 3; ++i)
    {
      const auto   r = cycle.solve_position(taus[i], nominal_load_N(kin));
      const double got[7] = {r.ste_mm, r.unloaded_ste_mm, r.k_total_tangent_N_per_mm,
                             r.hertz_penetration_mm, r.pairs[0].load_share, r.pairs[0].contact_b_mm,
                             r.contact_centre_z_mm};
      for (int q = 0; q < 7; ++q)
        EXPECT_NEAR(got[q], golden[i][q], 1e-12 * std::abs(golden[i][q])) << "tau " << taus[i] << " quantity " << q;
    }
  EXPECT_NEAR(kin.unloaded_gap_mm(0, 0.3, 20.0, 3.0), 0x1.036957780c8ecp+1, 1e-15 * 2.03);
  EXPECT_NEAR(kin.rigid_approach_mm(0.3), -0x1.47ae147ae147bp-13, 1e-15);
  EXPECT_NEAR(kin.separation_mm(1, 0.7, 28.0, -6.0), 0x1.2dfd05dd68ff1p+8, 1e-15 * 302);
}

// Requirement: the band centres of a pair's face columns, s_j(tau) + slope z on the pinion flank,
// lie on one straight generator of the helicoid (the contact line on the flank), which in the
// developed flank runs straight along the face: between the centres of any two columns the
// developed offset (FlankSurface::developed_offset_mm) has no component across the profile and the
// length (z_2 - z_1) / cos(beta_b), which is also their 3D distance. The columns shifted along the
// profile therefore form a regular band across the line in the developed flank, the premise of
// cells of one size du x dz / cos(beta_b) on a helical grid (docs/theory-tca.md). Both hands;
// tolerances: rounding of coordinates of order 50 mm, 1e-12 mm.
TEST(HelicalContact, ColumnCentresLieOnAStraightLineOfTheFlank)
{
  for (const auto hand : {meshing::HelixHand::right, meshing::HelixHand::left})
    {
      const meshing::PairKinematics kin(helical_pair(15 * deg, hand));
      const meshing::FlankSurface   flank  = kin.pinion().flank();
      const double                  cos_bb = kin.cos_base_helix();
      for (const double tau : {0.1, 0.6})
        for (const int j : kin.pairs_in_contact(tau))
          for (const double z1 : {-10.0, -3.0})
            for (const double z2 : {-2.5, 4.0, 10.0})
              {
                const meshing::FlankPoint a{j, kin.contact_roll_distance_mm(j, tau, z2), z2};
                const meshing::FlankPoint b{j, kin.contact_roll_distance_mm(j, tau, z1), z1};
                const Eigen::Vector2d     d = flank.developed_offset_mm(a, b);
                EXPECT_NEAR(d.x(), 0.0, 1e-12) << "tau " << tau << " pair " << j;
                EXPECT_NEAR(d.y(), (z2 - z1) / cos_bb, 1e-12);
                const double chord = (flank.point(a.roll_mm, z2) - flank.point(b.roll_mm, z1)).norm();
                EXPECT_NEAR(chord, (z2 - z1) / cos_bb, 1e-12);
              }
    }
}

// Requirements, helical pair (15 deg) with rigid bodies, the local half-space part alone
// (RigidFlankCompliance) and the half-space as the body (HalfSpaceFlankCompliance, cells of the
// flank's size du x dz / cos(beta_b)):
//  - the contact problem balances the normal force on the flanks: sum p A over all cells is
//    F / cos(beta_b) for the load F along the transverse line of action (1e-10 relative: the
//    solver enforces the balance exactly, round-off of a sum over ~1e3 cells), the load shares
//    sum to 1 and the pair forces to F;
//  - every face column centres its band on its pair's inclined contact line: the cells' pinion
//    roll at u = 0 is s_j(tau) + slope z (1e-12 mm: the exact inverse of the involute arc length);
//  - the loaded cells of a column straddle that line (loaded cells on both sides) and the
//    pressure-weighted mean offset from it is below half a cell (a Hertz strip is centred on its
//    line; the involute's change of curvature across the strip shifts it by far less), where the
//    line lies inside the path of contact by more than the band (away from the tips);
//  - no load off the path of contact: columns whose line lies beyond s_A or s_E carry none.
TEST(HelicalContact, LoadIsBalancedOnTheFlanksAndStraddlesTheInclinedLines)
{
  const meshing::PairKinematics kin(helical_pair(15 * deg));
  const double                  cos_bb = kin.cos_base_helix();
  ASSERT_LT(cos_bb, 0.98);
  const double s_A = kin.point('A').roll_distance_mm, s_E = kin.point('E').roll_distance_mm;
  MeshCycleSettings settings;
  settings.profile_cells = 16;
  settings.face_cells    = 12;
  const double F  = nominal_load_N(kin);
  const RigidFlankCompliance rigid(0.5);
  const double w  = MeshCycle(kin, steel, steel, rigid, rigid, settings).band_half_width(F);
  const double du = 2 * w / settings.profile_cells, dz = kin.face_width_mm() / settings.face_cells;
  const HalfSpaceFlankCompliance pinion_body(steel, 0.5, kin.pinion().flank(), 0.5 * du, 0.5 * dz / cos_bb);
  const HalfSpaceFlankCompliance gear_body(steel, 0.5, kin.gear().flank(), 0.5 * du, 0.5 * dz / cos_bb);
  const FlankCompliance *bodies[2][2] = {{&rigid, &rigid}, {&pinion_body, &gear_body}};
  for (const auto &body : bodies)
    {
      const MeshCycle cycle(kin, steel, steel, *body[0], *body[1], settings);
      int             n_straddling = 0;
      for (const double tau : {0.1, 0.35, 0.6, 0.85})
        {
          const auto p   = cycle.solve_position(tau, F);
          double     sum = 0, shares = 0, forces = 0;
          for (std::size_t k = 0; k < p.cell_pressure_MPa.size(); ++k)
            {
              EXPECT_NEAR(p.cell_area_mm2[k], du * dz / cos_bb, 1e-12 * du * dz);
              sum += p.cell_pressure_MPa[k] * p.cell_area_mm2[k];
            }
          for (const auto &pair : p.pairs)
            {
              shares += pair.load_share;
              forces += pair.force_N;
            }
          EXPECT_NEAR(sum, F / cos_bb, 1e-10 * F) << "tau " << tau;
          EXPECT_NEAR(shares, 1.0, 1e-10);
          EXPECT_NEAR(forces, F, 1e-10 * F);
          for (const auto &[key, cells] : columns_of(p))
            {
              const auto [pair, z] = key;
              const double line    = kin.contact_roll_distance_mm(pair, tau, z);
              double       load = 0, moment = 0;
              bool         before = false, after = false;
              for (const std::size_t k : cells)
                {
                  // The pinion roll of a cell at u is sqrt(line^2 + 2 r_b1 u).
                  const double s2 = line * line + 2 * kin.pinion().base_radius_mm() * p.cell_u_mm[k];
                  if (s2 > 0)
                    {
                      EXPECT_NEAR(p.cell_pinion_roll_mm[k], std::sqrt(s2), 1e-12 * line);
                    }
                  if (p.cell_pressure_MPa[k] > 0)
                    {
                      load += p.cell_pressure_MPa[k];
                      moment += p.cell_pressure_MPa[k] * p.cell_u_mm[k];
                      before = before || p.cell_u_mm[k] < 0;
                      after  = after || p.cell_u_mm[k] > 0;
                    }
                }
              if (line < s_A - 1e-12 || line > s_E + 1e-12)
                EXPECT_EQ(load, 0.0) << "tau " << tau << " pair " << pair << " z " << z;
              else if (line > s_A + w && line < s_E - w)
                {
                  EXPECT_TRUE(before && after) << "tau " << tau << " pair " << pair << " z " << z;
                  ASSERT_GT(load, 0.0);
                  EXPECT_LT(std::abs(moment / load), 0.5 * du) << "tau " << tau << " pair " << pair << " z " << z;
                  ++n_straddling;
                }
            }
        }
      EXPECT_GT(n_straddling, 40);
    }
}

// Requirement: the loaded contact of an unmodified helical pair lies along its contact lines:
// the total loaded length over the face, the number of face columns that carry load times their
// length on the flank dz / cos(beta_b), follows PairKinematics::contact_line_length_mm(tau) over
// the cycle, including its variation (the lines' ends entering and leaving the field of action;
// for this pair between about 25 and 41 mm). Tolerance from the cell size: a column carries load
// where its centre's line lies on the path of contact, so each end of a line inside the face is
// resolved to half a column, dz / (2 cos(beta_b)) per end; the ends at the face edges are exact.
TEST(HelicalContact, LoadedContactLengthFollowsTheContactLinesOverTheCycle)
{
  const meshing::PairKinematics kin(helical_pair(15 * deg));
  const double                  cos_bb = kin.cos_base_helix();
  const double s_A = kin.point('A').roll_distance_mm, s_E = kin.point('E').roll_distance_mm;
  const double half = 0.5 * kin.face_width_mm(), slope = kin.contact_line_slope();
  MeshCycleSettings settings;
  settings.profile_cells = 12;
  settings.face_cells    = 24;
  const double               dz = kin.face_width_mm() / settings.face_cells;
  const RigidFlankCompliance rigid(0.5);
  const MeshCycle            cycle(kin, steel, steel, rigid, rigid, settings);
  double                     lo_grid = 1e300, hi_grid = 0, lo_kin = 1e300, hi_kin = 0;
  for (int i = 0; i < 12; ++i)
    {
      const double tau = (i + 0.5) / 12;
      const auto   p   = cycle.solve_position(tau, nominal_load_N(kin));
      int          loaded_columns = 0;
      for (const auto &[key, cells] : columns_of(p))
        {
          bool loaded = false;
          for (const std::size_t k : cells)
            loaded = loaded || p.cell_pressure_MPa[k] > 0;
          loaded_columns += loaded;
        }
      const double length = loaded_columns * dz / cos_bb;
      const double exact  = kin.contact_line_length_mm(tau);
      // Ends of lines inside the face: where s_j + slope z crosses s_A or s_E for |z| < b/2.
      int n_ends = 0;
      for (const int j : kin.pairs_in_contact(tau))
        for (const double s_end : {s_A, s_E})
          n_ends += std::abs((s_end - kin.contact_roll_distance_mm(j, tau)) / slope) < half;
      EXPECT_NEAR(length, exact, n_ends * 0.5 * dz / cos_bb + 1e-9) << "tau " << tau << ", " << n_ends << " ends";
      lo_grid = std::min(lo_grid, length);
      hi_grid = std::max(hi_grid, length);
      lo_kin  = std::min(lo_kin, exact);
      hi_kin  = std::max(hi_kin, exact);
    }
  std::cout << "loaded length " << lo_grid << " .. " << hi_grid << " mm, contact lines " << lo_kin
            << " .. " << hi_kin << " mm" << std::endl;
  // The variation is resolved: at least 10 % of the mean, and the grid's agrees with the lines'
  // within two ends per extreme.
  EXPECT_GT(hi_kin - lo_kin, 0.1 * 0.5 * (hi_kin + lo_kin));
  EXPECT_NEAR(hi_grid - lo_grid, hi_kin - lo_kin, 4 * 0.5 * dz / cos_bb);
}

// Requirement: the helical contact grid (band per column, developed offsets, area factor, normal
// load) tends to the spur grid as the helix angle vanishes: at beta = 1e-6 rad every result is the
// spur pair's within 1e-6 relative. What differs is of first order in beta: the contact lines'
// inclination moves the columns' band centres by tan(beta_b) |z| <= 1e-5 mm against a band of
// ~0.4 mm and curvatures of ~10 mm (relative effect ~1e-6 and below); cos(beta_b), the transverse
// module and the base radii differ from the spur ones at second order (1e-12). 1e-6 therefore
// checks that the helical code path (its local matrix from developed offsets in particular) is
// the spur path in the limit, not merely close (measured: at most 2e-9 relative).
TEST(HelicalContact, VanishingHelixAngleIsTheSpurPair)
{
  const meshing::PairKinematics spur(helical_pair(0.0, meshing::HelixHand::right, 0.02));
  const meshing::PairKinematics thin(helical_pair(1e-6, meshing::HelixHand::right, 0.02));
  ASSERT_NE(thin.contact_line_slope(), 0.0);
  const RigidFlankCompliance rigid(0.5);
  MeshCycleSettings          settings;
  settings.profile_cells = 12;
  settings.face_cells    = 8;
  // The whole face for both: the load face band is a spur construction (a helical pair's grid
  // always covers the whole face), so the limit is taken on the grid both pairs share.
  settings.face_extent = MeshCycleSettings::FaceExtent::face_width;
  const MeshCycle a(spur, steel, steel, rigid, rigid, settings);
  const MeshCycle b(thin, steel, steel, rigid, rigid, settings);
  for (const double tau : {0.2, 0.7})
    {
      const auto p = a.solve_position(tau, nominal_load_N(spur));
      const auto q = b.solve_position(tau, nominal_load_N(spur));
      ASSERT_EQ(p.pairs.size(), q.pairs.size());
      EXPECT_EQ(p.n_active, q.n_active);
      EXPECT_NEAR(q.approach_mm, p.approach_mm, 1e-6 * p.approach_mm) << "tau " << tau;
      EXPECT_NEAR(q.k_total_tangent_N_per_mm, p.k_total_tangent_N_per_mm, 1e-6 * p.k_total_tangent_N_per_mm);
      EXPECT_NEAR(q.hertz_penetration_mm, p.hertz_penetration_mm, 1e-6 * p.hertz_penetration_mm);
      for (std::size_t i = 0; i < p.pairs.size(); ++i)
        EXPECT_NEAR(q.pairs[i].load_share, p.pairs[i].load_share, 1e-6);
    }
}

// Requirement: a left-hand pinion / right-hand gear pair is the mirror image (z -> -z) of the
// right-hand pinion / left-hand gear pair, so with modifications symmetric in z (crowning, tip
// relief) both have the same approach, STE, stiffness and load shares at every mesh position,
// and the load centre along the face at -z. Tolerance: the mirrored grids are the same discrete
// problem up to the rounding of the cell coordinates (z_min + (i + 1/2) dz against its mirror),
// so the results agree to round-off of the contact solve, 1e-10 relative (measured: at most
// 3e-14 relative).
TEST(HelicalContact, LeftHandPairIsTheMirrorOfTheRightHandPair)
{
  for (const double crowning : {0.0, 0.02})
    {
      auto right = helical_pair(15 * deg, meshing::HelixHand::right, crowning);
      auto left  = helical_pair(15 * deg, meshing::HelixHand::left, crowning);
      for (auto *p : {&right, &left})
        {
          p->pinion.tip_relief_mm        = 0.01;
          p->pinion.tip_relief_length_mm = 3.0;
        }
      const meshing::PairKinematics kr(right), kl(left);
      const RigidFlankCompliance    rigid(0.5);
      MeshCycleSettings             settings;
      settings.profile_cells = 12;
      settings.face_cells    = 10;
      const MeshCycle cr(kr, steel, steel, rigid, rigid, settings);
      const MeshCycle cl(kl, steel, steel, rigid, rigid, settings);
      for (const double tau : {0.15, 0.5, 0.8})
        {
          const auto a = cr.solve_position(tau, nominal_load_N(kr));
          const auto b = cl.solve_position(tau, nominal_load_N(kl));
          EXPECT_NEAR(b.approach_mm, a.approach_mm, 1e-10 * a.approach_mm) << "tau " << tau;
          EXPECT_NEAR(b.ste_mm, a.ste_mm, 1e-10 * a.ste_mm);
          EXPECT_NEAR(b.k_total_tangent_N_per_mm, a.k_total_tangent_N_per_mm, 1e-10 * a.k_total_tangent_N_per_mm);
          EXPECT_NEAR(b.contact_centre_z_mm, -a.contact_centre_z_mm, 1e-10 * kr.face_width_mm());
          ASSERT_EQ(a.pairs.size(), b.pairs.size());
          for (std::size_t i = 0; i < a.pairs.size(); ++i)
            EXPECT_NEAR(b.pairs[i].load_share, a.pairs[i].load_share, 1e-10);
        }
    }
}
