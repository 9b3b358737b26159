#include "app/dynamics_setup.h"

#include "app/meshing_setup.h"
#include "app/stiffness_setup.h"
#include "meshing/gear_geometry.h"
#include "meshing/pair_kinematics.h"
#include "common/errors.h"
#include "dynamics/parameter_families.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace hertzgear
{
  namespace
  {
    double base_radius_m(const GearScene &g)
    {
      return 1e-3 * meshing::base_radius_mm(gear_parameters(g, "gear"));
    }

    // The inertia of the gear body as a solid disc (meshing::disc_inertia_kg_m2).
    double disc_inertia_kg_m2(const GearScene &g, const Material &mat)
    {
      const auto   p   = gear_parameters(g, "gear");
      const double r_f = 1e-3 * meshing::root_radius_mm(p);
      HG_REQUIRE_INPUT(r_f > 1e-3 * g.bore_radius_mm, "root radius ", r_f * 1e3,
                       " mm is not larger than the bore radius ", g.bore_radius_mm,
                       " mm: give the inertias in Dynamics/*_inertia_kg_m2");
      return meshing::disc_inertia_kg_m2(p, mat.density_kg_per_m3);
    }

    // A zero mesh damping makes the penetration equation of the dynamic Hertzian layer algebraic.
    void check_damping(const Scene &scene, const double damping_N_s_per_m)
    {
      if (damping_N_s_per_m == 0.0 && scene.effects.hertzian_layer == "dynamic")
        HG_REQUIRE_INPUT(scene.dynamics.integrator == "ida",
                         "the mesh damping c is 0, which makes the penetration equation of the "
                         "dynamic Hertzian layer algebraic (a DAE): use Dynamics/integrator = ida, "
                         "or give c > 0");
    }

    // The integration settings of Dynamics/*, checked.
    dynamics::RunSettings run_settings(const Scene &scene)
    {
      const auto           &d = scene.dynamics;
      dynamics::RunSettings r;
      r.integrator.kind               = dynamics::integrator_kind_from_name(d.integrator);
      r.integrator.relative_tolerance = d.relative_tolerance;
      HG_REQUIRE_INPUT(d.radau_stages == 0 || (d.radau_stages >= 3 && d.radau_stages % 2 == 1),
                       "Dynamics/radau_stages = ", d.radau_stages, " must be 0 (by the tolerance) or "
                       "3, 5, 7 or 9");
      r.integrator.stages             = d.radau_stages;
      r.integrator.absolute_tolerance = d.absolute_tolerance_m;
      r.periods                       = d.periods;
      r.transient_periods             = d.transient_periods;
      r.samples_per_period            = d.samples_per_period;
      r.steps_per_period              = d.steps_per_period;
      HG_REQUIRE_INPUT(r.periods > r.transient_periods, "Dynamics/periods = ", r.periods,
                       " must exceed Dynamics/transient_periods = ", r.transient_periods);
      return r;
    }

    // The continuation parameter of Response/parameter: its key, column and range.
    ResponseFamily response_range(const Scene &scene)
    {
      ResponseFamily f;
      const auto    &r = scene.response;
      f.column         = r.parameter;
      if (r.parameter == "speed_rpm")
        {
          f.key = "Operating/speed_rpm";
          f.min = scene.sweep.speed_min_rpm;
          f.max = scene.sweep.speed_max_rpm;
        }
      else if (r.parameter == "torque_Nm")
        {
          f.key = "Operating/torque_Nm";
          f.min = r.torque_min_Nm;
          f.max = r.torque_max_Nm;
        }
      else
        {
          HG_REQUIRE_INPUT(r.parameter == "damping_ratio", "Response/parameter = ", r.parameter,
                           " is not one of speed_rpm, torque_Nm, damping_ratio");
          HG_REQUIRE_INPUT(scene.dynamics.damping_from == "ratio",
                           "Response/parameter = damping_ratio needs Dynamics/damping_from = ratio "
                           "(the scene gives the damping as a coefficient)");
          f.key = "Dynamics/damping_ratio";
          f.min = r.damping_ratio_min;
          f.max = r.damping_ratio_max;
        }
      return f;
    }

    dynamics::ContinuationSettings continuation_settings_of(const Scene &scene,
                                                            const dynamics::RunSettings &run,
                                                            const ResponseFamily &family)
    {
      const auto &r = scene.response;
      HG_REQUIRE_INPUT(run.integrator.kind != dynamics::IntegratorKind::rk4,
                       "Dynamics/integrator = rk4 cannot serve the shooting method of "
                       "hertzgear response (it does not locate the switching events the "
                       "saltation matrices need): use radau-iia, cvode-bdf, arkode-erk, "
                       "arkode-dirk or ida");
      HG_REQUIRE_INPUT(r.newton_tolerance >= 10.0 * r.relative_tolerance,
                       "Response/newton_tolerance = ", r.newton_tolerance,
                       " must be at least 10 Response/relative_tolerance (",
                       10.0 * r.relative_tolerance,
                       "): the period map is only as smooth as its integration across the "
                       "switching events, and Newton's method cannot converge below that");
      dynamics::ContinuationSettings s;
      s.shooting.integrator         = run.integrator;
      s.shooting.integrator.relative_tolerance = r.relative_tolerance;
      s.shooting.tolerance          = r.newton_tolerance;
      s.analysis                    = run;
      s.analysis.integrator.relative_tolerance = r.relative_tolerance;
      s.analysis.samples_per_period = r.samples_per_period;
      s.analysis.dense_extremes     = true;
      s.lambda_min                  = family.min;
      s.lambda_max                  = family.max;
      s.lambda_start                = r.start == "low" ? family.min : family.max;
      s.direction                   = r.start == "low" ? +1 : -1;
      s.step_max                    = r.step_max;
      s.step_initial                = std::min(0.005, r.step_max);
      s.step_min                    = std::min(1e-7, 0.1 * s.step_initial);
      s.max_points                  = r.max_points_per_branch;
      s.follow_period_doubling      = r.period_doubling_branches > 0;
      s.max_branches                = 1 + r.period_doubling_branches;
      try
        {
          dynamics::check_continuation_settings(s);
        }
      catch (const ParameterError &e)
        {
          throw InputError("Response/" + e.parameter() + " = " + e.text());
        }
      return s;
    }
  } // namespace

  table::StiffnessTable stiffness_table_for(const Scene &scene)
  {
    const auto &source = stiffness_source(scene);
    HG_REQUIRE_INPUT(!source.is_stage(),
                     "Stiffness/source = ", source.name(),
                     " is produced by the stiffness stage (`hertzgear stiffness SCENE --out DIR` writes "
                     "stiffness.json); the dynamics reads stiffness from a table or from Fourier "
                     "coefficients. Run the stiffness stage and set Stiffness/source = table with "
                     "Stiffness/table_file = DIR/stiffness.json, or give the coefficients with "
                     "Stiffness/source = fourier (subsection Stiffness/Fourier)");
    PhaseTimer timer;
    return source.compute(stiffness_input(scene), timer).table;
  }

  dynamics::MeshForceLawKind mesh_force_law_of(const Scene &scene, const table::StiffnessTable &t)
  {
    const auto &law = scene.effects.mesh_force_law;
    if (law != "auto")
      return dynamics::mesh_force_law_from_name(law);
    // auto: the FE law where the stiffness comes from the FE with its load ladder and the model
    // has the Hertzian layer that is the law's second member; the paper's law otherwise.
    return !t.ladder.empty() && scene.effects.hertzian_layer != "off" ?
             dynamics::MeshForceLawKind::fe_map :
             dynamics::MeshForceLawKind::serial_hertz;
  }

  void check_dynamics_scene(const Scene &scene)
  {
    const auto &op = scene.operating;
    HG_REQUIRE_INPUT(op.speed_rpm > 0.0, "Operating/speed_rpm must be > 0 for the dynamics");
    run_settings(scene);
    if (scene.dynamics.damping_from != "ratio")
      check_damping(scene, scene.dynamics.damping_coefficient_N_s_per_m);
  }

  DynamicsSetup make_dynamics_setup(const Scene &scene)
  {
    // The dynamics uses the geometry (F_0 = T_1 / r_b1, inertias, the backlash of a given centre
    // distance): check it.
    const meshing::PairKinematics kinematics(make_pair(scene));
    check_dynamics_scene(scene);
    DynamicsSetup s;
    const auto   &d  = scene.dynamics;
    const auto   &op = scene.operating;
    auto &p                = s.parameters;
    p.stiffness            = stiffness_table_for(scene);
    p.effects.mesh_force_law = mesh_force_law_of(scene, p.stiffness);
    p.effects.backlash     = scene.effects.backlash == "on";
    p.effects.hertzian_layer  = dynamics::hertzian_layer_from_name(scene.effects.hertzian_layer);
    p.effects.contact_damping = dynamics::contact_damping_from_name(scene.effects.contact_damping);
    p.effects.mesh_stiffness_variation = scene.effects.mesh_stiffness_variation == "fourier";
    p.effects.rest_stiffness_variation = scene.effects.rest_stiffness_variation == "fourier";
    p.effects.ste_excitation           = scene.effects.ste_excitation == "table";

    s.pinion_base_radius_m = base_radius_m(scene.pinion);
    s.gear_base_radius_m   = base_radius_m(scene.gear);
    s.pinion_inertia_kg_m2 = d.pinion_inertia_kg_m2 > 0 ?
                               d.pinion_inertia_kg_m2 :
                               disc_inertia_kg_m2(scene.pinion, scene.pinion_material);
    s.gear_inertia_kg_m2   = d.gear_inertia_kg_m2 > 0 ?
                               d.gear_inertia_kg_m2 :
                               disc_inertia_kg_m2(scene.gear, scene.gear_material);
    p.equivalent_mass_kg   = dynamics::equivalent_mass(s.pinion_inertia_kg_m2, s.gear_inertia_kg_m2,
                                                     s.pinion_base_radius_m, s.gear_base_radius_m);
    p.static_force_N       = op.torque_Nm / s.pinion_base_radius_m;
    // The total backlash along the line of action, b_c half of it: Operating/backlash_mm, or the
    // backlash that a given centre distance leaves (then backlash_mm is 0, check_consistency).
    p.half_backlash_m = 0.5e-3 * (op.center_distance_mm > 0.0 ? kinematics.backlash_loa_mm() : op.backlash_mm);
    s.speed_rpm            = op.speed_rpm;
    p.mesh_frequency_rad_per_s = 2.0 * M_PI * scene.pinion.teeth * op.speed_rpm / 60.0;
    p.alpha_s_per_m            = d.alpha_s_per_m;
    p.restitution_coefficient  = d.restitution_coefficient;
    s.equivalent_stiffness_N_per_m =
      dynamics::equivalent_mesh_stiffness(p.stiffness, p.effects.hertzian_layer, p.static_force_N);
    p.damping_N_s_per_m = d.damping_from == "ratio" ? dynamics::damping_of_ratio(p, d.damping_ratio) :
                                                      d.damping_coefficient_N_s_per_m;
    check_damping(scene, p.damping_N_s_per_m);
    s.run = run_settings(scene);
    // The model's own checks (an effect the table cannot serve, ...) here, before any stage runs.
    dynamics::GearPairModel{s.parameters};
    return s;
  }

  dynamics::InitialState initial_state(const Scene &scene)
  {
    const auto            &d = scene.dynamics;
    dynamics::InitialState s;
    s.static_equilibrium = d.initial_state == "static";
    s.dte_m              = 1e-6 * d.initial_dte_um;
    s.dte_rate_m_per_s   = d.initial_dte_rate_m_per_s;
    s.penetration_m      = 1e-6 * d.initial_penetration_um;
    return s;
  }

  std::vector<double> initial_state(const Scene &scene, const dynamics::GearPairModel &model)
  {
    return initial_state(scene).of(model);
  }

  nlohmann::json DynamicsSetup::describe() const
  {
    const auto &p = parameters;
    return {{"equivalent_mass_kg", p.equivalent_mass_kg},
            {"pinion_inertia_kg_m2", pinion_inertia_kg_m2},
            {"gear_inertia_kg_m2", gear_inertia_kg_m2},
            {"pinion_base_radius_mm", 1e3 * pinion_base_radius_m},
            {"gear_base_radius_mm", 1e3 * gear_base_radius_m},
            {"half_backlash_um", 1e6 * p.half_backlash_m},
            {"mesh_frequency_Hz", p.mesh_frequency_rad_per_s / (2 * M_PI)},
            {"damping_N_s_per_m", p.damping_N_s_per_m},
            {"equivalent_stiffness_N_per_m", equivalent_stiffness_N_per_m},
            {"hertz_exponent", p.stiffness.hertz_exponent},
            {"k_rest_mean_N_per_m", p.stiffness.k_rest_N_per_m.mean},
            {"k_hertz_mean_N_per_m_pow_n", p.stiffness.k_hertz_N_per_m_pow_n.mean},
            {"stiffness_source", p.stiffness.source}};
  }

  ResponseFamily response_family(const Scene &scene, const DynamicsSetup &setup)
  {
    ResponseFamily f    = response_range(scene);
    const auto    &base = setup.parameters;
    const auto    &d    = scene.dynamics;
    if (f.column == "speed_rpm")
      f.family = dynamics::speed_family(base, setup.speed_rpm);
    else if (f.column == "torque_Nm")
      f.family = dynamics::torque_family(base, setup.pinion_base_radius_m,
                                         d.damping_from == "ratio" ?
                                           std::optional<double>(d.damping_ratio) :
                                           std::nullopt);
    else
      f.family = dynamics::damping_ratio_family(base);
    return f;
  }

  dynamics::ContinuationSettings continuation_settings(const Scene &scene, const DynamicsSetup &setup,
                                                       const ResponseFamily &family)
  {
    return continuation_settings_of(scene, setup.run, family);
  }

  void check_response_scene(Scene scene, const bool speed_sweep)
  {
    if (speed_sweep)
      scene.response.parameter = "speed_rpm";
    continuation_settings_of(scene, run_settings(scene), response_range(scene));
  }
} // namespace hertzgear
