#pragma once
// How the meshing library names the input fields of a gear in its messages.
#include "meshing/gear_parameters.h"

#include <string>

namespace hertzgear::meshing
{
  // A field of gear `p` as messages name it, "{pinion.tip_radius_mm}": the program that filled the
  // field replaces the braces by its own key (app/scene_keys.h), other callers read the field.
  inline std::string field(const GearParameters &p, const std::string &f)
  {
    return "{" + p.name + "." + f + "}";
  }
} // namespace hertzgear::meshing
