#include "stiffness/iso6336.h"

#include <algorithm>
#include <cmath>

namespace hertzgear::stiffness
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    double basic_rack_factor(const meshing::GearParameters &p)
    {
      const double alpha_deg = p.pressure_angle_rad * 180 / pi;
      return (1 + 0.5 * (1.2 - p.dedendum_coefficient)) * (1 - 0.02 * (20 - alpha_deg));
    }
  } // namespace

  Iso6336Stiffness iso6336_method_b(const meshing::PairKinematics &pair, const double pinion_torque_Nm)
  {
    const meshing::GearParameters &p1 = pair.pinion().parameters(), &p2 = pair.gear().parameters();
    // Virtual numbers of teeth z_n = z / (cos^2(beta_b) cos(beta)) (z for a spur gear, where
    // both cosines are exactly 1), with the helix angle beta at the reference circle.
    const double beta = pair.helix_angle_rad(), cos_beta = std::cos(beta);
    const double cos_beta_b = std::cos(pair.base_helix_angle_rad());
    const double zn_factor  = 1 / (cos_beta_b * cos_beta_b * cos_beta);
    const double z1 = p1.teeth * zn_factor, z2 = p2.teeth * zn_factor;
    const double x1 = p1.profile_shift_coefficient, x2 = p2.profile_shift_coefficient;
    // ISO 6336-1:2006, clause 9 (method B): the coefficients C1..C9 of the flexibility q'.
    constexpr double C1 = 0.04723, C2 = 0.15551, C3 = 0.25791, C4 = -0.00635, C5 = -0.11654,
                     C6 = -0.00193, C7 = -0.24188, C8 = 0.00529, C9 = 0.00182;
    Iso6336Stiffness s;
    s.q_prime_mm_um_per_N = C1 + C2 / z1 + C3 / z2 + C4 * x1 + C5 * x1 / z1 + C6 * x2 +
                            C7 * x2 / z2 + C8 * x1 * x1 + C9 * x2 * x2;
    s.c_prime_th_N_per_mm_um = 1 / s.q_prime_mm_um_per_N;
    s.C_M                    = 0.8;
    s.C_R                    = 1.0;
    s.C_B                    = 0.5 * (basic_rack_factor(p1) + basic_rack_factor(p2));
    const double b           = std::min(p1.face_width_mm, p2.face_width_mm);
    const double d1          = p1.module_mm * p1.teeth / cos_beta; // reference diameter
    s.line_load_N_per_mm     = 2000 * pinion_torque_Nm / d1 / b;
    s.load_factor = s.line_load_N_per_mm >= 100 ? 1.0 : std::pow(s.line_load_N_per_mm / 100, 0.25);
    s.c_prime_N_per_mm_um =
      s.c_prime_th_N_per_mm_um * s.C_M * s.C_R * s.C_B * s.load_factor * cos_beta;
    const double eps      = pair.contact_ratio();
    s.c_gamma_alpha_N_per_mm_um = s.c_prime_N_per_mm_um * (0.75 * eps + 0.25);
    s.c_gamma_beta_N_per_mm_um  = 0.85 * s.c_gamma_alpha_N_per_mm_um;
    s.within_validity           = eps >= 1.2;
    return s;
  }

  NominalContactStress nominal_contact_stress(const meshing::PairKinematics &pair,
                                              const Material &pinion, const Material &gear,
                                              const double pinion_torque_Nm)
  {
    const meshing::GearParameters &p1 = pair.pinion().parameters(), &p2 = pair.gear().parameters();
    const double beta    = pair.helix_angle_rad(), cos_beta = std::cos(beta);
    const double cos_bb  = std::cos(pair.base_helix_angle_rad());
    const double d1      = p1.module_mm * p1.teeth / cos_beta;
    const double b       = std::min(p1.face_width_mm, p2.face_width_mm);
    const double u       = double(p2.teeth) / p1.teeth;
    const double alpha_t = pair.pinion().transverse_pressure_angle_rad();
    const double alpha_w = pair.operating_pressure_angle_rad(); // transverse
    const double eps_a = pair.contact_ratio(), eps_b = pair.face_contact_ratio();
    NominalContactStress s;
    s.Z_H   = std::sqrt(2 * cos_bb * std::cos(alpha_w) /
                      (std::cos(alpha_t) * std::cos(alpha_t) * std::sin(alpha_w)));
    s.Z_E   = std::sqrt(1 / (pi * ((1 - pinion.poisson_ratio * pinion.poisson_ratio) /
                                   pinion.youngs_modulus_MPa +
                                 (1 - gear.poisson_ratio * gear.poisson_ratio) /
                                   gear.youngs_modulus_MPa)));
    s.Z_eps = eps_b < 1 ? std::sqrt(std::max(0.0, 4 - eps_a) / 3 * (1 - eps_b) + eps_b / eps_a) :
                          std::sqrt(1 / eps_a);
    s.Z_beta = 1 / std::sqrt(cos_beta);
    s.tangential_force_N     = 2000 * std::abs(pinion_torque_Nm) / d1;
    s.specific_load_N_per_mm = s.tangential_force_N / b;
    s.sigma_H0_MPa = s.Z_H * s.Z_E * s.Z_eps * s.Z_beta *
                     std::sqrt(s.tangential_force_N / (d1 * b) * (u + 1) / u);
    return s;
  }
} // namespace hertzgear::stiffness
