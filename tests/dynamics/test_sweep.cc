// The speed sweep (dynamics/sweep.h): which rows it returns, in which order, and that every row is
// the single run it stands for.
#include "dynamics/sweep.h"

#include "common/errors.h"
#include "tests/dynamics/dynamics_fixtures.h"

#include <gtest/gtest.h>

#include <vector>

using namespace hertzgear::dynamics;
using namespace hertzgear::dynamics::testing;

namespace
{
  // The crowned paper pair (backlash, dynamic Hertzian layer) at 150 rpm, a few periods a point.
  SweepModel crowned_pair()
  {
    SweepModel m;
    m.parameters = paper_crowned();
    m.speed_rpm  = 150.0;
    m.run        = run_settings(IntegratorKind::cvode_bdf, 1e-8, 1e-13, 800, 400, 50);
    return m;
  }

  SweepSettings settings(const int points, const SweepMode mode,
                         const SweepDirection direction = SweepDirection::both)
  {
    SweepSettings s;
    s.speed_min_rpm               = 100.0;
    s.speed_max_rpm               = 400.0;
    s.points                      = points;
    s.mode                        = mode;
    s.direction                   = direction;
    s.periods_per_point           = 16;
    s.transient_periods_per_point = 8;
    s.threads                     = 2;
    return s;
  }

  // The run a row stands for: the pair at `speed_rpm` from state `y0`, with the sweep's periods.
  SimulationResult single_run(const SweepModel &m, const SweepSettings &s, const double speed_rpm,
                              const std::vector<double> &y0 = {})
  {
    GearPairModel model(at_speed(m.parameters, m.speed_rpm, speed_rpm));
    RunSettings   run       = m.run;
    run.periods           = s.periods_per_point;
    run.transient_periods = s.transient_periods_per_point;
    return simulate(model, run, y0.empty() ? m.initial.of(model) : y0);
  }

  void expect_row_is_run(const SweepRow &row, const SweepModel &m, const SimulationResult &r)
  {
    const SteadyStateSummary s = analyse(GearPairModel(at_speed(m.parameters, m.speed_rpm,
                                                                row.speed_rpm)),
                                         r);
    EXPECT_EQ(row.summary.rms_dte_m, s.rms_dte_m);
    EXPECT_EQ(row.summary.min_dte_m, s.min_dte_m);
    EXPECT_EQ(row.summary.max_dte_m, s.max_dte_m);
    EXPECT_EQ(row.summary.dynamic_factor, s.dynamic_factor);
    EXPECT_EQ(row.summary.contact_loss_fraction, s.contact_loss_fraction);
    EXPECT_EQ(row.summary.period_multiplicity, s.period_multiplicity);
    ASSERT_EQ(row.poincare_dte_m.size(), r.poincare.size());
    for (std::size_t i = 0; i < r.poincare.size(); ++i)
      EXPECT_EQ(row.poincare_dte_m[i], r.poincare[i].dte_m);
  }

  void expect_same_rows(const std::vector<SweepRow> &a, const std::vector<SweepRow> &b)
  {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i)
      {
        EXPECT_EQ(a[i].speed_rpm, b[i].speed_rpm);
        EXPECT_EQ(a[i].branch, b[i].branch);
        EXPECT_EQ(a[i].summary.rms_dte_m, b[i].summary.rms_dte_m);
        EXPECT_EQ(a[i].summary.max_dte_m, b[i].summary.max_dte_m);
        EXPECT_EQ(a[i].summary.period_multiplicity, b[i].summary.period_multiplicity);
        EXPECT_EQ(a[i].poincare_dte_m, b[i].poincare_dte_m);
      }
  }
} // namespace

// Requirement: the speeds are evenly spaced from the minimum to the maximum, both included; a
// sweep of one point is the one speed.
TEST(Sweep, SpeedsAreEvenlySpacedEndsIncluded)
{
  EXPECT_EQ(sweep_speeds(settings(4, SweepMode::both)), (std::vector<double>{100, 200, 300, 400}));
  SweepSettings one = settings(1, SweepMode::independent);
  one.speed_max_rpm = one.speed_min_rpm;
  EXPECT_EQ(sweep_speeds(one), std::vector<double>{100.0});
}

