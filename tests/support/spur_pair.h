#pragma once
// The spur pair the tests build: the reference paper's (module 3 mm, 20 degrees, 23/34 teeth,
// 20 mm face, bores 15/20 mm, 0.1172 mm backlash along the line of action) unless told otherwise.
#include "meshing/gear_parameters.h"

#include <cmath>

namespace hertzgear::testing
{
  struct SpurPairOptions
  {
    int    pinion_teeth    = 23;
    int    gear_teeth      = 34;
    double face_width_mm   = 20.0;
    double crowning_mm     = 0.0;
    double pinion_bore_mm  = 15.0;
    double gear_bore_mm    = 20.0;
    double backlash_loa_mm = 0.1172;
  };

  inline meshing::PairParameters spur_pair(const SpurPairOptions &o = {})
  {
    meshing::PairParameters p;
    for (auto *g : {&p.pinion, &p.gear})
      {
        g->module_mm          = 3.0;
        g->pressure_angle_rad = 20.0 * M_PI / 180.0;
        g->face_width_mm      = o.face_width_mm;
        g->crowning_mm        = o.crowning_mm;
      }
    p.pinion.teeth          = o.pinion_teeth;
    p.gear.teeth            = o.gear_teeth;
    p.pinion.bore_radius_mm = o.pinion_bore_mm;
    p.gear.bore_radius_mm   = o.gear_bore_mm;
    p.pinion.name           = "pinion";
    p.gear.name             = "gear";
    p.backlash_loa_mm       = o.backlash_loa_mm;
    return p;
  }
} // namespace hertzgear::testing
