#include "meshing/geometry_json.h"

#include <cmath>
#include <string>

namespace hertzgear::meshing
{
  namespace
  {
    nlohmann::json gear_json(const GearGeometry &g)
    {
      nlohmann::json j;
      j["teeth"]                   = g.n_teeth();
      j["reference_radius_mm"]     = g.reference_radius_mm();
      j["base_radius_mm"]          = g.base_radius_mm();
      j["tip_radius_mm"]           = g.tip_radius_mm();
      j["root_radius_mm"]          = g.root_radius_mm();
      j["form_radius_mm"]          = g.form_radius_mm();
      j["bore_radius_mm"]          = g.bore_radius_mm();
      j["reference_tooth_thickness_mm"] = g.reference_tooth_thickness_mm();
      j["top_land_mm"]             = g.top_land_mm();
      j["thickness_reduction_mm"]  = g.parameters().thickness_reduction_mm;
      const double R               = g.crowning_radius_mm();
      j["crowning_radius_mm"]      = std::isfinite(R) ? nlohmann::json(R) : nlohmann::json(nullptr);
      j["crowning_um"]             = g.parameters().crowning_mm * 1e3;
      return j;
    }
  } // namespace

  nlohmann::json pair_json(const PairKinematics &pair)
  {
    constexpr double rad_to_deg = 180.0 / M_PI;
    nlohmann::json   j;
    j["contact_ratio"]                = pair.contact_ratio(); // transverse, eps_alpha
    j["helix_angle_deg"]              = pair.helix_angle_rad() * rad_to_deg;
    j["base_helix_angle_deg"]         = pair.base_helix_angle_rad() * rad_to_deg;
    j["face_contact_ratio"]           = pair.face_contact_ratio();  // eps_beta
    j["total_contact_ratio"]          = pair.total_contact_ratio(); // eps_gamma
    j["center_distance_mm"]           = pair.center_distance_mm();
    j["reference_center_distance_mm"] = pair.reference_center_distance_mm();
    j["operating_pressure_angle_deg"] = pair.operating_pressure_angle_rad() * rad_to_deg;
    j["base_pitch_mm"]                = pair.base_pitch_mm();
    j["path_of_contact_mm"]           = pair.path_of_contact_mm();
    j["line_of_action_length_mm"]     = pair.line_of_action_length_mm();
    j["backlash_loa_mm"]              = pair.backlash_loa_mm();
    j["pinion"]                       = gear_json(pair.pinion());
    j["gear"]                         = gear_json(pair.gear());
    j["pinion"]["operating_pitch_radius_mm"] = pair.operating_pitch_radius_mm(0);
    j["gear"]["operating_pitch_radius_mm"]   = pair.operating_pitch_radius_mm(1);
    for (const char c : {'A', 'B', 'C', 'D', 'E'})
      {
        const auto p = pair.point(c);
        j["points"][std::string(1, c)] = {{"roll_distance_mm", p.roll_distance_mm},
                                          {"rho_pinion_mm", p.rho_pinion_mm},
                                          {"rho_gear_mm", p.rho_gear_mm},
                                          {"radius_pinion_mm", p.radius_pinion_mm},
                                          {"radius_gear_mm", p.radius_gear_mm}};
      }
    return j;
  }
} // namespace hertzgear::meshing
