#pragma once
// The load ladder of the paper's serial law itself (tests): at each load F_j and position s the
// structural compression F_j / k(theta_s) plus the Hertzian one (F_j / k_h(theta_s))^(1/n), so
// that the FE force law on it is the serial law again (docs/dynamics.md, "The FE force law").
#include "table/stiffness_table.h"

#include <cmath>
#include <vector>

namespace hertzgear::testing
{
  inline table::LoadLadder serial_law_ladder(const table::StiffnessTable &t,
                                             const std::vector<double> &loads_N,
                                             const unsigned positions, const double nominal_N)
  {
    table::LoadLadder l;
    l.nominal_load_N = nominal_N;
    l.load_N         = loads_N;
    for (const double F : loads_N)
      {
        std::vector<double> a, ah;
        for (unsigned s = 0; s < positions; ++s)
          {
            const double phase = double(s) / positions;
            const double d = std::pow(F / t.k_hertz_N_per_m_pow_n.at_phase(phase), 1.0 / t.hertz_exponent);
            a.push_back(F / t.k_rest_N_per_m.at_phase(phase) + d);
            ah.push_back(d);
          }
        l.approach_m.push_back(a);
        l.hertz_approach_m.push_back(ah);
      }
    return l;
  }

  // Rungs from 2 % to 400 % of F_0, denser at light load.
  inline std::vector<double> ladder_loads(const double F0)
  {
    std::vector<double> loads;
    for (const double percent : {2.0, 5.0, 10.0, 20.0, 35.0, 50.0, 70.0, 100.0, 140.0, 200.0,
                                 280.0, 400.0})
      loads.push_back(F0 * percent / 100.0);
    return loads;
  }
} // namespace hertzgear::testing
