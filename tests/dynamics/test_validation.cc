// Validation of the dynamics against closed forms, conservation laws and the literature.
#include "dynamics/analysis.h"
#include "dynamics/gear_pair_model.h"
#include "dynamics/integrator.h"

#include "tests/dynamics/dynamics_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>

using namespace hertzgear::dynamics;
using namespace hertzgear::dynamics::testing;

namespace
{
  // First-harmonic amplitude of the steady DTE (FFTW over whole periods: exact for a harmonic).
  double first_harmonic_amplitude(const SimulationResult &r)
  {
    for (const auto &line : dte_spectrum(r))
      if (std::abs(line.mesh_order - 1.0) < 1e-9)
        return line.amplitude_m;
    return -1.0;
  }
} // namespace

// Requirement (a): with backlash and the Hertzian layer off and constant k, the steady response to
// a harmonic transmission-error excitation e(t) = E cos(omega t) equals the closed-form linear
// response |X| = E |k + i c omega| / |k - m omega^2 + i c omega| within 1e-6 relative, and the
// mean DTE is F_0/k. The integrator runs at rtol 1e-11, so its error is far below 1e-6; the
// transient decays as exp(-zeta omega_n t) = e^-31 over the 50 transient periods.
TEST(Validation, LinearResponseMatchesClosedForm)
{
  for (const double ratio : {0.5, 0.9, 1.3})
    {
      const double omega = 1000.0 * ratio, zeta = 0.05, E = 1.0e-5;
      const auto   p     = unit_oscillator_with_ste(zeta, omega, E);
      GearPairModel model(p);
      const auto    r = simulate(model, run_settings(IntegratorKind::cvode_bdf, 1e-11, 1e-17, 70, 50),
                              model.static_equilibrium_state());
      const double k = p.stiffness.k_rest_N_per_m.mean;
      const double X = unit_oscillator_response(p, omega, E);
      EXPECT_NEAR(first_harmonic_amplitude(r), X, 1e-6 * X) << "omega/omega_n " << ratio;
      EXPECT_NEAR(analyse(model, r).mean_dte_m, p.static_force_N / k, 1e-6 * p.static_force_N / k);
    }
}

// Requirement (b): in a periodic steady state the mean mesh force equals F_0 within 0.1 %
// (m_e x'' averages to zero over a period). Checked on the paper's crowned pair (period 1, always
// in contact) and on a Kahraman-Singh pair that loses contact every period. The mean is the
// average of the samples over whole periods; the Kahraman-Singh force jumps by c x' at every
// contact (its viscous part is kept), so the sample mean is only first-order accurate there:
// 4000 samples per period bound that quadrature error to ~1e-4 relative (400 gave 1.2e-3).
TEST(Validation, MeanMeshForceEqualsStaticForce)
{
  {
    GearPairModel model(paper_crowned());
    const auto    r = simulate(model, run_settings(IntegratorKind::cvode_bdf, 1e-8, 1e-13, 60, 40),
                            model.static_equilibrium_state());
    const auto s = analyse(model, r);
    ASSERT_GE(s.period_multiplicity, 1);
    EXPECT_NEAR(s.mean_force_N, s.static_force_N, 1e-3 * s.static_force_N);
  }
  {
    // Dimensionless backlash oscillator (m = k = b_c = 1, zeta = 0.05) excited near resonance.
    GearPairParameters p;
    p.equivalent_mass_kg              = 1.0;
    p.static_force_N                  = 0.1;
    p.half_backlash_m                 = 1.0;
    p.mesh_frequency_rad_per_s        = 0.8;
    p.damping_N_s_per_m               = 0.1;
    p.stiffness.hertz_exponent        = 1.0;
    p.stiffness.k_rest_N_per_m.mean   = 1.0;
    p.stiffness.unloaded_ste_m        = {0.0, {0.5}, {0.0}};
    p.stiffness.has_unloaded_ste      = true;
    p.effects.hertzian_layer          = HertzianLayer::off;
    p.effects.mesh_stiffness_variation = false;
    p.effects.ste_excitation          = true;
    GearPairModel model(p);
    const auto    r = simulate(model, run_settings(IntegratorKind::cvode_bdf, 1e-10, 1e-12, 200, 150, 4000),
                            model.static_equilibrium_state());
    const auto s = analyse(model, r);
    ASSERT_GE(s.period_multiplicity, 1);
    ASSERT_GT(s.contact_loss_fraction, 0.0) << "the case must lose contact to test impacts";
    EXPECT_NEAR(s.mean_force_N, s.static_force_N, 1e-3 * s.static_force_N);
  }
}

