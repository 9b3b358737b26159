#pragma once
// Richardson extrapolation from three rungs of a refinement ladder, with the observed order: the
// generalised procedure of Celik et al. 2008, "Procedure for estimation and reporting of
// uncertainty due to discretization in CFD applications", J. Fluids Eng. 130, 078001 (eqs. 3-6,
// with its fixed-point iteration for non-constant refinement ratios).
#include <limits>
#include <string>

namespace hertzgear
{
  struct Extrapolation
  {
    double      value    = std::numeric_limits<double>::quiet_NaN();
    double      order    = std::numeric_limits<double>::quiet_NaN();
    bool        asymptotic = false;
    std::string note;
  };

  // Observed order and extrapolated value from three rungs f1 (coarsest), f2, f3 (finest) of
  // sizes h1 > h2 > h3; `expected_order` decides whether the rungs are in the asymptotic range.
  Extrapolation richardson(double h1, double h2, double h3, double f1, double f2, double f3,
                           double expected_order);
} // namespace hertzgear
