#pragma once
// The scene: every value a user may set, in the units gear engineers use (unit in the name),
// resolved into plain structs. Parsing, range checks and help texts live in scene.cc (on
// common/parameter_file); stages take plain values.
#include "common/material.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hertzgear
{
  struct GearScene
  {
    int         teeth                         = 0;
    double      module_mm                     = 0;
    double      pressure_angle_deg            = 0;
    double      face_width_mm                 = 0;
    double      helix_angle_deg               = 0; // beta at the reference circle; 0 = spur
    std::string hand;                              // right | left (ignored for a spur gear)
    double      profile_shift_coefficient     = 0; // x, in modules
    double      addendum_coefficient          = 0; // h_aP / m of the basic rack
    double      dedendum_coefficient          = 0; // h_fP / m of the basic rack
    double      cutter_tip_radius_coefficient = 0; // rho_fP / m of the basic rack
    double      tip_radius_mm                 = 0; // 0: from addendum and profile shift
    double      bore_radius_mm                = 0;
    double      crowning_um                   = 0; // lead crowning amplitude beta
    double      tip_relief_um                 = 0; // C_a at the tip
    double      tip_relief_length_mm          = 0; // along the line of action, from the tip
    std::string tip_relief_shape;                  // linear | parabolic
    double      helix_slope_deviation_um      = 0; // f_Hb over the face width, signed
    double      lead_end_relief_um            = 0; // C_b at both face ends
    double      lead_end_relief_length_mm     = 0; // L_b from each face end
    double      profile_crowning_um           = 0; // C_a (barrelling) over the active profile
    double      root_relief_um                = 0; // C_f at the start of the active profile
    double      root_relief_length_mm         = 0; // L_f along the line of action
  };

  struct OperatingScene
  {
    double torque_Nm          = 0; // on the pinion
    double speed_rpm          = 0; // of the pinion
    double center_distance_mm = 0; // 0: tight-mesh distance, backlash from thinned teeth
    double backlash_mm        = 0; // total, along the line of action
    double mesh_misalignment_um = 0; // f_ma along the line of action over the face width
    double axis_inclination_um  = 0; // f_Sd over the face width
    double axis_deviation_um    = 0; // f_Sb over the face width
  };

  struct EffectsScene
  {
    std::string mesh_force_law;           // auto | serial-hertz | fe-map
    std::string backlash;                 // on | off
    std::string hertzian_layer;           // dynamic | quasi-static | off
    std::string contact_damping;          // hunt-crossley | lankarani-nikravesh | viscous-only
    std::string mesh_stiffness_variation; // fourier | constant   (k_h)
    std::string rest_stiffness_variation; // constant | fourier   (k)
    std::string ste_excitation;           // off | table
  };

  struct FourierScene
  {
    double              k_rest_mean_N_per_m = 0;
    std::vector<double> k_rest_amplitudes_N_per_m;
    std::vector<double> k_rest_phases_rad;
    double              k_hertz_mean_N_per_m_pow_n = 0;
    std::vector<double> k_hertz_amplitudes_N_per_m_pow_n;
    std::vector<double> k_hertz_phases_rad;
  };

  struct StiffnessScene
  {
    std::string           source; // fem | table | fourier | iso6336 | hertz-analytic | potential-energy
    std::filesystem::path table_file; // resolved against the scene's folder
    std::string           table_file_entry; // as written in the scene
    int                   positions_per_cycle = 0;
    int                   harmonics           = 0;
    double                hertz_exponent      = 0;
    int                   fe_dimension        = 0;
    int                   fe_level            = 0;
    int                   fe_degree           = 0;
    int                   contact_grid_profile_points = 0;
    int                   contact_grid_face_points    = 0;
    std::string           contact_grid_face_extent; // face-width | load
    int                   contact_max_iterations      = 0;
    std::string           tooth_coupling; // coupled | decoupled (study switch)
    double                reference_depth_mm          = 0; // 0 = 3 x band element size
    int                   table_face_nodes            = 0; // 0 = automatic (3D)
    int                   table_roll_nodes            = 0; // 0 = automatic
    bool                  table_half_space_split      = true; // 3D: interpolate FE minus half-space
    std::string           linear_solver; // direct | amg-cg
    double                linear_solver_tolerance = 0;
    FourierScene          fourier;
    // Load and design map of the FE source: extra contact cycles on the same bodies.
    std::vector<double> map_torque_percent;        // of Operating/torque_Nm
    std::vector<double> load_ladder_percent;       // of Operating/torque_Nm (fe-map)
    std::vector<double> map_crowning_um;           // pinion lead crowning variants
    std::vector<double> map_mesh_misalignment_um;  // mesh misalignment variants
    std::vector<double> map_helix_slope_deviation_um; // pinion f_Hb variants
    std::string         map_combination;           // separate | product
  };

  struct MeshScene
  {
    std::string body_model;   // full-gear | sector
    int teeth_per_sector  = 0;
    int face_width_layers = 0;
  };

  struct DynamicsScene
  {
    std::string integrator; // rk4 | arkode-erk | cvode-bdf | ida | radau-iia
    int         radau_stages         = 0; // 0: by the tolerance
    double      relative_tolerance   = 0;
    double      absolute_tolerance_m = 0;
    int         steps_per_period     = 0;
    int         periods              = 0;
    int         transient_periods    = 0;
    int         samples_per_period   = 0;
    std::string initial_state; // static | given
    double      initial_dte_um              = 0;
    double      initial_dte_rate_m_per_s    = 0;
    double      initial_penetration_um      = 0;
    std::string damping_from; // ratio | coefficient
    double      damping_ratio               = 0;
    double      damping_coefficient_N_s_per_m = 0;
    double      alpha_s_per_m               = 0;
    double      restitution_coefficient     = 0;
    double      pinion_inertia_kg_m2        = 0; // 0: solid disc between bore and root radius
    double      gear_inertia_kg_m2          = 0;
  };

  struct SweepScene
  {
    bool        enabled = false;
    double      speed_min_rpm = 0;
    double      speed_max_rpm = 0;
    int         points        = 0;
    std::string direction; // up | down | both
    std::string mode;      // continuation | independent | both
    int         periods_per_point           = 0;
    int         transient_periods_per_point = 0;
  };

  // Periodic orbits followed by continuation (hertzgear response, or Sweep/mode = shooting).
  struct ResponseScene
  {
    std::string parameter; // speed_rpm | torque_Nm | damping_ratio
    double      torque_min_Nm = 0, torque_max_Nm = 0;
    double      damping_ratio_min = 0, damping_ratio_max = 0;
    std::string start; // low | high: the end of the range the continuation starts from
    double      step_max      = 0; // fraction of the range per step (scaled arclength)
    int         max_points_per_branch = 0;
    int         period_doubling_branches = 0;
    double      newton_tolerance = 0; // relative to the state scale
    double      relative_tolerance = 0; // of the period map's integration
    int         samples_per_period = 0;
  };

  struct OutputScene
  {
    int  timeseries_periods = 0;
    bool write_fields       = true;
    bool report             = true;
  };

  struct Scene
  {
    std::filesystem::path file; // empty for the built-in defaults
    GearScene             pinion, gear;
    Material              pinion_material, gear_material;
    OperatingScene        operating;
    EffectsScene          effects;
    StiffnessScene        stiffness;
    MeshScene             mesh;
    DynamicsScene         dynamics;
    SweepScene            sweep;
    ResponseScene         response;
    OutputScene           output;

    // The whole parameter set as resolved (defaults + file + overrides), in .prm form.
    std::string used_parameters_prm;
    // Stable hash of used_parameters_prm (without the helix keys of a spur gear, so that spur
    // scenes keep the hash they had before those keys).
    std::string hash;
  };

  // One `--set "Section/Subsection/key=value"` override.
  struct Override
  {
    std::string text;
  };

  // Read a scene (.prm or .json; an empty path gives the built-in defaults), apply overrides in
  // order, check ranges and cross-field consistency. Throws InputError naming the file, line and
  // key for anything wrong.
  Scene load_scene(const std::filesystem::path &file, const std::vector<std::string> &overrides = {});

  // Whether the stiffness stage runs the FE load ladder for the FE force law: Stiffness/source =
  // fem with Effects/mesh_force_law = fe-map, or = auto and a Hertzian layer (the law's second
  // member; docs/dynamics.md, "Which force law a scene gets").
  bool makes_load_ladder(const Scene &scene);

  // The documented default scene in .prm form (what `hertzgear defaults` prints).
  std::string default_scene_prm();

  // Every key as a Markdown reference (docs/scenes.md is generated from it).
  std::string scene_reference_markdown();

  // The subset of used parameters that one stage reads, for the artifact cache: one line per
  // "Section/key = value", sorted, for the listed sections (prefix match), without the keys that
  // start with one of `drop`.
  std::string scene_values_for(const Scene &scene, const std::vector<std::string> &section_prefixes,
                               const std::vector<std::string> &drop = {});
} // namespace hertzgear
