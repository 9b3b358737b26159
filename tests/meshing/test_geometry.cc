// Requirements on the gear geometry and the pair kinematics, checked against values computed
// independently: textbook formulas evaluated here by hand (not through GearGeometry's code
// path) and a published worked example (KHK Gear Technical Reference, Table 4.6: positive
// shifted spur gears m = 3, alpha = 20 deg, z = 12/24, x = 0.6/0.36).
#include "meshing/gear_geometry.h"
#include "meshing/involute.h"
#include "stiffness/iso6336.h"
#include "meshing/pair_kinematics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace hertzgear::meshing;
using hertzgear::stiffness::iso6336_method_b;

namespace
{
  constexpr double pi = 3.14159265358979323846;
  const double     alpha = 20 * pi / 180;

  GearParameters gear(const int z, const double x, const double bore, const std::string &name)
  {
    GearParameters g;
    g.teeth                     = z;
    g.module_mm                 = 3;
    g.pressure_angle_rad        = alpha;
    g.face_width_mm             = 20;
    g.profile_shift_coefficient = x;
    g.bore_radius_mm            = bore;
    g.name                      = name;
    return g;
  }

  // The paper's pair with standard ISO 53 teeth (tip radius r + m), backlash by thinning.
  PairParameters paper_pair(const double backlash = 0.1172)
  {
    PairParameters p;
    p.pinion          = gear(23, 0, 15, "pinion");
    p.gear            = gear(34, 0, 20, "gear");
    p.backlash_loa_mm = backlash;
    return p;
  }

  // KHK Table 4.6 with the tip diameters of the example, d_a = d + 2 (1 + y - x_other) m.
  PairParameters shifted_pair()
  {
    PairParameters p;
    p.pinion = gear(12, 0.6, 6, "pinion");
    p.gear   = gear(24, 0.36, 10, "gear");
    const double y = 0.83329; // centre distance modification coefficient of the example
    p.pinion.tip_radius_mm = 0.5 * (36 + 2 * (1 + y - 0.36) * 3);
    p.gear.tip_radius_mm   = 0.5 * (72 + 2 * (1 + y - 0.6) * 3);
    return p;
  }

  double inv(const double a) { return std::tan(a) - a; }

  // Hand formula: eps = (sqrt(ra1^2 - rb1^2) + sqrt(ra2^2 - rb2^2) - a_w sin(a_w)) / (pi m cos a).
  double hand_contact_ratio(double ra1, double ra2, double rb1, double rb2, double aw, double alpha_w)
  {
    return (std::sqrt(ra1 * ra1 - rb1 * rb1) + std::sqrt(ra2 * ra2 - rb2 * rb2) -
            aw * std::sin(alpha_w)) /
           (pi * 3 * std::cos(alpha));
  }
} // namespace

// The involute function's inverse shall be exact to rounding (it underlies every centre distance).
// inv(a) = tan(a) - a carries an absolute rounding error ~ eps tan(a); through the derivative
// tan^2(a) this becomes eps / tan(a) in a, so the tolerance is 4 eps (1 + 1 / tan(a)).
TEST(Involute, InverseRoundTrips)
{
  const double eps = std::numeric_limits<double>::epsilon();
  for (const double a : {1e-3, 0.1, 0.3490658503988659, 0.6, 1.0, 1.3})
    EXPECT_NEAR(inverse_involute(inv(a)), a, 4 * eps * (1 + 1 / std::tan(a))) << a;
}

