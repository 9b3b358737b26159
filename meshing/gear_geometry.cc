#include "meshing/gear_geometry.h"

#include "common/errors.h"
#include "meshing/field_names.h"
#include "meshing/involute.h"

#include <cmath>
#include <limits>

namespace hertzgear::meshing
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
  }

  Eigen::Vector2d GearGeometry::rotate(const Eigen::Vector2d &p, const double angle)
  {
    const double c = std::cos(angle), s = std::sin(angle);
    return {c * p.x() - s * p.y(), s * p.x() + c * p.y()};
  }

  double transverse_module_mm(const GearParameters &p)
  {
    return p.helix_angle_rad == 0 ? p.module_mm : p.module_mm / std::cos(p.helix_angle_rad);
  }

  double transverse_pressure_angle_rad(const GearParameters &p)
  {
    // atan(tan(alpha) / 1) need not return alpha to the last bit: spur skips the conversion.
    return p.helix_angle_rad == 0 ?
             p.pressure_angle_rad :
             std::atan(std::tan(p.pressure_angle_rad) / std::cos(p.helix_angle_rad));
  }

  double base_helix_angle_rad(const GearParameters &p)
  {
    return std::asin(std::sin(p.helix_angle_rad) * std::cos(p.pressure_angle_rad));
  }

  double pitch_radius_mm(const GearParameters &p) { return 0.5 * transverse_module_mm(p) * p.teeth; }

  double base_radius_mm(const GearParameters &p)
  {
    return pitch_radius_mm(p) * std::cos(transverse_pressure_angle_rad(p));
  }

  double root_radius_mm(const GearParameters &p)
  {
    const double m = p.module_mm;
    return pitch_radius_mm(p) + p.profile_shift_coefficient * m - p.dedendum_coefficient * m;
  }

  double disc_inertia_kg_m2(const GearParameters &p, const double density_kg_per_m3)
  {
    const double r_f  = 1e-3 * root_radius_mm(p);
    const double r_in = 1e-3 * p.bore_radius_mm;
    return density_kg_per_m3 * 1e-3 * p.face_width_mm * M_PI *
           (std::pow(r_f, 4) - std::pow(r_in, 4)) / 2.0;
  }

  GearGeometry::GearGeometry(const GearParameters &parameters) : params(parameters)
  {
    const auto  &p    = params;
    const auto   name = p.name;
    HG_REQUIRE_INPUT(p.teeth >= 6, name, ": ", p.teeth, " teeth is too few for a spur gear (>= 6; ",
                     field(p, "teeth"), ")");
    HG_REQUIRE_INPUT(p.module_mm > 0 && std::isfinite(p.module_mm), name, ": module ",
                     p.module_mm, " mm must be positive (", field(p, "module_mm"), ")");
    HG_REQUIRE_INPUT(p.face_width_mm > 0, name, ": face width ", p.face_width_mm,
                     " mm must be positive (", field(p, "face_width_mm"), ")");
    HG_REQUIRE_INPUT(p.pressure_angle_rad > 0 && p.pressure_angle_rad < pi / 4, name,
                     ": pressure angle ", p.pressure_angle_rad * 180 / pi,
                     " deg is outside (0, 45) deg (", field(p, "pressure_angle_rad"), ")");
    HG_REQUIRE_INPUT(p.helix_angle_rad >= 0 && p.helix_angle_rad < pi / 4, name, ": helix angle ",
                     p.helix_angle_rad * 180 / pi, " deg is outside [0, 45) deg (",
                     field(p, "helix_angle_rad"), ")");
    // A spur tooth narrower than half a module or wider than 50 modules is a plate or a
    // strip, not a gear tooth: the beam/plate assumptions behind every stiffness model fail.
    HG_REQUIRE_INPUT(p.face_width_mm >= 0.5 * p.module_mm && p.face_width_mm <= 50 * p.module_mm,
                     name, ": absurd dimensions: face width ", p.face_width_mm, " mm with module ",
                     p.module_mm, " mm (b/m = ", p.face_width_mm / p.module_mm,
                     "; a spur gear needs 0.5 <= b/m <= 50; ", field(p, "face_width_mm"), ", ",
                     field(p, "module_mm"), ")");
    HG_REQUIRE_INPUT(p.cutter_tip_radius_coefficient >= 0, name,
                     ": cutter tip radius coefficient must be >= 0 (",
                     field(p, "cutter_tip_radius_coefficient"), ")");

    // The transverse section: module m_t, pressure angle alpha_t (exactly m and alpha_n for a
    // spur gear); heights (addendum, dedendum, profile shift x m, the rack's round) stay normal
    // ones. The transverse tooth thickness on the reference circle is m_t (pi/2 + 2 x tan(alpha_n))
    // (ISO 21771:2007, 5.3), thinned by thickness_reduction_mm.
    const double m = p.module_mm, alpha_n = p.pressure_angle_rad, x = p.profile_shift_coefficient;
    m_t     = meshing::transverse_module_mm(p);
    alpha_t = meshing::transverse_pressure_angle_rad(p);
    r     = meshing::pitch_radius_mm(p);
    r_b   = meshing::base_radius_mm(p);
    s_ref = m_t * (0.5 * pi + 2 * x * std::tan(alpha_n)) - p.thickness_reduction_mm;
    psi_b = s_ref / (2 * r) + involute(alpha_t);
    r_a   = p.tip_radius_mm > 0 ? p.tip_radius_mm : r + m * (p.addendum_coefficient + x);
    r_f   = meshing::root_radius_mm(p);
    HG_REQUIRE_INPUT(r_f > 0, name, ": absurd dimensions: root radius ", r_f,
                     " mm is not positive (teeth ", p.teeth, ", dedendum ",
                     p.dedendum_coefficient, " m, profile shift ", x, "; ", field(p, "teeth"), ", ",
                     field(p, "dedendum_coefficient"), ", ", field(p, "profile_shift_coefficient"), ")");

    // Generating rack, in the generation frame: gear centre at the origin, the rack's rolling
    // line tangent to the reference circle at y = r, the cutter tooth centred on x = 0 filling
    // the tooth space. Its right flank x = e/2 + (y - r) tan(alpha_t) generates the +theta flank
    // of the tooth to the right of the space. e = pi m_t - s is the space width on the reference
    // circle, i.e. the cutter tooth thickness on its rolling line (thinning widens it).
    // Helical: the rack's transverse section (pitch pi m_t, flank angle alpha_t); its tip round
    // is taken as the circle of radius rho, while the true section of the round is an ellipse of
    // semi-axes rho and rho / cos(beta): the fillet and the form radius are exact for spur only.
    rho            = p.cutter_tip_radius_coefficient * m;
    const double e = pi * m_t - s_ref;
    y_c            = r + x * m - p.dedendum_coefficient * m + rho;
    x_c            = 0.5 * e + (y_c - r) * std::tan(alpha_t) - rho / std::cos(alpha_t);
    HG_REQUIRE_INPUT(x_c >= 0, name, ": cutter tip radius rho_fP = ",
                     p.cutter_tip_radius_coefficient, " m is too large for the rack's tip (the "
                     "rounds of both cutter flanks overlap; ",
                     field(p, "cutter_tip_radius_coefficient"), ")");
    HG_REQUIRE_INPUT(r - y_c > 0, name, ": profile shift x = ", x,
                     " puts the centre of the cutter's tip round outside the reference circle "
                     "(x must be below (h_fP - rho_fP)/m = ",
                     p.dedendum_coefficient - p.cutter_tip_radius_coefficient, "; ",
                     field(p, "profile_shift_coefficient"), ")");
    // The round touches the straight cutter flank at T; the involute starts where T is
    // generated, i.e. when T lies on the rack's line of action through the pitch point I.
    const double y_T           = y_c - rho * std::sin(alpha_t);
    const double roll_length_F = r * std::sin(alpha_t) - (r - y_T) / std::sin(alpha_t);
    // Undercut: the generating flank reaches below the interference point (the base tangent
    // point of the line of action), i.e. the involute would have to start inside the base
    // circle (ISO 21771:2007, 5.2; z_min = 2 cos(beta) (h_fP/m - rho (1 - sin a) / m - x) /
    // sin^2 a with a = alpha_t).
    const double x_min =
      (p.dedendum_coefficient - p.cutter_tip_radius_coefficient * (1 - std::sin(alpha_t))) -
      0.5 * p.teeth / std::cos(p.helix_angle_rad) * std::sin(alpha_t) * std::sin(alpha_t);
    HG_REQUIRE_INPUT(roll_length_F >= -1e-12 * m, name, ": undercut: ", p.teeth,
                     " teeth with profile shift x = ", x,
                     " are undercut by the cutter (the involute would start below the base "
                     "circle); use a profile shift x >= ",
                     x_min, " or more teeth (", field(p, "profile_shift_coefficient"), ", ",
                     field(p, "teeth"), ")");
    u_F = std::max(0.0, roll_length_F) / r_b;
    r_F = r_b * std::sqrt(1 + u_F * u_F);
    phi_form = (x_c - (r - y_c) / std::tan(alpha_t)) / r;
    phi_root = x_c / r;

    HG_REQUIRE_INPUT(r_a > r_F, name, ": tip radius ", r_a,
                     " mm is not above the form radius ", r_F,
                     " mm where the involute starts: the tooth has no involute flank (",
                     field(p, "tip_radius_mm"), ", ", field(p, "addendum_coefficient"), ")");
    u_a = roll_angle_at_radius(r_a);
    check();
  }

  void GearGeometry::check() const
  {
    const auto  &p    = params;
    const double m    = p.module_mm;
    const double s_a  = tooth_thickness_mm(r_a);
    const double limit = p.minimum_top_land_coefficient * m;
    HG_REQUIRE_INPUT(s_a >= limit, p.name, ": pointed tip: the top land is ", s_a,
                     " mm at the tip radius ", r_a, " mm, below the limit ",
                     p.minimum_top_land_coefficient, " m = ", limit,
                     " mm; reduce the tip radius (", field(p, "tip_radius_mm"),
                     ", or ", field(p, "addendum_coefficient"), " when it is 0) or the profile shift (",
                     field(p, "profile_shift_coefficient"), ")");
    HG_REQUIRE_INPUT(p.tip_relief_mm >= 0 && p.tip_relief_length_mm >= 0 && p.crowning_mm >= 0,
                     p.name, ": crowning and tip relief must be >= 0 (", field(p, "crowning_mm"), ", ",
                     field(p, "tip_relief_mm"), ", ", field(p, "tip_relief_length_mm"), ")");
    HG_REQUIRE_INPUT(p.lead_end_relief_mm >= 0 && p.lead_end_relief_length_mm >= 0 &&
                       p.profile_crowning_mm >= 0 && p.root_relief_mm >= 0 &&
                       p.root_relief_length_mm >= 0,
                     p.name, ": lead end relief, profile crowning and root relief must be >= 0 (",
                     field(p, "lead_end_relief_mm"), ", ", field(p, "lead_end_relief_length_mm"), ", ",
                     field(p, "profile_crowning_mm"), ", ", field(p, "root_relief_mm"), ", ",
                     field(p, "root_relief_length_mm"), ")");
    HG_REQUIRE_INPUT(p.lead_end_relief_length_mm <= 0.5 * p.face_width_mm, p.name,
                     ": lead end relief length ", p.lead_end_relief_length_mm,
                     " mm is larger than the flank allows: the reliefs at both face ends meet "
                     "beyond half the face width (", 0.5 * p.face_width_mm, " mm; ",
                     field(p, "lead_end_relief_length_mm"), ")");
    // The modifications remove material normal to the flank, Delta / cos(beta_b) in the transverse
    // section; at the tip this thins the tooth by 2 Delta / cos(beta_b) / cos(alpha_a) (an involute
    // moved by Delta normal is the same involute turned by Delta / r_b). The corners at the face
    // ends must keep the minimum top land.
    const double alpha_a = std::acos(r_b / r_a);
    const double removal = p.crowning_mm + p.tip_relief_mm + p.profile_crowning_mm +
                           p.lead_end_relief_mm + 0.5 * std::abs(p.helix_slope_deviation_mm);
    const double cos_beta_b = std::cos(base_helix_angle_rad(p)); // exactly 1 for a spur gear
    const double s_a_mod    = s_a - 2 * removal / cos_beta_b / std::cos(alpha_a);
    HG_REQUIRE_INPUT(s_a_mod >= limit, p.name, ": crowning ", p.crowning_mm * 1e3,
                     " um and tip relief ", p.tip_relief_mm * 1e3, " um",
                     (removal > p.crowning_mm + p.tip_relief_mm ?
                        " with the other micro-geometry (" +
                          std::to_string((removal - p.crowning_mm - p.tip_relief_mm) * 1e3) +
                          " um at the tip corners)" :
                        std::string()),
                     " are larger than the geometry allows: they leave a top land of ", s_a_mod,
                     " mm at the face ends, below the limit ", limit, " mm (",
                     field(p, "crowning_mm"), ", ", field(p, "tip_relief_mm"), ")");
    const double usable_mm = r_b * (u_a - u_F);
    HG_REQUIRE_INPUT(p.tip_relief_length_mm <= usable_mm, p.name, ": tip relief length ",
                     p.tip_relief_length_mm, " mm is larger than the geometry allows: the involute "
                     "flank is only ", usable_mm, " mm long along the line of action (",
                     field(p, "tip_relief_length_mm"), ")");
    HG_REQUIRE_INPUT(p.tip_relief_length_mm + p.root_relief_length_mm <= usable_mm, p.name,
                     ": tip relief length ", p.tip_relief_length_mm, " mm and root relief length ",
                     p.root_relief_length_mm, " mm are larger than the flank allows: the involute "
                     "flank is only ", usable_mm, " mm long along the line of action (",
                     field(p, "tip_relief_length_mm"), ", ", field(p, "root_relief_length_mm"), ")");
  }

  double GearGeometry::angular_pitch_rad() const
  {
    return 2 * pi / params.teeth;
  }

  double GearGeometry::base_pitch_mm() const
  {
    return pi * m_t * std::cos(alpha_t);
  }

  double GearGeometry::roll_angle_at_radius(const double radius) const
  {
    return std::sqrt(std::max(0.0, radius * radius / (r_b * r_b) - 1));
  }

  double GearGeometry::flank_polar_angle_rad(const double radius) const
  {
    const double u = roll_angle_at_radius(radius);
    return psi_b - (u - std::atan(u));
  }

  double GearGeometry::tooth_thickness_mm(const double radius) const
  {
    return 2 * radius * flank_polar_angle_rad(radius);
  }

  Eigen::Vector2d GearGeometry::involute_point(const double u) const
  {
    // Tangent point at polar angle psi_b - u, string of length r_b u wound off counter-clockwise.
    const double t = psi_b - u;
    return {r_b * (std::cos(t) - u * std::sin(t)), r_b * (std::sin(t) + u * std::cos(t))};
  }

  Eigen::Vector2d GearGeometry::involute_normal(const double u) const
  {
    // The normal of an involute is its generating string, tangent to the base circle at the
    // tangent point (polar angle t); on the +theta flank the string runs counter-clockwise,
    // away from the tooth's centre line, so its direction is the outward normal.
    const double t = psi_b - u;
    return {-std::sin(t), std::cos(t)};
  }

  Eigen::Vector2d GearGeometry::fillet_point_generation_frame(const double phi) const
  {
    // Rack shifted by -r phi while the gear turns by phi: the round's centre in the fixed
    // frame; the envelope point lies on the line from the pitch point I = (0, r) through the
    // centre (the contact normal passes through the instantaneous centre), on the far side.
    const Eigen::Vector2d centre(x_c - r * phi, y_c);
    const Eigen::Vector2d I(0, r);
    const Eigen::Vector2d dir  = (centre - I).normalized();
    const Eigen::Vector2d pnt  = centre + rho * dir;
    return rotate(pnt, -phi);
  }

  Eigen::Vector2d GearGeometry::fillet_point(const double t) const
  {
    const double phi = phi_root + t * (phi_form - phi_root);
    // Generation frame -> tooth frame: the tooth right of the space (centred at pi/2 - pi/z)
    // is turned onto the +x axis.
    return rotate(fillet_point_generation_frame(phi), -(0.5 * pi - pi / params.teeth));
  }

  double GearGeometry::root_fillet_angle_rad() const
  {
    return pi / params.teeth - phi_root;
  }

  double GearGeometry::crowning_mm(const double z_mm) const
  {
    const double q = 2 * z_mm / params.face_width_mm;
    return params.crowning_mm * q * q;
  }

  double GearGeometry::tip_relief_mm(const double roll_length_mm) const
  {
    if (params.tip_relief_mm <= 0 || params.tip_relief_length_mm <= 0)
      return 0;
    const double start = r_b * u_a - params.tip_relief_length_mm;
    if (roll_length_mm <= start)
      return 0;
    const double q = (roll_length_mm - start) / params.tip_relief_length_mm;
    return params.tip_relief_mm * (params.tip_relief_shape == TipReliefShape::linear ? q : q * q);
  }

  double GearGeometry::lead_modification_mm(const double z_mm) const
  {
    const auto  &p     = params;
    double       value = crowning_mm(z_mm) + p.helix_slope_deviation_mm * z_mm / p.face_width_mm;
    const double knee  = 0.5 * p.face_width_mm - p.lead_end_relief_length_mm;
    if (p.lead_end_relief_mm > 0 && p.lead_end_relief_length_mm > 0 && std::abs(z_mm) > knee)
      value += p.lead_end_relief_mm * (std::abs(z_mm) - knee) / p.lead_end_relief_length_mm;
    return value;
  }

  std::vector<double> GearGeometry::lead_breakpoints_mm() const
  {
    if (params.lead_end_relief_mm <= 0 || params.lead_end_relief_length_mm <= 0)
      return {};
    const double knee = 0.5 * params.face_width_mm - params.lead_end_relief_length_mm;
    return {-knee, knee};
  }

  double GearGeometry::profile_modification_mm(const double roll_length_mm) const
  {
    const auto  &p     = params;
    double       value = tip_relief_mm(roll_length_mm);
    const double xi_s  = std::max(p.active_profile_start_roll_mm, r_b * u_F);
    const double xi_a  = r_b * u_a;
    if (p.profile_crowning_mm > 0 && xi_a > xi_s)
      {
        const double q = (2 * roll_length_mm - xi_s - xi_a) / (xi_a - xi_s);
        value += p.profile_crowning_mm * q * q;
      }
    if (p.root_relief_mm > 0 && p.root_relief_length_mm > 0 &&
        roll_length_mm < xi_s + p.root_relief_length_mm)
      value += p.root_relief_mm * (1 - (roll_length_mm - xi_s) / p.root_relief_length_mm);
    return value;
  }

  double GearGeometry::crowning_radius_mm() const
  {
    if (params.crowning_mm <= 0)
      return std::numeric_limits<double>::infinity();
    return params.face_width_mm * params.face_width_mm / (8 * params.crowning_mm);
  }

  GearGeometry::HalfProfile GearGeometry::half_profile(const unsigned int n_root,
                                                       const unsigned int n_fillet,
                                                       const unsigned int n_flank) const
  {
    HalfProfile hp;
    const double a0 = pi / params.teeth, a1 = root_fillet_angle_rad();
    for (unsigned int i = 0; i <= n_root; ++i)
      {
        const double a = a0 + (a1 - a0) * i / n_root;
        hp.root_arc.emplace_back(r_f * std::cos(a), r_f * std::sin(a));
      }
    for (unsigned int i = 0; i <= n_fillet; ++i)
      hp.fillet.push_back(fillet_point(double(i) / n_fillet));
    // Equal steps in roll length cluster points where the curvature is high (near the base).
    for (unsigned int i = 0; i <= n_flank; ++i)
      hp.flank.push_back(involute_point(u_F + (u_a - u_F) * i / n_flank));
    return hp;
  }
} // namespace hertzgear::meshing
