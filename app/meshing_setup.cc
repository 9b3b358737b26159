#include "app/meshing_setup.h"

#include <cmath>

namespace hertzgear
{
  meshing::GearParameters gear_parameters(const GearScene &g, const std::string &name)
  {
    meshing::GearParameters p;
    p.teeth                         = g.teeth;
    p.module_mm                     = g.module_mm;
    p.pressure_angle_rad            = g.pressure_angle_deg * M_PI / 180;
    p.face_width_mm                 = g.face_width_mm;
    p.helix_angle_rad               = g.helix_angle_deg * M_PI / 180;
    p.hand = g.hand == "left" ? meshing::HelixHand::left : meshing::HelixHand::right;
    p.profile_shift_coefficient     = g.profile_shift_coefficient;
    p.addendum_coefficient          = g.addendum_coefficient;
    p.dedendum_coefficient          = g.dedendum_coefficient;
    p.cutter_tip_radius_coefficient = g.cutter_tip_radius_coefficient;
    p.tip_radius_mm                 = g.tip_radius_mm;
    p.bore_radius_mm                = g.bore_radius_mm;
    p.crowning_mm                   = g.crowning_um * 1e-3;
    p.tip_relief_mm                 = g.tip_relief_um * 1e-3;
    p.tip_relief_length_mm          = g.tip_relief_length_mm;
    p.tip_relief_shape = g.tip_relief_shape == "parabolic" ? meshing::TipReliefShape::parabolic :
                                                             meshing::TipReliefShape::linear;
    p.helix_slope_deviation_mm  = g.helix_slope_deviation_um * 1e-3;
    p.lead_end_relief_mm        = g.lead_end_relief_um * 1e-3;
    p.lead_end_relief_length_mm = g.lead_end_relief_length_mm;
    p.profile_crowning_mm       = g.profile_crowning_um * 1e-3;
    p.root_relief_mm            = g.root_relief_um * 1e-3;
    p.root_relief_length_mm     = g.root_relief_length_mm;
    p.name = name;
    return p;
  }

  meshing::PairParameters pair_parameters(const Scene &scene)
  {
    meshing::PairParameters p;
    p.pinion             = gear_parameters(scene.pinion, "pinion");
    p.gear               = gear_parameters(scene.gear, "gear");
    p.center_distance_mm = scene.operating.center_distance_mm;
    p.backlash_loa_mm    = scene.operating.center_distance_mm > 0 ? 0 : scene.operating.backlash_mm;
    p.mesh_misalignment_mm = scene.operating.mesh_misalignment_um * 1e-3;
    p.axis_inclination_mm  = scene.operating.axis_inclination_um * 1e-3;
    p.axis_deviation_mm    = scene.operating.axis_deviation_um * 1e-3;
    return p;
  }

  meshing::PairKinematics make_pair(const Scene &scene)
  {
    return meshing::PairKinematics(pair_parameters(scene));
  }
} // namespace hertzgear