// The radii and the contact ratio of the paper's pair shall match the textbook formulas.
TEST(PaperPair, RadiiContactRatioAndPointsMatchHandFormulas)
{
  const PairKinematics k(paper_pair());
  const double rb1 = 34.5 * std::cos(alpha), rb2 = 51 * std::cos(alpha);
  // Exact arithmetic on the same closed forms: only rounding separates them (1e-12 mm).
  EXPECT_NEAR(k.pinion().base_radius_mm(), rb1, 1e-12);
  EXPECT_NEAR(k.gear().base_radius_mm(), rb2, 1e-12);
  EXPECT_NEAR(k.pinion().tip_radius_mm(), 37.5, 1e-12);
  EXPECT_NEAR(k.gear().tip_radius_mm(), 54.0, 1e-12);
  EXPECT_NEAR(k.pinion().root_radius_mm(), 34.5 - 3.75, 1e-12);
  EXPECT_NEAR(k.center_distance_mm(), 85.5, 1e-10);
  EXPECT_NEAR(k.operating_pressure_angle_rad(), alpha, 1e-12);
  const double eps = hand_contact_ratio(37.5, 54, rb1, rb2, 85.5, alpha);
  EXPECT_NEAR(k.contact_ratio(), eps, 1e-12);
  // Rounded by hand on paper: 1.636 (four digits).
  EXPECT_NEAR(k.contact_ratio(), 1.636, 5e-4);
  // A-E: A on the gear's tip circle, E on the pinion's, B = E - p_b, D = A + p_b, C at
  // r_b1 tan(alpha_w); radii of curvature rho_1 = s, rho_2 = a sin(alpha) - s.
  const double L = 85.5 * std::sin(alpha), pb = pi * 3 * std::cos(alpha);
  const double sA = L - std::sqrt(54.0 * 54 - rb2 * rb2), sE = std::sqrt(37.5 * 37.5 - rb1 * rb1);
  const double expected[5] = {sA, sE - pb, rb1 * std::tan(alpha), sA + pb, sE};
  const char   names[5]    = {'A', 'B', 'C', 'D', 'E'};
  for (int i = 0; i < 5; ++i)
    {
      const auto p = k.point(names[i]);
      EXPECT_NEAR(p.roll_distance_mm, expected[i], 1e-10) << names[i];
      EXPECT_NEAR(p.rho_pinion_mm, expected[i], 1e-10) << names[i];
      EXPECT_NEAR(p.rho_gear_mm, L - expected[i], 1e-10) << names[i];
    }
  // The pitch point lies on both operating pitch circles.
  EXPECT_NEAR(k.point('C').radius_pinion_mm, 34.5, 1e-10);
  EXPECT_NEAR(k.point('C').radius_gear_mm, 51.0, 1e-10);
}

// The backlash made by thinning shall be the requested one: circumferential backlash on the
// reference circle j_t = p - s1 - s2 = 2 Delta_s, normal j_n = j_t cos(alpha).
TEST(PaperPair, BacklashFromThinningAndFromCentreDistance)
{
  const PairKinematics k(paper_pair(0.1172));
  const double ds = k.pinion().parameters().thickness_reduction_mm;
  EXPECT_NEAR(2 * ds * std::cos(alpha), 0.1172, 1e-12);
  EXPECT_NEAR(k.backlash_loa_mm(), 0.1172, 1e-12);
  EXPECT_NEAR(k.pinion().reference_tooth_thickness_mm(), 3 * pi / 2 - ds, 1e-12);

  // From a centre distance, unthinned teeth: j_bn = (z1 + z2) m cos(a) (inv a_w - inv a)
  // (obtained by subtracting the tight-mesh condition from the general one).
  PairParameters p = paper_pair(0);
  p.center_distance_mm = 85.7;
  const PairKinematics kc(p);
  const double aw = std::acos(85.5 * std::cos(alpha) / 85.7);
  EXPECT_NEAR(kc.operating_pressure_angle_rad(), aw, 1e-13);
  EXPECT_NEAR(kc.backlash_loa_mm(), 57 * 3 * std::cos(alpha) * (inv(aw) - inv(alpha)), 1e-12);
  // First-order check 2 da sin(a) = 0.1368 mm; the exact value is within 1 %.
  EXPECT_NEAR(kc.backlash_loa_mm(), 2 * 0.2 * std::sin(alpha), 0.01 * 0.1368);
}

