#pragma once
// A material point of a gear's drive flank, in the flank's own coordinates.

namespace hertzgear::meshing
{
  // Tooth index relative to the tooth of pair 0 (in a mesh cycle pair j uses pinion tooth +j and
  // gear tooth -j), roll distance from the body's own base tangent point (the involute parameter
  // r_b u, i.e. the radius of curvature of the transverse profile there) and face position
  // (0 = mid-face).
  struct FlankPoint
  {
    int    tooth   = 0;
    double roll_mm = 0;
    double z_mm    = 0;
  };
} // namespace hertzgear::meshing
