// Requirements on the iso6336 stiffness source (stiffness/iso6336_source.cc).
#include "common/errors.h"
#include "meshing/pair_kinematics.h"
#include "stiffness/iso6336.h"
#include "stiffness/registry.h"
#include "stiffness/table_writer.h"
#include "stiffness_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace hertzgear;
using namespace hertzgear::stiffness;

// The source shall be registered under its scene name and computed by the stiffness stage.
TEST(Iso6336Source, IsRegistered)
{
  const auto &s = find_source("iso6336");
  EXPECT_EQ(s.name(), "iso6336");
  EXPECT_TRUE(s.is_stage());
  EXPECT_FALSE(s.uses_fe());
}

// The table shall be constant over the cycle, with ISO's mesh-to-single stiffness ratio
// c_gamma_alpha / c' = 0.75 eps_alpha + 0.25 between its rest stiffness and the single pair's
// structural stiffness, and every row shall satisfy k_total = F / STE and the series-spring
// relation STE = F / k_rest + (F / k_h)^(1/n). Tolerance 1e-12: the same closed forms evaluated in
// another order (round-off only).
TEST(Iso6336Source, ConstantTableFromIsoMethodB)
{
  const StiffnessInput in = test_pairs::paper_pair();
  PhaseTimer           timer;
  const auto           r = find_source("iso6336").compute(in, timer);
  ASSERT_EQ(r.rows.size(), 16u);
  EXPECT_TRUE(r.table.k_rest_N_per_m.amplitudes.empty());
  EXPECT_TRUE(r.table.k_hertz_N_per_m_pow_n.amplitudes.empty());

  const meshing::PairKinematics pair(in.pair);
  const auto   iso   = iso6336_method_b(pair, in.torque_Nm);
  const double ratio = iso.c_gamma_alpha_N_per_mm_um / iso.c_prime_N_per_mm_um;
  EXPECT_NEAR(ratio, 0.75 * pair.contact_ratio() + 0.25, 1e-12);
  const double k_r1 = r.notes.at("pair_rest_stiffness_N_per_m").get<double>();
  EXPECT_NEAR(r.table.k_rest_N_per_m.mean, ratio * k_r1, 1e-12 * k_r1);

  const double F = in.torque_Nm * 1e3 / pair.pinion().base_radius_mm();
  EXPECT_NEAR(r.load_N, F, 1e-12 * F);
  for (const auto &row : r.rows)
    {
      const double ste_m = row.ste_um * 1e-6;
      EXPECT_NEAR(row.k_total_N_per_m, F / ste_m, 1e-12 * row.k_total_N_per_m);
      const double series = F / r.table.k_rest_N_per_m.mean +
                            std::pow(F / r.table.k_hertz_N_per_m_pow_n.mean, 1.0 / in.hertz_exponent);
      EXPECT_NEAR(ste_m, series, 1e-12 * ste_m);
      EXPECT_FALSE(row.load_share_1.has_value()); // ISO does not share load between pairs
    }
  EXPECT_NEAR(ste_peak_to_peak_um(r), 0.0, 1e-12);
}

// A torque that is not positive shall be refused before any work, naming the input field.
TEST(Iso6336Source, RefusesANonPositiveTorque)
{
  StiffnessInput in = test_pairs::paper_pair();
  in.torque_Nm      = 0;
  try
    {
      find_source("iso6336").check(in);
      FAIL() << "a zero torque was accepted";
    }
  catch (const ParameterError &e)
    {
      EXPECT_EQ(e.parameter(), "torque_Nm");
    }
}
