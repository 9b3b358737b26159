// The hard cases of the dynamics: each must give a bounded, NaN-free answer that converges as the
// tolerance is tightened, or the documented clear error.
#include "dynamics/analysis.h"
#include "dynamics/gear_pair_model.h"

#include "common/errors.h"
#include "tests/dynamics/dynamics_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>

using namespace hertzgear::dynamics;
using namespace hertzgear::dynamics::testing;

namespace
{
  struct Outcome
  {
    double rms_um = 0, max_um = 0, max_force_N = 0;
    int    backside_impacts = 0;
    double contact_loss     = 0;
  };

  Outcome run(const GearPairParameters &p, const IntegratorKind kind, const double rtol,
              const int periods, const int transient, std::vector<double> y0 = {})
  {
    GearPairModel model(p);
    if (y0.empty())
      y0 = model.static_equilibrium_state();
    // Absolute tolerance tied to rtol on the displacement scale: near delta = 0 the layer carries
    // k_h |delta|^n, nothing at 1e-2 rtol of the scale (a smaller one chases |delta| ~ 1e-19 m).
    const auto r = simulate(model, run_settings(kind, rtol, rtol * 1e-2 * model.characteristic_displacement(),
                                                periods, transient),
                            y0);
    const auto s = analyse(model, r);
    for (const auto &sample : r.steady)
      {
        EXPECT_TRUE(std::isfinite(sample.dte_m) && std::isfinite(sample.force_N) &&
                    std::isfinite(sample.penetration_m));
      }
    return {1e6 * s.rms_dte_m, 1e6 * std::max(std::abs(s.max_dte_m), std::abs(s.min_dte_m)),
            s.max_force_N, s.backside_impacts, s.contact_loss_fraction};
  }

  // Bounded, NaN-free (checked in run) and converging: against a reference run at rtol 1e-12
  // (cvode-bdf; IDA for the DAE case, which only IDA integrates), the error of the RMS DTE must not grow as rtol goes from
  // 1e-6 to 1e-8 to 1e-10 (errors below 1e-9 of the RMS, the reference's own level, count as
  // equal), and at 1e-10 it must be below `settle` relative. Successive differences alone would
  // fail a run whose coarse tolerance happens to land close to the answer.
  void expect_converged(const GearPairParameters &p, const IntegratorKind kind, const int periods,
                        const int transient, const double bound_um, const double settle,
                        const std::vector<double> &y0 = {}, const char *name = "")
  {
    static std::map<std::string, Outcome> references;
    if (!references.count(name))
      references[name] = run(p, kind == IntegratorKind::ida ? kind : IntegratorKind::cvode_bdf,
                             1e-12, periods, transient, y0);
    const Outcome ref = references[name];
    const Outcome a   = run(p, kind, 1e-6, periods, transient, y0);
    const Outcome b   = run(p, kind, 1e-8, periods, transient, y0);
    const Outcome c   = run(p, kind, 1e-10, periods, transient, y0);
    std::printf("%s: rms DTE %.9g / %.9g / %.9g um at rtol 1e-6/1e-8/1e-10 (reference %.9g), "
                "max %.4g um, contact loss %.3f, back-side impacts %d\n",
                name, a.rms_um, b.rms_um, c.rms_um, ref.rms_um, c.max_um, c.contact_loss,
                c.backside_impacts);
    EXPECT_LT(c.max_um, bound_um);
    const double e1 = std::abs(a.rms_um - ref.rms_um), e2 = std::abs(b.rms_um - ref.rms_um),
                 e3 = std::abs(c.rms_um - ref.rms_um), floor = 1e-9 * ref.rms_um;
    EXPECT_LE(e2, std::max(e1, floor));
    EXPECT_LE(e3, std::max(e2, floor));
    EXPECT_LT(e3, settle * ref.rms_um);
  }
} // namespace

// The hard cases below run with both stiff adaptive integrators: cvode-bdf (SUNDIALS, order <= 5)
// and radau-iia (Radau IIA collocation, order 2s - 1).
class HardCasesAdaptive : public ::testing::TestWithParam<IntegratorKind>
{};

INSTANTIATE_TEST_SUITE_P(Integrators, HardCasesAdaptive,
                         ::testing::Values(IntegratorKind::cvode_bdf, IntegratorKind::radau_iia),
                         [](const ::testing::TestParamInfo<IntegratorKind> &info) {
                           return info.param == IntegratorKind::cvode_bdf ? std::string("cvode_bdf") :
                                                                            std::string("radau_iia");
                         });

