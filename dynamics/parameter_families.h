#pragma once
// The gear pair as a one-parameter family for the continuation of periodic orbits
// (dynamics/continuation.h): in the pinion speed, the pinion torque or the damping ratio
// (`hertzgear response`, docs/dynamics.md).
#include "dynamics/continuation.h"
#include "dynamics/gear_pair_model.h"

#include <optional>

namespace hertzgear::dynamics
{
  // In the pinion speed [rpm]; `base` describes the pair at `base_speed_rpm` (at_speed: the mesh
  // frequency scales with the speed, nothing else changes).
  ParameterFamily speed_family(const GearPairParameters &base, double base_speed_rpm);

  // In the pinion torque T [N m]: F_0 = T / r_b1. With a damping ratio the damping follows the
  // linearised mesh stiffness at each load (damping_of_ratio); without, it stays that of `base`.
  ParameterFamily torque_family(const GearPairParameters &base, double pinion_base_radius_m,
                                std::optional<double> damping_ratio);

  // In the damping ratio zeta: c = 2 zeta sqrt(k_eq m_e) at the static force of `base`.
  ParameterFamily damping_ratio_family(const GearPairParameters &base);
} // namespace hertzgear::dynamics
