#pragma once
// Tooth compliance by the potential-energy method (docs/stiffness-closed-form.md), the analytical
// mesh-stiffness model of the gear-dynamics literature:
//
//   - the tooth is a cantilever of variable section from its root to the load point (Yang & Lin
//     1987, Tian 2004), with the exact half-thickness y(x) of the involute flank and trochoidal
//     fillet along its centre line x (as Chen & Shao 2011 do for the fillet):
//       1/k_b = int [cos a1 (x_P - x) - sin a1 y_P]^2 / (E' I_x) dx,  I_x = 2 y^3 L / 3
//       1/k_s = int 1.2 cos^2 a1 / (G A_x) dx,                         A_x = 2 y L
//       1/k_a = int sin^2 a1 / (E' A_x) dx
//     over x from the root circle to the load point P = (x_P, y_P), a1 the angle between the
//     normal load and the perpendicular to the centre line (positive when the load compresses);
//   - the fillet foundation (the body flexing under the tooth root), Sainsot, Velex & Duverger
//     2004 (ASME J. Mech. Des. 126, 748-752):
//       1/k_f = cos^2 a1 / (E' L) [L* (u_f/S_f)^2 + M* (u_f/S_f) + P* (1 + Q* tan^2 a1)]
//     u_f = x_P - r_f - y_P tan a1 (where the load line crosses the centre line, above the root
//     circle), S_f = 2 r_f theta_f (root thickness on the root circle), and
//       X*(h_f, theta_f) = A/theta_f^2 + B h_f^2 + C h_f/theta_f + D/theta_f + E h_f + F,
//     h_f = r_f / r_bore, with the coefficients A..F of their Table 1 for L*, M*, P*, Q*.
//
// E' = E as the sources write it (plane stress), or E / (1 - nu^2) for plane strain, which a tooth
// whose face width is several modules is closer to: it makes the tooth part (1 - nu^2) = 0.91 times
// as compliant for steel. G = E / (2 (1 + nu)) in both. Lengths in mm, forces in N, moduli in MPa:
// compliances in mm/N.
#include "meshing/gear_geometry.h"

#include <functional>

namespace hertzgear::stiffness
{
  struct ToothCompliance
  {
    double bending_mm_per_N = 0;
    double shear_mm_per_N   = 0;
    double axial_mm_per_N   = 0;
    double fillet_mm_per_N  = 0;
    double load_angle_rad   = 0; // a1
    double total_mm_per_N() const
    {
      return bending_mm_per_N + shear_mm_per_N + axial_mm_per_N + fillet_mm_per_N;
    }
  };

  // Bending, shear and axial compliance of a cantilever of half-thickness y(x) > 0 over
  // x0 <= x <= x_load, width L, loaded at (x_load, y_load) at the load angle a1. The integrals
  // are adaptive Gauss-Kronrod (relative tolerance 1e-10). `kinks` lists x values inside the range
  // where y(x) is not smooth (integration intervals are split there).
  ToothCompliance beam_compliance(const std::function<double(double)> &half_thickness_mm, double x0_mm,
                                  double x_load_mm, double y_load_mm, double load_angle_rad,
                                  double plane_strain_modulus_MPa, double shear_modulus_MPa,
                                  double width_mm, const std::vector<double> &kinks = {});

  // The fillet-foundation compliance of Sainsot et al. (2004) [mm/N].
  double fillet_foundation_compliance(double u_f_mm, double S_f_mm, double h_f, double theta_f_rad,
                                      double load_angle_rad, double plane_strain_modulus_MPa,
                                      double width_mm);

  // The compliance of one tooth of `gear` loaded normally on its drive flank at roll angle u
  // (the involute point at radius r_b sqrt(1 + u^2)), over the face width of the gear. Throws
  // InputError when the gear has no bore (the fillet foundation needs r_bore > 0) or the roll
  // angle is off the involute.
  ToothCompliance tooth_compliance(const meshing::GearGeometry &gear, double roll_angle, double youngs_modulus_MPa,
                                   double poisson_ratio, bool plane_strain = false);
} // namespace hertzgear::stiffness