// Profile-shifted pair: operating pressure angle and centre distance as published (KHK
// Table 4.6: inv a_w = 0.034316, a_w = 26.0886 deg, a = 56.4999 mm), to the printed digits.
TEST(ShiftedPair, MatchesPublishedExample)
{
  const PairKinematics k(shifted_pair());
  EXPECT_NEAR(inv(k.operating_pressure_angle_rad()), 0.034316, 5e-7);
  EXPECT_NEAR(k.operating_pressure_angle_rad() * 180 / pi, 26.0886, 5e-5);
  EXPECT_NEAR(k.center_distance_mm(), 56.4999, 5e-5);
  EXPECT_NEAR(k.backlash_loa_mm(), 0.0, 1e-12);
  const double rb1 = 18 * std::cos(alpha), rb2 = 36 * std::cos(alpha);
  const double aw  = k.center_distance_mm(), alpha_w = k.operating_pressure_angle_rad();
  const double ra1 = k.pinion().tip_radius_mm(), ra2 = k.gear().tip_radius_mm();
  EXPECT_NEAR(k.contact_ratio(), hand_contact_ratio(ra1, ra2, rb1, rb2, aw, alpha_w), 1e-12);
  // Root radius r + x m - 1.25 m; reference thickness m (pi/2 + 2 x tan a).
  EXPECT_NEAR(k.pinion().root_radius_mm(), 18 + 1.8 - 3.75, 1e-12);
  EXPECT_NEAR(k.pinion().reference_tooth_thickness_mm(), 3 * (pi / 2 + 1.2 * std::tan(alpha)), 1e-12);
  // Radii of curvature at the pitch point: r_b tan(a_w) on each gear.
  EXPECT_NEAR(k.point('C').rho_pinion_mm, rb1 * std::tan(alpha_w), 1e-10);
  EXPECT_NEAR(k.point('C').rho_gear_mm, rb2 * std::tan(alpha_w), 1e-10);
}

// Generated flank points shall satisfy the involute equation theta + inv(alpha_r) = psi_b to
// 1e-9 relative, with psi_b = s/(2r) + inv(alpha) from the hand formula for s.
TEST(Flank, PointsSatisfyTheInvoluteEquation)
{
  for (const auto &pp : {paper_pair(), shifted_pair()})
    {
      const PairKinematics k(pp);
      for (unsigned int b = 0; b < 2; ++b)
        {
          const GearGeometry &g = k.body(b);
          const double        r = 1.5 * g.n_teeth(), x = g.parameters().profile_shift_coefficient;
          const double s   = 3 * (pi / 2 + 2 * x * std::tan(alpha)) - g.parameters().thickness_reduction_mm;
          const double psi = s / (2 * r) + inv(alpha);
          const double rb  = r * std::cos(alpha);
          const auto   hp  = g.half_profile(4, 8, 50);
          for (const auto &p : hp.flank)
            {
              const double radius = p.norm();
              const double lhs    = std::atan2(p.y(), p.x()) + inv(std::acos(std::min(1.0, rb / radius)));
              EXPECT_NEAR(lhs, psi, 1e-9 * psi);
            }
          // Form and tip radii where the flank starts and ends.
          EXPECT_NEAR(hp.flank.front().norm(), g.form_radius_mm(), 1e-9);
          EXPECT_NEAR(hp.flank.back().norm(), g.tip_radius_mm(), 1e-9);
        }
    }
}

