#pragma once
// Scene -> dynamics model: the one place where scene units (mm, rpm, N m, um) become the SI values
// of the gear-pair model, and where the stiffness source of the scene is resolved.
#include "app/scene.h"
#include "dynamics/analysis.h"
#include "dynamics/continuation.h"
#include "dynamics/gear_pair_model.h"
#include "dynamics/sweep.h"

#include <nlohmann/json.hpp>

#include <vector>

namespace hertzgear
{
  struct DynamicsSetup
  {
    dynamics::GearPairParameters parameters;
    dynamics::RunSettings        run;
    double pinion_inertia_kg_m2 = 0.0, gear_inertia_kg_m2 = 0.0;
    double pinion_base_radius_m = 0.0, gear_base_radius_m = 0.0;
    double equivalent_stiffness_N_per_m = 0.0; // for the damping ratio
    double speed_rpm                    = 0.0;

    // What the summary records about the model (units in the keys).
    nlohmann::json describe() const;
  };

  // The stiffness table the scene asks for. fem and the closed forms (iso6336, hertz-analytic,
  // potential-energy) are produced by the stiffness stage: they raise an InputError that says
  // how to proceed.
  table::StiffnessTable stiffness_table_for(const Scene &scene);

  // Throws InputError for a scene the dynamics cannot run (unknown source, c = 0 without ida, an
  // effect the table cannot serve such as Effects/ste_excitation = table without unloaded STE:
  // every check of the gear-pair model is made here).
  DynamicsSetup make_dynamics_setup(const Scene &scene);

  // The mesh force law of the scene on its table: Effects/mesh_force_law, where auto is fe-map
  // when the table holds a load ladder and the Hertzian layer is on, serial-hertz otherwise.
  dynamics::MeshForceLawKind mesh_force_law_of(const Scene &scene, const table::StiffnessTable &t);

  // The checks of make_dynamics_setup that need no stiffness table (centre distance, speed,
  // integrator settings, periods): for a scene whose table the stiffness stage makes, so that
  // they run before any folder is made.
  void check_dynamics_scene(const Scene &scene);

  // The continuation parameter of Response/parameter as a family of models (speed: the mesh
  // frequency; torque: F_0 = T / r_b1 and, with Dynamics/damping_from = ratio, the damping of
  // the linearised stiffness at that load; damping ratio: c = 2 zeta sqrt(k_eq m_e)), and its
  // range in the scene's units (rpm, N m, or none). The families: dynamics/parameter_families.h.
  struct ResponseFamily
  {
    dynamics::ParameterFamily family;
    std::string               key;   // the scene key of the parameter ("Operating/speed_rpm" ...)
    std::string               column; // response.csv's column: speed_rpm, torque_Nm, damping_ratio
    double                    min = 0, max = 0;
  };
  ResponseFamily response_family(const Scene &scene, const DynamicsSetup &setup);

  // The continuation settings of Response/* for the family's range, checked: an integrator that
  // can shoot (not rk4), Response/newton_tolerance at least 10 Response/relative_tolerance, and
  // the settings check of dynamics/continuation.h. Throws InputError naming the key.
  dynamics::ContinuationSettings continuation_settings(const Scene &scene, const DynamicsSetup &setup,
                                                       const ResponseFamily &family);

  // The checks of continuation_settings on the scene alone, before any table is read (`check`
  // and `run` for Sweep/mode = shooting, with `speed_sweep`: in speed over the sweep's range).
  void check_response_scene(Scene scene, bool speed_sweep);

  // Dynamics/initial_state (static equilibrium or the given values) in SI units.
  dynamics::InitialState initial_state(const Scene &scene);
  // That initial state of `model`.
  std::vector<double> initial_state(const Scene &scene, const dynamics::GearPairModel &model);
} // namespace hertzgear
