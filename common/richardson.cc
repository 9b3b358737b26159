#include "common/richardson.h"

#include "common/errors.h"

#include <cmath>

namespace hertzgear
{
  Extrapolation richardson(const double h1, const double h2, const double h3, const double f1,
                           const double f2, const double f3, const double expected_order)
  {
    Extrapolation x;
    const double  e21 = f2 - f1, e32 = f3 - f2;
    const double  r21 = h1 / h2, r32 = h2 / h3;
    if (e32 == 0.0)
      {
        x.value = f3;
        x.order = std::numeric_limits<double>::infinity();
        x.note  = "the two finest rungs agree exactly";
        return x;
      }
    if (e21 == 0.0)
      {
        x.note = "the two coarsest rungs agree exactly: no order can be observed";
        return x;
      }
    const double ratio = e32 / e21;
    const double s     = ratio > 0 ? 1.0 : -1.0;
    double       p     = std::abs(std::log(std::abs(1.0 / ratio))) / std::log(r21);
    for (int it = 0; it < 100; ++it)
      {
        const double q  = std::log((std::pow(r21, p) - s) / (std::pow(r32, p) - s));
        const double pn = std::abs(std::log(std::abs(1.0 / ratio)) + q) / std::log(r21);
        if (!std::isfinite(pn))
          break;
        if (std::abs(pn - p) < 1e-10)
          {
            p = pn;
            break;
          }
        p = pn;
      }
    x.order = p;
    x.value = f3 + (f3 - f2) / (std::pow(r32, p) - 1.0);
    if (ratio < 0)
      x.note = "oscillatory convergence (the differences change sign): not in the asymptotic range";
    else if (std::abs(ratio) >= 1)
      x.note = "the differences grow with refinement: not in the asymptotic range";
    else if (p < 0.5 * expected_order || p > 2.0 * expected_order)
      x.note = msg("observed order ", p, " is far from the expected ", expected_order,
                   ": not in the asymptotic range");
    else
      {
        x.asymptotic = true;
        x.note       = "monotone, observed order near the expected one";
      }
    return x;
  }
} // namespace hertzgear
