#pragma once
// The power |a|^p of the Hertzian layer's laws, shared by the mesh force laws: G(delta) =
// sign(delta) |delta|^n and the Hunt-Crossley weight H(delta) = |delta|^n with their derivatives.
// The exponents of line and point contact (1, 3/2 and their derivatives' 0, 1/2) are written out:
// a right-hand side evaluates them at every stage.
#include <cmath>

namespace hertzgear::dynamics::power_law
{
  inline double sign(const double v) { return (v > 0.0) - (v < 0.0); }

  // a^p for a >= 0.
  inline double power(const double a, const double p)
  {
    if (p == 1.0)
      return a;
    if (p == 1.5)
      return a * std::sqrt(a);
    if (p == 0.5)
      return std::sqrt(a);
    if (p == 0.0)
      return 1.0;
    return std::pow(a, p);
  }

  // dG/ddelta = n |delta|^(n-1).
  inline double G_prime(const double d, const double n)
  {
    return n == 1.0 ? 1.0 : n * power(std::abs(d), n - 1.0);
  }

  // The Hunt-Crossley weight H(delta) = |delta|^n and dH/ddelta.
  inline double H(const double d, const double n) { return power(std::abs(d), n); }
  inline double H_prime(const double d, const double n)
  {
    return n == 1.0 ? sign(d) : n * sign(d) * power(std::abs(d), n - 1.0);
  }
} // namespace hertzgear::dynamics::power_law
