// Stiffness source hertz-analytic: Hertz closed forms per pair along the path of contact, the
// ISO 6336 structural stiffness, load sharing by compatibility (docs/stiffness-closed-form.md).
#include "meshing/pair_kinematics.h"
#include "stiffness/closed_form.h"

namespace hertzgear::stiffness
{
  namespace
  {
    class HertzAnalyticSource : public ClosedFormSource
    {
    public:
      HertzAnalyticSource()
        : ClosedFormSource("hertz-analytic", "Hertz closed forms along the path of contact")
      {}

      StiffnessResult compute(const StiffnessInput &input, PhaseTimer &timer) const override
      {
        check(input);
        PhaseTimer::Scope             scope(timer, "closed-form stiffness");
        const meshing::PairKinematics pair(input.pair);
        const ClosedFormPair          m(input, pair);
        StiffnessResult               r = shared_load_cycle(input, m, false);
        r.table.source = "hertz-analytic: Hertz closed forms per pair along the path of contact, "
                         "ISO 6336 structural stiffness, load sharing by compatibility";
        r.table.check();
        summarise_rows(r);
        return r;
      }
    };
  } // namespace

  const StiffnessSource &hertz_analytic_source() { return the_source<HertzAnalyticSource>(); }
} // namespace hertzgear::stiffness