// Requirement: period detection reads a steady motion that barely varies as period 1, not as
// aperiodic. With constant stiffness the steady DTE is constant up to the integrator's error
// (rtol |x|); the test must not compare Poincare points at a tolerance below that error.
TEST(Validation, NearlyConstantSteadyMotionIsPeriodOne)
{
  GearPairParameters p                   = paper_crowned();
  p.effects.mesh_stiffness_variation     = false;
  GearPairModel model(p);
  const auto    r = simulate(model, run_settings(IntegratorKind::cvode_bdf, 1e-8, 1e-13, 40, 20),
                          model.static_equilibrium_state());
  const auto s = analyse(model, r);
  EXPECT_LT(s.max_dte_m - s.min_dte_m, 1e-6 * s.max_dte_m) << "the motion should be constant";
  EXPECT_EQ(s.period_multiplicity, 1);
}

// Requirement (c): a single impact on the Hunt-Crossley layer F = k_h delta^n (1 + 3/2 alpha
// delta') returns the coefficient of restitution that law predicts. Integrating
// m v dv = -k_h delta^n (1 + chi v) d(delta), chi = 3/2 alpha, over the impact (delta from 0 back to
// 0) gives Phi(v_i) = Phi(-e v_i) with Phi(v) = v/chi - ln(1 + chi v)/chi^2, independent of m, k_h
// and n. The structure is rigid here so that the layer alone acts. rtol 1e-11 puts the integration
// error near 1e-9; 1e-7 relative on e.
TEST(Validation, HuntCrossleyRestitution)
{
  for (const double n : {1.0, 1.5})
    for (const double v_i : {0.05, 0.5, 1.5})
      {
        const double alpha = 0.26;
        const double e_law = hunt_crossley_restitution(alpha, v_i);
        const auto   p     = rigid_impact_pair(n, alpha);
        GearPairModel model(p);
        auto          integrator = make_integrator({IntegratorKind::cvode_bdf, 1e-11, 1e-18});
        std::vector<double> y    = model.state(0.0, v_i, 0.0);
        // From the middle of the backlash to the contact (b_c/v_i) and half-way back
        // (b_c/(2 e v_i)); the impact itself lasts ~1e-4 s. The end state is in free flight.
        const double t_end = p.half_backlash_m / v_i + 0.5 * p.half_backlash_m / (e_law * v_i);
        integrator->integrate(model, 0.0, y, t_end, 1, {});
        ASSERT_LT(y[0], 0.9 * p.half_backlash_m) << "not in free flight after the impact";
        ASSERT_GT(y[0], 0.1 * p.half_backlash_m) << "not in free flight after the impact";
        EXPECT_NEAR(-y[1] / v_i, e_law, 1e-7) << "n = " << n << ", v_i = " << v_i;
        EXPECT_EQ(integrator->stats().events, 2); // contact and separation, located
      }
}

