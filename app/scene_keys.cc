#include "app/scene_keys.h"

#include <map>

namespace hertzgear
{
  namespace
  {
    // Fields of the libraries' plain inputs (stiffness::StiffnessInput, the dynamics' settings, the
    // mesher's settings) and the scene keys app/ fills them from.
    const std::map<std::string, std::string> &scene_keys()
    {
      static const std::map<std::string, std::string> keys = {
        {"torque_Nm", "Operating/torque_Nm"},
        {"mesh_misalignment_mm", "Operating/mesh_misalignment_um"},
        {"axis_inclination_mm", "Operating/axis_inclination_um"},
        {"axis_deviation_mm", "Operating/axis_deviation_um"},
        {"center_distance_mm", "Operating/center_distance_mm"},
        {"backlash_loa_mm", "Operating/backlash_mm"},
        {"torque_map_percent", "Stiffness/Map/torque_percent"},
        {"crowning_map_mm", "Stiffness/Map/crowning_um"},
        {"misalignment_map_mm", "Stiffness/Map/mesh_misalignment_um"},
        {"helix_slope_map_mm", "Stiffness/Map/helix_slope_deviation_um"},
        {"map_combination", "Stiffness/Map/combination"},
        {"load_ladder_percent", "Stiffness/load_ladder_percent"},
        {"positions_per_cycle", "Stiffness/positions_per_cycle"},
        {"harmonics", "Stiffness/harmonics"},
        {"hertz_exponent", "Stiffness/hertz_exponent"},
        {"source", "Stiffness/source"},
        {"table_file", "Stiffness/table_file"},
        {"dimension", "Stiffness/fe_dimension"},
        {"level", "Stiffness/fe_level"},
        {"degree", "Stiffness/fe_degree"},
        {"teeth_per_sector", "Mesh/teeth_per_sector"},
        {"body_model", "Mesh/body_model"},
        {"face_width_layers", "Mesh/face_width_layers"},
        {"contact_grid_profile_cells", "Stiffness/contact_grid_profile_points"},
        {"contact_grid_face_cells", "Stiffness/contact_grid_face_points"},
        {"contact_max_iterations", "Stiffness/contact_max_iterations"},
        {"reference_depth_mm", "Stiffness/reference_depth_mm"},
        {"table_face_nodes", "Stiffness/table_face_nodes"},
        {"table_roll_nodes", "Stiffness/table_roll_nodes"},
        {"linear_solver", "Stiffness/linear_solver"},
        {"linear_solver_tolerance", "Stiffness/linear_solver_tolerance"},
        {"k_hertz_mean", "Stiffness/Fourier/k_hertz_mean_N_per_m_pow_n"},
        {"ste_excitation", "Effects/ste_excitation"},
        {"integrator", "Dynamics/integrator"},
        {"relative_tolerance", "Dynamics/relative_tolerance"},
        {"shooting_relative_tolerance", "Response/relative_tolerance"},
        {"steps_per_period", "Dynamics/steps_per_period"},
        {"periods", "Dynamics/periods"},
        {"transient_periods", "Dynamics/transient_periods"}};
      return keys;
    }

    // `text` with every {field} that `key_of` names (a key not empty) replaced by its key.
    std::string with_keys(std::string                                            text,
                          const std::function<std::string(const std::string &)> &key_of)
    {
      for (std::size_t open = text.find('{'); open != std::string::npos; open = text.find('{', open + 1))
        {
          const std::size_t close = text.find('}', open);
          if (close == std::string::npos)
            break;
          const std::string key = key_of(text.substr(open + 1, close - open - 1));
          if (!key.empty())
            text.replace(open, close - open + 1, key);
        }
      return text;
    }

    // Fields of one gear (meshing::GearParameters) whose scene key under "Gear pair/Pinion/" or
    // "Gear pair/Gear/" has another name; every other field is its own key
    // (app/meshing_setup.cc fills them).
    const std::map<std::string, std::string> &gear_keys()
    {
      static const std::map<std::string, std::string> keys = {
        {"pressure_angle_rad", "pressure_angle_deg"},
        {"helix_angle_rad", "helix_angle_deg"},
        {"crowning_mm", "crowning_um"},
        {"tip_relief_mm", "tip_relief_um"},
        {"helix_slope_deviation_mm", "helix_slope_deviation_um"},
        {"lead_end_relief_mm", "lead_end_relief_um"},
        {"profile_crowning_mm", "profile_crowning_um"},
        {"root_relief_mm", "root_relief_um"}};
      return keys;
    }

    // The scene key of a field, or empty. A gear's field is named "pinion.<field>" or
    // "gear.<field>" (meshing::field).
    std::string scene_key(const std::string &field)
    {
      for (const auto &[gear, section] : {std::pair<std::string, std::string>{"pinion.", "Gear pair/Pinion/"},
                                          std::pair<std::string, std::string>{"gear.", "Gear pair/Gear/"}})
        if (field.rfind(gear, 0) == 0)
          {
            const std::string own = field.substr(gear.size());
            const auto        it  = gear_keys().find(own);
            return section + (it == gear_keys().end() ? own : it->second);
          }
      const auto it = scene_keys().find(field);
      return it == scene_keys().end() ? std::string() : it->second;
    }
  } // namespace

  std::string with_scene_keys(const std::string &text) { return with_keys(text, scene_key); }

  std::string scene_message(const ParameterError &error)
  {
    const std::string key = scene_key(error.parameter());
    return (key.empty() ? error.parameter() : key) + " = " + with_scene_keys(error.text());
  }

  std::string keyed_message(const ParameterError                                   &error,
                            const std::function<std::string(const std::string &)> &key_of)
  {
    return key_of(error.parameter()) + " = " + with_keys(error.text(), key_of);
  }
} // namespace hertzgear
