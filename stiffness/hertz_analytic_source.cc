// Stiffness source hertz-analytic: Hertz closed forms per pair along the path of contact, the
// ISO 6336 structural stiffness, load sharing by compatibility (docs/stiffness-closed-form.md).
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

    protected:
      StiffnessResult tabulate(const StiffnessInput &input, ClosedFormPair &m) const override
      {
        StiffnessResult r = shared_load_cycle(input, m, false);
        r.table.source = "hertz-analytic: Hertz closed forms per pair along the path of contact, "
                         "ISO 6336 structural stiffness, load sharing by compatibility";
        return r;
      }
    };
  } // namespace

  const StiffnessSource &hertz_analytic_source() { return the_source<HertzAnalyticSource>(); }
} // namespace hertzgear::stiffness