// The structural damping 1000 times below nominal: the delta equation's time constant c/k drops
// to 5e-10 s against a mesh period of 1.7e-2 s.
TEST_P(HardCasesAdaptive, StiffDamping)
{
  auto p = paper_crowned();
  p.damping_N_s_per_m /= 1000.0;
  expect_converged(p, GetParam(), 30, 20, 1000.0, 1e-5, {}, "stiff damping");
}

// n = 1.5 with grazing contact: the pair starts at the edge of the backlash with zero speed and
// a light load closes the contact with zero approach speed, where G'(0) = 0.
TEST_P(HardCasesAdaptive, GrazingContactWithExponent15)
{
  auto p           = paper_crowned();
  p.static_force_N = 20.0;
  GearPairModel model(p);
  expect_converged(p, GetParam(), 30, 20, 1000.0, 1e-5,
                   model.state(p.half_backlash_m, 0.0, 0.0), "grazing n = 1.5");
}

// Double-sided impacts near the primary resonance at low load: a 30 um transmission-error
// excitation at the mesh natural frequency (about 3.3 kHz at F_0 = 50 N) drives the teeth
// through the backlash onto the back flanks.
TEST_P(HardCasesAdaptive, DoubleSidedImpactsNearResonance)
{
  const auto p                 = backside_impact_pair();
  const Outcome o              = run(p, GetParam(), 1e-8, 60, 40);
  EXPECT_GT(o.backside_impacts, 0) << "the case must reach the back flanks";
  expect_converged(p, GetParam(), 60, 40, 1000.0, 1e-2, {}, "double-sided");
}

// Zero backlash: f(x) = x, forward and back contact meet at x = 0.
TEST_P(HardCasesAdaptive, ZeroBacklash)
{
  auto p            = paper_crowned();
  p.half_backlash_m = 0.0;
  expect_converged(p, GetParam(), 30, 20, 1000.0, 1e-5, {}, "zero backlash");
}

// Zero static load (rattle): only a transmission-error excitation of 100 um (beyond the 58.6 um
// half backlash) drives the teeth, which hit both flanks.
TEST_P(HardCasesAdaptive, RattleWithoutLoad)
{
  const auto p = ste_driven_pair(0.0, 1000.0, 100e-6);
  EXPECT_GT(run(p, GetParam(), 1e-8, 60, 40).backside_impacts, 0);
  expect_converged(p, GetParam(), 60, 40, 1000.0, 1e-2, {}, "rattle");
}

// Hertzian stiffness variation near the principal parametric instability: mesh frequency twice
// the natural frequency (about 4.5 kHz at full load) with the paper's harmonics, and viscous-only
// contact damping so that the Hunt-Crossley term (an effective zeta of 0.2) does not suppress it.
TEST_P(HardCasesAdaptive, NearParametricInstability)
{
  auto p                     = paper_crowned();
  p.mesh_frequency_rad_per_s = 2 * 2 * M_PI * 4480.0;
  p.effects.contact_damping  = ContactDamping::viscous_only;
  expect_converged(p, GetParam(), 60, 40, 1000.0, 1e-2, {}, "parametric");
}

// c = 0: the delta equation is algebraic where mu H(delta) vanishes (a DAE); IDA integrates it.
TEST(HardCases, ZeroDampingDae)
{
  auto p              = paper_crowned();
  p.damping_N_s_per_m = 0.0;
  expect_converged(p, IntegratorKind::ida, 20, 10, 1000.0, 1e-5, {}, "c = 0 (IDA)");
}

// The paper's fixed-step RK4 at 100 steps per mesh period is unstable on the stiff coherent model:
// the run must end with a NumericalError that names the time, the state and the remedy.
TEST(HardCases, Rk4BlowUpIsAClearError)
{
  GearPairModel model(paper_crowned());
  RunSettings   r      = run_settings(IntegratorKind::rk4, 1e-8, 1e-13, 10, 5);
  r.steps_per_period   = 100;
  try
    {
      simulate(model, r, model.static_equilibrium_state());
      FAIL() << "rk4 at 100 steps per period should blow up";
    }
  catch (const hertzgear::NumericalError &e)
    {
      const std::string what = e.what();
      EXPECT_NE(what.find("t = "), std::string::npos) << what;
      EXPECT_NE(what.find("x = "), std::string::npos) << what;
      EXPECT_NE(what.find("radau-iia"), std::string::npos) << what;
    }
}