// Requirement: continuation up and down, with independent points, gives one row per speed per
// branch: the up chain at increasing speeds, then the down chain at decreasing speeds, then the
// independent points at increasing speeds; `direction` keeps one chain only. The integrator
// statistics are the sum over the points.
TEST(Sweep, OneRowPerSpeedPerBranchInOrder)
{
  const SweepModel          m      = crowned_pair();
  const auto                s      = settings(3, SweepMode::both);
  const std::vector<double> speeds = sweep_speeds(s);
  int                       calls  = 0;
  const SweepResult         result = sweep(m, s, [&](const SweepPointDone &p) {
    ++calls;
    EXPECT_EQ(p.done, calls);
    EXPECT_EQ(p.total, 9);
  });
  EXPECT_EQ(calls, 9);
  ASSERT_EQ(result.rows.size(), 9u);
  for (int i = 0; i < 3; ++i)
    {
      EXPECT_EQ(result.rows[i].branch, SweepBranch::up);
      EXPECT_EQ(result.rows[i].speed_rpm, speeds[i]);
      EXPECT_EQ(result.rows[3 + i].branch, SweepBranch::down);
      EXPECT_EQ(result.rows[3 + i].speed_rpm, speeds[2 - i]);
      EXPECT_EQ(result.rows[6 + i].branch, SweepBranch::independent);
      EXPECT_EQ(result.rows[6 + i].speed_rpm, speeds[i]);
    }
  EXPECT_GT(result.stats.steps, 0);
  EXPECT_GT(result.stats.rhs_evals, result.stats.steps);

  const SweepResult down = sweep(m, settings(3, SweepMode::continuation, SweepDirection::down));
  ASSERT_EQ(down.rows.size(), 3u);
  for (int i = 0; i < 3; ++i)
    {
      EXPECT_EQ(down.rows[i].branch, SweepBranch::down);
      EXPECT_EQ(down.rows[i].speed_rpm, speeds[2 - i]);
    }
}

// Requirement: a sweep of one point equals a single run at that speed from the initial state, the
// same numbers to the last bit.
TEST(Sweep, OnePointEqualsASingleRun)
{
  const SweepModel m = crowned_pair();
  SweepSettings    s = settings(1, SweepMode::independent);
  s.speed_min_rpm = s.speed_max_rpm = 250.0;
  const SweepResult result = sweep(m, s);
  ASSERT_EQ(result.rows.size(), 1u);
  EXPECT_EQ(result.rows[0].speed_rpm, 250.0);
  expect_row_is_run(result.rows[0], m, single_run(m, s, 250.0));
}

// Requirement: a continuation chain starts at its first speed from the initial state, and every
// further point starts from the final state of the point before it.
TEST(Sweep, ContinuationStartsFromTheLastState)
{
  const SweepModel m = crowned_pair();
  const auto       s = settings(3, SweepMode::continuation, SweepDirection::up);
  const SweepResult result = sweep(m, s);
  ASSERT_EQ(result.rows.size(), 3u);
  std::vector<double> y;
  for (int i = 0; i < 3; ++i)
    {
      const SimulationResult r = single_run(m, s, result.rows[i].speed_rpm, y);
      expect_row_is_run(result.rows[i], m, r);
      y = r.final_state;
    }
}

// Requirement: independent points do not depend on the order they run in, on the number of threads
// or on the other points of the sweep: each equals a sweep of that one speed.
TEST(Sweep, IndependentPointsDoNotDependOnOrder)
{
  const SweepModel m = crowned_pair();
  auto             s = settings(4, SweepMode::independent);
  s.threads          = 1;
  const SweepResult one = sweep(m, s);
  s.threads             = 4;
  const SweepResult four = sweep(m, s);
  expect_same_rows(one.rows, four.rows);
  ASSERT_EQ(one.rows.size(), 4u);
  for (const int i : {3, 0})
    {
      SweepSettings single = settings(1, SweepMode::independent);
      single.speed_min_rpm = single.speed_max_rpm = one.rows[i].speed_rpm;
      expect_same_rows(sweep(m, single).rows, {one.rows[i]});
    }
}

// Requirement: settings out of range raise a ParameterError naming the field.
TEST(Sweep, SettingsOutOfRangeNameTheField)
{
  const auto field_of = [](const SweepSettings &s) {
    try
      {
        check_sweep_settings(s);
      }
    catch (const hertzgear::ParameterError &e)
      {
        return e.parameter();
      }
    return std::string();
  };
  auto s = settings(3, SweepMode::both);
  EXPECT_EQ(field_of(s), "");
  s.speed_max_rpm = s.speed_min_rpm;
  EXPECT_EQ(field_of(s), "speed_max_rpm");
  s = settings(0, SweepMode::both);
  EXPECT_EQ(field_of(s), "points");
  s                   = settings(3, SweepMode::both);
  s.periods_per_point = s.transient_periods_per_point;
  EXPECT_EQ(field_of(s), "periods_per_point");
  EXPECT_THROW(sweep_mode_from_name("sideways"), hertzgear::ParameterError);
}
