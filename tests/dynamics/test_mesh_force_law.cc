// Requirements on the mesh force law seam (dynamics/mesh_force_law.h) and the paper's serial law
// behind it: the derivatives the Jacobian and the quasi-static layer use are those of the forces.
#include "dynamics/mesh_force_law.h"

#include "tests/dynamics/dynamics_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace hertzgear::dynamics;
using hertzgear::dynamics::testing::PhaseAt;

// Requirement: the serial law's derivatives in u, delta and time equal central differences of its
// forces, for line (n = 1) and point (n = 3/2) contact, compressions of both signs. Step 1e-4 of
// the compression (of a radian in theta): the truncation error of a central difference is
// O(h^2) relative to the value, about 1e-8, rounding about eps / 1e-4 = 2e-12; 1e-6 relative
// bounds both.
TEST(MeshForceLaw, SerialHertzDerivativesMatchFiniteDifferences)
{
  for (const double n : {1.0, 1.5})
    {
      auto table           = hertzgear::dynamics::testing::paper_crowned().stiffness;
      table.hertz_exponent = n;
      table.k_rest_N_per_m = {2.79e8, {3.0e7}, {0.4}};
      const auto   law     = serial_hertz_law(table);
      const double theta   = 0.7;
      const PhaseAt at(*law, theta), plus(*law, theta + 1e-4), minus(*law, theta - 1e-4);
      for (const double x : {-3.0e-6, 2.0e-7, 5.0e-6})
        {
          const double h = 1e-4 * std::abs(x);
          MeshLawForces f, fu_p, fu_m, fd_p, fd_m, ft_p, ft_m;
          law->evaluate(at.phase, x, x, f);
          law->evaluate(at.phase, x + h, x, fu_p);
          law->evaluate(at.phase, x - h, x, fu_m);
          law->evaluate(at.phase, x, x + h, fd_p);
          law->evaluate(at.phase, x, x - h, fd_m);
          law->evaluate(plus.phase, x, x, ft_p);
          law->evaluate(minus.phase, x, x, ft_m);
          const double tol = 1e-6;
          EXPECT_NEAR(f.structural_du, (fu_p.structural - fu_m.structural) / (2 * h),
                      tol * std::abs(f.structural_du));
          EXPECT_NEAR(f.hertz_ddelta, (fd_p.hertz - fd_m.hertz) / (2 * h),
                      tol * std::abs(f.hertz_ddelta));
          EXPECT_NEAR(f.damping_weight_slope, (fd_p.damping_weight - fd_m.damping_weight) / (2 * h),
                      tol * std::abs(f.damping_weight_slope));
          EXPECT_NEAR(f.structural_dt, (ft_p.structural - ft_m.structural) / 2e-4,
                      tol * std::abs(f.structural));
          EXPECT_NEAR(f.hertz_dt, (ft_p.hertz - ft_m.hertz) / 2e-4, tol * std::abs(f.hertz));
          // A compression and its force have the same sign; H is even.
          EXPECT_GT(f.structural * x, 0.0);
          EXPECT_GT(f.hertz * x, 0.0);
          EXPECT_GT(f.damping_weight, 0.0);
        }
    }
}

// Requirement: the quasi-static penetration balances the two springs, K_r(f - delta) =
// K_h(delta), with delta of the sign of f inside [0, |f|]. The Newton iteration stops at a step
// of 1e-15 |f|, so the balance holds to a few 1e-15 of the force; 1e-12 leaves margin.
TEST(MeshForceLaw, SerialHertzQuasiStaticPenetrationBalancesTheSprings)
{
  for (const double n : {1.0, 1.5})
    {
      auto table           = hertzgear::dynamics::testing::paper_crowned().stiffness;
      table.hertz_exponent = n;
      const auto    law    = serial_hertz_law(table);
      const PhaseAt at(*law, 2.1);
      for (const double f : {-4.0e-5, 1.0e-8, 3.0e-5})
        {
          const double d = law->quasi_static_penetration(at.phase, f);
          EXPECT_GE(d * f, 0.0);
          EXPECT_LE(std::abs(d), std::abs(f));
          MeshLawForces forces;
          law->evaluate(at.phase, f - d, d, forces);
          EXPECT_NEAR(forces.structural, forces.hertz, 1e-12 * std::abs(forces.hertz));
        }
    }
}