// The trochoidal fillet shall meet the involute at the form point with the same position and
// tangent, and the form radius shall match the rack-generation formula
// r_b u_F = r sin(a) - (h_fP - x m - rho_fP (1 - sin a)) / sin(a).
TEST(Fillet, MeetsTheInvoluteWithContinuousTangent)
{
  for (const auto &pp : {paper_pair(), shifted_pair()})
    {
      const PairKinematics k(pp);
      for (unsigned int b = 0; b < 2; ++b)
        {
          const GearGeometry &g = k.body(b);
          const double r = 1.5 * g.n_teeth(), x = g.parameters().profile_shift_coefficient;
          const double rb = r * std::cos(alpha);
          const double xi_F = r * std::sin(alpha) - (3.75 - 3 * x - 1.14 * (1 - std::sin(alpha))) / std::sin(alpha);
          EXPECT_NEAR(g.form_radius_mm(), std::hypot(rb, xi_F), 1e-10);
          const Eigen::Vector2d end = g.fillet_point(1.0);
          EXPECT_NEAR((end - g.involute_point(g.form_roll_angle())).norm(), 0, 1e-9);
          // One-sided difference of the fillet vs. the involute tangent (cos t, sin t),
          // t = psi_b - u_F. The difference quotient's error is O(h) ~ 1e-7 rad for h = 1e-7.
          const double          h  = 1e-7;
          const Eigen::Vector2d df = (end - g.fillet_point(1.0 - h)).normalized();
          const double          t  = g.half_base_thickness_angle_rad() - g.form_roll_angle();
          const Eigen::Vector2d di(std::cos(t), std::sin(t));
          EXPECT_LT(std::abs(df.x() * di.y() - df.y() * di.x()), 1e-5);
          EXPECT_GT(df.dot(di), 0.0);
          // The fillet starts on the root circle.
          EXPECT_NEAR(g.fillet_point(0.0).norm(), g.root_radius_mm(), 1e-10);
        }
    }
}

// ISO 6336-1 method B for the paper's pair, by hand: q' = C1 + C2/23 + C3/34 (x = 0),
// c'_th = 1/q', c' = c'_th * 0.8 * 1 * C_B, C_B = 1 + 0.5 (1.2 - 1.25), c_ga = c'(0.75 eps + 0.25).
TEST(Iso6336, PaperPairByHand)
{
  const PairKinematics k(paper_pair());
  const auto           s     = iso6336_method_b(k, 210);
  const double         q     = 0.04723 + 0.15551 / 23 + 0.25791 / 34;
  const double         c_th  = 1 / q;
  const double         c     = c_th * 0.8 * 0.975;
  EXPECT_NEAR(s.c_prime_th_N_per_mm_um, c_th, 1e-12);
  EXPECT_NEAR(s.c_prime_th_N_per_mm_um, 16.24, 5e-3); // rounded on paper
  EXPECT_NEAR(s.c_prime_N_per_mm_um, c, 1e-12);
  EXPECT_NEAR(s.c_gamma_alpha_N_per_mm_um, c * (0.75 * k.contact_ratio() + 0.25), 1e-12);
  // 210 N m on d1 = 69 mm over b = 20 mm is 304 N/mm, above 100 N/mm: no load correction.
  EXPECT_NEAR(s.line_load_N_per_mm, 2000 * 210 / 69.0 / 20, 1e-9);
  EXPECT_DOUBLE_EQ(s.load_factor, 1.0);
}

// ISO 6336-1 method B for the paper's pair made helical (beta = 15 deg), by hand: the virtual
// numbers of teeth z_n = z / (cos^2(beta_b) cos(beta)), sin(beta_b) = sin(beta) cos(alpha_n), in
// q'; c' carries cos(beta); the line load uses d1 = z1 m_n / cos(beta); c_gb = 0.85 c_ga.
// Tolerance 1e-12: the same operations in another order.
TEST(Iso6336, HelicalPaperPairByHand)
{
  auto p = paper_pair();
  const double beta = 15 * pi / 180;
  p.pinion.helix_angle_rad = p.gear.helix_angle_rad = beta;
  p.pinion.hand = HelixHand::right;
  p.gear.hand   = HelixHand::left;
  const PairKinematics k(p);
  const auto           s      = iso6336_method_b(k, 210);
  const double         sin_bb = std::sin(beta) * std::cos(20 * pi / 180);
  const double         zn     = 1 / ((1 - sin_bb * sin_bb) * std::cos(beta));
  const double         q      = 0.04723 + 0.15551 / (23 * zn) + 0.25791 / (34 * zn);
  const double         c      = 1 / q * 0.8 * 0.975 * std::cos(beta);
  EXPECT_NEAR(s.c_prime_th_N_per_mm_um, 1 / q, 1e-12);
  EXPECT_NEAR(s.c_prime_N_per_mm_um, c, 1e-12);
  EXPECT_NEAR(s.c_gamma_alpha_N_per_mm_um, c * (0.75 * k.contact_ratio() + 0.25), 1e-12);
  EXPECT_NEAR(s.c_gamma_beta_N_per_mm_um, 0.85 * s.c_gamma_alpha_N_per_mm_um, 1e-12);
  EXPECT_NEAR(s.line_load_N_per_mm, 2000 * 210 / (69.0 / std::cos(beta)) / 20, 1e-9);
  // The helix lowers c' against the spur pair's (cos(beta) = 0.966 against 1/z_n's 2 % rise of
  // c'_th) and the transverse contact ratio with it c_ga.
  const auto spur = iso6336_method_b(PairKinematics(paper_pair()), 210);
  EXPECT_LT(s.c_prime_N_per_mm_um, spur.c_prime_N_per_mm_um);
  EXPECT_GT(s.c_prime_th_N_per_mm_um, spur.c_prime_th_N_per_mm_um);
}

