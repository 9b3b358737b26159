// Requirements on the flank surface (meshing/flank_surface.h): for a spur gear it is exactly the
// transverse involute extruded along the axis, the same numbers as the spur expressions it
// replaces; for a helical gear it is the involute helicoid, checked against its definition
// (sections turned by z tan(beta) / r, ISO 21771) and against finite differences of itself.
#include "meshing/flank_surface.h"
#include "meshing/gear_geometry.h"
#include "meshing/involute.h"
#include "meshing/pair_kinematics.h"

#include "common/errors.h"
#include "common/material.h"
#include "contact/mesh_cycle.h"
#include "stiffness/iso6336.h"
#include "stiffness/registry.h"
#include "tests/support/spur_pair.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

using namespace hertzgear::meshing;

namespace
{
  constexpr double pi  = 3.14159265358979323846;
  const double     eps = std::numeric_limits<double>::epsilon();

  // The paper's pinion (z = 23, m = 3, alpha = 20 deg, b = 20) with every micro-geometry term
  // switched on, so that the modified flank differs from the nominal one everywhere.
  GearParameters pinion(const double helix_angle_rad = 0, const HelixHand hand = HelixHand::right)
  {
    GearParameters g            = hertzgear::testing::spur_pair().pinion;
    g.helix_angle_rad           = helix_angle_rad;
    g.hand                      = hand;
    g.crowning_mm               = 0.01;
    g.tip_relief_mm             = 0.008;
    g.tip_relief_length_mm      = 1.5;
    g.helix_slope_deviation_mm  = 0.004;
    g.lead_end_relief_mm        = 0.003;
    g.lead_end_relief_length_mm = 2;
    g.profile_crowning_mm       = 0.002;
    g.root_relief_mm            = 0.003;
    g.root_relief_length_mm     = 1;
    return g;
  }

  // Roll distances over the whole involute flank (form to tip) and face positions over the face.
  std::vector<double> rolls(const GearGeometry &g, const unsigned int n = 17)
  {
    std::vector<double> v;
    const double        lo = g.base_radius_mm() * g.form_roll_angle();
    const double        hi = g.base_radius_mm() * g.tip_roll_angle();
    for (unsigned int i = 0; i < n; ++i)
      v.push_back(lo + (hi - lo) * i / (n - 1.0));
    return v;
  }
  const std::vector<double> faces{-10, -9.3, -4.1, -0.5, 0, 1.7, 6.25, 8.9, 10};

  Eigen::Vector2d xy(const Eigen::Vector3d &v) { return v.head<2>(); }
} // namespace

