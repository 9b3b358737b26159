#pragma once
// The involute function and its inverse, used everywhere a radius, a pressure angle and a tooth
// thickness meet: inv(alpha) = tan(alpha) - alpha (angle in radians).
#include <cmath>

namespace hertzgear::meshing
{
  inline double involute(const double alpha)
  {
    return std::tan(alpha) - alpha;
  }

  // alpha with inv(alpha) = value, for 0 <= value < inv(pi/2 - eps). Newton from Cheng's
  // approximation converges to machine precision in a few steps for every gear-relevant angle.
  double inverse_involute(double value);
} // namespace hertzgear::meshing
