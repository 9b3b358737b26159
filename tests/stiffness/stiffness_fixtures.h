#pragma once
// The paper's uncrowned pair (data/scenes/paper_uncrowned.prm) as a plain stiffness input, for
// the tests of the stiffness sources; crowning_mm makes it the crowned pair.
#include "stiffness/stiffness_source.h"

#include <cmath>

namespace hertzgear::stiffness::test_pairs
{
  inline StiffnessInput paper_pair(const double crowning_mm = 0.0)
  {
    StiffnessInput in;
    auto           gear = [&](const int z, const double tip_mm, const double bore_mm, const char *name) {
      meshing::GearParameters g;
      g.teeth              = z;
      g.module_mm          = 3;
      g.pressure_angle_rad = 20 * M_PI / 180;
      g.face_width_mm      = 20;
      g.tip_radius_mm      = tip_mm;
      g.bore_radius_mm     = bore_mm;
      g.crowning_mm        = crowning_mm;
      g.name               = name;
      return g;
    };
    in.pair.pinion          = gear(23, 37.337, 15, "pinion");
    in.pair.gear            = gear(34, 53.837, 20, "gear");
    in.pair.backlash_loa_mm = 0.1172;
    in.torque_Nm            = 210;
    in.positions_per_cycle  = 16;
    in.harmonics            = 4;
    in.hertz_exponent       = crowning_mm > 0 ? 1.5 : 1.0;
    return in;
  }
} // namespace hertzgear::stiffness::test_pairs