// Requirement: a spur flank surface gives the numbers of the spur code it replaces, to the last
// bit (EXPECT_EQ, no tolerance): the transverse involute point and normal at every face position,
// a normal without axial component, the modified point as the old patch load computed it
// (p -= Delta n), the transverse removal equal to the normal one, and the developed offset
// ((s_a^2 - s_b^2) / (2 r_b), z_a - z_b) of the former contact::developed_offset_mm. Also the
// radii and the base pitch of the spur formulas (no helix conversion at beta = 0).
TEST(FlankSurface, SpurIsTheExtrudedInvoluteBitForBit)
{
  const GearParameters p = pinion();
  const GearGeometry   g(p);
  const FlankSurface   f = g.flank();
  const double         r_b = g.base_radius_mm();
  EXPECT_EQ(g.reference_radius_mm(), 0.5 * p.module_mm * p.teeth);
  EXPECT_EQ(g.base_radius_mm(), 0.5 * p.module_mm * p.teeth * std::cos(p.pressure_angle_rad));
  EXPECT_EQ(g.base_pitch_mm(), pi * p.module_mm * std::cos(p.pressure_angle_rad));
  EXPECT_EQ(g.transverse_pressure_angle_rad(), p.pressure_angle_rad);
  EXPECT_EQ(f.base_helix_angle_rad(), 0.0);
  EXPECT_EQ(f.cos_base_helix(), 1.0);
  for (const double z : faces)
    EXPECT_EQ(f.section_angle_rad(z), 0.0);

  for (const double s : rolls(g))
    for (const double z : faces)
      {
        const Eigen::Vector2d p_t = g.involute_point(s / r_b);
        const Eigen::Vector2d n_t = g.involute_normal(s / r_b);
        const Eigen::Vector3d x   = f.point(s, z);
        const Eigen::Vector3d n   = f.normal(s, z);
        EXPECT_EQ(x.x(), p_t.x());
        EXPECT_EQ(x.y(), p_t.y());
        EXPECT_EQ(x.z(), z);
        EXPECT_EQ(n.x(), n_t.x());
        EXPECT_EQ(n.y(), n_t.y());
        EXPECT_EQ(n.z(), 0.0);
        EXPECT_FALSE(std::signbit(n.z()));
        Eigen::Vector2d m_t = p_t;
        m_t -= g.modification_mm(s, z) * n_t;
        const Eigen::Vector3d m = f.modified_point(s, z);
        EXPECT_EQ(m.x(), m_t.x());
        EXPECT_EQ(m.y(), m_t.y());
        EXPECT_EQ(m.z(), z);
        EXPECT_EQ(f.modification_mm(s, z), g.modification_mm(s, z));
        EXPECT_EQ(f.transverse_removal_mm(s, z), g.modification_mm(s, z));
        EXPECT_EQ(f.lead_modification_mm(z), g.lead_modification_mm(z));
        EXPECT_EQ(f.profile_modification_mm(s), g.profile_modification_mm(s));
        for (const double s_b : rolls(g, 5))
          for (const double z_b : {-8.0, 0.0, 3.3})
            {
              const FlankPoint      a{1, s, z}, b{1, s_b, z_b};
              const Eigen::Vector2d d = f.developed_offset_mm(a, b);
              EXPECT_EQ(d.x(), (a.roll_mm * a.roll_mm - b.roll_mm * b.roll_mm) / (2.0 * r_b));
              EXPECT_EQ(d.y(), a.z_mm - b.z_mm);
            }
      }
}

namespace
{
  // Transverse quantities by hand (ISO 21771:2007, 4.3), not through GearGeometry's code.
  struct Transverse
  {
    double r, r_b, alpha_t, beta_b;
  };
  Transverse transverse(const GearParameters &p)
  {
    const double m_t     = p.module_mm / std::cos(p.helix_angle_rad);
    const double alpha_t = std::atan(std::tan(p.pressure_angle_rad) / std::cos(p.helix_angle_rad));
    const double r       = 0.5 * m_t * p.teeth;
    return {r, r * std::cos(alpha_t), alpha_t,
            std::atan(std::tan(p.helix_angle_rad) * std::cos(alpha_t))};
  }
  double hand_sign(const HelixHand h) { return h == HelixHand::right ? 1.0 : -1.0; }
  double wrap(const double a) { return std::remainder(a, 2 * pi); }
} // namespace

