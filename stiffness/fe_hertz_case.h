#pragma once
// The FE source's gear pair as the crowned-flank case of the Hertz validation study
// (fem/hertz_validation.h, `hertzgear validate hertz`): its pair, materials and torque, the
// contact grid of the 3D loaded TCA and its reference depth (FE build only).
#include "fem/hertz_validation.h"
#include "stiffness/stiffness_source.h"

namespace hertzgear::stiffness
{
  // The case's gear pair from the stiffness input of a gear scene (source left empty).
  fem::HertzCaseInput::GearPair hertz_case_gear_pair(const StiffnessInput &input);
} // namespace hertzgear::stiffness
