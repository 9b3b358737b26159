// Stiffness source fourier: the Fourier coefficients of k and k_h given in the scene, read by the
// dynamics directly; the unloaded STE, when asked for, from a stiffness table file.
#include "stiffness/stiffness_source.h"
#include "stiffness/table_file.h"

namespace hertzgear::stiffness
{
  namespace
  {
    class FourierSource : public DirectSource
    {
    public:
      FourierSource()
        : DirectSource("fourier", "Fourier coefficients given in the scene, no meshing or FE")
      {}

      StiffnessResult compute(const StiffnessInput &input, PhaseTimer &) const override
      {
        StiffnessResult r;
        auto           &t       = r.table;
        t.hertz_exponent        = input.hertz_exponent;
        t.k_rest_N_per_m        = input.k_rest_N_per_m;
        t.k_hertz_N_per_m_pow_n = input.k_hertz_N_per_m_pow_n;
        t.source                = "Fourier coefficients of the scene";
        if (input.unloaded_ste_from_table)
          {
            const auto from_file = read_table_for(input);
            t.unloaded_ste_m     = from_file.unloaded_ste_m;
            t.has_unloaded_ste   = from_file.has_unloaded_ste;
          }
        t.check();
        return r;
      }
    };
  } // namespace

  const StiffnessSource &fourier_source() { return the_source<FourierSource>(); }
} // namespace hertzgear::stiffness
