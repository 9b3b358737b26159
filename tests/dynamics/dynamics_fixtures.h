#pragma once
// Shared set-ups of the dynamics tests.
#include "dynamics/analysis.h"
#include "dynamics/gear_pair_model.h"

#include <cmath>

namespace hertzgear::dynamics::testing
{
  // The crowned pair of data/scenes/paper_crowned_fourier.prm as `hertzgear dynamics` resolves it
  // (m_e from solid discs, F_0 = T_1 / r_b1, c from zeta = 0.015, k_h from Hertz theory).
  inline GearPairParameters paper_crowned()
  {
    GearPairParameters p;
    p.equivalent_mass_kg       = 0.1432020538745814;
    p.static_force_N           = 6477.603832462074;
    p.half_backlash_m          = 58.6e-6;
    p.mesh_frequency_rad_per_s = 2.0 * M_PI * 57.5; // 23 teeth at 150 rpm
    p.damping_N_s_per_m        = 144.33635931367493;
    p.alpha_s_per_m            = 0.26;
    p.stiffness.hertz_exponent = 1.5;
    p.stiffness.k_rest_N_per_m.mean = 2.79e8;
    p.stiffness.k_hertz_N_per_m_pow_n = {5.095e10, {2.045e10, 3.769e9, 5.891e9, 3.513e9},
                                         {0.0, M_PI, M_PI, 0.0}};
    return p;
  }

  // A unit oscillator (m = 1 kg, k = 1e6 N/m, omega_n = 1000 rad/s) for closed-form checks.
  inline GearPairParameters unit_oscillator(const double zeta, const double omega)
  {
    GearPairParameters p;
    p.equivalent_mass_kg              = 1.0;
    p.static_force_N                  = 100.0;
    p.half_backlash_m                 = 0.0;
    p.mesh_frequency_rad_per_s        = omega;
    p.damping_N_s_per_m               = 2.0 * zeta * std::sqrt(1.0e6 * 1.0);
    p.stiffness.hertz_exponent        = 1.0;
    p.stiffness.k_rest_N_per_m.mean   = 1.0e6;
    p.effects.backlash                = false;
    p.effects.hertzian_layer          = HertzianLayer::off;
    p.effects.mesh_stiffness_variation = false;
    return p;
  }

  inline RunSettings run_settings(const IntegratorKind kind, const double rtol, const double atol,
                                  const int periods, const int transient, const int samples = 100)
  {
    RunSettings r;
    r.integrator.kind               = kind;
    r.integrator.relative_tolerance = rtol;
    r.integrator.absolute_tolerance = atol;
    r.periods                       = periods;
    r.transient_periods             = transient;
    r.samples_per_period            = samples;
    return r;
  }
} // namespace hertzgear::dynamics::testing
