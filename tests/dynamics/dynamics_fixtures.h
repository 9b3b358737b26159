#pragma once
// Shared set-ups of the dynamics tests.
#include "dynamics/analysis.h"
#include "dynamics/gear_pair_model.h"
#include "table/stiffness_table.h"

#include <cmath>
#include <complex>
#include <string>
#include <utility>
#include <vector>

namespace hertzgear::dynamics::testing
{
  // The phase coefficients at the angle theta as the model keeps them (dth = 0), with w = 1 so
  // that a rate is the derivative in theta.
  struct PhaseAt
  {
    std::vector<double> taylor;
    MeshPhase           phase;
    PhaseAt(const MeshForceLaw &law, const double theta)
      : taylor(3 * law.n_phase_coefficients())
    {
      law.phase_coefficients(theta, std::cos(theta), std::sin(theta), taylor.data());
      phase = MeshPhase{taylor.data(), 0.0, 1.0};
    }
  };

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

  // The crowned pair driven by a transmission-error excitation of `ste_amplitude_m` at mesh
  // frequency `mesh_frequency_hz` under the static load `static_force_N`.
  inline GearPairParameters ste_driven_pair(const double static_force_N, const double mesh_frequency_hz,
                                            const double ste_amplitude_m)
  {
    auto p                       = paper_crowned();
    p.static_force_N             = static_force_N;
    p.mesh_frequency_rad_per_s   = 2 * M_PI * mesh_frequency_hz;
    p.stiffness.unloaded_ste_m   = {0.0, {ste_amplitude_m}, {0.0}};
    p.stiffness.has_unloaded_ste = true;
    p.effects.ste_excitation     = true;
    return p;
  }

  // Double-sided impacts near the primary resonance at low load: a 30 um transmission-error
  // excitation at the mesh natural frequency (about 3.3 kHz at F_0 = 50 N) drives the teeth
  // through the backlash onto the back flanks (data/scenes/backside_impacts_fourier.prm).
  inline GearPairParameters backside_impact_pair() { return ste_driven_pair(50.0, 3300.0, 30e-6); }

  // The crowned pair of data/scenes/paper_crowned_table.prm as `hertzgear dynamics` resolves it
  // (the shipped FE table data/stiffness/paper_crowned.json, k constant at its mean, c from
  // zeta = 0.015 on the linearised stiffness), at 16000 rpm: near the primary resonance, where
  // the layer opens at delta = 0 and the teeth fly through the backlash and close again once per
  // mesh period once the transient from the scene's initial state (contact_loss_start) has settled.
  inline GearPairParameters contact_loss_pair()
  {
    GearPairParameters p;
    p.stiffness = table::read_stiffness_table(std::string(HERTZGEAR_SOURCE_DIR) +
                                       "/data/stiffness/paper_crowned.json");
    p.equivalent_mass_kg       = 0.1432020538745814;
    p.static_force_N           = 6477.603832462074;
    p.half_backlash_m          = 58.6e-6;
    p.mesh_frequency_rad_per_s = 2.0 * M_PI * 23.0 * 16000.0 / 60.0;
    p.alpha_s_per_m            = 0.26;
    p.effects.rest_stiffness_variation = false;
    p.damping_N_s_per_m =
      2.0 * 0.015 *
      std::sqrt(equivalent_mesh_stiffness(p.stiffness, HertzianLayer::dynamic, p.static_force_N) *
                p.equivalent_mass_kg);
    return p;
  }
  // The scene's given initial state (x = 58.6059 um, x' = 5.86e-5 m/s, delta = 0.05796 um).
  inline std::vector<double> contact_loss_start(const GearPairModel &model)
  {
    return model.state(58.6059e-6, 5.86e-5, 0.05796e-6);
  }

  // m x'' + c x' + k(t) f(x) = F_0 with m = 1 kg, k(t) = 1 - a cos(Omega t) - 0.1 cos(2 Omega t)
  // - 0.05 cos(3 Omega t) N/m and damping ratio 0.05 on the mean stiffness: a linear oscillator
  // with a periodic stiffness near its principal parametric resonance at Omega ~ 2 rad/s, and with
  // a half backlash b_c > 0 (f(x) = x -+ b_c outside it) a piecewise-linear one.
  inline GearPairParameters parametric_oscillator(const double omega, const double F0,
                                                  const double a = 0.2, const double b_c = 0.0)
  {
    GearPairParameters p;
    p.equivalent_mass_kg               = 1.0;
    p.static_force_N                   = F0;
    p.half_backlash_m                  = b_c;
    p.mesh_frequency_rad_per_s         = omega;
    p.damping_N_s_per_m                = 2.0 * 0.05 * std::sqrt(1.0 * 1.0);
    p.stiffness.hertz_exponent         = 1.0;
    p.stiffness.k_rest_N_per_m         = {1.0, {a, 0.1, 0.05}, {M_PI, M_PI, M_PI}};
    p.effects.backlash                 = b_c > 0.0;
    p.effects.hertzian_layer           = HertzianLayer::off;
    p.effects.mesh_stiffness_variation = false;
    p.effects.rest_stiffness_variation = true;
    return p;
  }

