#pragma once
// Hertz closed forms for line and elliptical (point) contact, and the load-penetration law of the
// reference paper. Plain C++, no deal.II. The scene units are mm-N-MPa (Material names its modulus in
// MPa), but every formula holds in any consistent unit system (the tests also run them in SI).
// Equations and sources: docs/theory-contact.md.
//
// Conventions
// - Curvatures are signed: positive for a convex surface, negative for a concave one (internal
//   gear, bearing race). A "relative curvature" is the sum over both bodies along one direction.
// - The unloaded gap near the initial contact point is h(x, y) = A x^2 + B y^2 with
//   A = kappa_x / 2, B = kappa_y / 2 (principal directions of both bodies aligned).
// - "Approach" delta is the distance by which two points far from the contact (in the half-space
//   idealisation: at infinity) move towards each other. For line contact the approach is not
//   defined by the half-space alone; each line-contact formula below says which distance it is.

#include "common/material.h"

namespace hertzgear
{
  namespace hertz
  {
    // 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2.
    double contact_modulus(const Material &body_1, const Material &body_2);

    // 1/R = 1/R1 + 1/R2 with signed radii (R = infinity for a plane: pass 0 curvature instead
    // through relative_curvature). Throws InputError when the sum is not positive.
    double effective_radius(const double radius_1, const double radius_2);

    // ---------------------------------------------------------------- line contact (2D, per length)
    struct LineContact
    {
      double half_width;    // b = sqrt(4 F' R / (pi E*))
      double peak_pressure; // p0 = 2 F' / (pi b) = sqrt(F' E* / (pi R))
    };

    LineContact line_contact(const double load_per_length, const double effective_radius,
                             const double contact_modulus);

    // Approach of the axes of two parallel cylinders of radii R1, R2 (each body's centre line
    // relative to the contact), Johnson (1985) ch. 5 after Puttock & Thwaite (1969):
    //   delta = sum_i 2 F' (1 - nu_i^2)/(pi E_i) [ln(4 R_i / b) - 1/2].
    double line_approach_johnson(const double load_per_length, const double radius_1,
                                 const Material &body_1, const double radius_2,
                                 const Material &body_2);

    // Approach of two points at depths h1, h2 below the contact, on the load line, after Weber &
    // Banaschek (1953) (the Hertzian term of the tooth-deflection model used in gear standards
    // and in most analytical mesh-stiffness models):
    //   delta = sum_i 2 F' (1 - nu_i^2)/(pi E_i) [ln(2 h_i / b) - nu_i / (2 (1 - nu_i))].
    double line_approach_weber(const double load_per_length, const double half_width,
                               const double depth_1, const Material &body_1, const double depth_2,
                               const Material &body_2);

    // Palmgren (1959), as given by Harris, Rolling Bearing Analysis: total approach of a steel
    // roller and a steel raceway, delta[mm] = 3.84e-5 Q[N]^0.9 / l[mm]^0.8, empirical (from
    // measurements, so the reference distance is that of the test rig). Extended to other
    // materials by the dimensionally coherent form delta = c (Q / E*)^0.9 / l^0.8 with c fixed by
    // steel (E = 206 GPa, nu = 0.3); the extension is ours and not validated.
    // Units: N, mm, MPa in, mm out.
    double line_approach_palmgren_mm(const double load_N, const double length_mm,
                                     const double contact_modulus_MPa);

    // ------------------------------------------------------------- elliptical (point) contact
    struct EllipticalContact
    {
      double semi_major;        // a, along the direction of the smaller relative curvature
      double semi_minor;        // b
      double eccentricity;      // e = sqrt(1 - b^2/a^2)
      double approach;          // delta = 3 F K(e) / (2 pi a E*)
      double peak_pressure;     // p0 = 3 F / (2 pi a b)
      double elliptic_k;        // K(e)
      double elliptic_e;        // E(e)
      bool   major_axis_along_x; // true if kappa_x <= kappa_y
    };

    // F and the relative principal curvatures kappa_x, kappa_y (> 0) of the gap
    // h = kappa_x x^2 / 2 + kappa_y y^2 / 2. The eccentricity solves (Johnson 1985, ch. 3-4,
    // Hertz's elliptical contact; Timoshenko & Goodier section 140)
    //   B / A = (E(e)/(1 - e^2) - K(e)) / (K(e) - E(e)),   B >= A,
    // then a^3 = 3 F (K - E) / (2 pi e^2 A E*), b = a sqrt(1 - e^2).
    EllipticalContact elliptical_contact(const double load, const double kappa_x,
                                         const double kappa_y, const double contact_modulus);

    // Eccentricity of the contact ellipse for the curvature ratio B/A >= 1 (Boost.Math TOMS 748).
    double ellipse_eccentricity(const double curvature_ratio);

    // The reference paper's eq. (5): delta = 3 F K(e) / (2 pi a E*), a the semi-major axis.
    double paper_approach(const double load, const double semi_major, const double eccentricity,
                          const double contact_modulus);

    // The paper's law F = k_h delta^n (n = 1 line contact, n = 3/2 point contact).
    double hertz_stiffness(const double load, const double approach, const double exponent);
    double hertz_load(const double stiffness, const double approach, const double exponent);

    // Sphere (or any circular contact) of effective radius R: a = (3 F R / (4 E*))^(1/3),
    // delta = a^2 / R, p0 = 3 F / (2 pi a^2); F = (4/3) E* sqrt(R) delta^(3/2).
    EllipticalContact circular_contact(const double load, const double effective_radius,
                                       const double contact_modulus);
  } // namespace hertz
} // namespace hertzgear
