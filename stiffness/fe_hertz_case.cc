#include "stiffness/fe_hertz_case.h"

#include "stiffness/fe_tca.h"

namespace hertzgear::stiffness
{
  fem::HertzCaseInput::GearPair hertz_case_gear_pair(const StiffnessInput &input)
  {
    fem::HertzCaseInput::GearPair g;
    g.pair                        = input.pair;
    g.pinion_material             = input.pinion_material;
    g.gear_material               = input.gear_material;
    g.torque_Nm                   = input.torque_Nm;
    g.grid                        = fe_contact_grid_settings(input);
    g.grid.plane_strain           = false;
    g.reference_depth_mm          = fe_reference_depth_mm(input.fe, input.pair.pinion.module_mm);
    return g;
  }
} // namespace hertzgear::stiffness
