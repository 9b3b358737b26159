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
    g.grid.profile_cells          = static_cast<unsigned int>(input.fe.contact_grid_profile_cells);
    g.grid.face_cells             = static_cast<unsigned int>(input.fe.contact_grid_face_cells);
    g.grid.hertz_exponent         = input.hertz_exponent;
    g.grid.plane_strain           = false;
    g.grid.face_extent            = input.fe.contact_grid_face_extent == "load" ?
                                      contact::MeshCycleSettings::FaceExtent::load :
                                      contact::MeshCycleSettings::FaceExtent::face_width;
    g.grid.max_contact_iterations = static_cast<unsigned int>(input.fe.contact_max_iterations);
    g.reference_depth_mm          = fe_reference_depth_mm(input.fe, input.pair.pinion.module_mm);
    return g;
  }
} // namespace hertzgear::stiffness
