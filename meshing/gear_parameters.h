#pragma once
// Plain inputs of the meshing stage, in millimetres and radians. The application fills them
// from a scene (app/meshing_setup.h); tests and other tools may fill them directly.
#include <string>

namespace hertzgear::meshing
{
  enum class TipReliefShape
  {
    linear,
    parabolic
  };

  // Hand of a helical gear's teeth: right-handed like a screw thread (the section of a tooth
  // turns counter-clockwise, seen from +z, as z grows) or left-handed. A pair meshes with
  // opposite hands.
  enum class HelixHand
  {
    right,
    left
  };

  // One spur or helical gear cut by an ISO 53 basic rack (generating rack = counterpart of the
  // basic rack). Module and pressure angle are those of the rack, i.e. normal values m_n, alpha_n
  // of a helical gear (ISO 21771); for a spur gear (helix angle 0) they are also transverse.
  struct GearParameters
  {
    int    teeth                         = 0;
    double module_mm                     = 0; // m_n
    double pressure_angle_rad            = 0; // alpha_P = alpha_n of the basic rack
    double helix_angle_rad               = 0; // beta at the reference circle, >= 0; 0 = spur
    HelixHand hand                       = HelixHand::right; // ignored when beta = 0
    double face_width_mm                 = 0; // b
    double profile_shift_coefficient     = 0; // x
    double addendum_coefficient          = 1.0;  // h_aP / m (tip radius when tip_radius_mm = 0)
    double dedendum_coefficient          = 1.25; // h_fP / m = addendum of the cutting rack
    double cutter_tip_radius_coefficient = 0.38; // rho_fP / m
    double tip_radius_mm                 = 0; // r_a; 0 = m z/2 + m (h_aP/m + x)
    double bore_radius_mm                = 0;
    double crowning_mm                   = 0; // beta of Delta(z) = beta (2 z / b)^2
    double tip_relief_mm                 = 0; // C_a at the tip
    double tip_relief_length_mm          = 0; // along the line of action, from the tip
    TipReliefShape tip_relief_shape      = TipReliefShape::linear;
    // Micro-geometry (docs/geometry.md, "Micro-geometry"), each material removed normal to the
    // flank, z measured from mid-face, roll lengths xi from the base tangent point:
    //   helix slope deviation f_Hb:  f_Hb z / b (signed: > 0 removes material at +z)
    //   lead end relief C_b over L_b at both face ends: C_b (|z| - (b/2 - L_b)) / L_b
    //   profile crowning C_a (barrelling) over the active profile [xi_s, xi_a]:
    //     C_a ((2 xi - xi_s - xi_a) / (xi_a - xi_s))^2
    //   root relief C_f over L_f from the start of the active profile: C_f (1 - (xi - xi_s)/L_f)
    double helix_slope_deviation_mm      = 0;
    double lead_end_relief_mm            = 0;
    double lead_end_relief_length_mm     = 0;
    double profile_crowning_mm           = 0;
    double root_relief_mm                = 0;
    double root_relief_length_mm         = 0;
    // Roll length xi_s of the start of the active profile; set by PairKinematics from the mating
    // gear (0: the form circle).
    double active_profile_start_roll_mm  = 0;
    // Reduction of the circular tooth thickness on the reference circle (makes backlash);
    // usually set by PairKinematics from the requested backlash, not by hand.
    double thickness_reduction_mm = 0;
    // Smallest acceptable top land as a multiple of the module: s_a >= 0.2 m is the usual design
    // limit for case-hardened gears (Niemann/Winter, Maschinenelemente II, 21.3).
    double minimum_top_land_coefficient = 0.2;
    std::string name = "gear"; // used in messages: "pinion" or "gear"
  };

  // A spur or helical pair: pinion (driving) and gear (driven); a helical pair has the same helix
  // angle on both gears and opposite hands.
  struct PairParameters
  {
    GearParameters pinion, gear;
    // Operating centre distance a_w; 0 = the tight-mesh distance of the (unthinned) pair, with
    // backlash_loa_mm made by thinning both gears equally.
    double center_distance_mm = 0;
    // Total backlash along the (transverse) line of action j_bn, used when center_distance_mm = 0.
    double backlash_loa_mm = 0;
    // Shaft misalignment, each as the difference over the face width b [mm] (ISO 6336-1,
    // ISO/TR 10064-3): the mesh misalignment f_ma along the line of action, the inclination
    // f_Sd of the axes in their common plane and their deviation f_Sb across it. Together they
    // open the gap along the line of action by f_eq z / b, f_eq = f_ma + f_Sd sin(alpha_w) +
    // f_Sb cos(alpha_w) (signed: > 0 opens the +z end).
    double mesh_misalignment_mm = 0;
    double axis_inclination_mm  = 0;
    double axis_deviation_mm    = 0;
  };
} // namespace hertzgear::meshing
