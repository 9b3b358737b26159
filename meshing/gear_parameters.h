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

  // One spur gear cut by an ISO 53 basic rack (generating rack = counterpart of the basic rack).
  struct GearParameters
  {
    int    teeth                         = 0;
    double module_mm                     = 0;
    double pressure_angle_rad            = 0; // alpha_P of the basic rack
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
    // Reduction of the circular tooth thickness on the reference circle (makes backlash);
    // usually set by PairKinematics from the requested backlash, not by hand.
    double thickness_reduction_mm = 0;
    // Smallest acceptable top land as a multiple of the module: s_a >= 0.2 m is the usual design
    // limit for case-hardened gears (Niemann/Winter, Maschinenelemente II, 21.3).
    double minimum_top_land_coefficient = 0.2;
    std::string name = "gear"; // used in messages: "pinion" or "gear"
  };

  // A spur pair: pinion (driving) and gear (driven).
  struct PairParameters
  {
    GearParameters pinion, gear;
    // Operating centre distance a_w; 0 = the tight-mesh distance of the (unthinned) pair, with
    // backlash_loa_mm made by thinning both gears equally.
    double center_distance_mm = 0;
    // Total backlash along the line of action j_bn, used when center_distance_mm = 0.
    double backlash_loa_mm = 0;
  };
} // namespace hertzgear::meshing