  // The Floquet multipliers of a linear model without backlash (x and x' as its state), from its
  // affine period map y(T) = M y(0) + b: the columns of M are the differences of the states one
  // period after (1, 0) and (0, 1) from the state after (0, 0). Independent of the shooting code.
  inline std::pair<std::complex<double>, std::complex<double>>
  linear_period_map_multipliers(const GearPairParameters &p, const double rtol, const double atol)
  {
    GearPairModel      model(p);
    IntegratorSettings set;
    set.kind               = IntegratorKind::radau_iia;
    set.relative_tolerance = rtol;
    set.absolute_tolerance = atol;
    const auto after_one_period = [&](std::vector<double> y) {
      make_integrator(set)->integrate(model, 0.0, y, model.mesh_period(), 1, {});
      return y;
    };
    const auto b = after_one_period({0.0, 0.0});
    double     M[2][2];
    for (int col = 0; col < 2; ++col)
      {
        const auto y = after_one_period({col == 0 ? 1.0 : 0.0, col == 1 ? 1.0 : 0.0});
        M[0][col]    = y[0] - b[0];
        M[1][col]    = y[1] - b[1];
      }
    const double tr = M[0][0] + M[1][1], det = M[0][0] * M[1][1] - M[0][1] * M[1][0];
    const std::complex<double> disc = std::sqrt(std::complex<double>(tr * tr / 4.0 - det));
    return {tr / 2.0 + disc, tr / 2.0 - disc};
  }

  // The dimensionless backlash oscillator of Kahraman & Singh (1990),
  //   p'' + 2 zeta c(p) p' + f(p) = F_m + F_a cos(Omega t),  f with half backlash 1,
  // as the gear-pair model at forcing frequency Omega (m = 1 kg, k = 1 N/m, b_c = 1 m, the layer
  // off): e(t) = E cos(Omega t) with E = F_a / Omega^2 puts F_a cos(Omega t) on p = x - e. The
  // viscous damping is the mesh's, so it acts in contact only (c(p) = 1 for |p| >= 1, 0 inside
  // the backlash), where Kahraman & Singh keep it everywhere.
  inline GearPairParameters kahraman_singh_oscillator(const double omega, const double zeta,
                                                      const double F_m, const double F_a)
  {
    GearPairParameters prm;
    prm.equivalent_mass_kg               = 1.0;
    prm.static_force_N                   = F_m;
    prm.half_backlash_m                  = 1.0;
    prm.mesh_frequency_rad_per_s         = omega;
    prm.damping_N_s_per_m                = 2 * zeta;
    prm.stiffness.hertz_exponent         = 1.0;
    prm.stiffness.k_rest_N_per_m.mean    = 1.0;
    prm.stiffness.unloaded_ste_m         = {0.0, {F_a / (omega * omega)}, {0.0}};
    prm.stiffness.has_unloaded_ste       = true;
    prm.effects.hertzian_layer           = HertzianLayer::off;
    prm.effects.mesh_stiffness_variation = false;
    prm.effects.ste_excitation           = true;
    return prm;
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

  // The unit oscillator driven by the STE harmonic e(t) = E cos(omega t), and the closed-form
  // amplitude of its linear response |X| = E |k + i c omega| / |k - m omega^2 + i c omega|.
  inline GearPairParameters unit_oscillator_with_ste(const double zeta, const double omega,
                                                     const double E)
  {
    auto p                       = unit_oscillator(zeta, omega);
    p.stiffness.unloaded_ste_m   = {0.0, {E}, {0.0}};
    p.stiffness.has_unloaded_ste = true;
    p.effects.ste_excitation     = true;
    return p;
  }
  inline double unit_oscillator_response(const GearPairParameters &p, const double omega,
                                         const double E)
  {
    const double               k = p.stiffness.k_rest_N_per_m.mean, m = p.equivalent_mass_kg;
    const double               c = p.damping_N_s_per_m;
    const std::complex<double> X =
      E * std::complex<double>(k, c * omega) / std::complex<double>(k - m * omega * omega, c * omega);
    return std::abs(X);
  }

  // The coefficient of restitution of the Hunt-Crossley law F = k_h delta^n (1 + chi delta'),
  // chi = 3/2 alpha, for the impact speed v_i: Phi(v_i) = Phi(-e v_i) with
  // Phi(v) = v/chi - ln(1 + chi v)/chi^2 (independent of m, k_h and n), solved by bisection
  // (Phi is decreasing on (-1/chi, 0]).
  inline double hunt_crossley_restitution(const double alpha, const double v_i)
  {
    const double chi = 1.5 * alpha;
    auto         Phi = [chi](const double v) { return v / chi - std::log1p(chi * v) / (chi * chi); };
    double       lo = 0.0, hi = 1.0;
    for (int it = 0; it < 200; ++it)
      {
        const double e = 0.5 * (lo + hi);
        (Phi(-e * v_i) < Phi(v_i) ? lo : hi) = e;
      }
    return 0.5 * (lo + hi);
  }

  // A single impact on the Hunt-Crossley layer alone (rigid structure, no load, long flights
  // through a 2 x 10 mm backlash, short impacts).
  inline GearPairParameters rigid_impact_pair(const double n, const double alpha)
  {
    GearPairParameters p;
    p.equivalent_mass_kg               = 0.15;
    p.static_force_N                   = 0.0;
    p.half_backlash_m                  = 1e-2;
    p.mesh_frequency_rad_per_s         = 100.0;
    p.alpha_s_per_m                    = alpha;
    p.stiffness.hertz_exponent         = n;
    p.stiffness.k_rest_N_per_m.mean    = 1e8; // unused: rigid structure
    p.stiffness.k_hertz_N_per_m_pow_n  = {n == 1.0 ? 5e8 : 3e10, {}, {}};
    p.effects.mesh_stiffness_variation = false;
    p.rigid_structure                  = true;
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