// ISO 6336-1 for the shifted pair, by hand with the shift terms.
TEST(Iso6336, ShiftedPairByHand)
{
  const PairKinematics k(shifted_pair());
  const auto           s = iso6336_method_b(k, 10); // light load: 2000*10/36/20 = 27.8 N/mm
  const double x1 = 0.6, x2 = 0.36;
  const double q  = 0.04723 + 0.15551 / 12 + 0.25791 / 24 - 0.00635 * x1 - 0.11654 * x1 / 12 -
                   0.00193 * x2 - 0.24188 * x2 / 24 + 0.00529 * x1 * x1 + 0.00182 * x2 * x2;
  const double load = std::pow(2000 * 10 / 36.0 / 20 / 100, 0.25);
  EXPECT_NEAR(s.c_prime_th_N_per_mm_um, 1 / q, 1e-12);
  EXPECT_NEAR(s.c_prime_N_per_mm_um, 1 / q * 0.8 * 0.975 * load, 1e-12);
}

// The unloaded gap shall vanish on the contact lines of an unmodified pair, grow on both sides
// of it, and contain exactly the crowning of both flanks along the face width.
TEST(Gap, ZeroOnContactLinePositiveBesideAndCrowningAlongFace)
{
  PairParameters p = paper_pair();
  const PairKinematics plain(p);
  for (const double tau : {0.0, 0.3, 0.8})
    for (const int j : plain.pairs_in_contact(tau))
      {
        const double s = plain.contact_roll_distance_mm(j, tau);
        EXPECT_NEAR(plain.unloaded_gap_mm(j, tau, s, 0), 0, 1e-11);
        // Beside the contact line both convex flanks separate.
        for (const double ds : {-0.1, 0.1})
          {
            const double g = plain.unloaded_gap_mm(j, tau, s + ds, 0);
            EXPECT_GT(g, 0);
          }
      }
  p.pinion.crowning_mm = 0.08;
  p.gear.crowning_mm   = 0.05;
  const PairKinematics crowned(p);
  for (const int j : crowned.pairs_in_contact(0.5))
    {
      const double s = crowned.contact_roll_distance_mm(j, 0.5);
      for (const double z : {-10.0, -3.0, 0.0, 7.0, 10.0})
        {
          const double q = 2 * z / 20;
          EXPECT_NEAR(crowned.unloaded_gap_mm(j, 0.5, s, z), (0.08 + 0.05) * q * q, 1e-11) << z;
        }
    }
  // Crowning radius b^2/(8 beta) = 400/0.64 = 625 mm.
  EXPECT_NEAR(crowned.pinion().crowning_radius_mm(), 625.0, 1e-9);
}

