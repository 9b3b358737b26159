#include "meshing/pair_kinematics.h"

#include "common/errors.h"
#include "meshing/field_names.h"
#include "meshing/involute.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace hertzgear::meshing
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    // The smallest value of f over [knots.front(), knots.back()] (after sorting) and where, for f
    // quadratic between neighbouring knots: on each piece the quadratic through three values gives
    // the minimum exactly (an end or the vertex).
    template <typename F>
    std::pair<double, double> smallest_piecewise_quadratic(const F &f, std::vector<double> knots)
    {
      std::sort(knots.begin(), knots.end());
      std::pair<double, double> best{0.0, std::numeric_limits<double>::infinity()};
      const auto consider = [&](const double z) {
        const double v = f(z);
        if (v < best.second)
          best = {z, v};
      };
      for (std::size_t i = 0; i + 1 < knots.size(); ++i)
        {
          const double a = knots[i], b = knots[i + 1], m = 0.5 * (a + b), h = 0.5 * (b - a);
          if (h <= 0)
            continue;
          // Evaluate just inside the piece so that a knee's kink does not enter the quadratic.
          const double e  = 1e-9 * h;
          const double fa = f(a + e), fm = f(m), fb = f(b - e);
          consider(a);
          consider(b);
          const double curvature = fa - 2 * fm + fb;
          if (curvature > 0)
            {
              const double vertex = m - (h - e) * (fb - fa) / (2 * curvature);
              if (vertex > a && vertex < b)
                consider(vertex);
            }
        }
      return best;
    }

    // Roll lengths where a gear's profile modification changes its formula: the start of the tip
    // relief and the end of the root relief (GearGeometry::profile_modification_mm).
    std::vector<double> profile_breakpoints_mm(const GearGeometry &g)
    {
      const auto         &p = g.parameters();
      std::vector<double> rolls;
      const double        tip = std::sqrt(std::pow(g.tip_radius_mm(), 2) - std::pow(g.base_radius_mm(), 2));
      if (p.tip_relief_mm > 0 && p.tip_relief_length_mm > 0)
        rolls.push_back(tip - p.tip_relief_length_mm);
      const double xi_s = std::max(p.active_profile_start_roll_mm, g.base_radius_mm() * g.form_roll_angle());
      if (p.root_relief_mm > 0 && p.root_relief_length_mm > 0)
        rolls.push_back(xi_s + p.root_relief_length_mm);
      return rolls;
    }
  } // namespace

  void require_spur_pair(const GearParameters &pinion, const GearParameters &gear,
                         const std::string &stage)
  {
    for (const GearParameters *g : {&pinion, &gear})
      HG_REQUIRE_INPUT(g->helix_angle_rad == 0, g->name, ": helix angle ",
                       g->helix_angle_rad * 180 / pi, " deg: helical pairs are not supported by ",
                       stage, " yet (only spur pairs, helix angle 0; ", field(*g, "helix_angle_rad"),
                       ")");
  }

  PairKinematics::PairKinematics(const PairParameters &parameters) : params(parameters)
  {
    GearParameters &p1 = params.pinion, &p2 = params.gear;
    HG_REQUIRE_INPUT(std::abs(p1.module_mm - p2.module_mm) <= 1e-12 * p1.module_mm,
                     "impossible gear pair: pinion module ", p1.module_mm,
                     " mm differs from gear module ", p2.module_mm, " mm (", field(p1, "module_mm"),
                     ", ", field(p2, "module_mm"), ")");
    HG_REQUIRE_INPUT(std::abs(p1.pressure_angle_rad - p2.pressure_angle_rad) <= 1e-14,
                     "impossible gear pair: the pressure angles of pinion and gear differ (",
                     field(p1, "pressure_angle_rad"), ", ", field(p2, "pressure_angle_rad"), ")");
    // An external helical pair: the same helix angle, opposite hands.
    HG_REQUIRE_INPUT(std::abs(p1.helix_angle_rad - p2.helix_angle_rad) <= 1e-14,
                     "impossible gear pair: the helix angles of pinion and gear differ (",
                     p1.helix_angle_rad * 180 / pi, " deg and ", p2.helix_angle_rad * 180 / pi,
                     " deg; ", field(p1, "helix_angle_rad"), ", ", field(p2, "helix_angle_rad"), ")");
    HG_REQUIRE_INPUT(p1.helix_angle_rad == 0 || p1.hand != p2.hand,
                     "impossible gear pair: pinion and gear are both ",
                     p1.hand == HelixHand::right ? "right" : "left",
                     "-handed; an external helical pair needs opposite hands (", field(p1, "hand"),
                     ", ", field(p2, "hand"), ")");
    HG_REQUIRE_INPUT(params.center_distance_mm >= 0 && params.backlash_loa_mm >= 0,
                     "centre distance and backlash must be >= 0 ({center_distance_mm}, "
                     "{backlash_loa_mm})");
    // The single-gear checks (undercut, pointed tip, ...) first: they name the gear and the cause.
    GearGeometry{p1};
    GearGeometry{p2};
    // The transverse section (ISO 21771:2007, 4.3): alpha_t, r = m_t z / 2, r_b = r cos(alpha_t);
    // for a spur pair exactly alpha and m z / 2 (the conversions are skipped).
    const double alpha = p1.pressure_angle_rad, alpha_t = transverse_pressure_angle_rad(p1);
    const double inv_tight = involute(alpha_t) + 2 * std::tan(alpha) *
                                                   (p1.profile_shift_coefficient + p2.profile_shift_coefficient) /
                                                   (p1.teeth + p2.teeth);
    HG_REQUIRE_INPUT(inv_tight > 0, "impossible gear pair: the profile shifts x1 + x2 = ",
                     p1.profile_shift_coefficient + p2.profile_shift_coefficient,
                     " are so negative that the pair has no tight mesh (inv alpha_w = ", inv_tight,
                     " < 0; ", field(p1, "profile_shift_coefficient"), ", ",
                     field(p2, "profile_shift_coefficient"), ")");
    const double rb1 = meshing::base_radius_mm(p1), rb2 = meshing::base_radius_mm(p2);

    // Tight mesh of the unthinned pair (zero backlash): inv(a_wt) = inv(a_t) + 2 tan(a_n) (x1 + x2)
    // / (z1 + z2), a_w = (r1 + r2) cos(a_t) / cos(a_wt) (ISO 21771:2007, 5.4).
    const double alpha_tight = inverse_involute(inv_tight);
    a_tight = (rb1 + rb2) / std::cos(alpha_tight);

    if (params.center_distance_mm > 0)
      {
        a_w = params.center_distance_mm;
        HG_REQUIRE_INPUT(a_w > rb1 + rb2, "centre distance ", a_w,
                         " mm jams the pair: it is not even above the sum of the base radii ",
                         rb1 + rb2, " mm (tight-mesh distance ", a_tight, " mm; {center_distance_mm})");
        alpha_w = std::acos((rb1 + rb2) / a_w);
      }
    else
      {
        a_w     = a_tight;
        alpha_w = alpha_tight;
      }
    // Backlash by thinning: each gear gives half of j_bn, a base-circle thickness reduction of
    // j_bn / 2, i.e. j_bn / (2 cos a_t) of (transverse) circular thickness on the reference circle.
    if (params.backlash_loa_mm > 0)
      for (GearParameters *g : {&p1, &p2})
        g->thickness_reduction_mm += 0.5 * params.backlash_loa_mm / std::cos(alpha_t);

    gears.emplace_back(p1);
    gears.emplace_back(p2);

    p_b = pinion().base_pitch_mm();
    // Normal backlash: base pitch minus both tooth thicknesses along the line of action,
    // s_bn = 2 r_b (psi_b - inv(a_w)) for each gear (the thickness on the operating pitch
    // circle, 2 r_w (psi_b - inv(a_w)), times cos(a_w)).
    j_bn = p_b - 2 * rb1 * (pinion().half_base_thickness_angle_rad() - involute(alpha_w)) -
           2 * rb2 * (gear().half_base_thickness_angle_rad() - involute(alpha_w));
    L   = a_w * std::sin(alpha_w);
    s_E = std::sqrt(std::pow(pinion().tip_radius_mm(), 2) - rb1 * rb1);
    s_A = L - std::sqrt(std::pow(gear().tip_radius_mm(), 2) - rb2 * rb2);
    // The profile modifications that start at the active profile (profile crowning, root
    // relief) need where the mating tip meets each flank: rebuild the gears with it.
    p1.active_profile_start_roll_mm = s_A;
    p2.active_profile_start_roll_mm = L - s_E;
    gears.clear();
    gears.emplace_back(p1);
    gears.emplace_back(p2);
    if (p1.helix_angle_rad != 0)
      {
        // The contact line's inclination in the plane of action: the pinion's section at z is
        // turned by psi(z) = h z tan(beta) / r_1 (FlankSurface), which moves its contact along the
        // line of action by r_b1 psi = h z tan(beta) cos(alpha_t) = h z tan(beta_b).
        beta          = p1.helix_angle_rad;
        beta_b        = meshing::base_helix_angle_rad(p1);
        cos_beta_b    = std::cos(beta_b);
        roll_per_face = (p1.hand == HelixHand::right ? 1.0 : -1.0) * std::tan(beta_b);
      }
    check();
  }

  double PairKinematics::face_contact_ratio() const
  {
    return beta == 0 ? 0.0 : face_width_mm() * std::sin(beta) / (pi * pinion().module_mm());
  }

  void PairKinematics::check() const
  {
    const GearGeometry &g1 = pinion(), &g2 = gear();
    HG_REQUIRE_INPUT(j_bn >= -1e-9 * g1.module_mm(), "centre distance ", a_w,
                     " mm jams the pair: the teeth overlap by ", -j_bn,
                     " mm along the line of action (the tight-mesh distance is ", a_tight,
                     " mm; {center_distance_mm})");
    const double c1 = a_w - g1.tip_radius_mm() - g2.root_radius_mm();
    const double c2 = a_w - g2.tip_radius_mm() - g1.root_radius_mm();
    HG_REQUIRE_INPUT(c1 > 0 && c2 > 0, "centre distance ", a_w,
                     " mm jams the pair: no tip clearance (pinion tip to gear root ", c1,
                     " mm, gear tip to pinion root ", c2, " mm; {center_distance_mm}, ",
                     field(g1.parameters(), "tip_radius_mm"), ", ", field(g2.parameters(), "tip_radius_mm"),
                     ")");
    const double form1 = g1.base_radius_mm() * g1.form_roll_angle();
    const double form2 = g2.base_radius_mm() * g2.form_roll_angle();
    HG_REQUIRE_INPUT(s_A >= form1 - 1e-12, "involute interference: the gear tip (radius ",
                     g2.tip_radius_mm(), " mm) meets the pinion below its form circle (roll length ",
                     s_A, " mm < ", form1, " mm of the pinion's form radius ", g1.form_radius_mm(),
                     " mm; ", field(g2.parameters(), "tip_radius_mm"), ", ",
                     field(g1.parameters(), "profile_shift_coefficient"), ")");
    HG_REQUIRE_INPUT(L - s_E >= form2 - 1e-12, "involute interference: the pinion tip (radius ",
                     g1.tip_radius_mm(), " mm) meets the gear below its form circle (roll length ",
                     L - s_E, " mm < ", form2, " mm of the gear's form radius ", g2.form_radius_mm(),
                     " mm; ", field(g1.parameters(), "tip_radius_mm"), ", ",
                     field(g2.parameters(), "profile_shift_coefficient"), ")");
    HG_REQUIRE_INPUT(path_of_contact_mm() > 0, "centre distance ", a_w,
                     " mm: the gears do not mesh, their tip circles do not reach each other's "
                     "flanks along the line of action (path of contact ", path_of_contact_mm(),
                     " mm; the tight-mesh distance is ", a_tight, " mm; {center_distance_mm})");
    HG_REQUIRE_INPUT(contact_ratio() >= 1.0, "contact ratio eps_alpha = ", contact_ratio(),
                     " is below 1: the next tooth pair is not in contact when the previous one "
                     "leaves (path of contact ", path_of_contact_mm(), " mm < base pitch ", p_b,
                     " mm; {center_distance_mm}, ", field(g1.parameters(), "tip_radius_mm"), ", ",
                     field(g2.parameters(), "tip_radius_mm"), ")");
    const double active = path_of_contact_mm();
    for (const GearGeometry *g : {&g1, &g2})
      {
        const auto &gp = g->parameters();
        HG_REQUIRE_INPUT(gp.tip_relief_length_mm <= active + 1e-12, gp.name, ": tip relief length ",
                         gp.tip_relief_length_mm,
                         " mm is larger than the geometry allows: the active profile (path of "
                         "contact) is only ", active, " mm long (", field(gp, "tip_relief_length_mm"), ")");
        HG_REQUIRE_INPUT(gp.tip_relief_length_mm + gp.root_relief_length_mm <= active + 1e-12,
                         gp.name, ": tip relief length ", gp.tip_relief_length_mm,
                         " mm and root relief length ", gp.root_relief_length_mm,
                         " mm are larger than the flank allows: together they exceed the active "
                         "profile (path of contact, ", active, " mm; ", field(gp, "tip_relief_length_mm"),
                         ", ", field(gp, "root_relief_length_mm"), ")");
      }
    // A misaligned pair touches at one face end; at the other the drive flanks stand f_eq apart
    // and the back flanks j_bn - f_eq.
    const double f_eq = std::abs(misalignment_mm());
    HG_REQUIRE_INPUT(f_eq <= 0 || f_eq < j_bn, "shaft misalignment: the drive flanks open by ",
                     f_eq * 1e3, " um along the line of action over the face width ({mesh_misalignment_mm} + "
                     "{axis_inclination_mm} sin(alpha_w) + {axis_deviation_mm} cos(alpha_w)), more "
                     "than the "
                     "backlash j_bn = ", j_bn * 1e3, " um: at the open face end the back flanks would "
                     "overlap by ", (f_eq - j_bn) * 1e3, " um, so the pair jams");
  }

  double PairKinematics::reference_center_distance_mm() const
  {
    return pinion().reference_radius_mm() + gear().reference_radius_mm();
  }

  double PairKinematics::operating_pitch_radius_mm(const unsigned int body) const
  {
    return gears[body].base_radius_mm() / std::cos(alpha_w);
  }

  double PairKinematics::gear_ratio() const
  {
    return double(gear().n_teeth()) / pinion().n_teeth();
  }

  double PairKinematics::radius_of_curvature_pinion_mm(const double s) const
  {
    return s;
  }

  double PairKinematics::radius_of_curvature_gear_mm(const double s) const
  {
    return L - s;
  }

  LineOfActionPoint PairKinematics::point_at(const double s) const
  {
    LineOfActionPoint pt;
    pt.roll_distance_mm = s;
    pt.rho_pinion_mm    = radius_of_curvature_pinion_mm(s);
    pt.rho_gear_mm      = radius_of_curvature_gear_mm(s);
    pt.radius_pinion_mm = std::hypot(pinion().base_radius_mm(), pt.rho_pinion_mm);
    pt.radius_gear_mm   = std::hypot(gear().base_radius_mm(), pt.rho_gear_mm);
    return pt;
  }

  double PairKinematics::active_profile_start_radius_mm(const unsigned int body) const
  {
    return body == 0 ? point('A').radius_pinion_mm : point('E').radius_gear_mm;
  }

  LineOfActionPoint PairKinematics::point(const char name) const
  {
    switch (name)
      {
        case 'A':
          return point_at(s_A);
        case 'B':
          return point_at(s_E - p_b);
        case 'C':
          return point_at(pinion().base_radius_mm() * std::tan(alpha_w));
        case 'D':
          return point_at(s_A + p_b);
        case 'E':
          return point_at(s_E);
        default:
          throw InputError(msg("unknown point of the line of action '", name, "' (A-E)"));
      }
  }

  double PairKinematics::contact_roll_distance_mm(const int pair, const double mesh_phase) const
  {
    return s_A + (mesh_phase + pair) * p_b;
  }

  double PairKinematics::contact_roll_distance_mm(const int pair, const double mesh_phase,
                                                  const double z_mm) const
  {
    const double s = contact_roll_distance_mm(pair, mesh_phase);
    return roll_per_face == 0 ? s : s + roll_per_face * z_mm;
  }

  std::vector<int> PairKinematics::pairs_in_contact(const double mesh_phase) const
  {
    std::vector<int> pairs;
    const double     tol = 1e-12 * p_b;
    // How far a contact line reaches from its mid-face roll over half the face (0 for spur: the
    // comparisons below are then exactly the spur ones).
    const double reach   = std::abs(roll_per_face) * 0.5 * face_width_mm();
    const int    n_reach = static_cast<int>(std::ceil(reach / p_b));
    for (int j = -1 - n_reach; j < 64 + n_reach; ++j)
      {
        const double s = contact_roll_distance_mm(j, mesh_phase);
        if (s - reach > s_E + tol)
          break;
        if (s + reach >= s_A - tol)
          pairs.push_back(j);
      }
    return pairs;
  }

  double PairKinematics::contact_line_length_mm(const double mesh_phase) const
  {
    const double b = face_width_mm(), half = 0.5 * b;
    double       extent = 0; // the lines' z-extent inside the field of action
    for (const int j : pairs_in_contact(mesh_phase))
      {
        if (roll_per_face == 0)
          {
            extent += b;
            continue;
          }
        // s_j + k z in [s_A, s_E]  <=>  z between (s_A - s_j) / k and (s_E - s_j) / k.
        const double s  = contact_roll_distance_mm(j, mesh_phase);
        double       z0 = (s_A - s) / roll_per_face, z1 = (s_E - s) / roll_per_face;
        if (z0 > z1)
          std::swap(z0, z1);
        extent += std::max(0.0, std::min(z1, half) - std::max(z0, -half));
      }
    return extent / cos_beta_b;
  }

  Eigen::Vector2d PairKinematics::line_of_action_direction() const
  {
    return {std::sin(alpha_w), std::cos(alpha_w)};
  }

  Eigen::Vector2d PairKinematics::line_of_action_point(const double s) const
  {
    const double rb1 = pinion().base_radius_mm();
    return Eigen::Vector2d(rb1 * std::cos(alpha_w), -rb1 * std::sin(alpha_w)) +
           s * line_of_action_direction();
  }

  double PairKinematics::pinion_tooth_angle(const double s) const
  {
    // The drive flank's tangent point (polar angle centre + psi_b - u) must be T1 at -a_w.
    return s / pinion().base_radius_mm() - alpha_w - pinion().half_base_thickness_angle_rad();
  }

  double PairKinematics::gear_tooth_angle(const double s) const
  {
    // The gear's drive flank touches T2, at polar angle pi - a_w seen from O2.
    return pi - alpha_w - gear().half_base_thickness_angle_rad() + (L - s) / gear().base_radius_mm();
  }

  BodyPlacement PairKinematics::placement(const unsigned int body, const double mesh_phase) const
  {
    const double  s0 = contact_roll_distance_mm(0, mesh_phase);
    BodyPlacement pl;
    if (body == 0)
      pl.rotation_rad = pinion_tooth_angle(s0);
    else
      {
        pl.centre_mm    = {a_w, 0};
        pl.rotation_rad = gear_tooth_angle(s0);
      }
    return pl;
  }

  int PairKinematics::sector_tooth_of_pair(const unsigned int body, const int central_tooth,
                                           const int pair)
  {
    return body == 0 ? central_tooth + pair : central_tooth - pair;
  }

  double PairKinematics::gear_roll_at_mm(const int pair, const double mesh_phase,
                                         const double pinion_roll_mm) const
  {
    return gear_roll_at_mm(pair, mesh_phase, pinion_roll_mm, 0.0);
  }

  double PairKinematics::gear_roll_at_mm(const int pair, const double mesh_phase,
                                         const double pinion_roll_mm, const double z_mm) const
  {
    // The section at z is the mid-face section of a spur pair whose contact line lies at s_j(tau, z)
    // (both gears turned in mesh by their section angles; spur: s_j(tau) exactly).
    const double s_j = contact_roll_distance_mm(pair, mesh_phase, z_mm);
    const double rb1 = pinion().base_radius_mm(), rb2 = gear().base_radius_mm();
    // Pinion flank point P of roll length s' (tangent point at theta_1 = centre + psi_b - u).
    const double    t1 = pinion_tooth_angle(s_j) + pinion().half_base_thickness_angle_rad() -
                      pinion_roll_mm / rb1;
    const Eigen::Vector2d P = rb1 * Eigen::Vector2d(std::cos(t1), std::sin(t1)) +
                              pinion_roll_mm * Eigen::Vector2d(-std::sin(t1), std::cos(t1));
    const Eigen::Vector2d n(std::cos(alpha_w), -std::sin(alpha_w)); // normal to e
    const double          c2 = gear_tooth_angle(s_j) + gear().half_base_thickness_angle_rad();
    const Eigen::Vector2d O2(a_w, 0);
    // Newton on f(v) = (Q(v) - P) . n for the gear flank point Q(v) on the line through P
    // along e; dQ/dv = r_b2 v (cos t2, sin t2). Start from the point P would meet if it lay on
    // the line of action.
    double v = std::max(1e-6, (L - pinion_roll_mm) / rb2);
    for (int it = 0; it < 60; ++it)
      {
        const double          t2 = c2 - v;
        const Eigen::Vector2d Q  = O2 + rb2 * Eigen::Vector2d(std::cos(t2), std::sin(t2)) +
                                  rb2 * v * Eigen::Vector2d(-std::sin(t2), std::cos(t2));
        const double f  = (Q - P).dot(n);
        const double df = rb2 * v * Eigen::Vector2d(std::cos(t2), std::sin(t2)).dot(n);
        HG_REQUIRE_NUMERIC(std::abs(df) > 1e-300, "gap: degenerate gear flank parameter");
        const double step = f / df;
        v -= step;
        if (std::abs(step) <= 1e-15 * std::max(1.0, std::abs(v)))
          break;
      }
    return rb2 * v;
  }

  double PairKinematics::transverse_separation_mm(const int pair, const double mesh_phase,
                                                  const double pinion_roll_mm, const double z_mm) const
  {
    const double s_j = contact_roll_distance_mm(pair, mesh_phase, z_mm);
    const double rb1 = pinion().base_radius_mm(), rb2 = gear().base_radius_mm();
    const double t1  = pinion_tooth_angle(s_j) + pinion().half_base_thickness_angle_rad() -
                      pinion_roll_mm / rb1;
    const Eigen::Vector2d P = rb1 * Eigen::Vector2d(std::cos(t1), std::sin(t1)) +
                              pinion_roll_mm * Eigen::Vector2d(-std::sin(t1), std::cos(t1));
    const double    xi2 = gear_roll_at_mm(pair, mesh_phase, pinion_roll_mm, z_mm);
    const double    v   = xi2 / rb2;
    const double    t2  = gear_tooth_angle(s_j) + gear().half_base_thickness_angle_rad() - v;
    const Eigen::Vector2d Q = Eigen::Vector2d(a_w, 0) +
                              rb2 * Eigen::Vector2d(std::cos(t2), std::sin(t2)) +
                              xi2 * Eigen::Vector2d(-std::sin(t2), std::cos(t2));
    return (Q - P).dot(line_of_action_direction());
  }

  double PairKinematics::separation_mm(const int pair, const double mesh_phase,
                                       const double pinion_roll_mm, const double z_mm) const
  {
    // Normal to the flanks: the transverse distance times cos(beta_b) (exactly 1 spur), plus the
    // removals of both flanks (normal) and the misalignment gap (taken normal as well).
    const double xi2       = gear_roll_at_mm(pair, mesh_phase, pinion_roll_mm, z_mm);
    const double geometric = cos_beta_b * transverse_separation_mm(pair, mesh_phase, pinion_roll_mm, z_mm);
    return geometric + pinion().modification_mm(pinion_roll_mm, z_mm) +
           gear().modification_mm(xi2, z_mm) + misalignment_gap_mm(z_mm);
  }

  double PairKinematics::misalignment_mm() const
  {
    return params.mesh_misalignment_mm + params.axis_inclination_mm * std::sin(alpha_w) +
           params.axis_deviation_mm * std::cos(alpha_w);
  }

  double PairKinematics::misalignment_gap_mm(const double z_mm) const
  {
    return misalignment_mm() * z_mm / face_width_mm();
  }

  double PairKinematics::face_width_mm() const
  {
    return std::min(pinion().face_width_mm(), gear().face_width_mm());
  }

  double PairKinematics::lead_gap_mm(const double z_mm) const
  {
    return pinion().lead_modification_mm(z_mm) + gear().lead_modification_mm(z_mm) +
           misalignment_gap_mm(z_mm);
  }

  std::pair<double, double> PairKinematics::smallest_lead_gap_mm() const
  {
    const double        half = 0.5 * face_width_mm();
    std::vector<double> knots{-half, half};
    for (const GearGeometry *g : {&pinion(), &gear()})
      for (const double z : g->lead_breakpoints_mm())
        if (std::abs(z) < half)
          knots.push_back(z);
    return smallest_piecewise_quadratic([this](const double z) { return lead_gap_mm(z); },
                                        std::move(knots));
  }

  double PairKinematics::rigid_approach_mm(const double mesh_phase) const
  {
    double approach = std::numeric_limits<double>::infinity();
    if (roll_per_face == 0)
      {
        // Spur: the modifications separate into a lead part (z) and a profile part (roll
        // length), so the smallest over the face is the profile part plus the smallest lead part.
        const double lead = smallest_lead_gap_mm().second;
        for (const int j : pairs_in_contact(mesh_phase))
          {
            const double s = contact_roll_distance_mm(j, mesh_phase);
            approach = std::min(approach, pinion().profile_modification_mm(s) +
                                            gear().profile_modification_mm(L - s) + lead);
          }
        return approach;
      }
    // Helical: along the contact line of pair j, s = s_j + k z, the sum of the profile parts at s
    // (pinion) and L - s (gear) and the lead part at z is piecewise quadratic in z, with knots
    // where the line leaves the field of action or the face, at the lead knees and where s or
    // L - s passes a profile knee: the same exact minimum per piece.
    const double half = 0.5 * face_width_mm();
    std::vector<double> rolls[2];
    for (unsigned int body = 0; body < 2; ++body)
      rolls[body] = profile_breakpoints_mm(gears[body]);
    for (const int j : pairs_in_contact(mesh_phase))
      {
        const double s  = contact_roll_distance_mm(j, mesh_phase);
        double       z0 = (s_A - s) / roll_per_face, z1 = (s_E - s) / roll_per_face;
        if (z0 > z1)
          std::swap(z0, z1);
        const double lo = std::max(z0, -half), hi = std::min(z1, half);
        const auto   along = [&](const double z) {
          const double sz = contact_roll_distance_mm(j, mesh_phase, z);
          return pinion().profile_modification_mm(sz) + gear().profile_modification_mm(L - sz) +
                 lead_gap_mm(z);
        };
        if (!(hi > lo)) // the line touches the field at a corner only (pairs_in_contact's tolerance)
          {
            approach = std::min(approach, along(std::min(std::max(lo, -half), half)));
            continue;
          }
        std::vector<double> knots{lo, hi};
        const auto          add = [&](const double z) {
          if (z > lo && z < hi)
            knots.push_back(z);
        };
        for (const GearGeometry *g : {&pinion(), &gear()})
          for (const double z : g->lead_breakpoints_mm())
            add(z);
        for (const double xi : rolls[0])
          add((xi - s) / roll_per_face);
        for (const double xi : rolls[1])
          add((L - xi - s) / roll_per_face);
        approach = std::min(approach, smallest_piecewise_quadratic(along, std::move(knots)).second);
      }
    return approach;
  }

  double PairKinematics::unloaded_gap_mm(const int pair, const double mesh_phase,
                                         const double pinion_roll_mm, const double z_mm) const
  {
    return separation_mm(pair, mesh_phase, pinion_roll_mm, z_mm) - rigid_approach_mm(mesh_phase);
  }
} // namespace hertzgear::meshing
