#include "contact/hertz.h"

#include "common/errors.h"

#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/ellint_2.hpp>
#include <boost/math/special_functions/ellint_d.hpp>
#include <boost/math/tools/toms748_solve.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace hertzgear
{
  namespace hertz
  {
    namespace
    {
      constexpr double pi = 3.14159265358979323846;

      void check_material(const Material &m)
      {
        HG_REQUIRE_INPUT(m.youngs_modulus_MPa > 0, "Young's modulus must be positive, got ", m.youngs_modulus_MPa);
        HG_REQUIRE_INPUT(m.poisson_ratio > -1.0 && m.poisson_ratio < 0.5,
                         "Poisson ratio must lie in (-1, 0.5), got ", m.poisson_ratio);
      }

      // Curvature ratio B/A of the gap as a function of the ellipse eccentricity, written with
      // D(e) = (K - E)/e^2 so that nothing cancels as e -> 0:
      //   B/A = (E/(1-e^2) - K)/(K - E) = (K - D) / ((1 - e^2) D).
      double curvature_ratio_of(const double e)
      {
        const double K = boost::math::ellint_1(e);
        const double D = boost::math::ellint_d(e);
        return (K - D) / ((1.0 - e * e) * D);
      }
    } // namespace

    double contact_modulus(const Material &body_1, const Material &body_2)
    {
      check_material(body_1);
      check_material(body_2);
      const double compliance = (1.0 - body_1.poisson_ratio * body_1.poisson_ratio) / body_1.youngs_modulus_MPa +
                                (1.0 - body_2.poisson_ratio * body_2.poisson_ratio) / body_2.youngs_modulus_MPa;
      return 1.0 / compliance;
    }

    double effective_radius(const double radius_1, const double radius_2)
    {
      HG_REQUIRE_INPUT(radius_1 != 0 && radius_2 != 0, "radii of curvature must be non-zero");
      const double curvature = 1.0 / radius_1 + 1.0 / radius_2;
      HG_REQUIRE_INPUT(curvature > 0, "the relative curvature 1/R1 + 1/R2 = ", curvature,
                       " is not positive: the surfaces do not touch in a point or line");
      return 1.0 / curvature;
    }

    LineContact line_contact(const double load_per_length, const double effective_radius,
                             const double contact_modulus)
    {
      HG_REQUIRE_INPUT(load_per_length > 0, "load per length must be positive, got ", load_per_length);
      HG_REQUIRE_INPUT(effective_radius > 0 && contact_modulus > 0,
                       "effective radius and contact modulus must be positive");
      LineContact c;
      c.half_width    = std::sqrt(4.0 * load_per_length * effective_radius / (pi * contact_modulus));
      c.peak_pressure = 2.0 * load_per_length / (pi * c.half_width);
      return c;
    }

    double line_approach_johnson(const double load_per_length, const double radius_1,
                                 const Material &body_1, const double radius_2,
                                 const Material &body_2)
    {
      HG_REQUIRE_INPUT(radius_1 > 0 && radius_2 > 0,
                       "the cylinder-axis approach needs two convex cylinders");
      const double E_star = contact_modulus(body_1, body_2);
      const double b      = line_contact(load_per_length, effective_radius(radius_1, radius_2), E_star).half_width;
      double       delta  = 0;
      for (const auto &[R, m] : {std::pair{radius_1, body_1}, std::pair{radius_2, body_2}})
        delta += 2.0 * load_per_length * (1.0 - m.poisson_ratio * m.poisson_ratio) / (pi * m.youngs_modulus_MPa) *
                 (std::log(4.0 * R / b) - 0.5);
      return delta;
    }

    double line_approach_weber(const double load_per_length, const double half_width,
                               const double depth_1, const Material &body_1, const double depth_2,
                               const Material &body_2)
    {
      HG_REQUIRE_INPUT(load_per_length > 0 && half_width > 0, "load and half-width must be positive");
      HG_REQUIRE_INPUT(depth_1 > half_width && depth_2 > half_width,
                       "the Weber reference depths must exceed the contact half-width");
      check_material(body_1);
      check_material(body_2);
      double delta = 0;
      for (const auto &[h, m] : {std::pair{depth_1, body_1}, std::pair{depth_2, body_2}})
        {
          const double nu = m.poisson_ratio;
          delta += 2.0 * load_per_length * (1.0 - nu * nu) / (pi * m.youngs_modulus_MPa) *
                   (std::log(2.0 * h / half_width) - nu / (2.0 * (1.0 - nu)));
        }
      return delta;
    }

    double line_approach_palmgren_mm(const double load_N, const double length_mm,
                                     const double contact_modulus_MPa)
    {
      HG_REQUIRE_INPUT(load_N > 0 && length_mm > 0 && contact_modulus_MPa > 0,
                       "Palmgren's approach needs positive load, length and modulus");
      // Steel: E = 206 000 MPa, nu = 0.3 for both bodies.
      const double E_star_steel = 206000.0 / (2.0 * (1.0 - 0.3 * 0.3));
      const double c            = 3.84e-5 * std::pow(E_star_steel, 0.9);
      return c * std::pow(load_N / contact_modulus_MPa, 0.9) / std::pow(length_mm, 0.8);
    }

    double ellipse_eccentricity(const double curvature_ratio)
    {
      HG_REQUIRE_INPUT(curvature_ratio >= 1.0, "the curvature ratio B/A must be >= 1, got ", curvature_ratio);
      if (curvature_ratio == 1.0)
        return 0.0;
      // ratio(e) grows monotonically from 1 at e = 0; at e = 1 - 1e-14 it is about 1e14.
      const double e_max = 1.0 - 1e-14;
      HG_REQUIRE_INPUT(curvature_ratio < curvature_ratio_of(e_max), "curvature ratio ", curvature_ratio,
                       " is too large for an elliptical contact: treat it as a line contact");
      const auto     f            = [&](const double e) { return curvature_ratio_of(e) - curvature_ratio; };
      std::uintmax_t n_iterations = 200;
      const auto     root = boost::math::tools::toms748_solve(
        f, 0.0, e_max, 1.0 - curvature_ratio, curvature_ratio_of(e_max) - curvature_ratio,
        boost::math::tools::eps_tolerance<double>(std::numeric_limits<double>::digits - 2), n_iterations);
      HG_REQUIRE_NUMERIC(n_iterations < 200, "the ellipse eccentricity did not converge for B/A = ",
                         curvature_ratio);
      return 0.5 * (root.first + root.second);
    }

    EllipticalContact elliptical_contact(const double load, const double kappa_x, const double kappa_y,
                                         const double contact_modulus)
    {
      HG_REQUIRE_INPUT(load > 0, "contact load must be positive, got ", load);
      HG_REQUIRE_INPUT(kappa_x > 0 && kappa_y > 0, "both relative curvatures must be positive (got ",
                       kappa_x, ", ", kappa_y, "); a zero curvature is a line contact");
      HG_REQUIRE_INPUT(contact_modulus > 0, "contact modulus must be positive");
      const double A = 0.5 * std::min(kappa_x, kappa_y);
      const double B = 0.5 * std::max(kappa_x, kappa_y);

      EllipticalContact c;
      c.major_axis_along_x = kappa_x <= kappa_y;
      c.eccentricity       = ellipse_eccentricity(B / A);
      const double e       = c.eccentricity;
      c.elliptic_k         = boost::math::ellint_1(e);
      c.elliptic_e         = boost::math::ellint_2(e);
      const double D       = boost::math::ellint_d(e); // (K - E)/e^2, finite at e = 0
      c.semi_major         = std::cbrt(3.0 * load * D / (2.0 * pi * A * contact_modulus));
      c.semi_minor         = c.semi_major * std::sqrt(1.0 - e * e);
      c.approach           = paper_approach(load, c.semi_major, e, contact_modulus);
      c.peak_pressure      = 3.0 * load / (2.0 * pi * c.semi_major * c.semi_minor);
      return c;
    }

    double paper_approach(const double load, const double semi_major, const double eccentricity,
                          const double contact_modulus)
    {
      HG_REQUIRE_INPUT(semi_major > 0 && contact_modulus > 0 && eccentricity >= 0 && eccentricity < 1,
                       "paper_approach: a > 0, E* > 0 and 0 <= e < 1 required");
      return 3.0 * load * boost::math::ellint_1(eccentricity) / (2.0 * pi * semi_major * contact_modulus);
    }

    double hertz_stiffness(const double load, const double approach, const double exponent)
    {
      HG_REQUIRE_INPUT(approach > 0, "Hertz stiffness needs a positive approach, got ", approach);
      return load / std::pow(approach, exponent);
    }

    double hertz_load(const double stiffness, const double approach, const double exponent)
    {
      return approach > 0 ? stiffness * std::pow(approach, exponent) : 0.0;
    }

    EllipticalContact circular_contact(const double load, const double effective_radius,
                                       const double contact_modulus)
    {
      HG_REQUIRE_INPUT(load > 0 && effective_radius > 0 && contact_modulus > 0,
                       "circular contact needs positive load, radius and modulus");
      EllipticalContact c;
      c.semi_major         = std::cbrt(3.0 * load * effective_radius / (4.0 * contact_modulus));
      c.semi_minor         = c.semi_major;
      c.eccentricity       = 0;
      c.elliptic_k         = pi / 2;
      c.elliptic_e         = pi / 2;
      c.approach           = c.semi_major * c.semi_major / effective_radius;
      c.peak_pressure      = 3.0 * load / (2.0 * pi * c.semi_major * c.semi_major);
      c.major_axis_along_x = true;
      return c;
    }
  } // namespace hertz
} // namespace hertzgear