// Requirement: a helical gear's transverse section (radii, base helix angle) follows ISO 21771
// (m_t = m_n / cos(beta), tan(alpha_t) = tan(alpha_n) / cos(beta), tan(beta_b) = tan(beta)
// cos(alpha_t)), and the flank surface is the involute helicoid: the section at face position z
// is the involute of the section z = 0 (polar angle flank_polar_angle_rad(radius) at radius
// r_b sqrt(1 + u^2)) turned by psi(z) = +-z tan(beta) / r (+ right hand). The closed forms differ
// from the code's formulas (atan/tan against asin/sin, the turn composed with the section) only
// by rounding: a few ulps of the radius (~40 mm) and of angles of order 1, hence 1e-12 (mm, rad).
TEST(FlankSurface, HelicalSectionsAreTheTurnedInvolute)
{
  for (const HelixHand hand : {HelixHand::right, HelixHand::left})
    {
      const GearParameters p = pinion(15 * pi / 180, hand);
      const GearGeometry   g(p);
      const FlankSurface   f = g.flank();
      const Transverse     t = transverse(p);
      const double         h = hand_sign(hand);
      EXPECT_NEAR(g.reference_radius_mm(), t.r, 1e-12 * t.r);
      EXPECT_NEAR(g.base_radius_mm(), t.r_b, 1e-12 * t.r);
      EXPECT_NEAR(g.transverse_pressure_angle_rad(), t.alpha_t, 1e-14);
      EXPECT_NEAR(g.base_pitch_mm(), 2 * pi * t.r_b / p.teeth, 1e-12 * t.r);
      EXPECT_NEAR(std::tan(f.base_helix_angle_rad()), std::tan(p.helix_angle_rad) * std::cos(t.alpha_t),
                  8 * eps);
      EXPECT_NEAR(f.cos_base_helix(), std::cos(t.beta_b), 4 * eps);
      for (const double z : faces)
        EXPECT_NEAR(f.section_angle_rad(z), h * z * std::tan(p.helix_angle_rad) / t.r, 1e-15);

      for (const double s : rolls(g))
        for (const double z : faces)
          {
            const Eigen::Vector3d x      = f.point(s, z);
            const double          u      = s / t.r_b;
            const double          radius = t.r_b * std::sqrt(1 + u * u);
            EXPECT_EQ(x.z(), z);
            EXPECT_NEAR(xy(x).norm(), radius, 1e-12);
            const double expected = g.flank_polar_angle_rad(radius) + h * z * std::tan(p.helix_angle_rad) / t.r;
            EXPECT_NEAR(wrap(std::atan2(x.y(), x.x()) - expected), 0.0, 1e-12) << s << " " << z;
            // The section at z is the section at 0 turned by psi(z).
            const Eigen::Vector2d turned = GearGeometry::rotate(xy(f.point(s, 0)), f.section_angle_rad(z));
            EXPECT_NEAR((xy(x) - turned).norm(), 0.0, 1e-12);
            // The normal's axial component is -h sin(beta_b) and its transverse part is the
            // transverse involute normal turned by psi(z), scaled by cos(beta_b).
            const Eigen::Vector3d n = f.normal(s, z);
            EXPECT_NEAR(n.z(), -h * std::sin(t.beta_b), 4 * eps);
            const Eigen::Vector2d n_t = GearGeometry::rotate(g.involute_normal(u), f.section_angle_rad(z));
            EXPECT_NEAR((xy(n) - std::cos(t.beta_b) * n_t).norm(), 0.0, 8 * eps);
          }
    }
}

// Requirement: the helical normal is a unit vector orthogonal to the flank's two tangent vectors,
// taken as central differences of point() (step 1e-4 mm in roll and in z). The difference's
// truncation error is h^2 |X'''| / 6 with |X'''| < 1 / mm^2 on this flank (curvatures below
// 1/xi, xi >= 2 mm from the base circle, and the section's turn 4e-3 rad/mm), i.e. < 2e-9; its
// rounding error is eps |X| / h ~ 1e-10 for |X| ~ 40 mm. Tangents are normalised (lengths 0.2 to
// 1.1), so 1e-8 bounds n.t; |n| = 1 to a few ulps.
TEST(FlankSurface, HelicalNormalIsUnitAndOrthogonalToTheTangents)
{
  const double step = 1e-4;
  for (const HelixHand hand : {HelixHand::right, HelixHand::left})
    {
      const GearGeometry g(pinion(15 * pi / 180, hand));
      const FlankSurface f = g.flank();
      double             worst = 0;
      for (const double s : rolls(g))
        for (const double z : faces)
          {
            const Eigen::Vector3d n    = f.normal(s, z);
            const Eigen::Vector3d t_s  = (f.point(s + step, z) - f.point(s - step, z)) / (2 * step);
            const Eigen::Vector3d t_z  = (f.point(s, z + step) - f.point(s, z - step)) / (2 * step);
            EXPECT_NEAR(n.norm(), 1.0, 4 * eps);
            EXPECT_NEAR(n.dot(t_s.normalized()), 0.0, 1e-8) << s << " " << z;
            EXPECT_NEAR(n.dot(t_z.normalized()), 0.0, 1e-8) << s << " " << z;
            worst = std::max({worst, std::abs(n.dot(t_s.normalized())), std::abs(n.dot(t_z.normalized()))});
            // Outward: it points away from the tooth's centre line (+theta side), as in 2D.
            EXPECT_GT(xy(n).dot(g.involute_normal(s / g.base_radius_mm())), 0.0);
          }
      RecordProperty(hand == HelixHand::right ? "worst_right" : "worst_left",
                     ::testing::PrintToString(worst));
    }
}

