#include "stiffness/potential_energy.h"

#include "common/errors.h"

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include <algorithm>
#include <cmath>

namespace hertzgear::stiffness
{
  namespace
  {
    // Adaptive 31-point Gauss-Kronrod over [a, b], split at the kinks inside it.
    double integrate(const std::function<double(double)> &f, const double a, const double b,
                     const std::vector<double> &kinks)
    {
      std::vector<double> cuts{a};
      for (const double k : kinks)
        if (k > a && k < b)
          cuts.push_back(k);
      cuts.push_back(b);
      std::sort(cuts.begin(), cuts.end());
      double sum = 0;
      for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
        sum += boost::math::quadrature::gauss_kronrod<double, 31>::integrate(f, cuts[i], cuts[i + 1],
                                                                             15, 1e-10);
      return sum;
    }

    // Coefficients A..F of X*(h_f, theta_f) for X = L*, M*, P*, Q* (Sainsot, Velex & Duverger
    // 2004, Table 1).
    struct FilletCoefficients
    {
      double A, B, C, D, E, F;
      double operator()(const double h, const double theta) const
      {
        return A / (theta * theta) + B * h * h + C * h / theta + D / theta + E * h + F;
      }
    };
    constexpr FilletCoefficients L_star{-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045};
    constexpr FilletCoefficients M_star{60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086};
    constexpr FilletCoefficients P_star{-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236};
    constexpr FilletCoefficients Q_star{-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904};

    // Root of a monotone increasing g on [lo, hi] with g(lo) <= target <= g(hi), by bisection.
    double invert(const std::function<double(double)> &g, const double target, double lo, double hi)
    {
      for (int it = 0; it < 200 && hi - lo > 1e-15 * std::max(1.0, std::abs(hi)); ++it)
        {
          const double mid = 0.5 * (lo + hi);
          (g(mid) < target ? lo : hi) = mid;
        }
      return 0.5 * (lo + hi);
    }
  } // namespace

  ToothCompliance beam_compliance(const std::function<double(double)> &y, const double x0,
                                  const double x_load, const double y_load, const double a1,
                                  const double E, const double G, const double L,
                                  const std::vector<double> &kinks)
  {
    HG_REQUIRE_INPUT(x_load > x0, "potential-energy tooth: load point x = ", x_load,
                     " mm is not above the root section x = ", x0, " mm");
    const double ca = std::cos(a1), sa = std::sin(a1);
    ToothCompliance c;
    c.load_angle_rad   = a1;
    c.bending_mm_per_N = integrate(
      [&](const double x) {
        const double m = ca * (x_load - x) - sa * y_load;
        const double h = y(x);
        return m * m / (E * 2.0 * h * h * h * L / 3.0);
      },
      x0, x_load, kinks);
    const double inv_area = integrate([&](const double x) { return 1.0 / (2.0 * y(x) * L); }, x0,
                                      x_load, kinks);
    c.shear_mm_per_N = 1.2 * ca * ca / G * inv_area;
    c.axial_mm_per_N = sa * sa / E * inv_area;
    return c;
  }

  double fillet_foundation_compliance(const double u_f, const double S_f, const double h_f,
                                      const double theta_f, const double a1, const double E,
                                      const double L)
  {
    const double ratio = u_f / S_f;
    const double t     = std::tan(a1);
    return std::cos(a1) * std::cos(a1) / (E * L) *
           (L_star(h_f, theta_f) * ratio * ratio + M_star(h_f, theta_f) * ratio +
            P_star(h_f, theta_f) * (1 + Q_star(h_f, theta_f) * t * t));
  }

  ToothCompliance tooth_compliance(const meshing::GearGeometry &g, const double u, const double E,
                                   const double nu, const bool plane_strain)
  {
    HG_REQUIRE_INPUT(g.bore_radius_mm() > 0, g.parameters().name, " bore_radius_mm = ",
                     g.bore_radius_mm(),
                     ": the potential-energy fillet foundation (Sainsot et al. 2004) needs a bore");
    HG_REQUIRE_INPUT(u >= g.form_roll_angle() - 1e-12 && u <= g.tip_roll_angle() + 1e-12,
                     g.parameters().name, ": roll angle ", u, " is off the involute [",
                     g.form_roll_angle(), ", ", g.tip_roll_angle(), "]");
    const double Ep = plane_strain ? E / (1 - nu * nu) : E;
    const double G  = E / (2 * (1 + nu));
    const double L  = g.face_width_mm();

    // The half-profile above the root circle, fillet then involute; x grows along both.
    const double u_F = g.form_roll_angle(), u_a = g.tip_roll_angle();
    const auto   fillet_x = [&](const double t) { return g.fillet_point(t).x(); };
    const auto   flank_x  = [&](const double s) { return g.involute_point(s).x(); };
    const double x0 = fillet_x(0), x_F = g.involute_point(u_F).x();
    const auto   y = [&](const double x) {
      if (x <= x_F)
        return g.fillet_point(invert(fillet_x, x, 0, 1)).y();
      return g.involute_point(invert(flank_x, x, u_F, u_a)).y();
    };

    const Eigen::Vector2d P = g.involute_point(u);
    // Load on the tooth: along the inward normal of the drive flank.
    const Eigen::Vector2d n  = -g.involute_normal(u);
    const double          a1 = std::atan2(-n.x(), std::abs(n.y()));

    ToothCompliance c = beam_compliance(y, x0, P.x(), P.y(), a1, Ep, G, L, {x_F});

    const double r_f     = g.root_radius_mm();
    const double theta_f = g.root_fillet_angle_rad();
    const double u_f     = P.x() - r_f - P.y() * std::tan(a1);
    c.fillet_mm_per_N = fillet_foundation_compliance(u_f, 2 * r_f * theta_f, r_f / g.bore_radius_mm(),
                                                     theta_f, a1, Ep, L);
    return c;
  }
} // namespace hertzgear::stiffness
