#pragma once
// The JSON record of a pair's geometry and kinematics (`hertzgear geometry --json`, geometry.json):
// lengths in mm, angles in degrees, units in the keys.
#include "meshing/gear_geometry.h"
#include "meshing/pair_kinematics.h"

#include <nlohmann/json.hpp>

namespace hertzgear::meshing
{
  // Contact ratio, centre distances, operating pressure angle, base pitch, path of contact,
  // backlash, both gears with their operating pitch radii, and the points A to E of the path of
  // contact; per gear its teeth, radii, tooth thickness, top land, thinning and crowning (a
  // crowning radius of null for an uncrowned gear).
  nlohmann::json pair_json(const PairKinematics &pair);
} // namespace hertzgear::meshing
