// Extremes located on the integrator's dense output between the output samples (docs/dynamics.md,
// "Extremes between the samples"): the minimum and maximum DTE, the peak mesh force (and with it
// the dynamic factor), the minimum force and the peak penetration of the steady window.
#include "dynamics/analysis.h"
#include "dynamics/gear_pair_model.h"

#include "tests/dynamics/dynamics_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

using namespace hertzgear::dynamics;
using namespace hertzgear::dynamics::testing;

namespace
{
  struct Quantity
  {
    const char                           *name;
    std::function<double(const Sample &)> of;    // maximised: a minimum is the maximum of -q
    std::function<double(const SteadyStateSummary &)> extreme;
  };

  const std::vector<Quantity> &quantities()
  {
    static const std::vector<Quantity> q = {
      {"max DTE", [](const Sample &s) { return s.dte_m; },
       [](const SteadyStateSummary &s) { return s.max_dte_m; }},
      {"min DTE", [](const Sample &s) { return -s.dte_m; },
       [](const SteadyStateSummary &s) { return -s.min_dte_m; }},
      {"max force", [](const Sample &s) { return s.force_N; },
       [](const SteadyStateSummary &s) { return s.max_force_N; }},
      {"min force", [](const Sample &s) { return -s.force_N; },
       [](const SteadyStateSummary &s) { return -s.min_force_N; }},
      {"max penetration", [](const Sample &s) { return std::abs(s.penetration_m); },
       [](const SteadyStateSummary &s) { return s.max_penetration_m; }}};
    return q;
  }

  struct Outcome
  {
    SimulationResult   result;
    SteadyStateSummary summary;
  };

  Outcome run(const IntegratorKind kind, const int stages, const double rtol, const int samples,
          const bool dense)
  {
    const auto    p = contact_loss_pair();
    GearPairModel model(p);
    RunSettings   r        = run_settings(kind, rtol, 1e-15, 20, 10, samples);
    r.integrator.stages    = stages;
    r.dense_extremes       = dense;
    Outcome out;
    out.result  = simulate(model, r, contact_loss_start(model));
    out.summary = analyse(model, out.result);
    return out;
  }

  // The sampled maximum of q and the bound of its error h^2 |q''| / 8, with h^2 q'' estimated by
  // the second difference of the samples around it.
  std::pair<double, double> sampled_maximum(const std::vector<Sample> &s,
                                            const std::function<double(const Sample &)> &q)
  {
    std::size_t i_max = 0;
    for (std::size_t i = 1; i < s.size(); ++i)
      if (q(s[i]) > q(s[i_max]))
        i_max = i;
    const std::size_t m  = std::clamp<std::size_t>(i_max, 1, s.size() - 2);
    const double      d2 = q(s[m - 1]) - 2.0 * q(s[m]) + q(s[m + 1]);
    return {q(s[i_max]), std::abs(d2) / 8.0};
  }
} // namespace

// Requirement: on the contact-loss case (the layer opening, the flight through the backlash and
// the closing again once per mesh period), the extremes the analysis locates on the dense output
// of a run sampled 100 times per mesh period equal the extremes of the samples of runs sampled
// 10 000 and 100 000 times per mesh period within 1e-9 of their scale plus the samples' own error (the DTE range's largest magnitude,
// the peak force, the peak penetration), for cvode-bdf (CVodeGetDky) and radau-iia (its
// collocation polynomial); and the samples at 100 per period miss them by far more.
//
// Why 1e-9: the largest of samples spaced h apart lies below a smooth maximum by at most
// h^2 |q''| / 8; the test estimates h^2 q'' by the second difference of the samples at their
// largest value (printed: at most 4.2e-10 of the scale for h = T / 1e5, and 1.4e-8 to 4.2e-8 at
// T / 1e4: there the samples themselves miss the extremes by more than 1e-9, so the comparison
// with the 1e4 run is within 1e-9 plus that bound, and the 1e5 run is the tight one). Both runs are at rtol 1e-12
// with an absolute tolerance of 1e-15 m, so their own errors of the extremes, ~ rtol times the
// scale with the growth across the events, differ by at most a few 1e-10 (measured: up to
// 4.9e-10 for cvode-bdf, 7e-11 for radau-iia, whose runs take entirely different steps: 100
// against 1e5 outputs per period). The
// sampling bound is added to the 1e-9, so a sampled maximum that would be too low is allowed
// for exactly as far as theory says, no more.
TEST(DenseExtremes, EqualFinelySampledExtremesOnContactLoss)
{
  for (const auto &[kind, stages] : std::vector<std::pair<IntegratorKind, int>>{
         {IntegratorKind::cvode_bdf, 0}, {IntegratorKind::radau_iia, 7}})
    {
      const Outcome dense  = run(kind, stages, 1e-12, 100, true);
      const Outcome coarse = run(kind, stages, 1e-12, 100, false);
      for (const int samples : {10000, 100000})
      {
      const Outcome fine   = run(kind, stages, 1e-12, samples, false);
      EXPECT_EQ(dense.summary.extremes_from, "dense output");
      EXPECT_EQ(fine.summary.extremes_from, "samples");
      EXPECT_GT(dense.summary.contact_losses_per_period, 0.0) << "the case must lose contact";
      const double dte_scale = std::max(dense.summary.max_dte_m, -dense.summary.min_dte_m);
      const double scales[5] = {dte_scale, dte_scale, dense.summary.max_force_N,
                                dense.summary.max_force_N, dense.summary.max_penetration_m};
      for (std::size_t k = 0; k < quantities().size(); ++k)
        {
          const auto  &q                = quantities()[k];
          const double d                = q.extreme(dense.summary);
          const auto [f, sampling_bound] = sampled_maximum(fine.result.steady, q.of);
          const double c                = q.extreme(coarse.summary);
          std::printf("%s %-16s dense %.15g, %d/period %.15g: %.2e of the scale (sampling bound "
                      "%.2e); 100/period %.2e\n",
                      integrator_name(kind).c_str(), q.name, d, samples, f, (d - f) / scales[k],
                      sampling_bound / scales[k], (d - c) / scales[k]);
          EXPECT_LE(std::abs(d - f), 1e-9 * scales[k] + sampling_bound)
            << integrator_name(kind) << ", " << q.name;
          if (std::abs(d) > 0.0)
            {
              EXPECT_GT(d - c, 1e-9 * scales[k])
                << integrator_name(kind) << ", " << q.name
                << ": the samples at 100 per period should miss the extreme";
            }
        }
      }
      EXPECT_NEAR(dense.summary.dynamic_factor,
                  dense.summary.max_force_N / dense.summary.static_force_N, 1e-15);
    }
}

// Requirement: without the dense output (RunSettings::dense_extremes = false) the extremes are
// those of the samples, and the summary says so.
TEST(DenseExtremes, SamplesOnlyWhenAskedFor)
{
  const Outcome o = run(IntegratorKind::cvode_bdf, 0, 1e-8, 100, false);
  EXPECT_EQ(o.summary.extremes_from, "samples");
  EXPECT_FALSE(o.result.has_dense_extremes);
  // Over whole periods: the last sample repeats the phase of the first and is left out
  // (analyse); the run of 10 periods after 10 transient ones need not be periodic yet.
  double max_force = -1e300;
  for (std::size_t i = 0; i + 1 < o.result.steady.size(); ++i)
    max_force = std::max(max_force, o.result.steady[i].force_N);
  EXPECT_EQ(o.summary.max_force_N, max_force);
}
