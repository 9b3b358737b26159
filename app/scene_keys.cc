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
        {"torque_map_percent", "Stiffness/Map/torque_percent"},
        {"crowning_map_mm", "Stiffness/Map/crowning_um"},
        {"misalignment_map_mm", "Stiffness/Map/mesh_misalignment_um"},
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
        {"steps_per_period", "Dynamics/steps_per_period"},
        {"periods", "Dynamics/periods"},
        {"transient_periods", "Dynamics/transient_periods"}};
      return keys;
    }
  } // namespace

  std::string with_scene_keys(const std::string &text)
  {
    std::string out = text;
    for (std::size_t open = out.find('{'); open != std::string::npos; open = out.find('{', open + 1))
      {
        const std::size_t close = out.find('}', open);
        if (close == std::string::npos)
          break;
        const auto it = scene_keys().find(out.substr(open + 1, close - open - 1));
        if (it != scene_keys().end())
          out.replace(open, close - open + 1, it->second);
      }
    return out;
  }

  std::string scene_message(const ParameterError &error)
  {
    const auto it = scene_keys().find(error.parameter());
    return (it == scene_keys().end() ? error.parameter() : it->second) + " = " +
           with_scene_keys(error.text());
  }
} // namespace hertzgear