// Requirement: the developed offset is an isometry of the helicoid to first order: in the
// coordinates (U = xi^2 / (2 r_b), z) the metric of point() from central differences, g = J^T J,
// has det g = 1 / cos^2(beta_b), and the Jacobian A of developed_offset_mm (also from central
// differences) gives A^T A = g. The entries of J and A carry the truncation and rounding errors of
// the previous test (< 2e-9 + 1e-10 with h = 1e-4 mm, entries of order 1); det g and A^T A sum at
// most 8 products of them: 2e-8.
TEST(FlankSurface, HelicalDevelopedOffsetHasTheHelicoidsMetric)
{
  const double step = 1e-4;
  for (const HelixHand hand : {HelixHand::right, HelixHand::left})
    {
      const GearGeometry g(pinion(15 * pi / 180, hand));
      const FlankSurface f   = g.flank();
      const double       r_b = g.base_radius_mm();
      const auto roll_of = [&](const double U) { return std::sqrt(2 * r_b * U); };
      const auto X = [&](const double U, const double z) { return f.point(roll_of(U), z); };
      const auto D = [&](const double Ua, const double za, const double Ub, const double zb) {
        return f.developed_offset_mm({0, roll_of(Ua), za}, {0, roll_of(Ub), zb});
      };
      const double cb    = f.cos_base_helix();
      double       worst = 0;
      for (const double s : rolls(g, 9))
        for (const double z : faces)
          {
            const double U = s * s / (2 * r_b);
            Eigen::Matrix<double, 3, 2> J;
            J.col(0) = (X(U + step, z) - X(U - step, z)) / (2 * step);
            J.col(1) = (X(U, z + step) - X(U, z - step)) / (2 * step);
            const Eigen::Matrix2d metric = J.transpose() * J;
            EXPECT_NEAR(metric.determinant(), 1 / (cb * cb), 2e-8) << s << " " << z;
            EXPECT_NEAR(metric(0, 0), 1.0, 2e-8);
            Eigen::Matrix2d A;
            A.col(0) = D(U + step, z, U - step, z) / (2 * step);
            A.col(1) = D(U, z + step, U, z - step) / (2 * step);
            const Eigen::Matrix2d AtA = A.transpose() * A;
            EXPECT_NEAR((AtA - metric).norm(), 0.0, 2e-8) << s << " " << z;
            worst = std::max({worst, std::abs(metric.determinant() - 1 / (cb * cb)),
                              (AtA - metric).norm()});
          }
      RecordProperty(hand == HelixHand::right ? "worst_right" : "worst_left",
                     ::testing::PrintToString(worst));
    }
}

// Requirement: the micro-geometry of a helical flank is removed along the 3D normal, and in the
// transverse section it turns the involute by transverse_removal_mm / r_b, i.e. Delta / cos(beta_b):
// the modified point lies on the section's involute turned back by that angle. Rounding as in the
// section test (angles of order 1, radii ~ 40 mm), 1e-12.
TEST(FlankSurface, HelicalRemovalInTheTransverseSection)
{
  for (const HelixHand hand : {HelixHand::right, HelixHand::left})
    {
      const GearGeometry g(pinion(15 * pi / 180, hand));
      const FlankSurface f = g.flank();
      for (const double s : rolls(g))
        for (const double z : faces)
          {
            const Eigen::Vector3d m      = f.modified_point(s, z);
            const double          radius = xy(m).norm();
            const double          psi    = f.section_angle_rad(m.z());
            const double expected = g.flank_polar_angle_rad(radius) + psi -
                                    f.transverse_removal_mm(s, z) / g.base_radius_mm();
            EXPECT_NEAR(wrap(std::atan2(m.y(), m.x()) - expected), 0.0, 1e-12) << s << " " << z;
            // A division and a multiplication: 2 roundings, relative.
            EXPECT_NEAR(f.transverse_removal_mm(s, z) * f.cos_base_helix(), f.modification_mm(s, z),
                        2 * eps * std::abs(f.modification_mm(s, z)));
          }
    }
}

