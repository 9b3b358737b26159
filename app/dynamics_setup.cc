#include "app/dynamics_setup.h"

#include "app/meshing_setup.h"
#include "app/stiffness_setup.h"
#include "meshing/gear_geometry.h"
#include "common/errors.h"
#include "dynamics/parameter_families.h"

#include <cmath>

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

  DynamicsSetup make_dynamics_setup(const Scene &scene)
  {
    make_pair(scene); // the dynamics uses the geometry (F_0 = T_1 / r_b1, inertias): check it
    DynamicsSetup s;
    const auto   &d  = scene.dynamics;
    const auto   &op = scene.operating;
    HG_REQUIRE_INPUT(op.center_distance_mm == 0.0,
                     "Operating/center_distance_mm = ", op.center_distance_mm,
                     ": the dynamics takes the backlash along the line of action from "
                     "Operating/backlash_mm; set center_distance_mm = 0 and give backlash_mm");
    auto &p                = s.parameters;
    p.stiffness            = stiffness_table_for(scene);
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
    // Operating/backlash_mm is the total backlash along the line of action: b_c is half of it.
    p.half_backlash_m      = 0.5e-3 * op.backlash_mm;
    s.speed_rpm            = op.speed_rpm;
    HG_REQUIRE_INPUT(op.speed_rpm > 0.0, "Operating/speed_rpm must be > 0 for the dynamics");
    p.mesh_frequency_rad_per_s = 2.0 * M_PI * scene.pinion.teeth * op.speed_rpm / 60.0;
    p.alpha_s_per_m            = d.alpha_s_per_m;
    p.restitution_coefficient  = d.restitution_coefficient;
    s.equivalent_stiffness_N_per_m =
      dynamics::equivalent_mesh_stiffness(p.stiffness, p.effects.hertzian_layer, p.static_force_N);
    p.damping_N_s_per_m = d.damping_from == "ratio" ? dynamics::damping_of_ratio(p, d.damping_ratio) :
                                                      d.damping_coefficient_N_s_per_m;
    if (p.damping_N_s_per_m == 0.0 && p.effects.hertzian_layer == dynamics::HertzianLayer::dynamic)
      HG_REQUIRE_INPUT(d.integrator == "ida",
                       "the mesh damping c is 0, which makes the penetration equation of the "
                       "dynamic Hertzian layer algebraic (a DAE): use Dynamics/integrator = ida, "
                       "or give c > 0");

    auto &r                          = s.run;
    r.integrator.kind                = dynamics::integrator_kind_from_name(d.integrator);
    r.integrator.relative_tolerance  = d.relative_tolerance;
    HG_REQUIRE_INPUT(d.radau_stages == 0 || (d.radau_stages >= 3 && d.radau_stages % 2 == 1),
                     "Dynamics/radau_stages = ", d.radau_stages, " must be 0 (by the tolerance) or "
                     "3, 5, 7 or 9");
    r.integrator.stages              = d.radau_stages;
    r.integrator.absolute_tolerance  = d.absolute_tolerance_m;
    r.periods                        = d.periods;
    r.transient_periods              = d.transient_periods;
    r.samples_per_period             = d.samples_per_period;
    r.steps_per_period               = d.steps_per_period;
    HG_REQUIRE_INPUT(r.periods > r.transient_periods, "Dynamics/periods = ", r.periods,
                     " must exceed Dynamics/transient_periods = ", r.transient_periods);
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
    ResponseFamily f;
    const auto    &base = setup.parameters;
    const auto    &r    = scene.response;
    const auto    &d    = scene.dynamics;
    f.column            = r.parameter;
    if (r.parameter == "speed_rpm")
      {
        f.key    = "Operating/speed_rpm";
        f.min    = scene.sweep.speed_min_rpm;
        f.max    = scene.sweep.speed_max_rpm;
        f.family = dynamics::speed_family(base, setup.speed_rpm);
      }
    else if (r.parameter == "torque_Nm")
      {
        f.key    = "Operating/torque_Nm";
        f.min    = r.torque_min_Nm;
        f.max    = r.torque_max_Nm;
        f.family = dynamics::torque_family(base, setup.pinion_base_radius_m,
                                           d.damping_from == "ratio" ?
                                             std::optional<double>(d.damping_ratio) :
                                             std::nullopt);
      }
    else
      {
        HG_REQUIRE_INPUT(r.parameter == "damping_ratio", "Response/parameter = ", r.parameter,
                         " is not one of speed_rpm, torque_Nm, damping_ratio");
        HG_REQUIRE_INPUT(d.damping_from == "ratio",
                         "Response/parameter = damping_ratio needs Dynamics/damping_from = ratio "
                         "(the scene gives the damping as a coefficient)");
        f.key    = "Dynamics/damping_ratio";
        f.min    = r.damping_ratio_min;
        f.max    = r.damping_ratio_max;
        f.family = dynamics::damping_ratio_family(base);
      }
    return f;
  }
} // namespace hertzgear
