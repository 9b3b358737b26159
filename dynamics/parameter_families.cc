#include "dynamics/parameter_families.h"

#include "dynamics/sweep.h"

namespace hertzgear::dynamics
{
  ParameterFamily speed_family(const GearPairParameters &pair, const double base_speed_rpm)
  {
    const GearPairParameters base = with_shared_mesh_force_law(pair);
    return {"speed_rpm", [base, base_speed_rpm](const double speed_rpm) {
              return at_speed(base, base_speed_rpm, speed_rpm);
            }};
  }

  ParameterFamily torque_family(const GearPairParameters &pair, const double pinion_base_radius_m,
                                const std::optional<double> damping_ratio)
  {
    const GearPairParameters base = with_shared_mesh_force_law(pair);
    return {"torque_Nm", [base, pinion_base_radius_m, damping_ratio](const double torque_Nm) {
              auto p           = base;
              p.static_force_N = torque_Nm / pinion_base_radius_m;
              if (damping_ratio)
                p.damping_N_s_per_m = damping_of_ratio(p, *damping_ratio);
              return p;
            }};
  }

  ParameterFamily damping_ratio_family(const GearPairParameters &pair)
  {
    const GearPairParameters base = with_shared_mesh_force_law(pair);
    return {"damping_ratio", [base](const double zeta) {
              auto p              = base;
              p.damping_N_s_per_m = damping_of_ratio(p, zeta);
              return p;
            }};
  }
} // namespace hertzgear::dynamics