// Requirement: a helical pair (same helix angle, opposite hands) is accepted by the pair
// kinematics, the contact stage (mesh cycle) and the 3D finite-element stiffness source (the 2D
// one refuses it naming its dimension), and every stage that handles spur pairs only refuses it
// with an input error that says helical pairs are not supported by that stage yet and names the
// helix angle and its field: the closed-form stiffness sources and the ISO 6336-2 nominal contact
// stress (ISO 6336-1's stiffness takes helical pairs).
TEST(FlankSurface, HelicalPairsAreRefusedByTheStagesThatCannotServeThem)
{
  EXPECT_NO_THROW(GearGeometry(pinion(15 * pi / 180)));
  PairParameters pair         = hertzgear::testing::spur_pair();
  pair.pinion.helix_angle_rad = 15 * pi / 180;
  pair.gear.helix_angle_rad   = 15 * pi / 180;
  pair.gear.hand              = HelixHand::left;
  const PairKinematics kin(pair);
  const auto refused = [](const std::function<void()> &stage, const std::string &name) {
    try
      {
        stage();
        ADD_FAILURE() << name << " accepted a helical pair";
      }
    catch (const hertzgear::InputError &e)
      {
        EXPECT_THAT(e.what(),
                    ::testing::HasSubstr("helical pairs are not supported by " + name + " yet"));
        EXPECT_THAT(e.what(), ::testing::HasSubstr("helix angle 15"));
        EXPECT_THAT(e.what(), ::testing::HasSubstr("{pinion.helix_angle_rad}"));
      }
  };
  const hertzgear::Material                     steel;
  const hertzgear::contact::RigidFlankCompliance rigid(0.3);
  EXPECT_NO_THROW(hertzgear::contact::MeshCycle(kin, steel, steel, rigid, rigid, {}));
  hertzgear::stiffness::StiffnessInput input;
  input.pair      = pair;
  input.torque_Nm = 210;
  // The FE source takes it in 3D and refuses the plane-strain model, naming its dimension.
  EXPECT_NO_THROW(hertzgear::stiffness::find_source("fem").check(input));
  input.fe.dimension = 2;
  try
    {
      hertzgear::stiffness::find_source("fem").check(input);
      ADD_FAILURE() << "the 2D FE model accepted a helical pair";
    }
  catch (const hertzgear::ParameterError &e)
    {
      EXPECT_EQ(e.parameter(), "dimension");
      EXPECT_THAT(e.what(), ::testing::HasSubstr("dimension = 2 cannot represent a helical pair"));
      EXPECT_THAT(e.what(), ::testing::HasSubstr("{pinion.helix_angle_rad}"));
    }
  input.fe.dimension = 3;
  for (const char *source : {"iso6336", "hertz-analytic", "potential-energy"})
    refused([&] { hertzgear::stiffness::find_source(source).check(input); },
            "the closed-form stiffness sources");
  // The ISO 6336-2 nominal contact stress takes helical pairs (its helical factors:
  // Scene.TheIsoTrExampleGivesThePublishedIsoStiffness).
  EXPECT_NO_THROW(hertzgear::stiffness::nominal_contact_stress(kin, steel, steel, 210));
  // The same gears as a spur pair pass every one of these checks.
  pair.pinion.helix_angle_rad = 0;
  pair.gear.helix_angle_rad   = 0;
  input.pair                  = pair;
  const PairKinematics spur(pair);
  EXPECT_NO_THROW(hertzgear::contact::MeshCycle(spur, steel, steel, rigid, rigid, {}));
  for (const char *source : {"fem", "iso6336", "hertz-analytic", "potential-energy"})
    EXPECT_NO_THROW(hertzgear::stiffness::find_source(source).check(input)) << source;
}
