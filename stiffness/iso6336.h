#pragma once
// Tooth stiffness of ISO 6336-1:2006 (Calculation of load capacity of spur and helical gears,
// Part 1), clause 9, method B: single stiffness c' and mesh stiffness c_gamma_alpha of a spur or
// helical pair with solid gear blanks, as an analytic reference and as a stiffness source for
// dynamics (spur pairs only there).
//
//   q'       = C1 + C2/z_n1 + C3/z_n2 + C4 x1 + C5 x1/z_n1 + C6 x2 + C7 x2/z_n2 + C8 x1^2 + C9 x2^2
//              [mm um / N], minimum flexibility of a tooth pair (ISO 6336-1:2006, clause 9, method B),
//              z_n = z / (cos^2(beta_b) cos(beta)) the virtual numbers of teeth (z for spur gears)
//   c'_th    = 1 / q'                                          [N / (mm um)]
//   c'       = c'_th C_M C_R C_B cos(beta)                       (F_t K_A / b >= 100 N/mm)
//   c'       = c'_th C_M C_R C_B cos(beta) (F_t K_A / b / 100)^0.25   (below 100 N/mm)
//   C_M      = 0.8 (theoretical correction factor)
//   C_R      = 1 + ln(b_s / b) / (5 e^(s_R / (5 m_n))) for webbed blanks, 1 for solid gears
//   C_B      = [1 + 0.5 (1.2 - h_fP/m_n)] [1 - 0.02 (20 deg - alpha_Pn)], averaged over both
//              gears when their basic racks differ (basic rack factor)
//   c_gamma_alpha = c' (0.75 eps_alpha + 0.25)                   (mesh stiffness, eps_alpha >= 1.2)
//   c_gamma_beta  = 0.85 c_gamma_alpha                          (for the face load factor K_Hbeta)
// with the reference diameter d1 = z1 m_n / cos(beta) in F_t = 2000 T1 / d1 and the normal basic
// rack in C_B.
#include "common/material.h"
#include "meshing/pair_kinematics.h"

#include <nlohmann/json.hpp>

namespace hertzgear::stiffness
{
  struct Iso6336Stiffness
  {
    double q_prime_mm_um_per_N      = 0;
    double c_prime_th_N_per_mm_um   = 0;
    double C_M                      = 0;
    double C_R                      = 0;
    double C_B                      = 0;
    double load_factor              = 0; // (F_t K_A / b / 100)^0.25, or 1
    double c_prime_N_per_mm_um      = 0;
    double c_gamma_alpha_N_per_mm_um = 0;
    double c_gamma_beta_N_per_mm_um  = 0;
    double line_load_N_per_mm       = 0; // F_t K_A / b used for the load factor
    // c_gamma_alpha of ISO 6336-1 is defined for eps_alpha >= 1.2; below, it is an extrapolation.
    bool within_validity = true;
  };
  // Its record in geometry.json, with the member names as keys: the stiffnesses, the factors, the
  // line load and the validity (q' is left out: c'_th = 1 / q').
  NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Iso6336Stiffness, c_prime_th_N_per_mm_um, c_prime_N_per_mm_um,
                                     c_gamma_alpha_N_per_mm_um, c_gamma_beta_N_per_mm_um, C_M, C_R, C_B, load_factor,
                                     line_load_N_per_mm, within_validity)

  // `pinion_torque_Nm` gives F_t = 2000 T1 / d1 on the reference circle (K_A = 1); the face
  // width is the smaller of both. Solid blanks (C_R = 1). Spur and helical pairs.
  Iso6336Stiffness iso6336_method_b(const meshing::PairKinematics &pair, double pinion_torque_Nm);

  // The nominal contact stress of ISO 6336-2 (method B) at the pitch point, spur or helical,
  //   sigma_H0 = Z_H Z_E Z_eps Z_beta sqrt(F_t / (d1 b) (u + 1) / u)   [MPa]
  // with F_t = 2000 |T1| / d1 on the reference circle (K factors 1), d1 = m_n z1 / cos(beta), b the
  // smaller face width, u = z2 / z1, the zone factor
  // Z_H = sqrt(2 cos(beta_b) cos(alpha_wt) / (cos^2(alpha_t) sin(alpha_wt))), the elasticity factor
  // Z_E = sqrt(1 / (pi ((1 - nu1^2) / E1 + (1 - nu2^2) / E2))), the contact ratio factor
  // Z_eps = sqrt((4 - eps_alpha) / 3 (1 - eps_beta) + eps_beta / eps_alpha) for eps_beta < 1 and
  // sqrt(1 / eps_alpha) from eps_beta = 1 on, and the helix angle factor Z_beta = 1 / sqrt(cos(beta))
  // (all 1 or their spur forms at beta = 0).
  struct NominalContactStress
  {
    double sigma_H0_MPa                = 0;
    double tangential_force_N          = 0; // F_t
    double specific_load_N_per_mm      = 0; // F_t / b
    double Z_H = 0, Z_E = 0, Z_eps = 0, Z_beta = 0;
  };
  NominalContactStress nominal_contact_stress(const meshing::PairKinematics &pair,
                                              const Material &pinion, const Material &gear,
                                              double pinion_torque_Nm);

  // The nominal contact stress above which a load is implausible for any gear: 3000 MPa, above
  // the largest permissible contact stress of ISO 6336 for case-hardened steel even under static
  // load (sigma_Hlim = 1650 MPa of ISO 6336-5, times the static life factor Z_NT = 1.6 of
  // ISO 6336-2: 2640 MPa).
  constexpr double implausible_contact_stress_MPa = 3000.0;
} // namespace hertzgear::stiffness
