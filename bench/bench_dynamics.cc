// Benchmark of the dynamics stage: the paper's crowned pair (data/scenes/paper_crowned_fourier.prm,
// 800 mesh periods, 400 of them transient) with cvode-bdf and radau-iia, reporting the wall time, the
// RHS evaluations and the accuracy reached against a reference run at rtol 1e-12 (relative error
// of the RMS DTE, largest error of the Poincare points).
//
//   build/bench/bench_dynamics --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// The SciPy LSODA comparison on the same equations is bench/bench_lsoda_dynamics.py.
#include "dynamics/analysis.h"
#include "dynamics/gear_pair_model.h"

#include "tests/dynamics/dynamics_fixtures.h"

#include <benchmark/benchmark.h>

#include <cmath>

using namespace hertzgear::dynamics;

namespace
{
  // The scene's initial state (Dynamics/initial_state = given).
  std::vector<double> initial_state(const GearPairModel &model)
  {
    return model.state(58.6059e-6, 5.86e-5, 0.05796e-6);
  }

  SimulationResult run(const IntegratorKind kind, const double rtol, const double atol)
  {
    GearPairModel model(testing::paper_crowned());
    return simulate(model, testing::run_settings(kind, rtol, atol, 800, 400), initial_state(model));
  }

  const SimulationResult &reference()
  {
    static const SimulationResult r = run(IntegratorKind::cvode_bdf, 1e-12, 1e-17);
    return r;
  }

  void accuracy_counters(benchmark::State &state, const SimulationResult &r)
  {
    GearPairModel model(testing::paper_crowned());
    const double  rms     = analyse(model, r).rms_dte_m;
    const double  rms_ref = analyse(model, reference()).rms_dte_m;
    double        p_error = 0;
    for (std::size_t j = 0; j < r.poincare.size(); ++j)
      p_error = std::max(p_error, std::abs(r.poincare[j].dte_m - reference().poincare[j].dte_m));
    state.counters["rhs_evals"]          = r.stats.rhs_evals;
    state.counters["steps"]              = r.stats.steps;
    state.counters["rms_dte_um"]         = 1e6 * rms;
    state.counters["rms_rel_error"]      = std::abs(rms - rms_ref) / rms_ref;
    state.counters["poincare_error_um"]  = 1e6 * p_error;
  }

  // Arguments: -log10(rtol); atol = 1e-13 m as in the scene at rtol 1e-8, scaled with rtol.
  template <IntegratorKind kind>
  void BM_PaperCrowned800Periods(benchmark::State &state)
  {
    const double rtol = std::pow(10.0, -double(state.range(0)));
    const double atol = 1e-13 * rtol / 1e-8;
    reference();
    SimulationResult r;
    for (auto _ : state)
      r = run(kind, rtol, atol);
    accuracy_counters(state, r);
  }
} // namespace

BENCHMARK_TEMPLATE(BM_PaperCrowned800Periods, IntegratorKind::cvode_bdf)
  ->Name("PaperCrowned800Periods/cvode_bdf")
  ->Arg(6)->Arg(8)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_TEMPLATE(BM_PaperCrowned800Periods, IntegratorKind::radau_iia)
  ->Name("PaperCrowned800Periods/radau_iia")
  ->Arg(6)->Arg(8)->Unit(benchmark::kMillisecond)->Iterations(1);

BENCHMARK_MAIN();