namespace
{
  // The gear-pair model plus two quadratures: the work of F_0 and the dissipated energy.
  class EnergyAudit : public OdeSystem
  {
  public:
    explicit EnergyAudit(GearPairModel &model) : model(model) {}
    unsigned n_states() const override { return model.n_states() + 2; }
    void     rhs(const double t, const double *y, double *y_dot) override
    {
      model.rhs(t, y, y_dot);
      const MeshState s      = model.mesh_state(t, y, true);
      y_dot[model.n_states()]     = model.parameters().static_force_N * y[1];
      y_dot[model.n_states() + 1] = s.dissipation_W;
    }
    std::vector<double> absolute_tolerances(const double atol) const override
    {
      auto a = model.absolute_tolerances(atol);
      a.push_back(1e-14);
      a.push_back(1e-14);
      return a;
    }
    double energy(const double t, const double *y) const
    {
      return 0.5 * model.parameters().equivalent_mass_kg * y[1] * y[1] +
             model.mesh_state(t, y, true).elastic_energy_J;
    }

  private:
    GearPairModel &model;
  };
} // namespace

// Requirement (d): work of F_0 minus the damping losses equals the change of kinetic plus elastic
// energy within the integrator tolerance. The pair starts 20 um away from its static equilibrium
// (constant stiffness, backlash off, dynamic layer with Hunt-Crossley damping) and rings down.
// The balance is exact for the equations, so its residual is integration error: it must shrink in
// proportion to the tolerance (by at least 10x per 100x of rtol, i.e. order >= 1/2 in rtol) and be
// below 1e-6 of the dissipated energy at rtol 1e-10. Measured: 1.4e-6 at rtol 1e-8 and 2.3e-8 at
// 1e-10 (the global error of CVODE is ~100-200 times its local tolerance here).
TEST(Validation, EnergyBalance)
{
  auto p                             = paper_crowned();
  p.effects.backlash                 = false;
  p.effects.mesh_stiffness_variation = false;
  double previous_error              = 1.0;
  for (const double rtol : {1e-6, 1e-8, 1e-10})
    {
      GearPairModel model(p);
      EnergyAudit   audit(model);
      auto          y = model.static_equilibrium_state();
      y[0] += 20e-6;
      y.push_back(0.0);
      y.push_back(0.0);
      const double E0         = audit.energy(0.0, y.data());
      auto         integrator = make_integrator({IntegratorKind::cvode_bdf, rtol, rtol * 1e-5});
      integrator->integrate(audit, 0.0, y, 0.01, 1, {});
      const double E1 = audit.energy(0.01, y.data());
      const double W = y[3], D = y[4];
      const double error = std::abs((E1 - E0) - (W - D)) / D;
      EXPECT_LT(error, 0.1 * previous_error) << "rtol " << rtol;
      if (rtol == 1e-10)
        {
          EXPECT_LT(error, 1e-6);
        }
      previous_error = error;
    }
}

// Requirement (f): the observed order of the paper's RK4 is 4 +- 0.1 on a smooth case (the linear
// pair with a Fourier-varying stiffness, no backlash, no Hertzian layer). Errors against the next
// halving of the step; the order from three successive halvings, in the asymptotic range
// (h omega_n <= 0.008; at 200 steps per period the pre-asymptotic order is 4.2).
TEST(Validation, RungeKutta4ObservedOrder)
{
  auto p                             = unit_oscillator(0.05, 300.0);
  p.stiffness.k_rest_N_per_m         = {1.0e6, {2.0e5, 5.0e4}, {0.0, 1.0}};
  p.effects.rest_stiffness_variation = true;
  GearPairModel model(p);
  std::vector<double> finals;
  for (const int steps : {800, 1600, 3200, 6400, 12800})
    {
      RunSettings r      = run_settings(IntegratorKind::rk4, 1e-8, 1e-13, 3, 2, 1);
      r.steps_per_period = steps;
      auto y0            = model.static_equilibrium_state();
      y0[0] += 1e-5; // a transient, so that the natural frequency is resolved too
      finals.push_back(simulate(model, r, y0).final_state[0]);
    }
  for (std::size_t i = 0; i + 2 < finals.size(); ++i)
    {
      const double e0 = std::abs(finals[i] - finals[i + 1]), e1 = std::abs(finals[i + 1] - finals[i + 2]);
      const double order = std::log2(e0 / e1);
      EXPECT_NEAR(order, 4.0, 0.1) << "steps " << (800 << i);
    }
}
