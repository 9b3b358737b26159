#pragma once
// From a scene to the plain inputs of the meshing stage (mm and radians).
#include "app/scene.h"
#include "meshing/gear_parameters.h"
#include "meshing/pair_kinematics.h"

namespace hertzgear
{
  meshing::GearParameters gear_parameters(const GearScene &gear, const std::string &name);
  meshing::PairParameters pair_parameters(const Scene &scene);

  // Builds the pair and runs every geometry check (throws InputError).
  meshing::PairKinematics make_pair(const Scene &scene);
} // namespace hertzgear