// Tip relief shall open the gap at the start and end of contact by exactly C_a (linear) and
// the rigid approach shall keep the smallest gap at 0.
TEST(Gap, TipReliefOpensTheEndsOfContact)
{
  PairParameters p              = paper_pair();
  p.pinion.tip_relief_mm        = 0.015;
  p.pinion.tip_relief_length_mm = 2.0;
  const PairKinematics k(p);
  // tau = 0: pair 0 enters at A (gear tip, no gear relief), pair 1 is near E (pinion tip).
  const double sE = k.point('E').roll_distance_mm;
  const double tau = (sE - k.point('A').roll_distance_mm) / k.base_pitch_mm() - 1; // pair 1 at E
  EXPECT_NEAR(k.contact_roll_distance_mm(1, tau), sE, 1e-12);
  EXPECT_NEAR(k.separation_mm(1, tau, sE, 0), 0.015, 1e-11);
  EXPECT_NEAR(k.unloaded_gap_mm(1, tau, sE, 0), 0.015, 1e-11);
  EXPECT_NEAR(k.unloaded_gap_mm(0, tau, k.contact_roll_distance_mm(0, tau), 0), 0, 1e-11);
  // Half-way into the relief zone a linear relief is C_a / 2.
  EXPECT_NEAR(k.pinion().tip_relief_mm(sE - 1.0), 0.0075, 1e-12);
}

// Pairs in contact follow the contact ratio: two pairs for tau < eps - 1, one pair after.
TEST(Kinematics, PairsInContactFollowContactRatio)
{
  const PairKinematics k(paper_pair());
  const double         e = k.contact_ratio() - 1;
  EXPECT_EQ(k.pairs_in_contact(0.5 * e).size(), 2u);
  EXPECT_EQ(k.pairs_in_contact(0.5 * (1 + e)).size(), 1u);
  // The placement turns the pinion's central tooth so its drive flank passes through the
  // contact point of pair 0 on the line of action.
  const double         tau = 0.37;
  const auto           pl  = k.placement(0, tau);
  const double         s   = k.contact_roll_distance_mm(0, tau);
  const Eigen::Vector2d P  = k.line_of_action_point(s);
  const double          radius = P.norm();
  const double          angle  = std::atan2(P.y(), P.x()) - pl.rotation_rad;
  EXPECT_NEAR(angle, k.pinion().flank_polar_angle_rad(radius), 1e-12);
  // ... and the gear's central tooth too, seen from O2.
  const auto            pg = k.placement(1, tau);
  const Eigen::Vector2d Q  = P - pg.centre_mm;
  double                ag = std::atan2(Q.y(), Q.x()) - pg.rotation_rad;
  ag = std::remainder(ag, 2 * pi);
  EXPECT_NEAR(ag, k.gear().flank_polar_angle_rad(Q.norm()), 1e-12);
}

// Across the profile the unloaded gap of unmodified flanks shall be, to leading order, the Hertz
// gap of two cylinders with the flanks' radii of curvature: d^2/2 (1/rho1 + 1/rho2), d the distance
// of the pinion flank point from the contact line. The involute's curvature changes along the
// profile (d rho / ds = 1), so the next term is of relative size ~ d / rho_min; the tolerance is
// 3 d / rho_min.
TEST(Gap, AcrossTheProfileFollowsTheHertzGap)
{
  const PairKinematics  k(paper_pair());
  const Eigen::Vector2d n(std::cos(k.operating_pressure_angle_rad()), -std::sin(k.operating_pressure_angle_rad()));
  for (const double tau : {0.1, 0.6})
    for (const int j : k.pairs_in_contact(tau))
      {
        const double s    = k.contact_roll_distance_mm(j, tau);
        const double rho1 = k.radius_of_curvature_pinion_mm(s), rho2 = k.radius_of_curvature_gear_mm(s);
        const auto   pl   = k.placement(0, tau);
        const double centre_angle = pl.rotation_rad + j * k.pinion().angular_pitch_rad();
        for (const double ds : {-0.05, -0.02, 0.02, 0.05})
          {
            const double          u = (s + ds) / k.pinion().base_radius_mm();
            const Eigen::Vector2d P = GearGeometry::rotate(k.pinion().involute_point(u), centre_angle);
            const double          d = std::abs((P - k.line_of_action_point(s)).dot(n));
            const double          hertz = 0.5 * d * d * (1 / rho1 + 1 / rho2);
            const double          gap   = k.unloaded_gap_mm(j, tau, s + ds, 0);
            EXPECT_NEAR(gap, hertz, 3 * d / std::min(rho1, rho2) * hertz)
              << "tau " << tau << " pair " << j << " ds " << ds;
          }
      }
}
