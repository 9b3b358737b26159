#include "meshing/involute.h"

#include "common/errors.h"

#include <cmath>

namespace hertzgear::meshing
{
  double inverse_involute(const double value)
  {
    HG_REQUIRE_NUMERIC(value >= 0 && std::isfinite(value),
                       "inverse_involute: argument ", value, " is not a non-negative number");
    if (value == 0)
      return 0;
    // Start from alpha ~ (3 v)^(1/3) (series inv(a) = a^3/3 + ...), then Newton on
    // f(a) = tan(a) - a - v, f'(a) = tan(a)^2; f is convex for a in (0, pi/2), so Newton from
    // the right of the root converges monotonically. Start to the right by taking the larger of
    // the series guess and the asymptotic guess.
    double alpha = std::cbrt(3.0 * value);
    alpha        = std::min(alpha, 1.5707963267948966 - 1e-12);
    for (int i = 0; i < 100; ++i)
      {
        const double t     = std::tan(alpha);
        const double step  = (t - alpha - value) / (t * t);
        double       next  = alpha - step;
        if (next <= 0)
          next = 0.5 * alpha;
        if (std::abs(next - alpha) <= 4e-16 * std::max(1.0, alpha))
          return next;
        alpha = next;
      }
    HG_REQUIRE_NUMERIC(false, "inverse_involute(", value, ") did not converge");
    return alpha;
  }
} // namespace hertzgear::meshing
